//! `swarf bench mpm`: the MPM step of a scene (docs/mpm.md), timed from the scene's start: with the captured
//! batches of 50 steps (CUDA graphs, as a run steps) and one step at a time, side by side in one process, after
//! one untimed step (which loads the kernels). Device events on the GPU, the wall clock on the CPU.

use crate::Result;
use crate::backend::Backend;
use crate::kernels::Real;
use crate::mpm::setup::setup;
use crate::mpm::solver::MpmSolver;
use crate::scene::mpm::MpmScene;

/// One scene's step times.
#[derive(Clone, Debug)]
pub struct MpmTimes {
    pub label: String,
    pub particles: usize,
    pub nodes: usize,
    pub precision: &'static str,
    pub steps: usize,
    /// Milliseconds per step, captured batches and one step at a time.
    pub batched_ms: f64,
    pub plain_ms: f64,
}

/// Times `steps` (rounded up to whole batches) of `scene` in precision `R` on `b`.
pub fn time<B: Backend, R: Real>(b: &B, scene: &MpmScene, steps: usize) -> Result<MpmTimes> {
    let s = setup(scene)?;
    let batch = crate::mpm::solver::BATCH;
    let steps = steps.div_ceil(batch).max(1) * batch;
    let mut solver = MpmSolver::<B, R>::new(b, &s, scene.damping.pic)?;
    solver.step(b)?;
    let batched = b.time_ms(&mut || solver.advance(b, steps as u64))? / steps as f64;
    let plain = b.time_ms(&mut || (0..steps).try_for_each(|_| solver.step(b)))? / steps as f64;
    Ok(MpmTimes {
        label: scene.name.clone(),
        particles: solver.particles(),
        nodes: solver.node_count(),
        precision: R::NAME,
        steps,
        batched_ms: batched,
        plain_ms: plain,
    })
}

pub fn header() -> &'static str {
    "| scene | particles | nodes | prec | steps | ms/step (batches of 50) | ms/step (one at a time) | particle-steps/s |\n\
     |---|---|---|---|---|---|---|---|"
}

pub fn row(t: &MpmTimes) -> String {
    format!(
        "| {} | {} | {} | {} | {} | {:.4} | {:.4} | {:.3e} |",
        t.label,
        t.particles,
        t.nodes,
        t.precision,
        t.steps,
        t.batched_ms,
        t.plain_ms,
        t.particles as f64 / (1e-3 * t.batched_ms)
    )
}
