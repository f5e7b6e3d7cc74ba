//! Criterion benchmarks of the neighbour search: hash + counting sort + reorder of the whole particle state
//! (steady state: particles sorted at the previous step), and one density pass with each grid layout, on the
//! CPU and, where a CUDA device is present, on the GPU. `swarf bench neighbours` gives the per-phase table.

mod common;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use std::time::Duration;
use swarf::backend::{Backend, CpuBackend, Passes};
use swarf::bench::jittered_lattice;
use swarf::grid::grid_for_support;
use swarf::kernels::sph::CubicSpline;
use swarf::kernels::{Dim, Dim2, Dim3, Real};
use swarf::neighbour::CellList;
use swarf::state::{HostParticles, Particles};

fn build_and_reorder<B: Backend, R: Real, D: Dim>(c: &mut Criterion, b: &B, tag: &str, n: usize) {
    let side = (n as f64).powf(1.0 / D::D as f64).ceil();
    let pos = jittered_lattice::<R, D>(n, 0.2, 3);
    let mut p = Particles::<B, R, D>::upload(b, &HostParticles::at_rest(pos, R::ONE, R::ONE)).expect("upload");
    let grid = grid_for_support([-1.0; 3], [side + 1.0; 3], D::D, 3.4, 2).expect("grid");
    let mut cl = CellList::new(b, grid, n).expect("cell list");
    cl.build::<R, D>(b, &p.pos.cur).expect("build");
    p.reorder(b, &cl.perm).expect("reorder");
    let mut g = c.benchmark_group(format!("neighbours/{tag}/{}d_{}", D::D, R::NAME));
    g.bench_function(BenchmarkId::new("hash_sort_reorder", n), |bench| {
        bench.iter(|| {
            cl.build::<R, D>(b, &p.pos.cur).expect("build");
            p.reorder(b, &cl.perm).expect("reorder");
            b.synchronize().expect("sync");
        })
    });
    let kernel = b.upload(&[CubicSpline::<R>::new(1.7, D::D)], "kernel").expect("upload");
    let mut rho = b.alloc::<R>(n, "rho").expect("alloc");
    for stencil in [2u32, 1] {
        let grid = grid_for_support([-1.0; 3], [side + 1.0; 3], D::D, 3.4, stencil).expect("grid");
        let mut cl = CellList::new(b, grid, n).expect("cell list");
        cl.build::<R, D>(b, &p.pos.cur).expect("build");
        p.reorder(b, &cl.perm).expect("reorder");
        g.bench_function(BenchmarkId::new(format!("density_stencil{stencil}"), n), |bench| {
            bench.iter(|| {
                b.density::<R, D>(n, &p.pos.cur, &p.mass.cur, &cl.grid_buf, &cl.starts, &kernel, &mut rho)
                    .expect("density");
                b.synchronize().expect("sync");
            })
        });
    }
    g.finish();
}

fn cpu(c: &mut Criterion) {
    let b = CpuBackend::new();
    build_and_reorder::<_, f64, Dim2>(c, &b, "cpu", 100_000);
    build_and_reorder::<_, f64, Dim3>(c, &b, "cpu", 100_000);
}

fn gpu(c: &mut Criterion) {
    let Some(b) = common::gpu() else { return };
    for n in [1_000_000, 4_000_000] {
        build_and_reorder::<_, f32, Dim2>(c, &b, "gpu", n);
        build_and_reorder::<_, f64, Dim2>(c, &b, "gpu", n);
        build_and_reorder::<_, f32, Dim3>(c, &b, "gpu", n);
        build_and_reorder::<_, f64, Dim3>(c, &b, "gpu", n);
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(2));
    targets = cpu, gpu
}
criterion_main!(benches);
