//! `swarf render <run folder>`: PNG pictures of a 2D run's frames without ParaView, the particles coloured by a
//! field with a colour bar, the tool drawn where it was, and a title naming the scene, field, unit and time.
//!
//! - **Frames** are read back from the run folder (`particles.pvd` and its `frame_*.vtu`, [`crate::output`]).
//!   `--frame N` counts the PVD's entries from 0 (frame_0000N.vtu in a run that was not resumed), `last` is the
//!   default, `all` draws every frame. One colour scale serves all frames drawn by one command, so that a series
//!   can be compared (and animated by any tool) frame to frame.
//! - **The tool** is not in the frames: its outline is rebuilt from the run folder's `scene.toml` (with the
//!   overrides its summary.json or checkpoint records) and placed by the run's own motion at the frame's time
//!   ([`crate::tool::outline`]). A run folder whose scene cannot be read is drawn without the tool, with a warning.
//! - **Refused:** a 3D run, a missing field (the message lists the fields the frame has), a frame that does not
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
}

/// What was drawn.
#[derive(Clone, Debug, Default)]
pub struct Rendered {
    pub files: Vec<PathBuf>,
    /// E.g. the scene could not be read, so the tool is not drawn.
    pub warnings: Vec<String>,
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
    if let Some(s) = &run.scene
        && s.dim != 2
    {
        return Err(refuse_3d(&opts.run, &format!("its scene.toml has dim = {}", s.dim)));
    }
    if planar(&first).is_none() {
        return Err(refuse_3d(&first_path, "its particles have z ≠ 0"));
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
    std::fs::create_dir_all(&out).map_err(|e| Error::Output(format!("{}: {e}", out.display())))?;
    for &k in &picks {
        let (path, frame) = read(&run, k)?;
        let file = out.join(format!("{}_{k:05}.png", field.name));
        picture(&run, &field, &path, &frame, run.frames[k].0, range, &file)?;
        done.files.push(file);
    }
    Ok(done)
}

/// Draws one frame to `file`.
fn picture(
    run: &RunFolder,
    field: &Field,
    path: &Path,
    frame: &vtu::ReadFrame,
    pvd_time: f64,
    range: (f64, f64),
    file: &Path,
) -> Result<()> {
    let points = planar(frame).ok_or_else(|| refuse_3d(path, "its particles have z ≠ 0"))?;
    let values = field.values(frame).ok_or_else(|| field::missing(&field.name, frame, path))?;
    let time = frame.time.unwrap_or(pvd_time);
    let tool = match run.scene.as_ref().and_then(|s| s.tool.as_ref()) {
        Some(t) => Some(crate::tool::outline::outline_at(t, time)?),
        None => None,
    };
    let (_, plot) = draw::layout(SIZE);
    let view = draw::view(&points, tool.as_deref(), plot);
    let dx = run.scene.as_ref().map_or_else(|| spacing(&points), |s| s.discretisation.dx);
    let unit = if field.unit.is_empty() { String::new() } else { format!(" ({})", field.unit) };
    let title = format!("{}: {}{unit}, t = {}", run.name, field.label, time_text(time));
    let bar_label = format!("{}{unit}", field.label);
    let pic = draw::Picture {
        title: &title,
        bar_label: &bar_label,
        points: &points,
        values: &values,
        range,
        tool: tool.as_deref(),
        view,
        dx,
    };
    draw::draw(file, &pic, SIZE).map_err(|e| Error::Output(e.to_string()))
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
    let scene = match Scene::load(dir.join("scene.toml"), &crate::run_folder::overrides(dir)) {
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

fn refuse_3d(what: &Path, why: &str) -> Error {
    Error::Scene(format!(
        "render draws 2D runs only; {} is 3D: {why} (open its particles.pvd in ParaView)",
        what.display()
    ))
}

/// The frame's positions in the plane; `None` if any particle has z ≠ 0 (a 3D frame).
fn planar(frame: &vtu::ReadFrame) -> Option<Vec<[f64; 2]>> {
    let xyz = frame.points.floats()?;
    xyz.chunks(3).map(|p| (p[2] == 0.0).then_some([p[0], p[1]])).collect()
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
