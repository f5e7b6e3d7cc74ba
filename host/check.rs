//! `swarf check <scene>`: validates a scene (everything `swarf run` checks before it starts) and prints what
//! the run will be: particles, h, c0, Δt, steps, the memory the backend needs, and the expected run time on this
//! backend, measured by timing a few steps of the real solver.

use crate::backend::{AnyBackend, Backend};
use crate::kernels::sph::TensorOps;
use crate::kernels::{Dim2, Dim3, Real};
use crate::run::setup;
use crate::scene::{Precision, Scene};
use crate::solver::Solver;
use crate::{Result, with_backend};
use std::fmt::Write;

/// What a scene will cost.
#[derive(Clone, Debug)]
pub struct CheckReport {
    pub particles: usize,
    pub h: f64,
    pub c0: f64,
    pub dt: f64,
    pub steps: u64,
    /// Device memory the solver allocates (state, scratch, cell list) [bytes].
    pub memory_bytes: usize,
    /// Measured time per step on this backend [s] (after one warm-up step).
    pub seconds_per_step: f64,
    pub backend: String,
    pub precision: &'static str,
    /// Input that runs but whose result is not meaningful.
    pub warnings: Vec<String>,
}

impl CheckReport {
    pub fn expected_run_time(&self) -> f64 {
        self.seconds_per_step * self.steps as f64
    }
}

/// Bytes the solver allocates: every per-particle buffer of the field registry (`solver::fields::FIELDS`, spares
/// included) and the buffers that are not per particle (cell starts, scan workspace, Verlet list, parameter
/// blocks); equal to what the backend allocates (tests/fields.rs).
pub fn memory_estimate<R: Real, D: TensorOps<R>>(s: &crate::solver::Setup<R, D>) -> usize {
    crate::solver::fields::memory_bytes(s)
}

/// Refuses a run that cannot fit the GPU's memory, naming the bytes needed and available (the CPU backend uses
/// host memory and is not checked).
pub fn fits(needed: usize, info: &crate::backend::DeviceInfo) -> Result<()> {
    if info.backend == "gpu" && needed > info.memory_bytes {
        return Err(crate::Error::OutOfMemory { what: "the scene", bytes: needed, free: 0, total: info.memory_bytes });
    }
    Ok(())
}

pub fn check(any: &AnyBackend, scene: &Scene, precision: Option<Precision>, probe_steps: u64) -> Result<CheckReport> {
    let scene = &*scene.with_precision(precision);
    with_backend!(any, b => match (scene.dim, scene.precision) {
        (2, Precision::F32 | Precision::Mixed) => typed::<_, f32, Dim2>(b, scene, probe_steps),
        (2, Precision::F64) => typed::<_, f64, Dim2>(b, scene, probe_steps),
        (_, Precision::F32 | Precision::Mixed) => typed::<_, f32, Dim3>(b, scene, probe_steps),
        (_, Precision::F64) => typed::<_, f64, Dim3>(b, scene, probe_steps),
    })
}

fn typed<B: Backend, R: Real, D: TensorOps<R>>(b: &B, scene: &Scene, probe_steps: u64) -> Result<CheckReport> {
    let s = setup::<R, D>(scene)?;
    let memory = memory_estimate(&s);
    let info = b.info();
    fits(memory, info)?;
    let steps = (scene.time.end / s.dt).ceil() as u64;
    let mut solver = Solver::<B, R, D>::new(b, &s)?;
    solver.step(b, s.dt)?;
    b.synchronize()?;
    let probe = probe_steps.clamp(1, steps.max(1));
    let t = std::time::Instant::now();
    for _ in 0..probe {
        solver.step(b, s.dt)?;
    }
    b.synchronize()?;
    Ok(CheckReport {
        particles: s.particles.len(),
        h: s.h,
        c0: s.c0,
        dt: s.dt,
        steps,
        memory_bytes: memory,
        seconds_per_step: t.elapsed().as_secs_f64() / probe as f64,
        backend: format!("{} ({})", info.backend, info.name),
        precision: s.precision(),
        warnings: s.warnings.clone(),
    })
}

pub fn format(scene: &Scene, r: &CheckReport) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "{}: ok", scene.origin);
    let _ = writeln!(s, "particles:          {}", r.particles);
    let _ = writeln!(s, "h:                  {:.4e} m (h/dx = {})", r.h, scene.discretisation.h_over_dx);
    let _ = writeln!(s, "c0:                 {:.1} m/s", r.c0);
    let _ = writeln!(s, "dt:                 {:.4e} s", r.dt);
    let _ = writeln!(s, "steps:              {} (to t = {:e} s)", r.steps, scene.time.end);
    let _ = writeln!(s, "memory:             {:.1} MiB", r.memory_bytes as f64 / (1u64 << 20) as f64);
    let _ = writeln!(
        s,
        "expected run time:  {:.1} s on {} in {} ({:.3} ms/step, measured over a few steps)",
        r.expected_run_time(),
        r.backend,
        r.precision,
        r.seconds_per_step * 1e3
    );
    for w in &r.warnings {
        let _ = writeln!(s, "warning:            {w}");
    }
    s
}
