//! Criterion benchmarks of the MPM step (docs/mpm.md) on Nairn's cut (cases/mpm/nairn-cut.toml, 15 particles
//! through h: 31 748 particles and 34 832 nodes): one step launched on its own, and a batch of 50 steps (on the GPU
//! the captured graph a run replays), from the state 500 steps in. The CPU runs the same passes (the CPU twin);
//! `swarf bench mpm` prints the same two figures as a table.

mod common;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use std::time::Duration;
use swarf::backend::{Backend, CpuBackend};
use swarf::kernels::Real;
use swarf::mpm::setup::setup;
use swarf::mpm::solver::{BATCH, MpmSolver};
use swarf::scene::mpm::MpmScene;

fn mpm_step<B: Backend, R: Real>(c: &mut Criterion, b: &B, tag: &str, sets: &[&str]) {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let scene = MpmScene::load("cases/mpm/nairn-cut.toml", &sets).expect("scene");
    let s = setup(&scene).expect("setup");
    let mut m = MpmSolver::<B, R>::new(b, &s, scene.damping.pic).expect("solver");
    m.advance(b, 500).expect("steps");
    b.synchronize().expect("sync");
    let mut g = c.benchmark_group(format!("mpm/{tag}/{}_{}", scene.name, R::NAME));
    g.bench_function(BenchmarkId::new("step", m.particles()), |bench| {
        bench.iter(|| {
            m.step(b).expect("step");
            b.synchronize().expect("sync");
        })
    });
    g.bench_function(BenchmarkId::new(format!("batch_of_{BATCH}"), m.particles()), |bench| {
        bench.iter(|| {
            m.advance(b, BATCH as u64).expect("batch");
            b.synchronize().expect("sync");
        })
    });
    g.finish();
}

fn cpu(c: &mut Criterion) {
    // A coarser cut on the CPU (7 particles through h: 6 906 particles), so that a sample takes seconds, not minutes.
    mpm_step::<_, f64>(c, &CpuBackend::new(), "cpu", &["cut.particles_across=7"]);
}

fn gpu(c: &mut Criterion) {
    let Some(b) = common::gpu() else { return };
    mpm_step::<_, f64>(c, &b, "gpu", &[]);
    mpm_step::<_, f32>(c, &b, "gpu", &[]);
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(2));
    targets = cpu, gpu
}
criterion_main!(benches);
