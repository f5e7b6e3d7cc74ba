//! `swarf bench`: standard workloads timed on the device (CUDA events on the GPU, wall clock on the CPU).
//! Workload `neighbours`: the cell-list build (hash, counting sort, cell starts) and the reorder of the particle
//! state, in steady state (particles sorted at the previous step, then moved by a small jitter, so the
//! permutation is near the identity as in a running simulation), plus one density pass over the neighbours with
//! cell h (±2 stencil) and cell 2h (±1 stencil) to choose between the two layouts.

pub mod ensemble;
pub mod mpm;
pub mod step;

use crate::Result;
use crate::backend::{Backend, Passes};
use crate::grid::grid_for_support;
use crate::kernels::sph::CubicSpline;
use crate::kernels::{Dim, Real, Vector};
use crate::neighbour::CellList;
use crate::rng::SplitMix64;
use crate::state::{HostParticles, Particles};

/// Median times in milliseconds of one neighbour-search configuration.
#[derive(Clone, Debug)]
pub struct NeighbourTimes {
    pub dim: usize,
    pub precision: &'static str,
    pub n: usize,
    pub hash: f64,
    /// Count, scan, scatter and per-cell sort: the part comparable to an argsort of the keys.
    pub sort: f64,
    /// Gather of 20 f32 arrays through the permutation (the reference workload of ../shared/GPU.md).
    pub gather20: f64,
    /// Reorder of the whole particle state (`HostParticles::bytes_per_particle` bytes per particle).
    pub reorder_state: f64,
    pub state_bytes: usize,
    /// Hash + sort + reorder of the state, launched back to back.
    pub build_total: f64,
    /// Density pass, cell h with a ±2 stencil, and its cell-list build.
    pub density_h: f64,
    pub build_h: f64,
    /// Density pass, cell 2h with a ±1 stencil, and its cell-list build.
    pub density_2h: f64,
    pub build_2h: f64,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// n particles on a jittered lattice of spacing 1 (shuffled), h = 1.7.
pub fn jittered_lattice<R: Real, D: Dim>(n: usize, jitter: f64, seed: u64) -> Vec<D::Vec<R>> {
    let side = (n as f64).powf(1.0 / D::D as f64).ceil() as usize;
    let mut rng = SplitMix64::new(seed);
    let mut pos: Vec<D::Vec<R>> = (0..n)
        .map(|i| {
            let idx = [i % side, (i / side) % side, i / (side * side)];
            let c: [R; 3] = std::array::from_fn(|k| R::from_f64(idx[k] as f64 + jitter * (rng.uniform() - 0.5)));
            D::Vec::<R>::new(c)
        })
        .collect();
    rng.shuffle(&mut pos);
    pos
}

pub fn neighbours<B: Backend, R: Real, D: Dim>(b: &B, n: usize, repeats: usize) -> Result<NeighbourTimes> {
    let h = 1.7;
    let pos0 = jittered_lattice::<R, D>(n, 0.2, 7);
    let side = (n as f64).powf(1.0 / D::D as f64).ceil();
    let lo = [-1.0; 3];
    let hi = [side + 1.0; 3];
    let mut p = Particles::<B, R, D>::upload(b, &HostParticles::at_rest(pos0, R::ONE, R::ONE))?;
    let grid_h = grid_for_support(lo, hi, D::D, 2.0 * h, 2)?;
    let grid_2h = grid_for_support(lo, hi, D::D, 2.0 * h, 1)?;
    let mut cl = CellList::new(b, grid_h, n)?;
    // First sort of the shuffled input, then a jitter relative to the sorted order.
    cl.build::<R, D>(b, &p.pos.cur)?;
    p.reorder(b, &cl.perm)?;
    let sorted = p.pos.read(b)?;
    let mut rng = SplitMix64::new(11);
    let moved: Vec<D::Vec<R>> = sorted
        .iter()
        .map(|v| D::Vec::<R>::new(std::array::from_fn(|k| v.get(k) + R::from_f64(0.05 * (rng.uniform() - 0.5)))))
        .collect();
    let mut arrays: Vec<B::Buf<f32>> = (0..20).map(|_| b.alloc::<f32>(n, "bench arrays")).collect::<Result<_>>()?;
    let mut arrays_out: Vec<B::Buf<f32>> = (0..20).map(|_| b.alloc::<f32>(n, "bench arrays")).collect::<Result<_>>()?;

    let (mut t_hash, mut t_sort, mut t_g20, mut t_state, mut t_total) = (vec![], vec![], vec![], vec![], vec![]);
    for _ in 0..repeats.max(1) {
        b.write(&mut p.pos.cur, &moved)?;
        t_total.push(b.time_ms(&mut || {
            cl.build::<R, D>(b, &p.pos.cur)?;
            p.reorder(b, &cl.perm)
        })?);
        b.write(&mut p.pos.cur, &moved)?;
        t_hash.push(b.time_ms(&mut || b.hash::<R, D>(n, &p.pos.cur, &cl.grid_buf, &mut cl.keys))?);
        // The full build repeats the hash; its share is subtracted below.
        let full = b.time_ms(&mut || cl.build::<R, D>(b, &p.pos.cur))?;
        t_sort.push((full - t_hash.last().copied().unwrap_or(0.0)).max(0.0));
        t_g20.push(b.time_ms(&mut || {
            for (s, d) in arrays.iter().zip(arrays_out.iter_mut()) {
                b.gather(n, &cl.perm, s, d)?;
            }
            Ok(())
        })?);
        t_state.push(b.time_ms(&mut || p.reorder(b, &cl.perm))?);
    }
    arrays.clear();

    // Density with both layouts, each on particles sorted for its own grid.
    let mass = p.mass.read(b)?;
    let kernel = b.upload(&[CubicSpline::<R>::new(h, D::D)], "kernel")?;
    let mut rho = b.alloc::<R>(n, "density")?;
    let mut out = Vec::new();
    for grid in [grid_h, grid_2h] {
        let mut cl = CellList::new(b, grid, n)?;
        let mut pos = b.upload(&moved, "positions")?;
        let mut pos_s = b.alloc(n, "positions")?;
        let m = b.upload(&mass, "mass")?;
        let mut m_s = b.alloc(n, "mass")?;
        let (mut tb, mut td) = (vec![], vec![]);
        for _ in 0..repeats.max(1) {
            b.write(&mut pos, &moved)?;
            tb.push(b.time_ms(&mut || {
                cl.build::<R, D>(b, &pos)?;
                b.gather(n, &cl.perm, &pos, &mut pos_s)?;
                b.gather(n, &cl.perm, &m, &mut m_s)
            })?);
            td.push(
                b.time_ms(&mut || b.density::<R, D>(n, &pos_s, &m_s, &cl.grid_buf, &cl.starts, &kernel, &mut rho))?,
            );
        }
        out.push((median(tb), median(td)));
    }
    Ok(NeighbourTimes {
        dim: D::D,
        precision: R::NAME,
        n,
        hash: median(t_hash),
        sort: median(t_sort),
        gather20: median(t_g20),
        reorder_state: median(t_state),
        state_bytes: HostParticles::<R, D>::bytes_per_particle(),
        build_total: median(t_total),
        build_h: out[0].0,
        density_h: out[0].1,
        build_2h: out[1].0,
        density_2h: out[1].1,
    })
}

pub fn header() -> String {
    "| dim | prec | N | hash ms | sort ms | gather 20×f32 ms | reorder state ms (B/particle) | build+reorder ms | \
     cell h: build / density ms | cell 2h: build / density ms |\n|---|---|---|---|---|---|---|---|---|---|"
        .to_string()
}

pub fn row(t: &NeighbourTimes) -> String {
    format!(
        "| {}D | {} | {} | {:.3} | {:.3} | {:.3} | {:.3} ({}) | {:.3} | {:.3} / {:.3} | {:.3} / {:.3} |",
        t.dim,
        t.precision,
        t.n,
        t.hash,
        t.sort,
        t.gather20,
        t.reorder_state,
        t.state_bytes,
        t.build_total,
        t.build_h,
        t.density_h,
        t.build_2h,
        t.density_2h
    )
}

/// One size of the rings scaling benchmark (roethlin-solver.md §8.2, Tab 6.5/6.6).
#[derive(Clone, Debug)]
pub struct RingsTimes {
    pub nbox: usize,
    pub n: usize,
    pub precision: &'static str,
    /// Steps to the thesis' end time 2.5 r_o/170 m/s with our Δt.
    pub steps_total: u64,
    pub steps_run: u64,
    pub ms_per_step: f64,
    /// Measured wall time of the whole run when it was run to the end, else ms/step × steps_total.
    pub whole_run_s: f64,
    pub measured_whole: bool,
}

/// Rubber rings with nbox lattice points per ring side (N = 4232 at nbox = 80): `steps` steps, or the whole run
/// when `steps` is None. Timed from the first step (after setup and upload) to the end of the last.
pub fn rings<B: Backend, M: crate::method::Method<B>>(
    b: &B,
    scene_path: &std::path::Path,
    nbox: usize,
    steps: Option<u64>,
    precision: crate::scene::Precision,
) -> Result<RingsTimes> {
    let dx = 0.08 / (nbox as f64 - 1.0);
    let mut scene = crate::scene::Scene::load(scene_path, &[format!("discretisation.dx={dx:e}")])
        .map_err(|e| crate::Error::Scene(e.to_string()))?;
    scene.precision = precision;
    let s = M::setup(&scene, crate::tuning::Tuning::current()?)?;
    let plan = M::plan(&s);
    let mut sv = M::new(b, &s)?;
    let steps_total = (scene.time.end / plan.dt).ceil() as u64;
    let run = steps.unwrap_or(steps_total).min(steps_total).max(1);
    // One warm-up step (module JIT, first allocations of the driver) outside the timing.
    sv.step(b, plan.dt)?;
    b.synchronize()?;
    let t = std::time::Instant::now();
    sv.advance(b, plan.dt, (run - 1) as usize)?;
    b.synchronize()?;
    let wall = t.elapsed().as_secs_f64();
    let ms = wall * 1e3 / (run - 1).max(1) as f64;
    let measured = run == steps_total;
    Ok(RingsTimes {
        nbox,
        n: plan.particles,
        precision: plan.precision,
        steps_total,
        steps_run: run,
        ms_per_step: ms,
        whole_run_s: if measured {
            wall * run as f64 / (run - 1).max(1) as f64
        } else {
            ms * 1e-3 * steps_total as f64
        },
        measured_whole: measured,
    })
}

pub fn rings_header() -> String {
    "| nbox | N | prec | steps (to 2.5 r_o/170 m/s) | ms/step | particle-steps/s | whole run s |\n|---|---|---|---|---|---|---|"
        .to_string()
}

pub fn rings_row(t: &RingsTimes) -> String {
    format!(
        "| {} | {} | {} | {} | {:.4} | {:.3e} | {:.2}{} |",
        t.nbox,
        t.n,
        t.precision,
        t.steps_total,
        t.ms_per_step,
        t.n as f64 / (t.ms_per_step * 1e-3),
        t.whole_run_s,
        if t.measured_whole { "" } else { " (from ms/step)" }
    )
}

/// Random plastic trial states for the return-map checks and benchmark: deviatoric 3D stresses up to ~3 σ_y,
/// plastic strains in [0, 2], rates in [0, 1e5] /s, temperatures 300…1300 K. Deterministic from `seed`.
pub fn trial_states(
    n: usize,
    sigma: f64,
    seed: u64,
) -> (Vec<crate::kernels::vector::S3f64>, Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut rng = SplitMix64::new(seed);
    let mut s = Vec::with_capacity(n);
    for _ in 0..n {
        let mut c: [f64; 6] = std::array::from_fn(|_| rng.normal() * sigma);
        let tr = (c[0] + c[3] + c[5]) / 3.0;
        c[0] -= tr;
        c[3] -= tr;
        c[5] -= tr;
        s.push(crate::kernels::vector::S3f64(c));
    }
    let eps = (0..n).map(|_| 2.0 * rng.uniform()).collect();
    let rate = (0..n).map(|_| 1e5 * rng.uniform()).collect();
    let temp = (0..n).map(|_| 300.0 + 1000.0 * rng.uniform()).collect();
    (s, eps, rate, temp)
}

/// Return maps per second of the plastic pass for each material of the library that has a flow-stress model
/// (3D f64 state, `n` particles, median of `repeats`).
pub fn plasticity<B: Backend>(
    b: &B,
    lib: &crate::material::Library,
    n: usize,
    repeats: usize,
) -> Result<Vec<(String, f64)>> {
    use crate::backend::PlasticInputs;
    use crate::kernels::Dim3;
    use crate::kernels::sph::plastic::PlasticConsts;
    let mut out = Vec::new();
    for m in lib.iter() {
        let (Some(model), Some(el)) = (m.flow_stress, m.elastic) else { continue };
        let shear = el.youngs_modulus / (2.0 * (1.0 + el.poisson_ratio));
        let (s, eps, rate, temp) = trial_states(n, 1e9, 5);
        let mut sb = b.upload(&s, "stress")?;
        let rho = b.upload(&vec![el.density; n], "rho")?;
        let mut eb = b.upload(&eps, "eps")?;
        let mut rb = b.upload(&rate, "rate")?;
        let mut tb = b.upload(&temp, "temp")?;
        let fl = b.upload(&vec![0u32; n], "flags")?;
        let c = PlasticConsts { shear, dt: 1e-8, taylor_quinney: 0.0, flags: 0, _pad: 0 };
        let mut times = Vec::new();
        for _ in 0..repeats.max(1) {
            b.write(&mut sb, &s)?;
            b.write(&mut eb, &eps)?;
            times.push(b.time_ms(&mut || {
                b.plastic_step::<f64, Dim3>(
                    n,
                    &model,
                    c,
                    PlasticInputs {
                        stress: &mut sb,
                        rho: &rho,
                        eps: &mut eb,
                        rate: &mut rb,
                        temp: &mut tb,
                        flags: &fl,
                        yield_stress: None,
                        work: None,
                        materials: None,
                        damage: None,
                    },
                )
            })?);
        }
        out.push((format!("{} ({})", m.name, model.name()), n as f64 / (median(times) * 1e-3)));
    }
    Ok(out)
}
