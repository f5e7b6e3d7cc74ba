//! GPU against its CPU twin (DESIGN.md "One physics, two backends"; roethlin-solver.md AT-51..AT-53).
//! Each test opens the CUDA backend; where none is available it says why and passes, unless
//! `SWARF_REQUIRE_GPU=1` (set by ci/gpu-run.sh on the GPU machine), where it fails.

#![allow(clippy::type_complexity, clippy::too_many_arguments)] // test harness closures over several buffers

mod common;

use common::*;
use swarf::backend::{Backend, CpuBackend, CudaBackend, Passes};
use swarf::grid::{bounding_box, grid_for_support};
use swarf::kernels::sph::CubicSpline;
use swarf::kernels::{Dim, Dim2, Dim3, Real};
use swarf::neighbour::CellList;
use swarf::rng::SplitMix64;
use swarf::state::{HostParticles, Particles};

fn gpu() -> Option<CudaBackend> {
    match CudaBackend::new(0) {
        Ok(b) => Some(b),
        Err(e) => {
            if std::env::var("SWARF_REQUIRE_GPU").is_ok_and(|v| v == "1") {
                panic!("SWARF_REQUIRE_GPU=1 but {e}");
            }
            eprintln!("skipped (no GPU): {e}");
            None
        }
    }
}

/// Cell keys, cell starts, permutation, sorted state, neighbour lists and the Verlet list equal the CPU's exactly;
/// the density
/// sum (same gather order, no FMA contraction) equals it bitwise.
fn compare<R: Real, D: Dim>(g: &CudaBackend, pos: &[D::Vec<R>], h: f64, stencil: u32, what: &str) {
    let c = CpuBackend::new();
    let support = 2.0 * h;
    let support2 = R::from_f64(support * support);
    let (lo, hi) = bounding_box::<R, D::Vec<R>>(pos);
    let mut grid = grid_for_support(lo, hi, D::D, support, stencil).expect("grid");
    // A Verlet list too (neighbour::verlet): about 36 (2D) and 165 (3D) candidates per particle at h = 1.7 Δx,
    // so that the random inputs also have rows beyond the capacity (their counts are compared too).
    grid.list_capacity = if D::D == 2 { 40 } else { 175 };
    let a = search::<_, R, D>(&c, pos, grid, support2);
    let b = search::<_, R, D>(g, pos, grid, support2);
    assert_eq!(a.verlet, b.verlet, "{what}: Verlet lists differ");
    let over = (0..pos.len()).filter(|&i| a.verlet[i] > grid.list_capacity).count();
    // (The clustered inputs overflow in most rows: their counts and the stencil fallback are what is compared.)
    assert!(over < pos.len(), "{what}: every Verlet row overflows: no stored row compared");
    assert_eq!(a.keys, b.keys, "{what}: cell keys differ");
    assert_eq!(a.starts, b.starts, "{what}: cell starts differ");
    assert_eq!(a.perm, b.perm, "{what}: permutations differ");
    assert!(a.sorted.bitwise_eq(&b.sorted), "{what}: sorted states differ");
    assert_eq!(a.raw_counts, b.raw_counts, "{what}: neighbour counts differ");
    assert_eq!(a.raw_list, b.raw_list, "{what}: neighbour lists (gather order) differ");
    assert!(a.raw_list.len() > pos.len(), "{what}: too few pairs for a meaningful test");
    if D::D == 3 {
        // The wide (32-bit) offsets (docs/neighbour-search.md, "Wide offsets"): equal lists, and no row far.
        let mut wide = grid;
        wide.list_wide = 1;
        let (aw, bw) = (search::<_, R, D>(&c, pos, wide, support2), search::<_, R, D>(g, pos, wide, support2));
        assert_eq!(aw.verlet, bw.verlet, "{what}: wide Verlet lists differ");
        let far = (0..pos.len()).filter(|&i| aw.verlet[i] == swarf::kernels::neighbour::verlet::FAR).count();
        assert_eq!(far, 0, "{what}: {far} rows far with 32-bit offsets");
    }

    let n = pos.len();
    let kernel = [CubicSpline::<R>::new(h, D::D)];
    let run = |bk: &dyn DensityRunner<R, D>| bk.density(&a.sorted, grid, &kernel);
    let rc = run(&(&c as &CpuBackend));
    let rg = run(&g);
    let same = rc.iter().zip(&rg).filter(|(x, y)| x.to_f64().to_bits() == y.to_f64().to_bits()).count();
    assert_eq!(same, n, "{what}: density differs from the CPU in {} of {n} particles", n - same);
}

trait DensityRunner<R: Real, D: Dim> {
    fn density(
        &self,
        sorted: &HostParticles<R, D>,
        grid: swarf::kernels::neighbour::GridParams,
        k: &[CubicSpline<R>],
    ) -> Vec<R>;
}

impl<R: Real, D: Dim, B: Backend> DensityRunner<R, D> for &B {
    fn density(
        &self,
        sorted: &HostParticles<R, D>,
        grid: swarf::kernels::neighbour::GridParams,
        k: &[CubicSpline<R>],
    ) -> Vec<R> {
        let b = *self;
        let n = sorted.len();
        let p = Particles::<B, R, D>::upload(b, sorted).expect("upload");
        let mut cl = CellList::new(b, grid, n).expect("cell list");
        cl.build::<R, D>(b, &p.pos.cur).expect("build");
        let kb = b.upload(k, "kernel").expect("upload");
        let mut rho = b.alloc::<R>(n, "rho").expect("alloc");
        // Already sorted: the permutation is the identity, so pos and mass are used as they are.
        Passes::density::<R, D>(b, n, &p.pos.cur, &p.mass.cur, &cl.grid_buf, &cl.starts, &kb, &mut rho)
            .expect("density");
        b.read(&rho).expect("read")
    }
}

fn h_for(n: usize, d: usize) -> f64 {
    1.7 * (n as f64).powf(-1.0 / d as f64)
}

#[test]
fn neighbour_search_equals_cpu_2d() {
    let Some(g) = gpu() else { return };
    let n = 200_000;
    for stencil in [2, 1] {
        compare::<f64, Dim2>(&g, &uniform::<f64, Dim2>(n, 1), h_for(n, 2), stencil, "uniform 2D f64");
        compare::<f32, Dim2>(&g, &uniform::<f32, Dim2>(n, 2), h_for(n, 2), stencil, "uniform 2D f32");
        compare::<f64, Dim2>(&g, &clustered::<f64, Dim2>(n, 3), h_for(n, 2), stencil, "clustered 2D f64");
        compare::<f32, Dim2>(&g, &lattice::<f32, Dim2>(400, 1.0 / 128.0, 4), 1.7 / 128.0, stencil, "lattice 2D f32");
    }
}

#[test]
fn neighbour_search_equals_cpu_3d() {
    let Some(g) = gpu() else { return };
    let n = 200_000;
    for stencil in [2, 1] {
        compare::<f64, Dim3>(&g, &uniform::<f64, Dim3>(n, 5), h_for(n, 3), stencil, "uniform 3D f64");
        compare::<f32, Dim3>(&g, &uniform::<f32, Dim3>(n, 6), h_for(n, 3), stencil, "uniform 3D f32");
        compare::<f64, Dim3>(&g, &clustered::<f64, Dim3>(n, 7), h_for(n, 3), stencil, "clustered 3D f64");
        compare::<f64, Dim3>(&g, &lattice::<f64, Dim3>(58, 1.0 / 64.0, 8), 1.7 / 64.0, stencil, "lattice 3D f64");
    }
}

/// Non-finite positions and particles outside the grid box, on both backends: equal lists and cells, and an equal
/// permutation except for the order within the void bucket, which the GPU leaves in arrival order (the same set).
/// The particles thrown out of the box crowd their clamped border cells (thousands to a cell: the heap sort), and
/// the void bucket holds a fifth of them (the blow-up that stalled a run when it was insertion-sorted).
#[test]
fn degenerate_positions_equal_cpu() {
    let Some(g) = gpu() else { return };
    let n = 50_000;
    let mut pos = uniform::<f64, Dim2>(n, 9);
    pos[10].0[0] = f64::NAN;
    pos[20].0[1] = f64::INFINITY;
    for p in pos.iter_mut().take(3000).skip(100) {
        p.0[0] += 3.0; // far outside the box below
    }
    for p in pos.iter_mut().skip(40_000) {
        p.0[1] = f64::NAN;
    }
    let c = CpuBackend::new();
    let h = h_for(n, 2);
    let grid = grid_for_support([0.0; 3], [1.0, 1.0, 0.0], 2, 2.0 * h, 2).unwrap();
    let a = search::<_, f64, Dim2>(&c, &pos, grid, 4.0 * h * h);
    let b = search::<_, f64, Dim2>(&g, &pos, grid, 4.0 * h * h);
    assert_eq!(a.starts, b.starts);
    let void = a.starts[grid.n_cells as usize] as usize;
    assert_eq!(n - void, 10_002, "void bucket size");
    assert_eq!(a.perm[..void], b.perm[..void], "the cells' permutation");
    let mut tail = b.perm[void..].to_vec();
    tail.sort();
    assert_eq!(a.perm[void..], tail[..], "the void bucket's particles");
    assert_eq!(a.lists, b.lists);
}

/// The GPU scan against its CPU twin, over sizes around the tile and level boundaries.
#[test]
fn scan_equals_cpu() {
    let Some(g) = gpu() else { return };
    let mut rng = SplitMix64::new(17);
    for n in [1usize, 2, 31, 32, 33, 1023, 1024, 1025, 4096, 1_048_575, 1_048_576, 1_048_577, 5_000_011] {
        let v: Vec<u32> = (0..n).map(|_| (rng.next_u64() % 1000) as u32).collect();
        let mut expect = v.clone();
        swarf::backend::cpu::exclusive_scan(&mut expect);
        let mut buf = g.upload(&v, "scan").unwrap();
        let mut levels = swarf::backend::scan_levels(&g, n).unwrap();
        g.exclusive_scan(n, &mut buf, &mut levels).unwrap();
        assert_eq!(g.read(&buf).unwrap(), expect, "scan of {n} elements");
    }
}

/// Gathers of every element size class used by the state (4, 8, 16, 24, 32, 48 bytes) equal the CPU's.
#[test]
fn reorder_equals_cpu_for_every_field_type() {
    let Some(g) = gpu() else { return };
    fn one<R: Real, D: Dim>(g: &CudaBackend) {
        let n = 100_003;
        let c = CpuBackend::new();
        let mut h = HostParticles::<R, D>::at_rest(uniform::<R, D>(n, 21), R::ONE, R::ONE);
        let mut rng = SplitMix64::new(5);
        for i in 0..n {
            h.rho[i] = R::from_f64(rng.uniform());
            h.mass[i] = R::from_f64(rng.uniform());
            h.flags[i] = rng.next_u64() as u32;
            let s: &mut [R] = bytemuck::cast_slice_mut(std::slice::from_mut(&mut h.stress[i]));
            for x in s.iter_mut() {
                *x = R::from_f64(rng.normal());
            }
        }
        let mut perm: Vec<u32> = (0..n as u32).collect();
        rng.shuffle(&mut perm);
        let on = |be: &dyn ReorderRunner<R, D>| be.run(&h, &perm);
        let a = on(&(&c as &CpuBackend));
        let b = on(&g);
        assert!(a.bitwise_eq(&b), "{}D {}: reordered states differ", D::D, R::NAME);
    }
    one::<f32, Dim2>(&g);
    one::<f64, Dim2>(&g);
    one::<f32, Dim3>(&g);
    one::<f64, Dim3>(&g);
}

trait ReorderRunner<R: Real, D: Dim> {
    fn run(&self, h: &HostParticles<R, D>, perm: &[u32]) -> HostParticles<R, D>;
}

impl<R: Real, D: Dim, B: Backend> ReorderRunner<R, D> for &B {
    fn run(&self, h: &HostParticles<R, D>, perm: &[u32]) -> HostParticles<R, D> {
        let b = *self;
        let mut p = Particles::<B, R, D>::upload(b, h).unwrap();
        let pb = b.upload(perm, "perm").unwrap();
        p.reorder(b, &pb).unwrap();
        p.download(b).unwrap()
    }
}

/// Two GPU builds of the same heavily clustered input give the same permutation, despite the atomics (AT-53).
#[test]
fn gpu_build_is_deterministic() {
    let Some(g) = gpu() else { return };
    let n = 1_000_000;
    let pos = clustered::<f32, Dim3>(n, 23);
    let (lo, hi) = bounding_box::<f32, _>(&pos);
    let grid = grid_for_support(lo, hi, 3, 2.0 * h_for(n, 3), 2).unwrap();
    let p = g.upload(&pos, "pos").unwrap();
    let mut runs = Vec::new();
    for _ in 0..3 {
        let mut cl = CellList::new(&g, grid, n).unwrap();
        cl.build::<f32, Dim3>(&g, &p).unwrap();
        runs.push((g.read(&cl.perm).unwrap(), g.read(&cl.starts).unwrap()));
    }
    assert!(runs[0] == runs[1] && runs[1] == runs[2], "GPU cell-list builds differ between runs");
}

/// AT-52: one step of the rubber rings (4232 particles, f64, all stabilisers) on the GPU equals the CPU: every
/// rate and every field within 1e-12 relative (the same gather order and IEEE operations give bitwise equality).
/// AT-53: two GPU runs of 200 steps are bitwise identical. Also f32 and a 3D case.
#[test]
fn sph_step_equals_cpu_and_is_deterministic() {
    let Some(g) = gpu() else { return };
    use swarf::kernels::sph::TensorOps;
    use swarf::kernels::{Dim, Dim2, Dim3};
    use swarf::run::setup;
    use swarf::scene::Scene;
    use swarf::solver::Solver;

    fn rel_diff<R: Real>(a: &[R], b: &[R]) -> f64 {
        let scale = a.iter().fold(0.0f64, |m, x| m.max(x.to_f64().abs())).max(f64::MIN_POSITIVE);
        a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x.to_f64() - y.to_f64()).abs())) / scale
    }
    fn flat<R: Real, T: bytemuck::Pod>(v: &[T]) -> Vec<R> {
        bytemuck::cast_slice::<T, R>(v).to_vec()
    }
    fn steps<B: Backend, R: Real, D: TensorOps<R>>(
        b: &B,
        scene: &Scene,
        n: usize,
    ) -> (HostParticles<R, D>, Vec<Vec<R>>) {
        let s = setup::<R, D>(scene).expect("setup");
        let mut sv = Solver::<B, R, D>::new(b, &s).expect("solver");
        for _ in 0..n {
            sv.step(b, s.dt).expect("step");
        }
        let (x, v, r, st) = sv.download_rates(b).expect("rates");
        (sv.download(b).expect("state"), vec![flat::<R, _>(&x), flat::<R, _>(&v), r, flat::<R, _>(&st)])
    }
    fn compare_one<R: Real, D: TensorOps<R>>(g: &CudaBackend, scene: &Scene, n: usize, tol: f64, what: &str)
    where
        <D as Dim>::Vec<R>: bytemuck::Pod,
    {
        let c = CpuBackend::new();
        let (sc, rc) = steps::<_, R, D>(&c, scene, n);
        let (sg, rg) = steps::<_, R, D>(g, scene, n);
        assert_eq!(sc.id, sg.id, "{what}: particle order differs");
        let names = ["pos_t", "vel_t", "rho_t", "stress_t"];
        for (k, (a, b)) in rc.iter().zip(&rg).enumerate() {
            let d = rel_diff(a, b);
            eprintln!("{what}: {} max relative difference {d:e}", names[k]);
            assert!(d <= tol, "{what}: rate {} differs from the CPU by {d:e}", names[k]);
        }
        let fields = [
            ("pos", rel_diff(&flat::<R, _>(&sc.pos), &flat::<R, _>(&sg.pos))),
            ("vel", rel_diff(&flat::<R, _>(&sc.vel), &flat::<R, _>(&sg.vel))),
            ("rho", rel_diff(&sc.rho, &sg.rho)),
            ("stress", rel_diff(&flat::<R, _>(&sc.stress), &flat::<R, _>(&sg.stress))),
        ];
        for (name, d) in fields {
            eprintln!("{what}: {name} max relative difference {d:e}");
            assert!(d <= tol, "{what}: {name} differs from the CPU by {d:e}");
        }
        eprintln!("{what}: bitwise equal to the CPU: {}", sc.bitwise_eq(&sg));
    }
    let rings = Scene::load("cases/rings.toml", &[]).expect("rings");
    compare_one::<f64, Dim2>(&g, &rings, 1, 1e-12, "rings f64, 1 step");
    compare_one::<f64, Dim2>(&g, &rings, 50, 1e-12, "rings f64, 50 steps");
    compare_one::<f32, Dim2>(&g, &rings, 1, 1e-6, "rings f32, 1 step");
    let cyl = Scene::load("cases/cylinders-3d.toml", &[]).expect("cylinders");
    compare_one::<f64, Dim3>(&g, &cyl, 1, 1e-12, "cylinders 3D f64, 1 step");
    // Determinism: two GPU runs of 200 steps.
    let (a, _) = steps::<_, f64, Dim2>(&g, &rings, 200);
    let (b, _) = steps::<_, f64, Dim2>(&g, &rings, 200);
    assert!(a.bitwise_eq(&b), "two GPU runs of the rings differ");
}

/// Issue 4: the plastic pass (radial return, f64) on the GPU equals the CPU over 10⁴ random trial states for
/// every flow-stress model of the library: stresses, plastic strains and rates within 1 ulp (the helper functions
/// are the same IEEE operations and the same libm code on both sides, so equality is expected).
#[test]
fn plastic_pass_equals_cpu_within_one_ulp() {
    let Some(g) = gpu() else { return };
    use swarf::backend::PlasticInputs;
    use swarf::kernels::Dim3;
    use swarf::kernels::sph::plastic::PlasticConsts;
    let lib = swarf::material::Library::load_dir("cases/materials").expect("library");
    let c = CpuBackend::new();
    let ulp = |a: f64, b: f64| (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs();
    let mut models = 0;
    for m in lib.iter() {
        let (Some(model), Some(el)) = (m.flow_stress, m.elastic) else { continue };
        models += 1;
        let n = 10_000;
        let shear = el.youngs_modulus / (2.0 * (1.0 + el.poisson_ratio));
        let (s, eps, rate, temp) = swarf::bench::trial_states(n, 1e9, 31);
        let run =
            |be: &dyn Fn(&mut Vec<swarf::kernels::vector::S3f64>, &mut Vec<f64>, &mut Vec<f64>, &mut Vec<f64>)| {
                let (mut s, mut e, mut r, mut t) = (s.clone(), eps.clone(), rate.clone(), temp.clone());
                be(&mut s, &mut e, &mut r, &mut t);
                (s, e, r, t)
            };
        fn go<B: Backend>(
            b: &B,
            model: &swarf::material::FlowModel,
            shear: f64,
            rho: f64,
            s: &mut Vec<swarf::kernels::vector::S3f64>,
            e: &mut Vec<f64>,
            r: &mut Vec<f64>,
            t: &mut Vec<f64>,
        ) {
            let n = s.len();
            let mut sb = b.upload(s, "s").unwrap();
            let mut eb = b.upload(e, "e").unwrap();
            let mut rb = b.upload(r, "r").unwrap();
            let mut tb = b.upload(t, "t").unwrap();
            let rho = b.upload(&vec![rho; n], "rho").unwrap();
            let fl = b.upload(&vec![0u32; n], "flags").unwrap();
            let c = PlasticConsts { shear, dt: 1e-8, taylor_quinney: 0.0, flags: 0, _pad: 0 };
            b.plastic_step::<f64, Dim3>(
                n,
                model,
                c,
                PlasticInputs {
                    stress: &mut sb,
                    rho: &rho,
                    eps: &mut eb,
                    rate: &mut rb,
                    temp: &mut tb,
                    flags: &fl,
                    materials: None,
                    yield_stress: None,
                    work: None,
                    damage: None,
                },
            )
            .unwrap();
            *s = b.read(&sb).unwrap();
            *e = b.read(&eb).unwrap();
            *r = b.read(&rb).unwrap();
            *t = b.read(&tb).unwrap();
        }
        let a = run(&|s, e, r, t| go(&c, &model, shear, el.density, s, e, r, t));
        let b = run(&|s, e, r, t| go(&g, &model, shear, el.density, s, e, r, t));
        let mut worst = 0u64;
        for i in 0..n {
            for k in 0..6 {
                worst = worst.max(ulp(a.0[i].0[k], b.0[i].0[k]));
            }
            worst = worst.max(ulp(a.1[i], b.1[i])).max(ulp(a.2[i], b.2[i]));
        }
        let plastic = (0..n).filter(|&i| a.1[i] > eps[i]).count();
        eprintln!("{}: worst difference {worst} ulp, {plastic} of {n} states plastic", m.name);
        assert!(worst <= 1, "{}: GPU return map differs from the CPU by {worst} ulp", m.name);
        assert!(plastic > n / 10, "{}: too few plastic states for a meaningful check", m.name);
    }
    assert!(models >= 20, "the library's flow-stress sets must all be checked");
}

/// Issue 4: the plastic impact with heat conduction (Brookshaw) on the GPU equals the CPU over 20 steps (f64):
/// every field, temperature and plastic strain within 1e-12 relative.
#[test]
fn plastic_thermal_run_equals_cpu() {
    let Some(g) = gpu() else { return };
    use swarf::kernels::Dim2;
    use swarf::run::setup;
    use swarf::scene::Scene;
    use swarf::solver::Solver;
    let scene =
        Scene::load("cases/impact.toml", &["discretisation.dx=2e-3".into(), "physics.conduction=\"brookshaw\"".into()])
            .expect("scene");
    fn steps<B: Backend>(b: &B, scene: &Scene) -> (HostParticles<f64, Dim2>, Vec<f64>, Vec<f64>) {
        let s = setup::<f64, Dim2>(scene).expect("setup");
        let mut sv = Solver::<B, f64, Dim2>::new(b, &s).expect("solver");
        for _ in 0..300 {
            sv.step(b, s.dt).expect("step");
        }
        let (t, e, _) = sv.download_internal(b).expect("internal");
        (sv.download(b).expect("state"), t.expect("temperature"), e.expect("plastic strain"))
    }
    let (a, ta, ea) = steps(&CpuBackend::new(), &scene);
    let (b, tb, eb) = steps(&g, &scene);
    assert_eq!(a.id, b.id);
    let rel = |x: &[f64], y: &[f64]| {
        let scale = x.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(f64::MIN_POSITIVE);
        x.iter().zip(y).fold(0.0f64, |m, (p, q)| m.max((p - q).abs())) / scale
    };
    let flat = |v: &[swarf::kernels::vector::V2f64]| v.iter().flat_map(|p| p.0).collect::<Vec<f64>>();
    let diffs = [
        ("pos", rel(&flat(&a.pos), &flat(&b.pos))),
        ("vel", rel(&flat(&a.vel), &flat(&b.vel))),
        ("rho", rel(&a.rho, &b.rho)),
        ("temperature", rel(&ta, &tb)),
        ("plastic strain", rel(&ea, &eb)),
    ];
    for (name, d) in diffs {
        eprintln!("impact + conduction, 300 steps: {name} max relative difference {d:e}");
        assert!(d <= 1e-12, "{name} differs from the CPU by {d:e}");
    }
    assert!(ea.iter().any(|&e| e > 0.0), "the 300 steps must include plastic flow");
    eprintln!("impact + conduction: bitwise equal to the CPU: {}", a.bitwise_eq(&b) && ta == tb && ea == eb);
}

/// Issue 7: steps run in captured CUDA graphs (batches of GRAPH_STEPS, both buffer parities, an odd remainder)
/// end bit for bit where the same steps submitted one by one end, and where the CPU ends.
#[test]
fn graph_batches_equal_plain_steps_and_cpu() {
    let Some(g) = gpu() else { return };
    use swarf::kernels::Dim2;
    use swarf::run::setup;
    use swarf::scene::Scene;
    use swarf::solver::{GRAPH_STEPS, Solver};
    let scene =
        Scene::load("cases/impact.toml", &["discretisation.dx=2e-3".into(), "physics.conduction=\"brookshaw\"".into()])
            .expect("scene");
    let count = 3 + 3 * GRAPH_STEPS + 7;
    fn run<B: Backend>(b: &B, scene: &Scene, graphs: bool, count: usize) -> (HostParticles<f64, Dim2>, Vec<f64>) {
        let s = setup::<f64, Dim2>(scene).expect("setup");
        let mut sv = Solver::<B, f64, Dim2>::new(b, &s).expect("solver");
        sv.use_graphs = graphs;
        sv.advance(b, s.dt, count).expect("advance");
        assert_eq!(sv.steps, count as u64);
        let (t, _, _) = sv.download_internal(b).expect("internal");
        (sv.download(b).expect("state"), t.expect("temperature"))
    }
    let (a, ta) = run(&CpuBackend::new(), &scene, true, count);
    let (b, tb) = run(&g, &scene, true, count);
    let (c, tc) = run(&g, &scene, false, count);
    assert!(b.bitwise_eq(&c) && tb == tc, "graph batches differ from plain steps");
    assert!(a.bitwise_eq(&b) && ta == tb, "graph batches differ from the CPU");
    eprintln!("{count} steps in graph batches: bitwise equal to plain GPU steps and to the CPU");
}

/// Issue 7 on the GPU: a captured step puts its cell-list rebuild in an IF node (`backend::cuda`, module
/// `conditional`) that skips the rebuild's gated launches when the step does not rebuild. Over graph batches in
/// which the impact's moving disk rebuilds the list again and again, the IF nodes end bit for bit where the plain
/// gated nodes and the CPU end, after the same rebuilds. On the GPU machine (`SWARF_REQUIRE_GPU=1`) a driver that
/// cannot build the IF nodes fails the test: there it must.
#[test]
fn conditional_rebuilds_equal_gated_nodes_and_cpu() {
    let Some(g) = gpu() else { return };
    use swarf::kernels::Dim2;
    use swarf::run::setup;
    use swarf::scene::Scene;
    use swarf::solver::{GRAPH_STEPS, Solver};
    if let Err(why) = g.conditional_rebuild() {
        if std::env::var("SWARF_REQUIRE_GPU").is_ok_and(|v| v == "1") {
            panic!("SWARF_REQUIRE_GPU=1 but no IF nodes for the rebuild: {why}");
        }
        eprintln!("skipped (no IF nodes for the rebuild: {why})");
        return;
    }
    let scene =
        Scene::load("cases/impact.toml", &["discretisation.dx=2e-3".into(), "physics.conduction=\"brookshaw\"".into()])
            .expect("scene");
    // Two plain steps, then whole batches only: every rebuild after the first two steps ran inside a graph.
    fn run<B: Backend>(b: &B, scene: &Scene, graphs: bool) -> (HostParticles<f64, Dim2>, Vec<f64>, u32, u32) {
        let s = setup::<f64, Dim2>(scene).expect("setup");
        let mut sv = Solver::<B, f64, Dim2>::new(b, &s).expect("solver");
        sv.use_graphs = graphs;
        sv.advance(b, s.dt, 2).expect("advance");
        let before = sv.cell_rebuilds(b).expect("rebuilds");
        sv.advance(b, s.dt, 3 * GRAPH_STEPS).expect("advance");
        let after = sv.cell_rebuilds(b).expect("rebuilds");
        let (t, _, _) = sv.download_internal(b).expect("internal");
        (sv.download(b).expect("state"), t.expect("temperature"), before, after)
    }
    let (a, ta, _, ra) = run(&CpuBackend::new(), &scene, false);
    let (b, tb, b0, rb) = run(&g, &scene, true);
    let mut gated = gpu().expect("GPU");
    gated.set_conditional_rebuild(false);
    let (c, tc, _, rc) = run(&gated, &scene, true);
    assert!(rb > b0 + 2, "only {} rebuilds inside the graph batches: the IF nodes are not exercised", rb - b0);
    assert_eq!((rb, rc), (ra, ra), "rebuild counts: IF nodes {rb}, gated nodes {rc}, CPU {ra}");
    assert!(b.bitwise_eq(&c) && tb == tc, "IF nodes differ from the gated nodes");
    assert!(a.bitwise_eq(&b) && ta == tb, "IF nodes differ from the CPU");
    eprintln!(
        "{} rebuilds inside {} captured steps: IF nodes bitwise equal to the gated nodes and to the CPU",
        rb - b0,
        3 * GRAPH_STEPS
    );
}

/// Issue 6 on the GPU: the plastic impact with conduction, stopped at its checkpoint half way and resumed,
/// ends bit for bit where the uninterrupted GPU run ends (positions, velocities, temperatures, plastic strains).
#[test]
fn resumed_gpu_run_equals_uninterrupted() {
    if gpu().is_none() {
        return;
    }
    use swarf::backend::{AnyBackend, BackendChoice};
    use swarf::run::{RunOptions, Snapshot, resume_scene, run_observed};
    use swarf::scene::Scene;
    let ov: Vec<String> =
        vec!["discretisation.dx=2e-3".into(), "physics.conduction=\"brookshaw\"".into(), "time.end=1e-4".into()];
    let scene = Scene::load("cases/impact.toml", &ov).expect("scene");
    let any = AnyBackend::select(BackendChoice::Gpu).expect("gpu").0;
    let end = scene.time.end;
    let opts = |d: &std::path::Path, resume: bool| RunOptions {
        overrides: ov.clone(),
        checkpoint_every: Some(0.5 * end),
        resume,
        ..RunOptions::quiet(d.to_path_buf())
    };
    let bits = |s: &Snapshot| -> Vec<u64> {
        let mut v: Vec<u64> = s.pos.iter().chain(&s.vel).flat_map(|p| p.map(f64::to_bits)).collect();
        v.extend(s.temperature.unwrap_or(&[]).iter().map(|x| x.to_bits()));
        v.extend(s.plastic_strain.unwrap_or(&[]).iter().map(|x| x.to_bits()));
        v
    };
    let tmp = std::env::temp_dir();
    let (a, b) = (tmp.join("swarf-gpu-ckpt-a"), tmp.join("swarf-gpu-ckpt-b"));
    let _ = std::fs::remove_dir_all(&a);
    let _ = std::fs::remove_dir_all(&b);
    let mut last_a = Vec::new();
    let mut obs = |s: &Snapshot| {
        last_a = bits(s);
        true
    };
    run_observed(&any, &scene, &opts(&a, false), Some(&mut obs)).expect("uninterrupted");
    let mut stop = |s: &Snapshot| s.diagnostics.time < 0.5 * end;
    run_observed(&any, &scene, &opts(&b, false), Some(&mut stop)).expect("first half");
    let (resumed, _) = resume_scene(&b).expect("resume scene");
    let mut last_b = Vec::new();
    let mut obs = |s: &Snapshot| {
        last_b = bits(s);
        true
    };
    run_observed(&any, &resumed, &opts(&b, true), Some(&mut obs)).expect("second half");
    eprintln!("GPU resume: {} values compared, bitwise equal: {}", last_a.len(), last_a == last_b);
    assert!(!last_a.is_empty() && last_a == last_b, "the resumed GPU run differs from the uninterrupted one");
}

/// Issue 5 on the GPU: the coarse V0060 cut (contact, friction, plasticity, conduction) and the thermal-tool
/// reference cut give the same force trace (forces.csv) and the same final state as the CPU. Expected bitwise
/// (same gather order, no atomics, correctly rounded f64 on both sides); the assertion allows 1e-9 relative on
/// the forces so that a difference is reported with its size rather than hidden.
#[test]
fn cutting_force_trace_equals_cpu() {
    let Some(_) = gpu() else { return };
    use swarf::backend::{AnyBackend, BackendChoice};
    use swarf::run::RunOptions;
    use swarf::scene::Scene;
    let cases: [(&str, Vec<&str>); 3] = [
        (
            "cases/cutting/v0060.toml",
            vec![
                "discretisation.dx=2.0e-5",
                "body.0.max=[1.0e-3,2.8e-4]",
                "boundary.1.max=[1.0e-9,1.4e-4]",
                "boundary.2.min=[0.9999e-3,-1.0]",
                "tool.position=[-3.6e-5]",
                "tool.depth_of_cut=0.9e-4",
                "time.end=1.2e-5",
                "output.every=1.2e-6",
            ],
        ),
        (
            "cases/cutting/reference-cut.toml",
            vec!["time.end=1.0e-5", "output.every=1.0e-6", "tool.friction_cap=\"current\"", "tool.usui={}"],
        ),
        // The original code's formulas (issue 22, `model = "mfree_iwf"`): its return, rate form, kernel value,
        // componentwise slip, datum, Δt, cutoff and thermal boundary, each a run-time flag of the same kernels.
        ("cases/cutting/reference-cut.toml", vec!["time.end=1.0e-5", "output.every=1.0e-6", "model=\"mfree_iwf\""]),
    ];
    for (file, ov) in cases {
        let ov: Vec<String> = ov.iter().map(|s| s.to_string()).collect();
        let scene = Scene::load(file, &ov).expect("scene");
        let mut traces = Vec::new();
        for (k, choice) in [BackendChoice::Cpu, BackendChoice::Gpu].into_iter().enumerate() {
            let any = AnyBackend::select(choice).expect("backend").0;
            let dir = std::env::temp_dir().join(format!("swarf-gpu-cut-{k}-{}", std::process::id()));
            let opts = RunOptions { overrides: ov.clone(), ..RunOptions::quiet(dir.clone()) };
            let (last, _) = final_state(&any, &scene, &opts);
            let (_, rows) = swarf::output::csv::read(&dir.join("forces.csv")).expect("forces.csv");
            traces.push((rows, last));
        }
        let (a, b) = (&traces[0], &traces[1]);
        assert_eq!(a.0.len(), b.0.len(), "{file}: sample counts");
        let mut worst = 0.0f64;
        for (ra, rb) in a.0.iter().zip(&b.0) {
            for k in [2, 3] {
                let scale = ra[k].abs().max(1e-30);
                worst = worst.max((ra[k] - rb[k]).abs() / scale);
            }
        }
        let contacts = a.0.iter().map(|r| r[4]).fold(0.0, f64::max);
        eprintln!(
            "GPU cut {file}: {} force samples (up to {contacts} particles in contact), worst relative force \
             difference {worst:e}, final state bitwise equal: {}",
            a.0.len(),
            a.1 == b.1
        );
        assert!(contacts > 0.0, "{file}: the tool must touch the workpiece");
        assert!(worst <= 1e-9, "{file}: GPU force trace differs from the CPU by {worst:e}");
    }
}

/// Issue 25 on the GPU: damage (JC initiation, Hillerborg softening, the stress degraded in the pre-pass, the plastic
/// heating of the degraded stress) and the interaction mask (a fully damaged pre-crack in tension) in both its forms
/// (`damage.mask_form`, printed and invariant) give the CPU's run bit for bit: a strip pulled apart at 50 m/s for
/// 10 µs, until its particles yield and its damaged volume has grown beyond the pre-crack's; the damaged volume and the
/// elastic energy the degradation released (energy.csv) equal over time.
#[test]
fn damaged_strip_equals_cpu() {
    let Some(_) = gpu() else { return };
    use swarf::backend::{AnyBackend, BackendChoice};
    use swarf::run::RunOptions;
    use swarf::scene::Scene;
    // The third run models thermal expansion: the triaxiality then reads ρ0(T) (`material::eos`).
    for (form, expansion) in [("printed", 0.0), ("invariant", 0.0), ("invariant", 9e-6)] {
        let over = [format!("damage.mask_form=\"{form}\""), format!("physics.thermal_expansion={expansion:e}")];
        let form = if expansion > 0.0 { format!("{form}, thermal expansion") } else { form.to_string() };
        let text = common::scenes::pulled_strip_scene(50.0, 1.0e-5);
        let scene = Scene::from_str(&text, "strip.toml", &over).expect("scene");
        let mut runs = Vec::new();
        for (k, choice) in [BackendChoice::Cpu, BackendChoice::Gpu].into_iter().enumerate() {
            let any = AnyBackend::select(choice).expect("backend").0;
            let tag = form.replace([' ', ','], "_");
            let dir = std::env::temp_dir().join(format!("swarf-gpu-strip-{tag}-{k}-{}", std::process::id()));
            let (last, yielded) = final_state(&any, &scene, &RunOptions::quiet(dir.clone()));
            let (header, rows) = swarf::output::csv::read(&dir.join("energy.csv")).expect("energy.csv");
            // The damaged volume and the energy the degradation released, over time.
            let col = |name: &str| header.iter().position(|c| c == name).expect("an energy.csv column");
            let (k, kr) = (col("damaged_volume"), col("damage_dissipation"));
            let damaged: Vec<[u64; 2]> = rows.iter().map(|r| [r[k].to_bits(), r[kr].to_bits()]).collect();
            runs.push((last, yielded, damaged, rows, k));
        }
        let (first, last, k) = (runs[0].3.first().expect("rows"), runs[0].3.last().expect("rows"), runs[0].4);
        let (d0, d1) = (first[k], last[k]);
        eprintln!(
            "damaged strip ({form} mask): {} particles yielded, damaged volume {d0:e} -> {d1:e} m², final state \
             bitwise equal: {}",
            runs[0].1,
            runs[0].0 == runs[1].0
        );
        assert!(runs[0].1 > 0 && d1 > d0, "{form}: the strip must yield and its damage grow ({d0} -> {d1})");
        let released = runs[0].2.last().map_or(f64::NAN, |r| f64::from_bits(r[1]));
        eprintln!("damaged strip ({form} mask): the degradation released {released:e} J/m");
        assert!(released > 0.0, "{form}: the degradation must release energy ({released})");
        assert_eq!(runs[0].2, runs[1].2, "{form}: the damaged volume or released energy differs between CPU and GPU");
        assert!(runs[0].0 == runs[1].0, "{form}: GPU damaged strip differs from the CPU");
    }
}

/// Issue 26 on the GPU: the SPH cohesive path (the bonds' pass and id map, the `_cut` interaction entries) gives
/// the CPU's run bit for bit: the bonded blocks of V15 torn open in mode I (also with XSPH and the smoothed-velocity
/// damping) and slid apart in mode II (every bond failing), and Nairn's SPH cut at a coarse 5 particles through h until the tool has crossed the starter and
/// loaded the bonds. The final states and the energy histories (with the bonds' work and failures) are compared.
#[test]
fn sph_cohesive_path_equals_cpu() {
    let Some(_) = gpu() else { return };
    use swarf::backend::{AnyBackend, BackendChoice};
    use swarf::run::RunOptions;
    use swarf::scene::Scene;
    let coarse = [
        "discretisation.dx=2e-4",
        "boundary.0.max=[1.0, -2.7e-3]",
        "tool.position=[-2e-4]",
        "tool.ramp=0",
        "time.end=2e-3",
        "output.every=2e-4",
    ];
    // The coarse cut with CSPM on the faces (`_cspm_cut`; docs/mpm.md, "CSPM on the faces"), at Nairn's σ_c.
    let mut coarse_cspm = coarse.to_vec();
    coarse_cspm.push("stabilisation.cspm={}");
    // The same with the correction on the faces' rows only (`scope = "path"`: the pass's count of cut pairs).
    let mut coarse_faces = coarse.to_vec();
    coarse_faces.push("stabilisation.cspm={scope=\"path\"}");
    // The same with the plane continuum until the onset (`coupling = "continuum"`: the onset and opening passes).
    let mut coarse_continuum = coarse.to_vec();
    coarse_continuum.push("cohesive.coupling=\"continuum\"");
    let continuum: &[&str] = &["cohesive.coupling=\"continuum\""];
    let cases: [(&str, &[&str]); 9] = [
        ("cases/mpm/sph-bond-mode1.toml", &[]),
        ("cases/mpm/sph-bond-mode1.toml", continuum),
        ("cases/mpm/sph-bond-mode2.toml", continuum),
        ("cases/mpm/nairn-cut-sph.toml", &coarse_continuum),
        // With XSPH and the smoothed-velocity damping (docs/mpm.md).
        ("cases/mpm/sph-bond-mode1.toml", &["stabilisation.xsph={epsilon=0.5, pic=0.5}"]),
        ("cases/mpm/sph-bond-mode2.toml", &[]),
        ("cases/mpm/nairn-cut-sph.toml", &coarse),
        ("cases/mpm/nairn-cut-sph.toml", &coarse_cspm),
        ("cases/mpm/nairn-cut-sph.toml", &coarse_faces),
    ];
    for (file, ov) in cases {
        let ov: Vec<String> = ov.iter().map(|s| s.to_string()).collect();
        let scene = Scene::load(file, &ov).expect("scene");
        let mut runs = Vec::new();
        for (k, choice) in [BackendChoice::Cpu, BackendChoice::Gpu].into_iter().enumerate() {
            let any = AnyBackend::select(choice).expect("backend").0;
            let dir = std::env::temp_dir().join(format!("swarf-gpu-sph-cohesive-{k}-{}", std::process::id()));
            let (last, _) = final_state(&any, &scene, &RunOptions::quiet(dir.clone()));
            let (header, rows) = swarf::output::csv::read(&dir.join("energy.csv")).expect("energy.csv");
            let bits: Vec<u64> = rows.iter().flat_map(|r| r.iter().map(|x| x.to_bits())).collect();
            let end = rows.last().expect("rows").clone();
            let col = |name: &str| header.iter().position(|c| c == name).expect("column");
            runs.push((last, bits, (end[col("cohesive_work")], end[col("bonds_failed")])));
        }
        let (work, failed) = runs[0].2;
        eprintln!(
            "{file}: {failed} bonds failed, cohesive work {work:.4e} J/m, final state bitwise equal: {}, energy \
             history bitwise equal: {}",
            runs[0].0 == runs[1].0,
            runs[0].1 == runs[1].1
        );
        assert!(work > 0.0 && (failed > 0.0 || file.contains("cut")), "{file}: the bonds must be loaded (and fail)");
        assert!(runs[0].0 == runs[1].0, "{file}: GPU final state differs from the CPU");
        assert!(runs[0].1 == runs[1].1, "{file}: GPU energy history differs from the CPU");
    }
}

/// The bits of a run's last snapshot (positions, velocities, temperatures and plastic strains where modelled) and
/// how many particles have yielded by then.
fn final_state(
    any: &swarf::backend::AnyBackend,
    scene: &swarf::scene::Scene,
    opts: &swarf::run::RunOptions,
) -> (Vec<u64>, usize) {
    let (mut last, mut yielded) = (Vec::new(), 0);
    let mut obs = |s: &swarf::run::Snapshot| {
        last = s.pos.iter().chain(&s.vel).flat_map(|p| p.map(f64::to_bits)).collect::<Vec<u64>>();
        last.extend(s.temperature.unwrap_or(&[]).iter().map(|x| x.to_bits()));
        let eps = s.plastic_strain.unwrap_or(&[]);
        last.extend(eps.iter().map(|x| x.to_bits()));
        yielded = eps.iter().filter(|e| **e > 0.0).count();
        true
    };
    swarf::run::run_observed(any, scene, opts, Some(&mut obs)).expect("run");
    assert!(!last.is_empty(), "no snapshot");
    (last, yielded)
}

/// Issue 7 on the GPU: the block size and the block order of the neighbour passes and of the plastic corrector
/// (`SWARF_PAIR_BLOCK`, `SWARF_PLASTIC_BLOCK`, `SWARF_PAIR_ORDER`, `SWARF_PLASTIC_ORDER`) change no bit: the thermal
/// reference cut (contact, plastic flow with heating, fused conduction; its 7 069 particles take eight lanes each, a
/// group always within one warp), run until particles yield, ends in the same state (positions, velocities,
/// temperatures, plastic strains) with blocks of 256, 128, 96 and 64 (the defaults: 64 for the neighbour passes,
/// 256 for the corrector), forward and reversed; sizes that are not whole warps are refused.
#[test]
fn block_sizes_change_no_bit() {
    let Some(mut g) = gpu() else { return };
    use swarf::backend::AnyBackend;
    use swarf::run::RunOptions;
    use swarf::scene::Scene;
    for bad in [0, 16, 100, 2048] {
        assert!(g.set_blocks(bad, 256).is_err() && g.set_blocks(256, bad).is_err(), "block {bad} accepted");
    }
    let file = "cases/cutting/reference-cut.toml";
    let ov: Vec<String> = vec!["time.end=1.5e-5".into(), "output.every=5.0e-6".into()];
    let scene = Scene::load(file, &ov).expect("scene");
    let mut finals: Vec<(String, Vec<u64>, usize)> = Vec::new();
    // Sizes, and the block orders (reverse: `ptx::ordered_index`) of the interaction and the corrector.
    for (pair, plastic, pair_rev, plastic_rev) in
        [(256, 256, false, false), (128, 128, true, true), (96, 64, false, true), (64, 96, true, false)]
    {
        let mut b = gpu().expect("GPU");
        b.set_blocks(pair, plastic).expect("block sizes");
        b.set_block_order(pair_rev, plastic_rev);
        let any = AnyBackend::Cuda(Box::new(b));
        let name = format!("{pair}{}/{plastic}{}", if pair_rev { "r" } else { "" }, if plastic_rev { "r" } else { "" });
        let dir =
            std::env::temp_dir().join(format!("swarf-gpu-blocks-{}-{}", name.replace('/', "-"), std::process::id()));
        let (state, yielded) =
            final_state(&any, &scene, &RunOptions { overrides: ov.clone(), ..RunOptions::quiet(dir) });
        finals.push((name, state, yielded));
    }
    assert!(finals[0].2 > 0, "no particle yielded: the plastic corrector's block size is not exercised");
    for (name, state, _) in &finals[1..] {
        assert!(*state == finals[0].1, "blocks {name}: the final state differs from the default blocks'");
    }
    eprintln!(
        "block sizes and orders 256/256, 128r/128r, 96/64r, 64r/96 (r: reverse): final states bitwise equal ({} words, {} particles yielded)",
        finals[0].1.len(),
        finals[0].2
    );
}

/// Issue 7 on the GPU: the interaction fused with the Brookshaw conduction (`swarf_sph_rates_heat_*`) ends bit
/// for bit where the separate conduction pass ends, and where the CPU ends, on the thermal-tool reference cut with
/// a temperature gradient across tool and workpiece, with one and eight lanes (tests/cutting.rs checks the CPU).
#[test]
fn fused_conduction_equals_separate_pass_and_cpu() {
    let Some(g) = gpu() else { return };
    use swarf::kernels::{Dim2, Vector};
    use swarf::run::setup;
    use swarf::scene::Scene;
    use swarf::solver::{GRAPH_STEPS, Solver};
    let scene = Scene::load("cases/cutting/reference-cut.toml", &[]).expect("scene");
    let mut s = setup::<f64, Dim2>(&scene).expect("setup");
    s.temperature = Some(s.particles.pos.iter().map(|p| 300.0 + 2.0e6 * (p.get(0) + p.get(1))).collect());
    let count = 2 + GRAPH_STEPS + 5;
    fn run<B: Backend>(
        b: &B,
        s: &swarf::solver::Setup<f64, Dim2>,
        fuse: bool,
        lanes: u32,
        count: usize,
    ) -> (HostParticles<f64, Dim2>, Vec<f64>) {
        let mut sv = Solver::<B, f64, Dim2>::new(b, s).expect("solver");
        sv.fuse_conduction = fuse;
        sv.lanes = lanes;
        sv.advance(b, s.dt, count).expect("advance");
        let (t, _, _) = sv.download_internal(b).expect("internal");
        (sv.download(b).expect("state"), t.expect("temperature"))
    }
    for lanes in [1, 8] {
        let (a, ta) = run(&CpuBackend::new(), &s, true, lanes, count);
        let (f, tf) = run(&g, &s, true, lanes, count);
        let (u, tu) = run(&g, &s, false, lanes, count);
        assert!(f.bitwise_eq(&u) && tf == tu, "{lanes} lanes: fused GPU pass differs from the separate one");
        assert!(a.bitwise_eq(&f) && ta == tf, "{lanes} lanes: fused GPU pass differs from the CPU");
        eprintln!("{lanes} lanes, {count} steps: fused conduction bitwise equal to the separate pass and the CPU");
    }
}

/// Issue 7 on the GPU: the pre-pass fused into the predictor and the contact pass fused into the plastic corrector's
/// launch (`Solver::fuse_prepare`, `Solver::fuse_contact`, the defaults) end bit for bit where the separate passes
/// end, and where the CPU ends (tests/cutting.rs checks the CPU): the plastic block dropped on the tool with the
/// CURRENT friction cap, friction heating and wear, in graph batches (the pre-pass after a rebuild in the IF
/// node), until it has touched the tool and yielded.
#[test]
fn fused_prepass_and_contact_equal_separate_passes_and_cpu() {
    let Some(g) = gpu() else { return };
    use swarf::kernels::Dim2;
    use swarf::run::setup;
    use swarf::scene::Scene;
    use swarf::solver::{GRAPH_STEPS, Solver};
    let scene = Scene::from_str(&common::scenes::plastic_drop_scene(), "cases/cutting/drop.toml", &[]).expect("scene");
    let s = setup::<f64, Dim2>(&scene).expect("setup");
    fn run<B: Backend>(
        b: &B,
        s: &swarf::solver::Setup<f64, Dim2>,
        fuse: bool,
    ) -> (HostParticles<f64, Dim2>, Vec<u64>, usize, usize) {
        let mut sv = Solver::<B, f64, Dim2>::new(b, s).expect("solver");
        (sv.fuse_contact, sv.fuse_prepare) = (fuse, fuse);
        let mut touched = 0;
        for _ in 0..12 {
            sv.advance(b, s.dt, GRAPH_STEPS).expect("steps");
            touched = touched.max(sv.contact_sample(b).expect("sample").expect("a tool").contacts);
        }
        let (t, e, _) = sv.download_internal(b).expect("internal");
        let (t, e) = (t.expect("temperature"), e.expect("plastic strain"));
        let yielded = e.iter().filter(|x| **x > 0.0).count();
        let f = sv.contact_sample(b).expect("sample").expect("a tool");
        let mut bits: Vec<u64> = t.iter().chain(&e).map(|x| x.to_bits()).collect();
        bits.extend([f.force[0].to_bits(), f.force[1].to_bits(), f.contacts as u64, f.wear_rate.to_bits()]);
        (sv.download(b).expect("state"), bits, touched, yielded)
    }
    let (a, ba, _, _) = run(&CpuBackend::new(), &s, true);
    let (f, bf, touched, yielded) = run(&g, &s, true);
    let (u, bu, _, _) = run(&g, &s, false);
    assert!(touched > 0 && yielded > 0, "contact ({touched}) and yielding ({yielded}) not both exercised");
    assert!(f.bitwise_eq(&u) && bf == bu, "the fused passes differ from the separate passes on the GPU");
    assert!(a.bitwise_eq(&f) && ba == bf, "the fused passes on the GPU differ from the CPU");
    eprintln!(
        "{} steps, up to {touched} particles in contact, {yielded} yielded: fused pre-pass and contact bitwise \
         equal to the separate passes and the CPU",
        12 * GRAPH_STEPS
    );
}

/// Issue 7 on the GPU: the mixed precision (f32 state, the positions' low parts in the corrector's compensated sum)
/// ends bit for bit where the CPU ends, low parts included: the translating block (the elastic corrector entry;
/// 1600 particles, rebuilds and reorders under way) and the plastic block dropped on the tool (the plastic corrector
/// with the fused contact), in graph batches. tests/mixed_precision.rs checks the positions against the exact ones.
#[test]
fn mixed_precision_equals_cpu() {
    let Some(g) = gpu() else { return };
    use swarf::kernels::Dim2;
    use swarf::run::setup;
    use swarf::scene::{Precision, Scene};
    use swarf::solver::{GRAPH_STEPS, Solver};
    fn run<B: Backend>(b: &B, s: &swarf::solver::Setup<f32, Dim2>) -> (HostParticles<f32, Dim2>, Vec<u64>, u32) {
        let mut sv = Solver::<B, f32, Dim2>::new(b, s).expect("solver");
        assert_eq!(sv.precision(), "mixed");
        sv.advance(b, s.dt, 2 + 12 * GRAPH_STEPS).expect("steps");
        let lo = sv.download_pos_lo(b).expect("low parts").expect("mixed");
        let mut bits: Vec<u64> = bytemuck::cast_slice::<_, u32>(&lo).iter().map(|&x| x as u64).collect();
        let (t, e, _) = sv.download_internal(b).expect("internal");
        bits.extend(t.iter().chain(&e).flatten().map(|x| x.to_bits()));
        (sv.download(b).expect("state"), bits, sv.cell_rebuilds(b).expect("rebuilds"))
    }
    let block = Scene::load("cases/block-translation.toml", &[]).expect("block");
    let drop = Scene::from_str(&common::scenes::plastic_drop_scene(), "cases/cutting/drop.toml", &[]).expect("drop");
    for (name, scene) in [("translating block", block), ("plastic drop", drop)] {
        let scene = scene.with_precision(Some(Precision::Mixed));
        let s = setup::<f32, Dim2>(&scene).expect("setup");
        let (a, ba, ra) = run(&CpuBackend::new(), &s);
        let (f, bf, rf) = run(&g, &s);
        assert!(ba.iter().any(|&x| x != 0), "{name}: the low parts are all zero");
        assert!(a.bitwise_eq(&f) && ba == bf && ra == rf, "{name}: the mixed GPU run differs from the CPU");
        eprintln!(
            "{name}: {} mixed steps, {ra} rebuilds, bitwise equal to the CPU (low parts included)",
            2 + 12 * GRAPH_STEPS
        );
    }
}

/// Ensemble members on the GPU (host/ensemble: a stream each, sharing the loaded kernels) equal their solo GPU runs
/// and their CPU runs bit for bit: forces and energies at every sample of 7 coarse cuts that differ in material,
/// friction, tool geometry, speed, feed and resolution (tests/ensemble.rs does the same on the CPU alone).
#[test]
fn ensemble_members_equal_solo_runs_and_cpu() {
    use common::scenes::{ensemble_jobs, ensemble_members, run_record};
    use swarf::backend::AnyBackend;
    let Some(g) = gpu() else { return };
    let gpu_any = AnyBackend::Cuda(Box::new(g));
    let cpu_any = AnyBackend::Cpu(CpuBackend::new());
    let root = std::env::temp_dir().join(format!("swarf-gpu-ensemble-{}", std::process::id()));
    let run = |b: &AnyBackend, tag: &str, width: usize| {
        let jobs = ensemble_jobs(ensemble_members(), &root.join(tag));
        swarf::ensemble::run(b, &jobs, width, &mut |k, r| {
            assert!(r.is_ok(), "{tag} member {k}: {:?}", r.as_ref().err());
            Ok(())
        })
        .expect(tag);
        jobs.iter().map(|j| run_record(&j.options.out_dir)).collect::<Vec<_>>()
    };
    let batch = run(&gpu_any, "batch", 7);
    let solo = run(&gpu_any, "solo", 1);
    let cpu = run(&cpu_any, "cpu", 1);
    for k in 0..batch.len() {
        assert!(batch[k] == solo[k], "member {k}: the batch differs from its solo GPU run");
        assert!(batch[k] == cpu[k], "member {k}: the GPU batch differs from the CPU run");
    }
    let _ = std::fs::remove_dir_all(root);
}

/// An MPM checkpoint on the GPU (host/mpm/checkpoint.rs): a short cut with the start-up damping stepped 1 000
/// steps in captured batches, saved, restored into a new GPU solver (whose first step runs plainly, loading the
/// kernels) and stepped 1 000 more, equals the GPU's and the CPU's 2 000 steps at once, every stateful buffer bit
/// for bit.
#[test]
fn mpm_checkpoint_resumes_bitwise_on_gpu() {
    use swarf::mpm::solver::{MpmSolver, Tallies};
    let Some(g) = gpu() else { return };
    let sets: Vec<String> =
        ["cut.particles_across=7", "cut.cut_length=2.0", "time.end=1.3e-3"].iter().map(|s| s.to_string()).collect();
    let scene = swarf::scene::mpm::MpmScene::load("cases/mpm/nairn-cut.toml", &sets).expect("scene");
    let s = swarf::mpm::setup::setup(&scene).expect("setup");
    let dir = std::env::temp_dir().join(format!("swarf-gpu-mpm-ck-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("folder");
    let mut first = MpmSolver::<CudaBackend, f64>::new(&g, &s, 1.0).expect("solver");
    first.advance(&g, 1000).expect("advance");
    let last = (first.time, Tallies::default());
    swarf::mpm::checkpoint::save(&g, &first, &dir, &sets, 1, &last).expect("save");
    let mut resumed = MpmSolver::<CudaBackend, f64>::new(&g, &s, 1.0).expect("solver");
    swarf::mpm::checkpoint::restore(&g, &mut resumed, &dir).expect("restore");
    resumed.advance(&g, 1000).expect("advance");
    let mut whole = MpmSolver::<CudaBackend, f64>::new(&g, &s, 1.0).expect("solver");
    whole.advance(&g, 2000).expect("advance");
    let c = CpuBackend::new();
    let mut cpu = MpmSolver::<CpuBackend, f64>::new(&c, &s, 1.0).expect("solver");
    cpu.advance(&c, 2000).expect("advance");
    let state = resumed.save_state(&g).expect("state");
    assert!(state == whole.save_state(&g).expect("state"), "the resumed GPU run differs from the whole GPU run");
    assert!(state == cpu.save_state(&c).expect("state"), "the resumed GPU run differs from the CPU run");
    eprintln!("MPM checkpoint at step 1000, resumed on the GPU to 2000: bitwise equal to the GPU and CPU runs");
    let _ = std::fs::remove_dir_all(dir);
}

/// An MPM sweep on the GPU (issue 26: the h × α × μ generator; host/ensemble, a stream each) gives each point's
/// forces.csv byte for byte as its solo GPU run and its CPU run: three short coarse cuts at rakes 15°, 20° and 30°
/// (the sweep's table holds their steady forces), run 3 at once, one at a time, and on the CPU.
#[test]
fn mpm_sweep_batch_equals_solo_runs_and_cpu() {
    use common::scenes::mpm_sweep;
    use swarf::backend::AnyBackend;
    let Some(g) = gpu() else { return };
    let gpu_any = AnyBackend::Cuda(Box::new(g));
    let cpu_any = AnyBackend::Cpu(CpuBackend::new());
    let root = std::env::temp_dir().join(format!("swarf-gpu-mpm-sweep-{}", std::process::id()));
    let sets = ["cut.particles_across=7", "cut.cut_length=2.0", "time.end=1.3e-3"];
    let grids = ["cut.rake=15,20,30"];
    let file = "cases/mpm/nairn-cut.toml";
    let (sweep, batch) = mpm_sweep(&gpu_any, file, &sets, &grids, 3, &root.join("batch"));
    let (_, solo) = mpm_sweep(&gpu_any, file, &sets, &grids, 1, &root.join("solo"));
    let (_, cpu) = mpm_sweep(&cpu_any, file, &sets, &grids, 1, &root.join("cpu"));
    for k in 0..batch.len() {
        assert_eq!(batch[k], solo[k], "point {k}: the batch differs from its solo GPU run");
        assert_eq!(batch[k], cpu[k], "point {k}: the GPU batch differs from the CPU run");
    }
    assert!(batch[0] != batch[2], "the rakes ran the same");
    let fc = sweep.columns.iter().position(|c| c.name == "fc_n_per_m").expect("F_c column");
    for p in &sweep.points {
        let swarf::sweep::Outcome::Done(v) = &p.outcome else { panic!("{:?}: {:?}", p.values, p.outcome) };
        assert!(v[fc].is_some_and(|f| f > 0.0), "{:?}: steady F_c {:?}", p.values, v[fc]);
        eprintln!("rake {}: steady F_c {:?} N/m, bitwise equal in the batch, alone and on the CPU", p.values[0], v[fc]);
    }
    let _ = std::fs::remove_dir_all(root);
}

/// `scene` run on the CPU and then on the GPU into `dir`/`tag`-0 and -1: each run's final state and forces.csv text.
fn cpu_and_gpu_runs(scene: &swarf::scene::Scene, dir: &std::path::Path, tag: &str) -> Vec<(Vec<u64>, String)> {
    use swarf::backend::{AnyBackend, BackendChoice};
    [BackendChoice::Cpu, BackendChoice::Gpu]
        .into_iter()
        .enumerate()
        .map(|(k, choice)| {
            let any = AnyBackend::select(choice).expect("backend").0;
            let out = dir.join(format!("{tag}-{k}"));
            let (last, _) = final_state(&any, scene, &swarf::run::RunOptions::quiet(out.clone()));
            (last, std::fs::read_to_string(out.join("forces.csv")).expect("forces.csv"))
        })
        .collect()
}

/// Issue 24 on the GPU: the contact pass in 3D, with the parametric tool's prism (`swarf_contact_3d_*`) and with the
/// same prism as a triangle mesh (`swarf_contact_mesh_3d_*`, its grid's arrays in device memory), gives the CPU's
/// run bit for bit: tests/tool_3d.rs's block dropped at 10 m/s (sliding at 2 m/s) onto the tool's top face, in f64
/// and f32 (final positions and velocities, and forces.csv's text: forces and moments).
#[test]
fn tool_3d_runs_equal_cpu() {
    let Some(_) = gpu() else { return };
    use swarf::scene::Scene;
    let dir = std::env::temp_dir().join(format!("swarf-gpu-tool3d-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("folder");
    let obj = dir.join("prism.obj");
    std::fs::write(&obj, common::scenes::prism_obj(-1e-3, 1e-3)).expect("mesh");
    let mesh = format!(
        "mesh = {{ file = {:?} }}\nposition = [0.0, 0.0, 0.0]\nvelocity = [0.0, 0.0, 0.0]",
        obj.display().to_string()
    );
    for (tool, what) in [(common::scenes::PRISM_TOOL.to_string(), "prism"), (mesh, "mesh")] {
        for precision in ["f64", "f32"] {
            let text = common::scenes::drop_scene_3d(10.0, 2.0, &tool)
                .replace("dim = 3", &format!("dim = 3\nprecision = \"{precision}\""));
            let scene = Scene::from_str(&text, "drop3d.toml", &[]).expect("scene");
            let runs = cpu_and_gpu_runs(&scene, &dir, &format!("{what}-{precision}"));
            let contacts = runs[0].1.lines().skip(1).filter(|l| l.split(',').nth(4).is_some_and(|c| c != "0")).count();
            eprintln!(
                "3D {what} tool, {precision}: {contacts} force samples in contact; final state bitwise equal: {}, \
                 forces.csv equal: {}",
                runs[0].0 == runs[1].0,
                runs[0].1 == runs[1].1
            );
            assert!(contacts > 0, "{what}: the block must land on the tool");
            assert!(runs[0].1 == runs[1].1, "{what} {precision}: GPU forces.csv differs from the CPU's");
            assert!(runs[0].0 == runs[1].0, "{what} {precision}: GPU final state differs from the CPU's");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 24 on the GPU: several tools (`[[tool]]`, one contact launch looping over the tools, the owner field)
/// give the CPU's run bit for bit: tests/several_tools.rs's twin cuts (2D, two parametric tools, the standalone
/// contact pass, not the fused one) and the block dropped across two mesh tools with different contact laws (3D),
/// in f64 and f32 (final positions and velocities, and forces.csv's text with every tool's columns).
#[test]
fn several_tools_equal_cpu() {
    let Some(_) = gpu() else { return };
    use swarf::scene::Scene;
    let dir = std::env::temp_dir().join(format!("swarf-gpu-tools-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("folder");
    let pair = [common::scenes::prism_mesh_tool(&dir, -2.4e-4, ""), common::scenes::prism_mesh_tool(&dir, 1.6e-4, "")];
    let scenes = [
        (common::scenes::twin_cut_scene(true), "twin cuts"),
        (common::scenes::drop_scene_3d_tools(10.0, 2.0, &pair), "mesh pair"),
    ];
    for (text, what) in scenes {
        for precision in ["f64", "f32"] {
            let text = text.replacen("dim = ", &format!("precision = \"{precision}\"\ndim = "), 1);
            let scene = Scene::from_str(&text, "tools.toml", &[]).expect("scene");
            let runs = cpu_and_gpu_runs(&scene, &dir, &format!("{}-{precision}", what.replace(' ', "-")));
            let second =
                runs[0].1.lines().skip(1).filter(|l| l.split(',').next_back().is_some_and(|c| c != "0")).count();
            eprintln!(
                "several tools, {what}, {precision}: {second} samples with the second tool in contact; final state \
                 bitwise equal: {}, forces.csv equal: {}",
                runs[0].0 == runs[1].0,
                runs[0].1 == runs[1].1
            );
            assert!(second > 0, "{what}: the second tool must touch");
            assert!(runs[0].1 == runs[1].1, "{what} {precision}: GPU forces.csv differs from the CPU's");
            assert!(runs[0].0 == runs[1].0, "{what} {precision}: GPU final state differs from the CPU's");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// V0060 extruded by 8 layers on a periodic z domain (cases/3d/orthogonal-v0060.toml at Δx = 20 µm, 6 120
/// particles), `end` seconds of cut, five frames, with `extra` overrides.
fn periodic_cut(end: f64, extra: &[String]) -> swarf::scene::Scene {
    let ov: Vec<String> = [
        "discretisation.dx=2.0e-5",
        "discretisation.period_z=1.6e-4",
        "body.0.max=[1.0e-3,2.8e-4,1.4e-4]",
        "boundary.2.max=[1.0e-9,1.4e-4,1.0]",
        "boundary.3.min=[0.9999e-3,-1.0,-1.0]",
        "tool.position=[-3.6e-5]",
        "tool.depth_of_cut=0.9e-4",
    ]
    .iter()
    .map(|s| s.to_string())
    .chain([format!("time.end={end:e}"), format!("output.every={:e}", end / 5.0)])
    .chain(extra.iter().cloned())
    .collect();
    swarf::scene::Scene::load("cases/3d/orthogonal-v0060.toml", &ov).expect("scene")
}

/// Issue 24 on the GPU: the periodic z domain (the wrapped stencil rows and nearest-image pairs in every neighbour
/// pass) with the plane-strain condition gives the CPU's run bit for bit: V0060 extruded by 8 layers
/// (cases/3d/orthogonal-v0060.toml at Δx = 20 µm, 6 120 particles), 1 µs of cut, f64 and f32; and f64 again with the
/// Verlet list's wide offsets (`discretisation.verlet_offsets = 32`, docs/neighbour-search.md "Wide offsets"),
/// whose run is also the packed f64 run's bit for bit.
#[test]
fn periodic_plane_strain_cut_equals_cpu() {
    let Some(_) = gpu() else { return };
    use swarf::backend::{AnyBackend, BackendChoice};
    use swarf::run::RunOptions;
    let mut packed_f64 = None;
    for (precision, bits) in [("f64", 16), ("f32", 16), ("f64", 32)] {
        let scene = periodic_cut(
            1.0e-6,
            &[format!("precision=\"{precision}\""), format!("discretisation.verlet_offsets={bits}")],
        );
        let mut runs = Vec::new();
        for (k, choice) in [BackendChoice::Cpu, BackendChoice::Gpu].into_iter().enumerate() {
            let any = AnyBackend::select(choice).expect("backend").0;
            let dir =
                std::env::temp_dir().join(format!("swarf-gpu-periodic-{precision}-{bits}-{k}-{}", std::process::id()));
            let (last, _) = final_state(&any, &scene, &RunOptions::quiet(dir.clone()));
            runs.push((last, std::fs::read_to_string(dir.join("forces.csv")).expect("forces.csv")));
        }
        let fc = runs[0].1.lines().last().and_then(|l| l.split(',').nth(2).map(str::to_string)).unwrap_or_default();
        eprintln!(
            "periodic extruded cut, {precision}, {bits}-bit offsets: last F_c {fc} N/mm; final state bitwise equal: {}, \
             forces.csv equal: {}",
            runs[0].0 == runs[1].0,
            runs[0].1 == runs[1].1
        );
        assert!(runs[0].1 == runs[1].1, "{precision}, {bits} bits: GPU forces.csv differs from the CPU's");
        assert!(runs[0].0 == runs[1].0, "{precision}, {bits} bits: GPU final state differs from the CPU's");
        match (precision, bits) {
            ("f64", 16) => packed_f64 = Some(runs.swap_remove(1)),
            ("f64", 32) => {
                let p = packed_f64.as_ref().expect("the packed f64 run came first");
                assert!(runs[1] == *p, "f64: the wide offsets' GPU run differs from the packed one's");
            }
            _ => {}
        }
    }
}

/// Issue 24 on the GPU: the CSPM kernel-gradient correction (`swarf_sph_correction_*` and the `_cspm` pair
/// entries) gives the CPU's run bit for bit: the spinning rubber disk (cases/disk-rotation.toml, 2D, AV, 0.01 s),
/// f64 and f32; the extruded V0060 cut on a periodic z domain (3D, plasticity, contact, nearest-image pairs in the
/// correction's own walk, 0.5 µs), f64 and f32; and the block dropped on a triangle-mesh tool (3D), f64.
#[test]
fn cspm_runs_equal_cpu() {
    let Some(_) = gpu() else { return };
    use swarf::backend::{AnyBackend, BackendChoice};
    use swarf::scene::Scene;
    let dir = std::env::temp_dir().join(format!("swarf-gpu-cspm-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("folder");
    let cspm = "stabilisation.cspm={}".to_string();
    for precision in ["f64", "f32"] {
        let ov = [cspm.clone(), "time.cfl=0.4".into(), "time.end=0.01".into(), format!("precision=\"{precision}\"")];
        let scene = Scene::load("cases/disk-rotation.toml", &ov).expect("scene");
        let runs: Vec<_> = [BackendChoice::Cpu, BackendChoice::Gpu]
            .into_iter()
            .enumerate()
            .map(|(k, c)| {
                let any = AnyBackend::select(c).expect("backend").0;
                final_state(&any, &scene, &swarf::run::RunOptions::quiet(dir.join(format!("disk-{precision}-{k}")))).0
            })
            .collect();
        eprintln!("CSPM disk, {precision}: final state bitwise equal: {}", runs[0] == runs[1]);
        assert!(runs[0] == runs[1], "disk {precision}: GPU final state differs from the CPU's");
        let scene = periodic_cut(5.0e-7, &[cspm.clone(), format!("precision=\"{precision}\"")]);
        let runs = cpu_and_gpu_runs(&scene, &dir, &format!("cut-{precision}"));
        eprintln!(
            "CSPM periodic extruded cut, {precision}: final state bitwise equal: {}, forces.csv equal: {}",
            runs[0].0 == runs[1].0,
            runs[0].1 == runs[1].1
        );
        assert!(runs[0].1 == runs[1].1, "cut {precision}: GPU forces.csv differs from the CPU's");
        assert!(runs[0].0 == runs[1].0, "cut {precision}: GPU final state differs from the CPU's");
    }
    let tool = common::scenes::prism_mesh_tool(&dir, -2.4e-4, "");
    let text = common::scenes::drop_scene_3d_tools(10.0, 2.0, &[tool]).replacen(
        "[time]",
        "[stabilisation.cspm]\n\n[time]\ncfl = 0.3",
        1,
    );
    let scene = Scene::from_str(&text, "drop-cspm.toml", &[]).expect("scene");
    assert!(scene.stabilisation.cspm.is_some(), "the drop scene takes the CSPM table");
    let runs = cpu_and_gpu_runs(&scene, &dir, "drop");
    eprintln!(
        "CSPM mesh drop: final state bitwise equal: {}, forces.csv equal: {}",
        runs[0].0 == runs[1].0,
        runs[0].1 == runs[1].1
    );
    assert!(runs[0].1 == runs[1].1 && runs[0].0 == runs[1].0, "mesh drop: GPU run differs from the CPU's");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 24 on the GPU: blanking (the active count read by every per-particle pass on the device, the blanked
/// cells' keys, the box's jumps forcing rebuilds inside captured batches) gives the CPU's run bit for bit: the
/// coarse V0060 cut (2D, fused passes) and the periodic extruded cut (3D, the standalone contact pass and the
/// Verlet list), each with a box whose front starts 0.3 mm ahead and moves with the tool, and the 2D cut with the
/// box's top 5 µm above the surface, through which material leaves in motion (the rest speed reads the
/// velocities); f64 and f32 (final state and forces.csv).
#[test]
fn blanked_cut_equals_cpu() {
    let Some(_) = gpu() else { return };
    let dir = std::env::temp_dir().join(format!("swarf-gpu-blanked-{}", std::process::id()));
    for precision in ["f64", "f32"] {
        let p = format!("precision=\"{precision}\"");
        let cut2 = common::scenes::coarse_cut(&[&p, "blanking.min=[-0.2e-3,-1.0e-3]", "blanking.max=[0.3e-3,1.0e-3]"]);
        let box3 = ["blanking.min=[-0.2e-3,-1.0e-3,-1.0e-3]", "blanking.max=[0.3e-3,1.0e-3,1.0e-3]"];
        let cut3 = periodic_cut(1.0e-6, &[p.clone(), box3[0].into(), box3[1].into()]);
        // The box's top 5 µm above the surface: material leaves it in motion and stays active (the rest speed).
        let top = ["blanking.min=[-0.2e-3,-1.0e-3]", "blanking.max=[0.6e-3,0.285e-3]", "time.end=8.0e-6"];
        let cut_top = common::scenes::coarse_cut(&[&p, top[0], top[1], top[2]]);
        for (scene, what) in [(cut2, "2D"), (cut3, "3D periodic"), (cut_top, "2D top-out")] {
            let runs = cpu_and_gpu_runs(&scene, &dir, &format!("{what}-{precision}").replace(' ', "-"));
            let fc = runs[0].1.lines().last().and_then(|l| l.split(',').nth(2).map(str::to_string)).unwrap_or_default();
            eprintln!(
                "blanked {what} cut, {precision}: last F_c {fc}; final state bitwise equal: {}, forces.csv equal: {}",
                runs[0].0 == runs[1].0,
                runs[0].1 == runs[1].1
            );
            assert!(runs[0].1 == runs[1].1, "{what} {precision}: GPU forces.csv differs from the CPU's");
            assert!(runs[0].0 == runs[1].0, "{what} {precision}: GPU final state differs from the CPU's");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The MPM solver (issue 26; docs/mpm.md) on the GPU equals its CPU twin bit for bit, in f64 and f32: a bonded
/// block pulled in mode I through the failure of its plane (V15), and a coarse cut whose crack runs ahead of the
/// tool, with the start-up damping. Every particle's state, every crack point's history and the tool's and grip's
/// tallies are compared; the GPU replays captured batches of steps (CUDA graphs), the CPU runs the same launches
/// directly.
#[test]
fn mpm_runs_equal_cpu() {
    let Some(g) = gpu() else { return };
    fn run<B: Backend, R: Real>(
        b: &B,
        s: &swarf::mpm::setup::MpmSetup,
        steps: u64,
    ) -> (swarf::mpm::output::Snapshot, Vec<[f64; 4]>, swarf::mpm::solver::Tallies) {
        let mut m = swarf::mpm::solver::MpmSolver::<B, R>::new(b, s, 1.0).expect("solver");
        // Captured batches (on the GPU) from the start, with an odd remainder.
        m.advance(b, steps).expect("advance");
        assert_eq!(m.take_flags(b).expect("flags"), (false, false));
        (m.snapshot(b).expect("snapshot"), m.crack_state(b).expect("crack"), m.tallies(b).expect("tallies"))
    }
    fn bits(v: &[f64]) -> Vec<u64> {
        v.iter().map(|x| x.to_bits()).collect()
    }
    fn compare<R: Real>(g: &CudaBackend, file: &str, sets: &[&str], what: &str) {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let scene = swarf::scene::mpm::MpmScene::load(file, &sets).expect("scene");
        let s = swarf::mpm::setup::setup(&scene).expect("setup");
        let c = CpuBackend::new();
        let (a, ca, ta) = run::<_, R>(&c, &s, s.steps);
        let (b, cb, tb) = run::<_, R>(g, &s, s.steps);
        let flat = |v: &[[f64; 2]]| bits(&v.iter().flatten().copied().collect::<Vec<_>>());
        let flat4 = |v: &[[f64; 4]]| bits(&v.iter().flatten().copied().collect::<Vec<_>>());
        assert_eq!(flat(&a.pos), flat(&b.pos), "{what}: positions differ");
        assert_eq!(flat(&a.vel), flat(&b.vel), "{what}: velocities differ");
        assert_eq!(flat4(&a.stress), flat4(&b.stress), "{what}: stresses differ");
        assert_eq!(flat4(&a.be), flat4(&b.be), "{what}: B_e differ");
        assert_eq!(bits(&a.jac), bits(&b.jac), "{what}: J differ");
        assert_eq!(flat4(&a.def), flat4(&b.def), "{what}: deformation gradients differ");
        assert_eq!(bits(&a.eps), bits(&b.eps), "{what}: plastic strains differ");
        assert_eq!(flat4(&ca), flat4(&cb), "{what}: crack points differ");
        assert_eq!(ta, tb, "{what}: tallies differ");
        let failed = ca.iter().filter(|c| c[2] != 0.0).count();
        assert!(failed > 0, "{what}: no crack point failed: the comparison misses the crack");
        eprintln!("{what}: {} particles, {} steps, {failed} crack points failed: bitwise equal", a.pos.len(), s.steps);
    }
    // With the start-up damping, so that its tile sums and update are compared too.
    let cut = ["cut.particles_across=7", "cut.cut_length=2.0", "time.end=1.3e-3", "damping.feedback=1000"];
    compare::<f64>(&g, "cases/mpm/bond-mode1.toml", &[], "bond f64");
    compare::<f32>(&g, "cases/mpm/bond-mode1.toml", &[], "bond f32");
    compare::<f64>(&g, "cases/mpm/nairn-cut.toml", &cut, "cut f64");
    compare::<f32>(&g, "cases/mpm/nairn-cut.toml", &cut, "cut f32");
    // The triangular law and the position updates of Fig. 2 (V14).
    compare::<f64>(&g, "cases/mpm/bond-mode1.toml", &["cohesive.law=\"triangular\""], "bond triangular f64");
    for order in ["first", "zeroth"] {
        let set = format!("damping.position_update=\"{order}\"");
        let sets: Vec<&str> = cut.iter().copied().chain([set.as_str(), "cohesive.law=\"triangular\""]).collect();
        compare::<f64>(&g, "cases/mpm/nairn-cut.toml", &sets, &format!("cut {order}-order update, triangular f64"));
    }
    // A fragment (a stressed particle alone on its nodes) and its controls: the unloading branch of the update.
    let (s, f) = common::mpm_fragment::fragment_setup();
    let c = CpuBackend::new();
    let mut on_cpu = common::mpm_fragment::fragment_solver::<_, f64>(&c, &s, &f);
    let mut on_gpu = common::mpm_fragment::fragment_solver::<_, f64>(&g, &s, &f);
    on_cpu.advance(&c, 120).expect("advance");
    on_gpu.advance(&g, 120).expect("advance");
    let (a, b) = (on_cpu.save_state(&c).expect("state"), on_gpu.save_state(&g).expect("state"));
    assert!(a == b, "fragment f64: the state differs");
    let snap = on_gpu.snapshot(&g).expect("snapshot");
    assert_eq!(snap.stress[f.lone], [0.0; 4], "fragment f64: the fragment keeps a stress on the GPU");
    eprintln!("fragment f64: {} particles, 120 steps: bitwise equal, the fragment unloaded", snap.pos.len());
}

/// The artificial viscosity's Balsara switch on the GPU (`stabilisation.artificial_viscosity.switch = "balsara"`:
/// the factor written by the interaction entries, read by the predictor's fused pre-pass and the gated pre-pass
/// after a rebuild, reordered with the particles) gives the CPU's run bit for bit: the copper Taylor bar on the
/// rigid mesh wall (cases/3d/taylor-bar-wall.toml at Δx = 0.8 mm, 1 845 particles, 30 µs: 298 steps, through the
/// impact), f64 and f32: the final state, forces.csv, energy.csv and the last frame (which holds the factor,
/// `av_switch`) are equal.
#[test]
fn balsara_switch_equals_cpu() {
    let Some(_) = gpu() else { return };
    use swarf::backend::{AnyBackend, BackendChoice};
    use swarf::scene::Scene;
    let dir = std::env::temp_dir().join(format!("swarf-gpu-balsara-{}", std::process::id()));
    for precision in ["f64", "f32"] {
        let ov: Vec<String> = [
            "discretisation.dx=0.8e-3",
            "time.end=3.0e-5",
            "output.every=3.0e-5",
            "stabilisation.artificial_viscosity.switch=\"balsara\"",
        ]
        .iter()
        .map(|s| s.to_string())
        .chain([format!("precision=\"{precision}\"")])
        .collect();
        let scene = Scene::load("cases/3d/taylor-bar-wall.toml", &ov).expect("scene");
        let runs: Vec<(Vec<u64>, Vec<Vec<u8>>)> = [BackendChoice::Cpu, BackendChoice::Gpu]
            .into_iter()
            .enumerate()
            .map(|(k, choice)| {
                let any = AnyBackend::select(choice).expect("backend").0;
                let out = dir.join(format!("bar-{precision}-{k}"));
                let opts = swarf::run::RunOptions { frames: true, ..swarf::run::RunOptions::quiet(out.clone()) };
                let (last, yielded) = final_state(&any, &scene, &opts);
                assert!(yielded > 0, "{precision}: the bar yields within 30 µs");
                let bytes = |f: &str| std::fs::read(out.join(f)).unwrap_or_else(|e| panic!("{f}: {e}"));
                (last, ["forces.csv", "energy.csv", "frame_00001.vtu"].map(bytes).to_vec())
            })
            .collect();
        let same: Vec<bool> = (0..3).map(|k| runs[0].1[k] == runs[1].1[k]).collect();
        eprintln!(
            "Balsara Taylor bar, {precision}: final state bitwise equal: {}, forces.csv {}, energy.csv {}, last frame {}",
            runs[0].0 == runs[1].0,
            same[0],
            same[1],
            same[2]
        );
        let frame = &runs[0].1[2];
        assert!(frame.windows(9).any(|w| w == b"av_switch"), "{precision}: the frame holds the switch's factor");
        assert!(runs[0].0 == runs[1].0, "{precision}: GPU final state differs from the CPU's");
        assert!(same.iter().all(|&s| s), "{precision}: GPU forces.csv, energy.csv or frame differs from the CPU's");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
