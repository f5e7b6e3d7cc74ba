//! The frame chip analysis ([`super::chip_frame`]) of a run: its set-up from the scene (the tool where the scene's
//! motion puts it at the frame's time, the uncut surface from the generated workpiece), and the analysis of a
//! frame of a run folder (`swarf chip`).

use super::chip_frame::{FrameChip, analyse};
use super::chip_profile::FrameSetup;
use crate::output::{pvd, vtu};
use crate::scene::Scene;
use crate::{Error, Result};
use std::path::{Path, PathBuf};

/// The uncut surface's height (the highest workpiece particle plus Δx/2) and the uncut chip thickness t1 (the
/// surface's height above the tool's frame origin, at least Δx) of a scene with a tool whose workpiece starts at
/// `pos` (as the cutting record measures them).
pub fn surface_and_uncut(scene: &Scene, tool_y: f64, pos: &[[f64; 3]]) -> (f64, f64) {
    let dx = scene.discretisation.dx;
    let surface_y = pos.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max) + 0.5 * dx;
    (surface_y, (surface_y - tool_y).max(dx))
}

/// The set-up of a frame at `time` of a 2D scene with a translating tool, whose uncut surface is `surface_y`.
pub fn frame_setup(scene: &Scene, surface_y: f64, time: f64) -> Result<FrameSetup> {
    let refuse = |why: &str| Error::Chip(format!("scene {}: {why}", scene.name));
    let t = scene.tool.as_ref().ok_or_else(|| refuse("has no [tool]: there is no chip to analyse"))?;
    if scene.dim != 2 || t.rotation.is_some() {
        return Err(refuse("the chip analysis is for 2D cuts with a translating tool"));
    }
    let tool = crate::tool::setup::build_tool(t)?;
    let offset = crate::tool::setup::motion(t).offset_at(time);
    let rake = tool.rake_tangent();
    let dx = scene.discretisation.dx;
    Ok(FrameSetup {
        rake_point: [rake[0] + offset[0], rake[1] + offset[1]],
        rake_angle: tool.rake_angle,
        surface_y,
        spacing: dx,
        uncut: (surface_y - t.position[1]).max(dx),
        speed: t.velocity[0].hypot(t.velocity[1]),
    })
}

/// A frame of a run folder and its chip.
#[derive(Clone, Debug)]
pub struct FrameReport {
    pub scene: String,
    pub frame: PathBuf,
    pub time: f64,
    pub setup: FrameSetup,
    /// None: the frame holds no chip (no cross-section at the rake face).
    pub chip: Option<FrameChip>,
}

/// The chip of a frame: `path` is a run folder (its last frame, or frame `index` of its particles.pvd) or a
/// frame file (.vtu) in one. The run folder's scene.toml (with its recorded overrides) gives the tool and Δx.
pub fn analyse_path(path: &Path, index: Option<usize>) -> Result<FrameReport> {
    let (dir, frame) = locate(path, index)?;
    let scene = crate::run_folder::scene(&dir)
        .map_err(|e| Error::Scene(format!("swarf chip: the run's scene cannot be read: {e}")))?;
    let read = vtu::read(&frame).map_err(|e| Error::Output(e.to_string()))?;
    let time = read.time.ok_or_else(|| Error::Chip(format!("{}: the frame has no TimeValue", frame.display())))?;
    let (pos, eps) =
        workpiece(&read, scene.bodies.len()).map_err(|why| Error::Chip(format!("{}: {why}", frame.display())))?;
    let set = scene.generate().map_err(|e| Error::Scene(e.to_string()))?;
    let tool_y = scene.tool.as_ref().map_or(0.0, |t| t.position[1]);
    let (surface_y, _) = surface_and_uncut(&scene, tool_y, &set.pos);
    let setup = frame_setup(&scene, surface_y, time)?;
    let chip = analyse(&setup, &pos, eps.as_deref());
    Ok(FrameReport { scene: scene.name.clone(), frame, time, setup, chip })
}

/// The run folder and the frame file of `path` (module doc of [`analyse_path`]).
fn locate(path: &Path, index: Option<usize>) -> Result<(PathBuf, PathBuf)> {
    if path.is_file() {
        let dir = path.parent().map_or_else(|| PathBuf::from("."), Path::to_path_buf);
        return Ok((dir, path.to_path_buf()));
    }
    if !path.is_dir() {
        return Err(Error::Chip(format!("{}: no such run folder or frame file", path.display())));
    }
    let pvd_path = path.join("particles.pvd");
    let frames = pvd::read(&pvd_path)
        .map_err(|e| Error::Output(format!("{} is not a run folder with frames ({e})", path.display())))?;
    let k = index.unwrap_or(frames.len().saturating_sub(1));
    let (_, file) = frames.get(k).ok_or_else(|| {
        Error::Chip(format!("{}: frame {k} asked, it lists {} frames", pvd_path.display(), frames.len()))
    })?;
    Ok((path.to_path_buf(), path.join(file)))
}

/// Positions (x, y) and, where the frame has it, the plastic strain of each.
type Workpiece = (Vec<[f64; 2]>, Option<Vec<f64>>);

/// The workpiece particles' (x, y) (body index below `bodies`: not the tool's thermal particles) and their
/// plastic strain where the frame has it; Err names what the frame lacks.
fn workpiece(f: &vtu::ReadFrame, bodies: usize) -> std::result::Result<Workpiece, String> {
    let xyz = f.points.floats().ok_or("the points are not floating point")?;
    let body = match f.point_data.iter().find(|a| a.0 == "body") {
        Some((_, 1, vtu::OwnedValues::U32(b))) => b.clone(),
        _ => return Err("no \"body\" array (UInt32) in the frame".into()),
    };
    let eps = f.point_data.iter().find(|a| a.0 == "plastic_strain" && a.1 == 1).and_then(|a| a.2.floats());
    let keep = |i: &usize| (body[*i] as usize) < bodies && xyz[3 * i + 2] == 0.0;
    let idx: Vec<usize> = (0..f.n).filter(keep).collect();
    let pos = idx.iter().map(|&i| [xyz[3 * i], xyz[3 * i + 1]]).collect();
    Ok((pos, eps.map(|e| idx.iter().map(|&i| e[i]).collect())))
}
