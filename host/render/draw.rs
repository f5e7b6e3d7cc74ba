//! One picture of a 2D frame: the particles as squares of the lattice spacing coloured by a field (viridis), the
//! tool's outline over them, a colour bar on the right and a title. Axes are in mm with equal scales, so the
//! picture has the run's proportions. Written atomically through [`crate::plot`]'s scratch-file path, with its
//! embedded font.

use std::path::Path;

use plotters::prelude::*;

use crate::plot::{FAMILY, Metrics, PlotError, draw_atomic, pad, tick_formatter};

/// Colour of particles whose value is not finite.
const MISSING: RGBColor = RGBColor(200, 200, 200);
/// Slices of the colour bar.
const BAR_STEPS: usize = 256;
/// The viridis colour map (matplotlib's default, readable in grey and by most colour vision) at 8 even stops,
/// interpolated linearly; the values of plotters' `ViridisRGB` (its `colormaps` feature does not build alone).
const VIRIDIS: [(u8, u8, u8); 8] = [
    (68, 1, 84),
    (70, 50, 127),
    (54, 92, 141),
    (39, 127, 143),
    (31, 162, 136),
    (74, 194, 110),
    (160, 219, 57),
    (254, 232, 37),
];

/// What one picture shows. Positions are in m, `values` in the field's display unit.
pub struct Picture<'a> {
    pub title: &'a str,
    /// The colour bar's label, e.g. "temperature (K)".
    pub bar_label: &'a str,
    pub points: &'a [[f64; 2]],
    pub values: &'a [f64],
    /// The colour scale's (low, high) value (shared by every frame of one `render`).
    pub range: (f64, f64),
    /// The tool's outline (world frame), if drawn.
    pub tool: Option<&'a [[f64; 2]]>,
    /// The region shown, ((x0, x1), (y0, y1)) in m.
    pub view: Region,
    /// The page's horizontal and vertical axes, e.g. ("x", "y").
    pub axes: (&'a str, &'a str),
    /// The particle spacing [m]: the squares' side.
    pub dx: f64,
}

/// Draws `pic` as a PNG of `size` pixels at `path`.
pub fn draw(path: &Path, pic: &Picture, size: (u32, u32)) -> Result<(), PlotError> {
    draw_atomic(path, 0, |target| render(target, pic, size)).map(|_| ())
}

/// A region of the page, ((x0, x1), (y0, y1)) in m.
pub type Region = ((f64, f64), (f64, f64));

/// Whether the point `p` lies in `region` (its edges included).
pub fn contains(((x0, x1), (y0, y1)): Region, p: &[f64; 2]) -> bool {
    p[0] >= x0 && p[0] <= x1 && p[1] >= y0 && p[1] <= y1
}

/// The view: `window` if given, else the bounding box of `points` and `tool` padded by 4 %; then widened on one
/// axis so that a plot area of `plot` = (width, height) pixels shows it at equal scales.
pub fn view(points: &[[f64; 2]], tool: Option<&[[f64; 2]]>, plot: (u32, u32), window: Option<Region>) -> Region {
    let (x, y) = match window {
        Some(w) => w,
        None => {
            let all = points.iter().chain(tool.unwrap_or(&[])).filter(|p| p[0].is_finite() && p[1].is_finite());
            let (mut x, mut y) = ((f64::INFINITY, f64::NEG_INFINITY), (f64::INFINITY, f64::NEG_INFINITY));
            for p in all {
                x = (x.0.min(p[0]), x.1.max(p[0]));
                y = (y.0.min(p[1]), y.1.max(p[1]));
            }
            if !(x.0.is_finite() && y.0.is_finite()) {
                return ((-1.0, 1.0), (-1.0, 1.0));
            }
            (pad(x, 0.04), pad(y, 0.04))
        }
    };
    let scale = ((x.1 - x.0) / f64::from(plot.0.max(1))).max((y.1 - y.0) / f64::from(plot.1.max(1)));
    let widen = |(lo, hi): (f64, f64), pixels: u32| {
        let half = 0.5 * scale * f64::from(pixels);
        let mid = 0.5 * (lo + hi);
        (mid - half, mid + half)
    };
    (widen(x, plot.0), widen(y, plot.1))
}

/// `polygon` clipped to the rectangle `view` (Sutherland–Hodgman, one edge of the rectangle at a time): exact
/// for the tool's convex outline, where clamping its corners to the plot area, as plotters does, would bend it.
pub fn clip(polygon: &[[f64; 2]], view: Region) -> Vec<[f64; 2]> {
    let ((x0, x1), (y0, y1)) = view;
    // Each edge: the axis, its coordinate, and whether the inside lies above it.
    let edges = [(0, x0, true), (0, x1, false), (1, y0, true), (1, y1, false)];
    let mut out = polygon.to_vec();
    for (a, c, above) in edges {
        let inside = |p: &[f64; 2]| if above { p[a] >= c } else { p[a] <= c };
        let cut = |p: &[f64; 2], q: &[f64; 2]| {
            let t = (c - p[a]) / (q[a] - p[a]);
            [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]
        };
        let input = std::mem::take(&mut out);
        for (k, q) in input.iter().enumerate() {
            let p = &input[(k + input.len() - 1) % input.len()];
            match (inside(p), inside(q)) {
                (true, true) => out.push(*q),
                (true, false) => out.push(cut(p, q)),
                (false, true) => out.extend([cut(p, q), *q]),
                (false, false) => {}
            }
        }
    }
    out
}

/// The layout of an image of `size`: (the colour bar's width, the plot area's (width, height)), so that
/// [`view`] can match the plot area's proportions before drawing.
pub fn layout(size: (u32, u32)) -> (u32, (u32, u32)) {
    let m = Metrics::new(size);
    let bar = m.font * 9;
    let plot_w = size.0.saturating_sub(bar + 2 * m.margin + y_label_area(&m));
    let plot_h = size.1.saturating_sub(2 * m.margin + m.title * 2 + m.font * 3);
    (bar, (plot_w, plot_h))
}

fn y_label_area(m: &Metrics) -> u32 {
    m.font * 6
}

fn colour(v: f64, (lo, hi): (f64, f64)) -> RGBColor {
    if !v.is_finite() {
        return MISSING;
    }
    let t = if hi > lo { ((v - lo) / (hi - lo)).clamp(0.0, 1.0) } else { 0.5 };
    let x = t * (VIRIDIS.len() - 1) as f64;
    let k = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let f = x - k as f64;
    let mix = |a: u8, b: u8| (f64::from(a) + f * (f64::from(b) - f64::from(a))).round() as u8;
    let (a, b) = (VIRIDIS[k], VIRIDIS[k + 1]);
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

fn render(target: &Path, pic: &Picture, size: (u32, u32)) -> Result<(), String> {
    let err = |e: &dyn std::fmt::Display| e.to_string();
    let m = Metrics::new(size);
    let (bar_w, _) = layout(size);
    let root = BitMapBackend::new(target, size).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let (main, bar) = root.split_horizontally(size.0.saturating_sub(bar_w));
    let font = (FAMILY, m.font);
    let mm = |(a, b): (f64, f64)| (a * 1e3, b * 1e3);
    let ((x0, x1), (y0, y1)) = (mm(pic.view.0), mm(pic.view.1));
    let mut cc = ChartBuilder::on(&main)
        .caption(pic.title, (FAMILY, m.title))
        .margin(m.margin)
        .x_label_area_size(m.font * 3)
        .y_label_area_size(y_label_area(&m))
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| err(&e))?;
    let (x_fmt, y_fmt) = (tick_formatter((x0, x1)), tick_formatter((y0, y1)));
    cc.configure_mesh()
        .x_desc(format!("{} (mm)", pic.axes.0))
        .y_desc(format!("{} (mm)", pic.axes.1))
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .label_style(font)
        .axis_desc_style(font)
        .disable_mesh()
        .draw()
        .map_err(|e| err(&e))?;
    // Each particle is its cell: a square of side dx, widened by 0.6 px on each side so that neighbours rounded
    // to whole pixels leave no seam of white between them.
    let mm_per_px = (x1 - x0) / f64::from(cc.plotting_area().dim_in_pixel().0.max(1));
    let half = 0.5 * pic.dx * 1e3 + 0.6 * mm_per_px;
    // plotters clamps each corner to the plot area, which cuts a square that crosses the border exactly but
    // would pile those wholly outside (a --window's) onto the border: they are left out.
    let seen = |x: f64, y: f64| x + half > x0 && x - half < x1 && y + half > y0 && y - half < y1;
    let cells = pic.points.iter().zip(pic.values).filter(|(p, _)| seen(p[0] * 1e3, p[1] * 1e3)).map(|(p, &v)| {
        let (x, y) = (p[0] * 1e3, p[1] * 1e3);
        Rectangle::new([(x - half, y - half), (x + half, y + half)], colour(v, pic.range).filled())
    });
    cc.draw_series(cells).map_err(|e| err(&e))?;
    if let Some(tool) = pic.tool.map(|t| clip(t, pic.view)).filter(|t| t.len() > 2) {
        let pts: Vec<(f64, f64)> = tool.iter().map(|p| (p[0] * 1e3, p[1] * 1e3)).collect();
        cc.draw_series(std::iter::once(Polygon::new(pts.clone(), RGBColor(150, 150, 150).mix(0.7))))
            .map_err(|e| err(&e))?;
        let mut closed = pts;
        closed.extend(closed.first().copied());
        cc.draw_series(std::iter::once(PathElement::new(closed, BLACK.stroke_width(m.stroke + 1))))
            .map_err(|e| err(&e))?;
    }
    colour_bar(&bar, pic, &m)?;
    root.present().map_err(|e| err(&e))
}

/// The colour bar: a column of the colour map from the range's low to its high value, ticks and the label on
/// its right.
fn colour_bar(
    area: &DrawingArea<BitMapBackend, plotters::coord::Shift>,
    pic: &Picture,
    m: &Metrics,
) -> Result<(), String> {
    let err = |e: &dyn std::fmt::Display| e.to_string();
    let (lo, hi) = if pic.range.1 > pic.range.0 { pic.range } else { pad(pic.range, 0.0) };
    let font = (FAMILY, m.font);
    let mut cc = ChartBuilder::on(area)
        .margin_top(m.margin + m.title * 2)
        .margin_bottom(m.margin + m.font * 3)
        .margin_left(m.font)
        .margin_right(m.font)
        .right_y_label_area_size(m.font * 5)
        .build_cartesian_2d(0.0..1.0, lo..hi)
        .map_err(|e| err(&e))?;
    let y_fmt = tick_formatter((lo, hi));
    cc.configure_mesh()
        .disable_x_mesh()
        .disable_y_mesh()
        .disable_x_axis()
        .y_desc(pic.bar_label)
        .y_label_formatter(&y_fmt)
        .label_style(font)
        .axis_desc_style(font)
        .draw()
        .map_err(|e| err(&e))?;
    let step = (hi - lo) / BAR_STEPS as f64;
    let slices = (0..BAR_STEPS).map(|k| {
        let a = lo + step * k as f64;
        Rectangle::new([(0.0, a), (1.0, a + step)], colour(a + 0.5 * step, (lo, hi)).filled())
    });
    cc.draw_series(slices).map_err(|e| err(&e))?;
    Ok(())
}
