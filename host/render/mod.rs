//! `swarf render <run folder>`: PNG pictures of a run's frames without ParaView, the particles coloured by a
//! field with a colour bar, the tool drawn where it was (2D), and a title naming the scene, field, unit and time.
//!
//! - **3D runs** are drawn as seen from the positive side of an axis (`--along`, default z) looking down it: along
//!   z the page shows (x, y), along y (z, x), along x (y, z), each a right-handed view, not a mirror image. Only
//!   the particles of a slab min ≤ coordinate ≤ max are drawn where `--slab` gives one (default: all), painted from
//!   the lowest coordinate up, so that the surface facing the viewer (or the slab's upper face) is what shows. The
//!   tool is not drawn (its mesh is beside each frame for ParaView).
//!
//! - **Frames** are read back from the run folder (`particles.pvd` and its `frame_*.vtu`, [`crate::output`]).
//!   `--frame N` counts the PVD's entries from 0 (frame_0000N.vtu in a run that was not resumed), `last` is the
//!   default, `all` draws every frame. One colour scale serves all frames drawn by one command, so that a series
//!   can be compared (and animated by any tool) frame to frame.
//! - **The tool** is not in the frames: its outline is rebuilt from the run folder's `scene.toml` (with the
//!   overrides its summary.json or checkpoint records) and placed by the run's own motion at the frame's time
//!   ([`crate::tool::outline`]). A run folder whose scene cannot be read is drawn without the tool, with a warning.
//! - **Refused:** a slab for a 2D run, a slab that holds no particle, a missing field (the message lists the fields the frame has), a frame that does not
//!   exist, a folder without frames. Nothing is written then.
//! - No animated GIF: plotters' GIF backend needs the `gif` crate, a dependency the project does not have; the
//!   `all` frames are numbered PNGs that ffmpeg or ImageMagick turn into one.

pub mod draw;
pub mod field;

use std::path::{Path, PathBuf};

use crate::output::{pvd, vtu};
use crate::scene::Scene;
use crate::study::table::sig;
use crate::{Error, Result};
pub use field::Field;

/// Image size in pixels.
pub const SIZE: (u32, u32) = (1200, 800);

/// Which frames to draw.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Frames {
    Last,
    All,
    /// The PVD's entry N, from 0.
    Index(usize),
}

impl Frames {
    /// `last`, `all` or a frame number.
    pub fn parse(text: &str) -> std::result::Result<Frames, String> {
        match text.trim() {
            "last" => Ok(Frames::Last),
            "all" => Ok(Frames::All),
            n => n
                .parse()
                .map(Frames::Index)
                .map_err(|_| format!("--frame {text}: expected a frame number (0 is the first), 'last' or 'all'")),
        }
    }
}

/// What to draw.
#[derive(Clone, Debug)]
pub struct RenderOptions {
    /// The run folder.
    pub run: PathBuf,
    /// A frame array or a short name (see [`field`]).
    pub field: String,
    pub frames: Frames,
    /// Output folder (default `<run>/render`).
    pub out: Option<PathBuf>,
    /// A 3D run's slab min ≤ coordinate ≤ max along `along` [m] (None: every particle).
    pub slab: Option<(f64, f64)>,
    /// The axis a 3D run is seen along (0, 1, 2: x, y, z), from its positive side.
    pub along: usize,
    /// The region shown, ((x0, x1), (y0, y1)) in m along the page's axes, widened on one axis to equal scales
    /// (None: every particle drawn and the tool).
    pub window: Option<draw::Region>,
}

/// The page's (horizontal, vertical) axes of a view along axis `along`, right-handed (page right × page up points
/// at the viewer, along +`along`).
pub fn page_axes(along: usize) -> (usize, usize) {
    match along {
        0 => (1, 2),
        1 => (2, 0),
        _ => (0, 1),
    }
}

/// What was drawn.
#[derive(Clone, Debug, Default)]
pub struct Rendered {
    pub files: Vec<PathBuf>,
    /// E.g. the scene could not be read, so the tool is not drawn.
    pub warnings: Vec<String>,
    /// The particles drawn in each picture (those whose centre lies in the region shown).
    pub drawn: Vec<usize>,
}

/// The run folder as `render` sees it: its frames (time, file) and its scene, if readable.
struct RunFolder {
    frames: Vec<(f64, PathBuf)>,
    scene: Option<Scene>,
    name: String,
}

/// Draws the chosen frames of `opts.run`; writes `<field>_<NNNNN>.png` (N: the frame's PVD entry) into the
/// output folder.
pub fn render(opts: &RenderOptions) -> Result<Rendered> {
    let mut done = Rendered::default();
    let run = open(&opts.run, &mut done.warnings)?;
    let picks = select(&run, opts)?;
    let (first_path, first) = read(&run, picks[0])?;
    let dim3 = run.scene.as_ref().map_or_else(|| planar(&first).is_none(), |s| s.dim == 3);
    if !dim3 && opts.slab.is_some() {
        return Err(Error::Scene(format!("render: --slab: {} is a 2D run; a slab is for 3D runs", opts.run.display())));
    }
    let field = Field::resolve(&opts.field, &first, &first_path)?;
    // One colour scale for all frames drawn: the range over them (the first is already read).
    let mut range = (f64::INFINITY, f64::NEG_INFINITY);
    for &k in &picks {
        let frame = if k == picks[0] { first.clone() } else { read(&run, k)?.1 };
        for v in field.values(&frame).unwrap_or_default().into_iter().filter(|v| v.is_finite()) {
            range = (range.0.min(v), range.1.max(v));
        }
    }
    if !range.0.is_finite() {
        range = (0.0, 0.0);
    }
    let out = opts.out.clone().unwrap_or_else(|| opts.run.join("render"));
    let mut pictures = Vec::new();
    for &k in &picks {
        let (path, frame) = read(&run, k)?;
        let view = if dim3 { Some((opts.along.min(2), opts.slab)) } else { None };
        let (points, order) = projected(&frame, view).ok_or_else(|| refuse_planar(&path))?;
        if points.is_empty() {
            return Err(Error::Scene(format!(
                "render: --slab {:?}: no particle of {} lies in it",
                opts.slab,
                path.display()
            )));
        }
        if let Some(w) = opts.window.filter(|&w| !points.iter().any(|p| draw::contains(w, p))) {
            return Err(Error::Scene(format!(
                "render: --window {:?}: no particle of {} lies in it (x0, x1, y0, y1 in m, along the page's axes)",
                [w.0.0, w.0.1, w.1.0, w.1.1],
                path.display()
            )));
        }
        pictures.push((k, path, frame, points, order));
    }
    std::fs::create_dir_all(&out).map_err(|e| Error::Output(format!("{}: {e}", out.display())))?;
    for (k, path, frame, points, order) in pictures {
        let file = out.join(format!("{}_{k:05}.png", field.name));
        let shown = Shown { points: &points, order: &order, dim3, slab: opts.slab, along: opts.along.min(2) };
        let view = picture(&run, &field, &path, &frame, run.frames[k].0, range, &shown, opts.window, &file)?;
        done.drawn.push(points.iter().filter(|p| draw::contains(view, p)).count());
        done.files.push(file);
    }
    Ok(done)
}

/// The particles a picture shows: their (x, y) and their indices in the frame (painting order).
struct Shown<'a> {
    points: &'a [[f64; 2]],
    order: &'a [usize],
    dim3: bool,
    slab: Option<(f64, f64)>,
    along: usize,
}

/// Draws one frame to `file`; returns the region shown.
#[allow(clippy::too_many_arguments)]
fn picture(
    run: &RunFolder,
    field: &Field,
    path: &Path,
    frame: &vtu::ReadFrame,
    pvd_time: f64,
    range: (f64, f64),
    shown: &Shown<'_>,
    window: Option<draw::Region>,
    file: &Path,
) -> Result<draw::Region> {
    let all = field.values(frame).ok_or_else(|| field::missing(&field.name, frame, path))?;
    let values: Vec<f64> = shown.order.iter().map(|&i| all[i]).collect();
    let points = shown.points;
    let time = frame.time.unwrap_or(pvd_time);
    let tool = match run.scene.as_ref().and_then(|s| s.tool.as_ref()).filter(|_| !shown.dim3) {
        Some(t) => Some(crate::tool::outline::outline_at(t, time)?),
        None => None,
    };
    let (_, plot) = draw::layout(SIZE);
    let view = draw::view(points, tool.as_deref(), plot, window);
    let dx = run.scene.as_ref().map_or_else(|| spacing(points), |s| s.discretisation.dx);
    let unit = if field.unit.is_empty() { String::new() } else { format!(" ({})", field.unit) };
    const NAMES: [&str; 3] = ["x", "y", "z"];
    let (h, v) = if shown.dim3 { page_axes(shown.along) } else { (0, 1) };
    let a = NAMES[shown.along];
    let seen = match (shown.dim3, shown.slab) {
        (false, _) => String::new(),
        (true, None) => format!(", seen along −{a}"),
        (true, Some((lo, hi))) => format!(", {a} = {}..{} µm seen along −{a}", sig(lo * 1e6, 4), sig(hi * 1e6, 4)),
    };
    let title = format!("{}: {}{unit}, t = {}{seen}", run.name, field.label, time_text(time));
    let bar_label = format!("{}{unit}", field.label);
    let pic = draw::Picture {
        title: &title,
        bar_label: &bar_label,
        points,
        values: &values,
        range,
        tool: tool.as_deref(),
        view,
        axes: (NAMES[h], NAMES[v]),
        dx,
    };
    draw::draw(file, &pic, SIZE).map_err(|e| Error::Output(e.to_string()))?;
    Ok(view)
}

/// The run folder's frames and scene (a scene that cannot be read is a warning: the tool is then not drawn).
fn open(dir: &Path, warnings: &mut Vec<String>) -> Result<RunFolder> {
    let pvd_path = dir.join("particles.pvd");
    let entries = pvd::read(&pvd_path)
        .map_err(|e| Error::Output(format!("render: {} is not a run folder with frames ({e})", dir.display())))?;
    if entries.is_empty() {
        return Err(Error::Output(format!("render: {} lists no frames", pvd_path.display())));
    }
    let frames = entries.into_iter().map(|(t, f)| (t, dir.join(f))).collect();
    let scene = match crate::run_folder::scene(dir) {
        Ok(s) => Some(s),
        Err(e) => {
            warnings.push(format!("{}: the scene is not read ({e}); the tool is not drawn", dir.display()));
            None
        }
    };
    let folder = dir.file_name().map_or_else(|| dir.display().to_string(), |n| n.to_string_lossy().into_owned());
    let name = scene.as_ref().map_or(folder, |s| s.name.clone());
    Ok(RunFolder { frames, scene, name })
}

/// The PVD entries to draw.
fn select(run: &RunFolder, opts: &RenderOptions) -> Result<Vec<usize>> {
    let n = run.frames.len();
    match opts.frames {
        Frames::Last => Ok(vec![n - 1]),
        Frames::All => Ok((0..n).collect()),
        Frames::Index(k) if k < n => Ok(vec![k]),
        Frames::Index(k) => Err(Error::Scene(format!(
            "render: --frame {k}: {} has frames 0 to {} (particles.pvd)",
            opts.run.display(),
            n - 1
        ))),
    }
}

fn read(run: &RunFolder, k: usize) -> Result<(PathBuf, vtu::ReadFrame)> {
    let path = run.frames[k].1.clone();
    let frame = vtu::read(&path).map_err(|e| Error::Output(e.to_string()))?;
    Ok((path, frame))
}

fn refuse_planar(what: &Path) -> Error {
    Error::Scene(format!(
        "render: {} has particles with z ≠ 0 but its scene.toml says dim = 2 (open its particles.pvd in ParaView)",
        what.display()
    ))
}

/// The frame's particles as drawn: their page coordinates and their indices. `view` None: a 2D frame, (x, y)
/// (None if any particle has z ≠ 0); Some((axis, slab)): a 3D frame seen along −axis ([`page_axes`]), the particles
/// in the slab (all without one), lowest coordinate first.
#[allow(clippy::type_complexity)]
fn projected(frame: &vtu::ReadFrame, view: Option<(usize, Option<(f64, f64)>)>) -> Option<(Vec<[f64; 2]>, Vec<usize>)> {
    let xyz = frame.points.floats()?;
    let p: Vec<&[f64]> = xyz.chunks(3).collect();
    let (along, (h, v)) = view.map_or((2, (0, 1)), |(a, _)| (a, page_axes(a)));
    let mut order: Vec<usize> = match view {
        None if p.iter().any(|q| q[2] != 0.0) => return None,
        None => (0..p.len()).collect(),
        Some((_, slab)) => {
            (0..p.len()).filter(|&i| slab.is_none_or(|(a, b)| p[i][along] >= a && p[i][along] <= b)).collect()
        }
    };
    if view.is_some() {
        order.sort_by(|&i, &j| p[i][along].total_cmp(&p[j][along]));
    }
    Some((order.iter().map(|&i| [p[i][h], p[i][v]]).collect(), order))
}

/// The frame's positions in the plane; `None` if any particle has z ≠ 0 (a 3D frame).
fn planar(frame: &vtu::ReadFrame) -> Option<Vec<[f64; 2]>> {
    projected(frame, None).map(|(p, _)| p)
}

/// A particle spacing for a frame without its scene: the side of the bounding box's area per particle.
fn spacing(points: &[[f64; 2]]) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in points {
        for a in 0..2 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    ((hi[0] - lo[0]) * (hi[1] - lo[1]) / points.len().max(1) as f64).sqrt()
}

/// A frame time for a title, in µs, ms or s by its size.
fn time_text(t: f64) -> String {
    match t.abs() {
        a if a > 0.0 && a < 1e-3 => format!("{} µs", sig(t * 1e6, 4)),
        a if a > 0.0 && a < 1.0 => format!("{} ms", sig(t * 1e3, 4)),
        _ => format!("{} s", sig(t, 4)),
    }
}
