//! Criterion benchmarks of the step's kernels on the thermal-tool reference cut (cases/cutting/reference-cut.toml,
//! 5 640 + 1 429 particles; on the GPU also the 150k cut): the whole step, and the pre-pass, the interaction (fused
//! with the Brookshaw conduction), the corrector with the plastic update and the contact, each submitted on its
//! own on the state of a running cut. The CPU runs the same kernels (the CPU twin); `swarf bench step` gives the
//! per-phase table of whole steps as runs take them.

mod common;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use std::time::Duration;
use swarf::backend::{Backend, CpuBackend};
use swarf::kernels::{Dim2, Real};
use swarf::run::setup;
use swarf::scene::Scene;
use swarf::solver::{Phase, Solver};

fn step_kernels<B: Backend, R: Real>(c: &mut Criterion, b: &B, tag: &str, scene: &str) {
    let scene = Scene::load(scene, &[]).expect("scene");
    let s = setup::<R, Dim2>(&scene).expect("setup");
    let mut sv = Solver::<B, R, Dim2>::new(b, &s).expect("solver");
    // A few steps so that every table, rate and contact force is that of a running cut.
    sv.advance(b, s.dt, 4).expect("steps");
    b.synchronize().expect("sync");
    let mut g = c.benchmark_group(format!("step/{tag}/{}_{}", scene.name, R::NAME));
    g.bench_function(BenchmarkId::new("whole_step", sv.n), |bench| {
        bench.iter(|| {
            sv.step(b, s.dt).expect("step");
            b.synchronize().expect("sync");
        })
    });
    // Phases that can be submitted again on their own (the cell list cannot: its scan consumes the counts), as
    // separate passes: the pre-pass and the contact are otherwise fused into the predictor and the corrector.
    sv.fuse_prepare = false;
    sv.fuse_contact = false;
    for ph in [Phase::Prepare, Phase::Interact, Phase::Correct, Phase::Contact] {
        g.bench_function(BenchmarkId::new(ph.name().replace([' ', '+', '-'], "_"), sv.n), |bench| {
            bench.iter(|| {
                sv.bench_phase(b, ph).expect("phase");
                b.synchronize().expect("sync");
            })
        });
    }
    g.finish();
}

fn cpu(c: &mut Criterion) {
    let b = CpuBackend::new();
    step_kernels::<_, f64>(c, &b, "cpu", "cases/cutting/reference-cut.toml");
}

fn gpu(c: &mut Criterion) {
    let Some(b) = common::gpu() else { return };
    for scene in ["cases/cutting/reference-cut.toml", "cases/cutting/reference-cut-150k.toml"] {
        step_kernels::<_, f64>(c, &b, "gpu", scene);
        step_kernels::<_, f32>(c, &b, "gpu", scene);
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(2));
    targets = cpu, gpu
}
criterion_main!(benches);
