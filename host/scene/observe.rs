//! The scalar observables of a scene: what `swarf study` compares between resolutions and precisions, and what a
//! scene's `[experiment]` table may give measured values for.
//!
//! The set depends on the kind of scene, decided from the scene itself (never from its name):
//!
//! - **A scene with a `[tool]`** (a cut): the steady-state numbers the cutting recorder writes to `summary.json`
//!   ([`SUMMARY_OBSERVABLES`]: `fc_n_per_mm`, `ff_n_per_mm`, `chip_thickness_um`,
//!   `segmentation`). They are what the experiments measure; a run that cannot measure one (too few chip samples)
//!   writes null, and the study reports it as missing.
//! - **Any other scene**: the state at the end of the run, which every run writes: the kinetic and elastic energy
//!   of the last row of `energy.csv` (`kinetic_energy_j`, `elastic_energy_j`; J, per m of depth in 2D) and each
//!   body's final extent per axis (`<body>_extent_<axis>_m`), plus, for round bodies (disk, ring, spherical shell,
//!   cylinder), its largest distance from the body's initial centre axis in the x–y plane
//!   (`<body>_radius_xy_max_m`: a Taylor bar's footprint radius, an impacted ring's bulge). These are the extents
//!   of the material, not of the particle centres that summary.json reports: each particle stands for a cell of
//!   side dx, so the extent is the centres' extent + dx and the radius the centres' + dx/2. Otherwise a body at
//!   rest would measure dx shorter at each level and the study would report the lattice, not the physics.
//!
//! The catalogue is a pure function of the scene's dimension, tool and bodies, so the scene reader can check an
//! `[experiment]` table against it before anything runs.

use std::path::Path;

use super::{Body, Shape};
use crate::{Error, Result};

/// Where a run folder holds an observable.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Source {
    /// A top-level number of `summary.json` (null or absent: not measured in that run).
    Summary(&'static str),
    /// A number of `summary.json` at a JSON pointer (`/steady/fc`; null or absent: not measured).
    Pointer(&'static str),
    /// The last row of a column of `energy.csv`.
    Energy(&'static str),
    /// `summary.json` `bodies[body].extent_m[axis]`.
    Extent { body: usize, axis: usize },
    /// `summary.json` `bodies[body].radius_xy_max_m`.
    Radius { body: usize },
}

/// One scalar observable of a run.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Observable {
    /// Its name: the column of study.csv and the key of `[experiment]`.
    pub name: String,
    /// Its unit, for tables and plots.
    pub unit: &'static str,
    pub source: Source,
}

/// The scalar results a cutting run adds to summary.json, with their units (the keys of
/// `cutting::record::CutAnalysis::json`): the observables of a scene with a tool. Declared here, below the
/// cutting recorder, so that the scene reader can check `[experiment]` against them.
pub const SUMMARY_OBSERVABLES: &[(&str, &str)] =
    &[("fc_n_per_mm", "N/mm"), ("ff_n_per_mm", "N/mm"), ("chip_thickness_um", "µm"), ("segmentation", "-")];

const AXES: [&str; 3] = ["x", "y", "z"];

/// An MPM cut's results in summary.json (name, unit, JSON pointer): the steady forces beside Nairn's two models
/// (`mpm::run::Steady`), and the glyph test's coverage at the end (`mpm::coverage`, V14).
const MPM_CUT: &[(&str, &str, &str)] = &[
    ("fc_n_per_m", "N/m", "/steady/fc"),
    ("ft_n_per_m", "N/m", "/steady/ft"),
    ("fc_cov", "-", "/steady/fc_cov"),
    ("touching_model_n_per_m", "N/m", "/steady/touching_model"),
    ("fc_over_model", "-", "/steady/fc_over_model"),
    ("bending_model_n_per_m", "N/m", "/steady/bending_model"),
    ("fc_over_bending", "-", "/steady/fc_over_bending"),
    ("rubbing_n_per_m", "N/m", "/steady/rubbing"),
    ("eta", "-", "/steady/eta"),
    ("coverage_mismatch", "-", "/coverage/mismatch"),
    ("gap_share", "-", "/coverage/gap_share"),
    ("chip_mismatch", "-", "/chip_coverage/mismatch"),
    ("chip_gap_share", "-", "/chip_coverage/gap_share"),
];
/// An MPM bond's result: the energy its crack released per unit area (`mpm::run::Released`).
const MPM_BOND: &[(&str, &str, &str)] = &[("released_j_per_m2", "J/m²", "/released/per_area")];

/// The observables of an MPM scene (a cut, else a bond): the mean mode-I share of the failed cohesive points, then
/// the set-up's results, all read from summary.json. `swarf sweep` and `swarf study` tabulate these.
pub fn mpm_catalogue(cut: bool) -> Vec<Observable> {
    let mode = ("mode_i_share", "-", "/mode_i_share");
    std::iter::once(&mode)
        .chain(if cut { MPM_CUT } else { MPM_BOND })
        .map(|&(name, unit, at)| Observable { name: name.to_string(), unit, source: Source::Pointer(at) })
        .collect()
}

/// The observables of a scene of dimension `dim`, with or without a tool, with `bodies` (see the module docs).
pub fn catalogue(dim: usize, has_tool: bool, bodies: &[Body]) -> Vec<Observable> {
    if has_tool {
        return SUMMARY_OBSERVABLES
            .iter()
            .map(|&(key, unit)| Observable { name: key.to_string(), unit, source: Source::Summary(key) })
            .collect();
    }
    let energy_unit = if dim == 2 { "J/m" } else { "J" };
    let mut out = vec![
        Observable { name: "kinetic_energy_j".into(), unit: energy_unit, source: Source::Energy("kinetic") },
        Observable { name: "elastic_energy_j".into(), unit: energy_unit, source: Source::Energy("elastic") },
    ];
    for (k, b) in bodies.iter().enumerate() {
        for (axis, name) in AXES.iter().enumerate().take(dim) {
            out.push(Observable {
                name: format!("{}_extent_{name}_m", b.name),
                unit: "m",
                source: Source::Extent { body: k, axis },
            });
        }
        let round = matches!(
            b.shape,
            Shape::Disk { .. } | Shape::Ring { .. } | Shape::SphericalShell { .. } | Shape::Cylinder { .. }
        );
        if round {
            out.push(Observable {
                name: format!("{}_radius_xy_max_m", b.name),
                unit: "m",
                source: Source::Radius { body: k },
            });
        }
    }
    out
}

/// The values of `observables` in the run folder `dir` (its `summary.json` and `energy.csv`) of a run at lattice
/// spacing `dx`, in order; `None` where the run did not measure one (null in summary.json) or it is not finite.
pub fn measure(dir: &Path, observables: &[Observable], dx: f64) -> Result<Vec<Option<f64>>> {
    let path = dir.join("summary.json");
    let text = std::fs::read_to_string(&path).map_err(|e| Error::Output(format!("{}: {e}", path.display())))?;
    let summary: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| Error::Output(format!("{}: {e}", path.display())))?;
    let needs_energy = observables.iter().any(|o| matches!(o.source, Source::Energy(_)));
    let energy = if needs_energy {
        let path = dir.join("energy.csv");
        Some(crate::output::csv::read(&path).map_err(|e| Error::Output(e.to_string()))?)
    } else {
        None
    };
    let finite = |v: Option<f64>| v.filter(|x| x.is_finite());
    let body = |k: usize| summary.get("bodies").and_then(|b| b.get(k));
    observables
        .iter()
        .map(|o| {
            Ok(match &o.source {
                Source::Summary(key) => finite(summary.get(*key).and_then(serde_json::Value::as_f64)),
                Source::Pointer(at) => finite(summary.pointer(at).and_then(serde_json::Value::as_f64)),
                Source::Extent { body: k, axis } => {
                    let centres = body(*k).and_then(|b| b.get("extent_m")).and_then(|e| e.get(*axis));
                    finite(centres.and_then(|v| v.as_f64()).map(|e| e + dx))
                }
                Source::Radius { body: k } => finite(
                    body(*k).and_then(|b| b.get("radius_xy_max_m")).and_then(|v| v.as_f64()).map(|r| r + 0.5 * dx),
                ),
                Source::Energy(column) => {
                    let (head, rows) = energy.as_ref().ok_or_else(|| Error::Output("energy.csv not read".into()))?;
                    let c = head.iter().position(|h| h == column).ok_or_else(|| {
                        Error::Output(format!("{}: no column '{column}'", dir.join("energy.csv").display()))
                    })?;
                    finite(rows.last().and_then(|r| r.get(c)).copied())
                }
            })
        })
        .collect()
}
