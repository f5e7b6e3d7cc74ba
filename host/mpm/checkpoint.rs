//! Checkpoints of an MPM run (docs/mpm.md "Checkpoints"): `checkpoint.bin` in the run folder, in the format of
//! [`crate::checkpoint`] (a JSON header, then named buffers with their checksums): the solver's stateful buffers
//! ([`MpmSolver::save_state`]), the last force sample's time and tallies (`last_sample`), and the clock. The samples
//! so far are forces.csv's rows and the frames particles.pvd's entries, which a resumed run reads back, so that it
//! goes on bit for bit.

use super::solver::{MpmSolver, Tallies};
use crate::backend::Backend;
use crate::checkpoint::{Header, read, read_header, write};
use crate::kernels::Real;
use crate::{Error, Result};
use std::path::{Path, PathBuf};

/// The checkpoint's file in a run folder.
pub const FILE: &str = "checkpoint.bin";

/// Writes `solver`'s state, the clock, `frames` (written so far) and the last sample into `dir`/checkpoint.bin;
/// returns its path.
pub fn save<B: Backend, R: Real>(
    b: &B,
    solver: &MpmSolver<B, R>,
    dir: &Path,
    overrides: &[String],
    frames: usize,
    last: &(f64, Tallies),
) -> Result<PathBuf> {
    let mut state = solver.save_state(b)?;
    let (t, l) = last;
    let sample = [*t, l.tool[0], l.tool[1], l.grip[0], l.grip[1], l.work];
    state.push(("last_sample".into(), bytemuck::cast_slice::<f64, u8>(&sample).to_vec()));
    let header = Header {
        overrides: overrides.to_vec(),
        precision: R::NAME.to_string(),
        dim: 2,
        particles: solver.particles(),
        time: solver.time,
        steps: solver.steps,
        dt: solver.dt,
        frame: frames,
        next_out: 0.0,
        next_checkpoint: None,
        fields: Vec::new(),
        version: String::new(),
        provenance: None,
        rebuilds: 0,
        checksums: Vec::new(),
    };
    let path = dir.join(FILE);
    write(&path, header, &state)?;
    Ok(path)
}

/// The header of `dir`'s checkpoint (the overrides and precision a resumed run is built with), without its
/// buffers, which [`restore`] reads.
pub fn header(dir: &Path) -> Result<Header> {
    read_header(&dir.join(FILE))
}

/// Restores `dir`'s checkpoint into `solver` (built from the same scene): its buffers and clock. Returns the last
/// sample's time and tallies. A checkpoint of another precision, particle count or time step is refused, saying
/// which.
pub fn restore<B: Backend, R: Real>(b: &B, solver: &mut MpmSolver<B, R>, dir: &Path) -> Result<(f64, Tallies)> {
    let path = dir.join(FILE);
    let (h, state) = read(&path)?;
    let bad = |what: String| Error::Checkpoint(format!("{}: {what}", path.display()));
    if h.precision != R::NAME || h.particles != solver.particles() || h.dim != 2 {
        return Err(bad(format!(
            "{} particles in {} ({}D), the scene gives {} in {} (2D)",
            h.particles,
            h.precision,
            h.dim,
            solver.particles(),
            R::NAME
        )));
    }
    if h.dt.to_bits() != solver.dt.to_bits() {
        return Err(bad(format!("dt = {:e} s, the scene gives {:e} s: the scene changed", h.dt, solver.dt)));
    }
    if !(h.time.is_finite() && h.time >= 0.0) {
        return Err(bad(format!("time = {:e}: expected a finite time >= 0", h.time)));
    }
    solver.load_state(b, &state)?;
    let s = state
        .iter()
        .find(|(n, _)| n == "last_sample")
        .filter(|(_, v)| v.len() == 6 * size_of::<f64>())
        .map(|(_, v)| bytemuck::pod_collect_to_vec::<u8, f64>(v))
        .ok_or_else(|| bad("field 'last_sample' missing or not 6 values".into()))?;
    solver.time = h.time;
    solver.steps = h.steps;
    Ok((s[0], Tallies { tool: [s[1], s[2]], grip: [s[3], s[4]], work: s[5] }))
}
