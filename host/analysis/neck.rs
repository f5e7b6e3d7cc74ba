//! The fracture strain and fracture diameter of a round tensile specimen (the SHTB of klippel-constitutive.md §4.6,
//! `cases/damage/shtb-50sib8.toml`), measured from the particles of its frames: the neck is the thinnest slab of
//! the live (not deleted) particles across the specimen's axis; the specimen has fractured at the first frame where
//! its live particles fall into two pieces; the fracture diameter d_f is the neck's diameter at the frame before,
//! and the fracture strain ε_f = 2 ln(d0/d_f) (the logarithmic strain of the area reduction, with which the
//! experiment's 62.7–81.1 % and 2.00–2.20 mm pair up for d0 = 3 mm).

use std::path::Path;

use crate::output::vtu::{self, OwnedValues, ReadFrame};
use crate::{Error, Result};

/// The thinnest slab of a specimen along z at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Neck {
    /// The slab's centre on the axis [m].
    pub z: f64,
    /// Its outer diameter: twice the largest distance of its particles from their mean x–y, plus one spacing [m].
    pub diameter: f64,
}

/// The result of [`fracture`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fracture {
    /// The neck at t = 0 (the gauge diameter d0) [m].
    pub initial_diameter: f64,
    /// The time of the first frame in two pieces [s].
    pub time: f64,
    /// The neck's diameter at the frame before it [m].
    pub diameter: f64,
    /// ε_f = 2 ln(d0/d_f).
    pub strain: f64,
}

/// The outer diameter of the particles `pts` (x, y) about their mean, plus `dx` (each particle's extent).
fn outer_diameter(pts: &[[f64; 3]], dx: f64) -> f64 {
    let n = pts.len() as f64;
    let (cx, cy) = pts.iter().fold((0.0, 0.0), |(x, y), p| (x + p[0] / n, y + p[1] / n));
    let r = pts.iter().map(|p| ((p[0] - cx).powi(2) + (p[1] - cy).powi(2)).sqrt()).fold(0.0, f64::max);
    2.0 * r + dx
}

/// The thinnest slab of width `width` along z among the slabs between the live particles' lowest and highest z
/// (each slab holding at least one particle; `None` without particles).
pub fn neck(pos: &[[f64; 3]], live: &[bool], width: f64, dx: f64) -> Option<Neck> {
    let pts: Vec<[f64; 3]> = pos.iter().zip(live).filter(|(_, l)| **l).map(|(p, _)| *p).collect();
    let lo = pts.iter().map(|p| p[2]).fold(f64::INFINITY, f64::min);
    let hi = pts.iter().map(|p| p[2]).fold(f64::NEG_INFINITY, f64::max);
    let slabs = (((hi - lo) / width).floor() as usize).max(1);
    let mut bins = vec![Vec::new(); slabs];
    for p in &pts {
        bins[(((p[2] - lo) / width) as usize).min(slabs - 1)].push(*p);
    }
    let mut best: Option<Neck> = None;
    for (k, b) in bins.iter().enumerate().filter(|(_, b)| !b.is_empty()) {
        let d = outer_diameter(b, dx);
        if best.is_none_or(|n| d < n.diameter) {
            best = Some(Neck { z: lo + (k as f64 + 0.5) * width, diameter: d });
        }
    }
    best
}

/// Whether the live particles form more than one piece (particles closer than `radius` are connected).
pub fn separated(pos: &[[f64; 3]], live: &[bool], radius: f64) -> Result<bool> {
    let pts: Vec<[f64; 3]> = pos.iter().zip(live).filter(|(_, l)| **l).map(|(p, _)| *p).collect();
    let group = vec![0u32; pts.len()];
    Ok(super::components_per_group(&pts, &group, radius)?.first().is_some_and(|&c| c > 1))
}

/// Positions and liveness (`damage_mask` ≥ 0; all live without damage) of a frame.
fn live_particles(f: &ReadFrame) -> (Vec<[f64; 3]>, Vec<bool>) {
    let p = f.points.floats().unwrap_or_default();
    let pos: Vec<[f64; 3]> = p.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let mask = f.point_data.iter().find(|(n, _, _)| n == "damage_mask").map(|(_, _, v)| v);
    let live = match mask {
        Some(OwnedValues::F64(m)) => m.iter().map(|&x| x >= 0.0).collect(),
        _ => vec![true; pos.len()],
    };
    (pos, live)
}

/// The fracture of the specimen in the frames `paths` (in time order), with slabs and connections of width
/// `support` (the kernel support 2h) and particles of spacing `dx`. `None` if it never falls into two pieces.
pub fn fracture(paths: &[impl AsRef<Path>], support: f64, dx: f64) -> Result<Option<Fracture>> {
    let read = |p: &Path| vtu::read(p).map_err(|e| Error::Output(e.to_string()));
    let Some(first) = paths.first() else { return Ok(None) };
    let (pos, live) = live_particles(&read(first.as_ref())?);
    let Some(d0) = neck(&pos, &live, support, dx) else { return Ok(None) };
    let mut before = d0;
    for p in &paths[1..] {
        let f = read(p.as_ref())?;
        let (pos, live) = live_particles(&f);
        if separated(&pos, &live, support)? {
            let (d0, df) = (d0.diameter, before.diameter);
            let time = f.time.unwrap_or(f64::NAN);
            return Ok(Some(Fracture { initial_diameter: d0, time, diameter: df, strain: 2.0 * (d0 / df).ln() }));
        }
        if let Some(n) = neck(&pos, &live, support, dx) {
            before = n;
        }
    }
    Ok(None)
}

/// The kernel support 2h and the spacing Δx a run folder ran with (`run_folder::scene`: its `scene.toml` with the
/// run's `--set` overrides), so that a run at another spacing is measured at its own.
pub fn run_spacing(run: &Path) -> Result<(f64, f64)> {
    let scene = crate::run_folder::scene(run).map_err(|e| Error::Scene(e.to_string()))?;
    Ok((2.0 * scene.h(), scene.discretisation.dx))
}

/// [`fracture`] of a run folder: its frames (`frame_*.vtu`, in order) with the support 2h and spacing it ran with
/// ([`run_spacing`]).
pub fn run_fracture(run: &Path) -> Result<Option<Fracture>> {
    let (support, dx) = run_spacing(run)?;
    let mut paths: Vec<std::path::PathBuf> = std::fs::read_dir(run)
        .map_err(|e| Error::Output(format!("{}: {e}", run.display())))?
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.file_name().is_some_and(|n| n.to_string_lossy().starts_with("frame_")))
        .filter(|p| p.extension().is_some_and(|x| x == "vtu"))
        .collect();
    paths.sort();
    fracture(&paths, support, dx)
}

/// The JSON line of a fracture (null fields when the specimen never separated).
pub fn to_json(f: Option<Fracture>) -> String {
    match f {
        Some(f) => format!(
            "{{\"fractured\": true, \"d0_mm\": {:.4}, \"fracture_time_s\": {:e}, \"fracture_diameter_mm\": {:.4}, \
             \"fracture_strain\": {:.4}}}",
            f.initial_diameter * 1e3,
            f.time,
            f.diameter * 1e3,
            f.strain
        ),
        None => "{\"fractured\": false}".to_string(),
    }
}
