//! PNG plots of a run's time series (energies, momenta; later forces and temperatures).
//!
//! [`draw`] renders one [`Chart`] (any number of x–y [`Series`]) to a PNG; [`plot_run`] draws the standard plots
//! of a run folder from its CSV files (see [`run`]). Rendering is plotters' bitmap backend; text uses DejaVu Sans
//! (a Latin/Greek/math-symbol subset, `assets/fonts/`, Bitstream Vera licence) embedded in the binary and
//! registered with plotters' `ab_glyph` font table on first use, so no system font library is needed.
//!
//! - **Atomic.** plotters writes the image to a hidden scratch file beside the destination
//!   (`.<name>.plot-<pid>-<n>.png`), which is then copied to the destination with
//!   [`write_atomic`](crate::output::write_atomic) and removed: a viewer refreshing the PNG during a run sees the
//!   old image or the new one, never a partial one. The image is PNG whatever the destination's extension.
//! - **Ranges.** Each axis spans the finite data; the y axis gets a 5 % margin on each side (the x axis, usually
//!   time, none, so that it starts at the first sample). A zero range (a constant series, a single point, or a
//!   span below 10⁻⁹ of the values' magnitude: rounding noise) is widened to ±5 % of the value (±1 around zero).
//!   Tick labels are plain decimals for magnitudes in [10⁻³, 10⁵) and exponent form otherwise (`2e-5`, `2.5e-5`),
//!   with as many digits as the tick spacing needs. Panels of one image share the y label width, so their time
//!   axes line up. The legend goes to the corner (or side) where it hides the fewest data.
//! - **Non-finite values.** A point whose x or y is NaN, ±∞ or beyond ±10³⁰⁰ is skipped and its line is broken
//!   there (not bridged). The count is returned in [`Drawn::skipped`] (no error: a run that blew up still gets
//!   its plot up to the blow-up); [`Drawn::warning`] words it for the user. A series with no drawable point
//!   keeps its legend entry, marked "(no finite values)"; a chart with no drawable point at all is refused.
//! - **Refused input** ([`PlotError`], never a panic): no series, an empty series, x and y of different lengths,
//!   an image size outside [`MIN_SIZE`]..=[`MAX_SIDE`]. Every error names the file it concerns.

mod loglog;
pub mod run;

use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::sync::atomic::{AtomicU64, Ordering};

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::register_font;
use thiserror::Error;

use crate::output::write_atomic;

pub use loglog::draw_log_log;
pub use run::{plot_run, plot_run_sized};

/// The embedded font: DejaVu Sans 2.37, subset to Latin-1, Greek and common math symbols (see
/// `assets/fonts/README.md` and `LICENSE-DejaVu.txt`).
static FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans-subset.ttf");

/// The family name every text style here uses; the embedded font is registered under it.
pub(crate) const FAMILY: &str = "sans-serif";

/// Smallest accepted image (width, height) in pixels: below it the axes leave no room for data.
pub const MIN_SIZE: (u32, u32) = (160, 120);
/// Largest accepted image side in pixels (16384² RGB is 768 MiB of pixels).
pub const MAX_SIDE: u32 = 16384;

/// Values beyond this magnitude are skipped with the non-finite ones: their differences would overflow.
const MAX_ABS: f64 = 1e300;

/// Line colours, in series order (the "tab10" palette, distinct in print and for most colour vision).
const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// One line of a chart: `y` against `x`, point by point.
#[derive(Clone, Copy, Debug)]
pub struct Series<'a> {
    pub label: &'a str,
    pub x: &'a [f64],
    pub y: &'a [f64],
}

/// One plot: a title, axis descriptions and the series drawn on common axes.
#[derive(Clone, Debug)]
pub struct Chart<'a> {
    pub title: &'a str,
    pub x_label: &'a str,
    pub y_label: &'a str,
    pub series: Vec<Series<'a>>,
}

/// A PNG written by [`draw`], [`draw_panels`] or [`plot_run`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Drawn {
    pub path: PathBuf,
    /// Points skipped because x or y was NaN, infinite or beyond ±10³⁰⁰ (summed over all series).
    pub skipped: usize,
}

impl Drawn {
    /// A line for the user when points were skipped, e.g. `runs/x/energy.png: 3 non-finite points skipped`.
    pub fn warning(&self) -> Option<String> {
        match self.skipped {
            0 => None,
            1 => Some(format!("{}: 1 non-finite point skipped", self.path.display())),
            n => Some(format!("{}: {n} non-finite points skipped", self.path.display())),
        }
    }
}

/// Why a plot could not be made. `path` is the file concerned: the CSV read or the PNG to write.
#[derive(Debug, Error)]
pub enum PlotError {
    /// An input file could not be read or parsed; the message names the file.
    #[error("{error}")]
    Read { path: PathBuf, error: io::Error },
    /// The image could not be written; the message names the file.
    #[error("{error}")]
    Write { path: PathBuf, error: io::Error },
    /// A CSV lacks a column a plot needs.
    #[error("{}: no column {column:?} (columns: {})", path.display(), columns.join(", "))]
    MissingColumn { path: PathBuf, column: String, columns: Vec<String> },
    /// A CSV has a header but no data rows.
    #[error("{}: no data rows to plot", path.display())]
    NoRows { path: PathBuf },
    /// A chart without any series.
    #[error("{}: chart {title:?} has no series", path.display())]
    NoSeries { path: PathBuf, title: String },
    /// A series without any point.
    #[error("{}: series {label:?} is empty", path.display())]
    EmptySeries { path: PathBuf, label: String },
    /// A series whose x and y differ in length.
    #[error("{}: series {label:?} has {x} x values and {y} y values", path.display())]
    LengthMismatch { path: PathBuf, label: String, x: usize, y: usize },
    /// Every point of every series of a chart was skipped as non-finite.
    #[error("{}: chart {title:?} has no finite point to draw ({skipped} non-finite points)", path.display())]
    NoFiniteData { path: PathBuf, title: String, skipped: usize },
    /// The requested image size is out of range.
    #[error(
        "{}: image size {width}x{height} out of range ({}x{} to {MAX_SIDE}x{MAX_SIDE} pixels)",
        path.display(), MIN_SIZE.0, MIN_SIZE.1
    )]
    Size { path: PathBuf, width: u32, height: u32 },
    /// The plotting library failed (font, drawing or encoding); the message says how.
    #[error("{}: drawing failed: {message}", path.display())]
    Draw { path: PathBuf, message: String },
}

/// Draws `chart` as a PNG of `size` = (width, height) pixels at `path`, atomically. Returns the path and the
/// number of non-finite points skipped (see the module docs).
pub fn draw(path: &Path, chart: &Chart, size: (u32, u32)) -> Result<Drawn, PlotError> {
    draw_panels(path, std::slice::from_ref(chart), size)
}

/// Refuses a stack of `charts` that `size` cannot hold (each panel at least [`MIN_SIZE`], no side above
/// [`MAX_SIDE`]) or an empty one.
pub(super) fn check_panels(path: &Path, charts: &[Chart], size: (u32, u32)) -> Result<(), PlotError> {
    let (width, height) = size;
    let panels = u32::try_from(charts.len()).unwrap_or(u32::MAX).max(1);
    let size_ok = (MIN_SIZE.0..=MAX_SIDE).contains(&width)
        && (MIN_SIZE.1..=MAX_SIDE).contains(&height)
        && height / panels >= MIN_SIZE.1;
    if !size_ok {
        return Err(PlotError::Size { path: path.to_path_buf(), width, height });
    }
    if charts.is_empty() {
        return Err(PlotError::NoSeries { path: path.to_path_buf(), title: String::new() });
    }
    Ok(())
}

/// Draws `charts` stacked top to bottom in one PNG of `size` pixels (each chart gets an equal share of the
/// height, which must leave each at least [`MIN_SIZE`]`.1` pixels), atomically. For quantities of different units
/// that share an x axis, such as linear and angular momentum.
pub fn draw_panels(path: &Path, charts: &[Chart], size: (u32, u32)) -> Result<Drawn, PlotError> {
    check_panels(path, charts, size)?;
    let prepared = charts.iter().map(|c| Prepared::new(path, c)).collect::<Result<Vec<_>, _>>()?;
    let skipped = prepared.iter().map(|p| p.skipped).sum();
    draw_atomic(path, skipped, |target| render(target, &prepared, size))
}

/// Draws with `render` into a scratch file beside `path` (the embedded font registered first) and moves the
/// finished PNG to `path` atomically: a failed or interrupted plot leaves no half-written file. Shared by the
/// run plots and the study's log–log plot.
pub(crate) fn draw_atomic(
    path: &Path,
    skipped: usize,
    render: impl FnOnce(&Path) -> Result<(), String>,
) -> Result<Drawn, PlotError> {
    register_embedded_font(path)?;
    // Said plainly, not as plotters' `ImageError(IoError(Os { .. }))`.
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty() && !d.is_dir()) {
        let e = io::Error::new(
            io::ErrorKind::NotFound,
            format!("{}: the folder {} does not exist", path.display(), dir.display()),
        );
        return Err(PlotError::Write { path: path.to_path_buf(), error: e });
    }
    let scratch = Scratch::new(path)?;
    render(&scratch.path).map_err(|message| PlotError::Draw {
        path: path.to_path_buf(),
        message: format!("{message} (scratch file {})", scratch.path.display()),
    })?;
    let bytes = fs::read(&scratch.path).map_err(|e| PlotError::Write {
        path: path.to_path_buf(),
        error: io::Error::new(
            e.kind(),
            format!("{}: reading scratch file {}: {e}", path.display(), scratch.path.display()),
        ),
    })?;
    write_atomic(path, &bytes).map_err(|error| PlotError::Write { path: path.to_path_buf(), error })?;
    drop(scratch);
    Ok(Drawn { path: path.to_path_buf(), skipped })
}

/// Registers the embedded font once per process; every later call returns the first outcome.
fn register_embedded_font(path: &Path) -> Result<(), PlotError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    if *REGISTERED.get_or_init(|| register_font(FAMILY, FontStyle::Normal, FONT).is_ok()) {
        Ok(())
    } else {
        Err(PlotError::Draw {
            path: path.to_path_buf(),
            message: "the embedded font is not a valid TrueType font".into(),
        })
    }
}

/// The hidden file plotters renders into, beside the destination; removed when dropped (on success and on every
/// error path). Its name ends in `.png` because plotters picks the image format from the extension.
struct Scratch {
    path: PathBuf,
}

impl Scratch {
    fn new(path: &Path) -> Result<Self, PlotError> {
        static COUNTER: AtomicU64 = AtomicU64::new(0);
        let name = path.file_name().ok_or_else(|| PlotError::Write {
            path: path.to_path_buf(),
            error: io::Error::new(io::ErrorKind::InvalidInput, format!("{}: not a file name", path.display())),
        })?;
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let scratch = format!(".{}.plot-{}-{n}.png", name.to_string_lossy(), std::process::id());
        Ok(Self { path: path.with_file_name(scratch) })
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        // Absent when rendering failed before plotters created it; nothing to report either way.
        let _ = fs::remove_file(&self.path);
    }
}

/// A chart checked and reduced to drawable segments, with its axis ranges.
struct Prepared<'a> {
    chart: &'a Chart<'a>,
    /// Per series: runs of consecutive drawable points (a skipped point ends a run).
    segments: Vec<Vec<Vec<(f64, f64)>>>,
    x_range: (f64, f64),
    y_range: (f64, f64),
    skipped: usize,
}

impl<'a> Prepared<'a> {
    fn new(path: &Path, chart: &'a Chart<'a>) -> Result<Self, PlotError> {
        if chart.series.is_empty() {
            return Err(PlotError::NoSeries { path: path.to_path_buf(), title: chart.title.to_string() });
        }
        let mut segments = Vec::with_capacity(chart.series.len());
        let mut skipped = 0;
        let (mut x_lim, mut y_lim) = (Limits::default(), Limits::default());
        for s in &chart.series {
            if s.x.len() != s.y.len() {
                let (label, x, y) = (s.label.to_string(), s.x.len(), s.y.len());
                return Err(PlotError::LengthMismatch { path: path.to_path_buf(), label, x, y });
            }
            if s.x.is_empty() {
                return Err(PlotError::EmptySeries { path: path.to_path_buf(), label: s.label.to_string() });
            }
            let mut runs: Vec<Vec<(f64, f64)>> = Vec::new();
            let mut run = Vec::new();
            for (&x, &y) in s.x.iter().zip(s.y) {
                if drawable(x) && drawable(y) {
                    x_lim.add(x);
                    y_lim.add(y);
                    run.push((x, y));
                } else {
                    skipped += 1;
                    if !run.is_empty() {
                        runs.push(std::mem::take(&mut run));
                    }
                }
            }
            if !run.is_empty() {
                runs.push(run);
            }
            segments.push(runs);
        }
        let (Some(x), Some(y)) = (x_lim.range(), y_lim.range()) else {
            return Err(PlotError::NoFiniteData { path: path.to_path_buf(), title: chart.title.to_string(), skipped });
        };
        Ok(Self { chart, segments, x_range: pad(x, 0.0), y_range: pad(y, 0.05), skipped })
    }
}

fn drawable(v: f64) -> bool {
    v.is_finite() && v.abs() <= MAX_ABS
}

#[derive(Default)]
struct Limits(Option<(f64, f64)>);

impl Limits {
    fn add(&mut self, v: f64) {
        self.0 = Some(match self.0 {
            None => (v, v),
            Some((lo, hi)) => (lo.min(v), hi.max(v)),
        });
    }

    fn range(&self) -> Option<(f64, f64)> {
        self.0
    }
}

/// `(lo, hi)` widened by `margin` of its span on each side; a zero span, or one below 10⁻⁹ of the magnitude
/// (beyond what tick labels of 15 decimals can resolve), is widened to ±5 % of the value, or ±1 around zero.
pub(crate) fn pad((lo, hi): (f64, f64), margin: f64) -> (f64, f64) {
    let span = hi - lo;
    let mag = lo.abs().max(hi.abs());
    if span <= mag * 1e-9 {
        let mid = 0.5 * (lo + hi);
        let half = if mid == 0.0 { 1.0 } else { 0.05 * mid.abs() };
        return (mid - half, mid + half);
    }
    (lo - margin * span, hi + margin * span)
}

/// Formats tick values of an axis spanning `(lo, hi)`: plain decimals for magnitudes in [10⁻³, 10⁵), with the
/// decimals the tick spacing (about a tenth of the span) needs; exponent form otherwise, without trailing zeros
/// (`2e-5`, `2.5e-5`).
pub(crate) fn tick_formatter((lo, hi): (f64, f64)) -> impl Fn(&f64) -> String {
    let mag = lo.abs().max(hi.abs());
    let step = (hi - lo) / 10.0;
    let step_exp = step.log10().floor() as i32;
    let mag_exp = mag.log10().floor() as i32;
    let plain = (1e-3..1e5).contains(&mag);
    move |&v: &f64| {
        // Tick arithmetic leaves residues such as 3e-21 for zero; print those as 0, not -0.000 or 3.0e-21.
        let v = if v.abs() < step * 1e-6 { 0.0 } else { v };
        if plain {
            let decimals = (-step_exp).clamp(0, 15) as usize;
            format!("{v:.decimals$}")
        } else if v == 0.0 {
            "0".to_string()
        } else {
            let digits = (mag_exp - step_exp).clamp(0, 12) as usize;
            let s = format!("{v:.digits$e}");
            match s.split_once('e') {
                Some((mantissa, exp)) if mantissa.contains('.') => {
                    format!("{}e{exp}", mantissa.trim_end_matches('0').trim_end_matches('.'))
                }
                _ => s,
            }
        }
    }
}

/// The place in the plotting area where the legend covers the fewest data: points and 4 samples along each
/// segment are counted inside a legend-sized box at each corner and at mid-height on either side, in
/// axis-normalised coordinates; ties go to the upper right, then upper left, lower right, lower left, middle right,
/// middle left. `legend` and `plot` are (width, height) in pixels.
fn legend_place(p: &Prepared, legend: (u32, u32), plot: (u32, u32)) -> SeriesLabelPosition {
    let box_w = f64::from(legend.0) / f64::from(plot.0.max(1));
    let box_h = f64::from(legend.1) / f64::from(plot.1.max(1));
    let ((x0, x1), (y0, y1)) = (p.x_range, p.y_range);
    let norm = |(x, y): (f64, f64)| ((x - x0) / (x1 - x0), (y - y0) / (y1 - y0));
    // (right side, upper side) per corner, in preference order.
    // (horizontal, vertical) place per candidate: -1 left/lower, 0 middle, 1 right/upper.
    let corners = [
        (1, 1, SeriesLabelPosition::UpperRight),
        (-1, 1, SeriesLabelPosition::UpperLeft),
        (1, -1, SeriesLabelPosition::LowerRight),
        (-1, -1, SeriesLabelPosition::LowerLeft),
        (1, 0, SeriesLabelPosition::MiddleRight),
        (-1, 0, SeriesLabelPosition::MiddleLeft),
    ];
    let inside = |t: f64, side: i32, size: f64| match side {
        1 => t >= 1.0 - size,
        -1 => t <= size,
        _ => (t - 0.5).abs() <= 0.5 * size,
    };
    let mut counts = [0usize; 6];
    let mut count = |(u, v): (f64, f64)| {
        for (c, &(h, w, _)) in counts.iter_mut().zip(&corners) {
            *c += usize::from(inside(u, h, box_w) && inside(v, w, box_h));
        }
    };
    for run in p.segments.iter().flatten() {
        for (i, &point) in run.iter().enumerate() {
            let (u, v) = norm(point);
            count((u, v));
            if let Some(&next) = run.get(i + 1) {
                let (u1, v1) = norm(next);
                for k in 1..5 {
                    let f = f64::from(k) / 5.0;
                    count((u + f * (u1 - u), v + f * (v1 - v)));
                }
            }
        }
    }
    let best = (0..corners.len()).min_by_key(|&i| (counts[i], i)).unwrap_or(0);
    corners.into_iter().nth(best).map_or(SeriesLabelPosition::UpperRight, |c| c.2)
}

/// Sizes derived from the image: the base font size in pixels and the line width.
pub(crate) struct Metrics {
    pub(crate) font: u32,
    pub(crate) title: u32,
    pub(crate) stroke: u32,
    pub(crate) margin: u32,
}

impl Metrics {
    pub(crate) fn new((width, height): (u32, u32)) -> Self {
        let side = width.min(height);
        let font = (side / 40).clamp(10, 48);
        Self { font, title: font * 5 / 4, stroke: (side / 400).clamp(1, 8), margin: font }
    }

    /// Approximate pixel width of `text` in the base font (DejaVu Sans digits are 0.64 em).
    fn text_width(&self, text: &str) -> u32 {
        (text.chars().count() as f64 * 0.64 * self.font as f64).ceil() as u32
    }
}

/// Renders the prepared charts into a PNG at `target` (the scratch file).
fn render(target: &Path, charts: &[Prepared], size: (u32, u32)) -> Result<(), String> {
    let root = BitMapBackend::new(target, size).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let areas = root.split_evenly((charts.len(), 1));
    // Stacked panels share one text size, from the panel height but less shrunk than it.
    let panel_height = size.1 / charts.len().max(1) as u32;
    let m = Metrics::new((size.0, size.1.min(panel_height * 3 / 2)));
    // One y label area for all panels, so that their plotting areas (and time axes) line up.
    let y_label_area = charts.iter().map(|p| y_tick_width(p, &m)).max().unwrap_or(0) + m.font * 2;
    for (area, chart) in areas.iter().zip(charts) {
        render_chart(area, chart, &m, y_label_area)?;
    }
    root.present().map_err(|e| e.to_string())
}

/// Pixel width of the widest y tick label of `p` (the extremes are the longest, give or take a sign).
fn y_tick_width(p: &Prepared, m: &Metrics) -> u32 {
    let y_fmt = tick_formatter(p.y_range);
    [p.y_range.0, p.y_range.1, 0.5 * (p.y_range.0 + p.y_range.1)]
        .iter()
        .map(|v| m.text_width(&y_fmt(v)))
        .max()
        .unwrap_or(0)
}

fn render_chart(
    area: &DrawingArea<BitMapBackend, Shift>,
    p: &Prepared,
    m: &Metrics,
    y_label_area: u32,
) -> Result<(), String> {
    let err = |e: &dyn std::fmt::Display| e.to_string();
    let (x_fmt, y_fmt) = (tick_formatter(p.x_range), tick_formatter(p.y_range));
    let font = (FAMILY, m.font);
    let mut cc = ChartBuilder::on(area)
        .caption(p.chart.title, (FAMILY, m.title))
        .margin(m.margin)
        .margin_right(m.margin + m.text_width("0.0e-00") / 2)
        .x_label_area_size(m.font * 3)
        .y_label_area_size(y_label_area)
        .build_cartesian_2d(p.x_range.0..p.x_range.1, p.y_range.0..p.y_range.1)
        .map_err(|e| err(&e))?;
    cc.configure_mesh()
        .x_desc(p.chart.x_label)
        .y_desc(p.chart.y_label)
        .x_labels(8)
        .y_labels(8)
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .label_style(font)
        .axis_desc_style(font)
        .bold_line_style(RGBColor(225, 225, 225))
        .light_line_style(RGBColor(245, 245, 245))
        .draw()
        .map_err(|e| err(&e))?;
    let dot = m.stroke + 2;
    for (i, (series, runs)) in p.chart.series.iter().zip(&p.segments).enumerate() {
        let style = PALETTE[i % PALETTE.len()].stroke_width(m.stroke);
        let label = if runs.is_empty() { format!("{} (no finite values)", series.label) } else { series.label.into() };
        // A line per run of drawable points, a dot for an isolated point (a line of one point is invisible).
        let lines = runs.iter().filter(|r| r.len() > 1).map(|r| PathElement::new(r.clone(), style));
        cc.draw_series(lines).map_err(|e| err(&e))?;
        let dots = runs.iter().filter(|r| r.len() == 1).map(|r| Circle::new(r[0], dot, style.filled()));
        cc.draw_series(dots)
            .map_err(|e| err(&e))?
            .label(label)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], style));
    }
    // Legend box: a 24 px line sample, the widest label (text averages about 0.6 em), padding; one row per series.
    let label_width = p
        .chart
        .series
        .iter()
        .zip(&p.segments)
        .map(|(s, runs)| m.text_width(s.label) + if runs.is_empty() { m.text_width(" (no finite values)") } else { 0 })
        .max()
        .unwrap_or(0);
    let legend = (label_width + 24 + 4 * m.font, (m.font * 3 / 2) * p.chart.series.len() as u32 + m.font);
    let position = legend_place(p, legend, cc.plotting_area().dim_in_pixel());
    cc.configure_series_labels()
        .position(position)
        .label_font(font)
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(160, 160, 160))
        .margin(m.font / 2)
        .draw()
        .map_err(|e| err(&e))?;
    Ok(())
}
