//! Per-particle state tables at given step counts (`swarf run --state-at 0,1,10,100`): one CSV per step,
//! `states/state_NNNNNN.csv` in the run folder (NNNNNN: steps completed), a row per particle keyed by its initial
//! position, in SI units. They are what a side-by-side comparison with another code reads
//! (`ci/original/compare.py states`, docs/original-code.md): two runs started from the same state are compared
//! after the same number of steps, field by field.
//!
//! Columns: `id`, `x0 y0 [z0]` (initial position), `x y [z]`, `vx vy [vz]`, `rho`, the deviatoric stress `sxx sxy
//! syy szz` (3D: and `sxz syz`), `tool` (1 for the tool's thermal-only particles), then every frame field of the
//! run's field registry, with the names the comparison reads for the common ones: `T` (temperature), `eps_pl`
//! (plastic strain), `fcx fcy [fcz]` and `ftx fty [ftz]` (the contact's normal and friction force on the particle,
//! N per m of depth in 2D), and `<name>` or `<name>_<k>` for the others.

use std::fmt::Write as _;
use std::path::Path;

use crate::kernels::sph::TensorOps;
use crate::kernels::sph::params::flags;
use crate::kernels::{Real, Vector};
use crate::output::io_err;
use crate::solver::fields::FrameField;
use crate::state::HostParticles;
use crate::{Error, Result};

/// Parses `--state-at`'s list: step counts, each a non-negative integer, returned sorted without repeats.
pub fn parse_steps(text: &str) -> std::result::Result<Vec<u64>, String> {
    let mut steps = Vec::new();
    for part in text.split(',') {
        let s = part.trim();
        steps.push(s.parse::<u64>().map_err(|_| {
            format!("--state-at {text}: `{s}` is not a step count (expected non-negative integers, e.g. 0,1,10,100)")
        })?);
    }
    steps.sort_unstable();
    steps.dedup();
    Ok(steps)
}

/// The file of the state after `step` steps in the run folder `dir`.
pub fn path(dir: &Path, step: u64) -> std::path::PathBuf {
    dir.join("states").join(format!("state_{step:06}.csv"))
}

/// The column names of the frame field `name` with `components` components.
fn field_columns(name: &str, components: usize) -> Vec<String> {
    let axes = ["x", "y", "z"];
    match (name, components) {
        ("temperature", 1) => vec!["T".into()],
        ("plastic_strain", 1) => vec!["eps_pl".into()],
        ("contact_normal_force", c) => axes[..c.min(3)].iter().map(|a| format!("fc{a}")).collect(),
        ("contact_friction_force", c) => axes[..c.min(3)].iter().map(|a| format!("ft{a}")).collect(),
        (n, 1) => vec![n.to_string()],
        (n, c) => (0..c).map(|k| format!("{n}_{k}")).collect(),
    }
}

/// Writes the state table of `p` (positions `now` in f64, initial positions by id `initial`, the frame fields
/// `fields`) to `path` (atomically, its folder created).
pub fn write<R: Real, D: TensorOps<R>>(
    path: &Path,
    p: &HostParticles<R, D>,
    now: &[[f64; 3]],
    initial: &[[f64; 3]],
    fields: &[FrameField],
) -> Result<()> {
    let d = D::D;
    let axes = &["x", "y", "z"][..d];
    let mut head: Vec<String> = vec!["id".into()];
    head.extend(axes.iter().map(|a| format!("{a}0")));
    head.extend(axes.iter().map(|a| a.to_string()));
    head.extend(axes.iter().map(|a| format!("v{a}")));
    head.push("rho".into());
    // Stored 2D (xx, xy, yy, zz), 3D (xx, xy, xz, yy, yz, zz).
    let stress: &[&str] =
        if d == 2 { &["sxx", "sxy", "syy", "szz"] } else { &["sxx", "sxy", "sxz", "syy", "syz", "szz"] };
    head.extend(stress.iter().map(|s| s.to_string()));
    head.push("tool".into());
    for f in fields {
        head.extend(field_columns(f.name, f.components));
    }
    let mut text = head.join(",");
    text.push('\n');
    for (i, x) in now.iter().enumerate().take(p.len()) {
        let id = p.id[i] as usize;
        let x0 = initial
            .get(id)
            .ok_or_else(|| Error::Output(format!("{}: particle id {id} has no initial position", path.display())))?;
        let _ = write!(text, "{id}");
        for c in x0[..d].iter().chain(&x[..d]) {
            let _ = write!(text, ",{c:?}");
        }
        for k in 0..d {
            let _ = write!(text, ",{:?}", p.vel[i].get(k).to_f64());
        }
        let _ = write!(text, ",{:?}", p.rho[i].to_f64());
        for s in bytemuck::cast_slice::<_, R>(std::slice::from_ref(&p.stress[i])).iter().take(stress.len()) {
            let _ = write!(text, ",{:?}", s.to_f64());
        }
        let _ = write!(text, ",{}", u8::from(p.flags[i] & flags::THERMAL_ONLY != 0));
        for f in fields {
            for v in &f.values[i * f.components..(i + 1) * f.components] {
                let _ = write!(text, ",{v:?}");
            }
        }
        text.push('\n');
    }
    let dir = path.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir).map_err(|e| io_err(dir, e))?;
    crate::output::write_atomic(path, text.as_bytes()).map_err(|e| io_err(path, e))
}
