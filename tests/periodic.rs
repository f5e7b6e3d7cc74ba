//! Issue 24's extruded 2D models: a domain periodic in z (`discretisation.period_z`) and the plane-strain condition
//! (`kind = "plane_strain"`), docs/3d.md. The periodic neighbour search against a brute force over nearest images,
//! and V0060 extruded in z against the 2D run.

use crate::common;

use common::*;
use rayon::prelude::*;
use swarf::backend::CpuBackend;
use swarf::kernels::{Dim3, Real, Vector};
use swarf::scene::Scene;

/// The neighbours of every particle within the support in the nearest-image metric of a z period P: |Δz| reduced
/// to P/2 at most (brute force, O(N²)).
fn brute_force_periodic(pos: &[swarf::kernels::vector::V3f64], support2: f64, period: f64) -> Vec<Vec<u32>> {
    let d2 = |a: &swarf::kernels::vector::V3f64, b: &swarf::kernels::vector::V3f64| {
        let dz = a.get(2) - b.get(2);
        let dz = dz - period * (dz / period + 0.5).floor();
        (a.get(0) - b.get(0)).powi(2) + (a.get(1) - b.get(1)).powi(2) + dz * dz
    };
    (0..pos.len())
        .into_par_iter()
        .map(|i| (0..pos.len()).filter(|&j| j != i && d2(&pos[i], &pos[j]) < support2).map(|j| j as u32).collect())
        .collect()
}

/// The cell list of a grid periodic in z (z cells tiling the period, the stencil's rows wrapping) finds exactly the
/// pairs within 2h of the nearest-image metric, for 20 000 uniform points in [0, 1]² × [0, P) with P = 6 cells and
/// with P = the fewest cells allowed (5), with the Verlet list's and the CSR list's searches alike; pairs across
/// the period (|z_i − z_j| > P/2) are among them.
#[test]
fn periodic_search_matches_nearest_image_brute_force() {
    let b = CpuBackend::new();
    let n = 20_000;
    let h = 0.012;
    let support = 2.0 * h;
    for cells in [6.0, 5.0] {
        let probe = swarf::grid::grid_with_skin([0.0; 3], [1.0; 3], 3, support, 0.1 * h).expect("grid");
        let period = cells * probe.cell_size * 1.0001;
        let mut pos = uniform::<f64, Dim3>(n, 11);
        for p in pos.iter_mut() {
            *p = swarf::kernels::vector::V3f64([p.get(0), p.get(1), p.get(2) * period * 0.999_999, 0.0]);
        }
        let grid = swarf::grid::periodic_z(&probe, [1.0; 3], period).expect("periodic grid");
        assert_eq!(grid.dims[2], cells as u32, "the z cells tile the period");
        let reference = brute_force_periodic(&pos, support * support, period);
        let across = (0..n)
            .flat_map(|i| reference[i].iter().map(move |&j| (i, j as usize)))
            .filter(|&(i, j)| (pos[i].get(2) - pos[j].get(2)).abs() > 0.5 * period)
            .count();
        let s = search::<_, f64, Dim3>(&b, &pos, grid, f64::from_f64(support * support));
        assert_same_pairs(&s.lists, &reference, &format!("periodic z, {cells} cells"));
        eprintln!("periodic search, {cells} z cells: {across} of the pairs are across the period");
        assert!(across > 1000, "pairs across the period must be tested ({across})");
    }
    let probe = swarf::grid::grid_with_skin([0.0; 3], [1.0; 3], 3, support, 0.1 * h).expect("grid");
    let e = swarf::grid::periodic_z(&probe, [1.0; 3], 4.9 * probe.cell_size).expect_err("too short a period");
    assert!(e.to_string().contains("at least 5 cells"), "{e}");
}

/// The `--set` overrides of V0060 at Δx = 20 µm (as tests/cutting.rs's CI cut), 3 µs of cut, for the 2D scene or
/// its extrusion (cases/3d/orthogonal-v0060.toml: 8 layers, periodic in z, plane strain; boundary 0 is the plane
/// strain, so the fixed ones are one index up).
fn coarse(three_d: bool) -> Vec<String> {
    let (b, k) = if three_d { ("[1.0e-3,2.8e-4,1.4e-4]", 1) } else { ("[1.0e-3,2.8e-4]", 0) };
    let mut v = vec![
        "discretisation.dx=2.0e-5".to_string(),
        format!("body.0.max={b}"),
        format!("boundary.{}.max=[1.0e-9,1.4e-4{}]", k + 1, if three_d { ",1.0" } else { "" }),
        format!("boundary.{}.min=[0.9999e-3,-1.0{}]", k + 2, if three_d { ",-1.0" } else { "" }),
        "tool.position=[-3.6e-5]".into(),
        "tool.depth_of_cut=0.9e-4".into(),
        "time.end=3.0e-6".into(),
        "output.every=1.0e-6".into(),
    ];
    if three_d {
        v.push("discretisation.period_z=1.6e-4".into());
    }
    v
}

/// Means of F_c and F_f [N/mm] over forces.csv's samples in [2, 3] µs of a run of `file` with `over`; and the
/// largest |v_z| of any particle at any output.
fn cut(file: &str, over: &[String], tag: &str) -> ([f64; 2], f64) {
    let scene = Scene::load(file, over).expect("scene");
    let dir = std::env::temp_dir().join(format!("swarf-test-periodic-{tag}-{}", std::process::id()));
    let opts = swarf::run::RunOptions::quiet(dir.clone());
    let mut vz = 0.0f64;
    let mut obs = |s: &swarf::run::Snapshot| {
        vz = s.vel.iter().fold(vz, |m, v| m.max(v[2].abs()));
        true
    };
    swarf::run::run_observed(&test_backend(), &scene, &opts, Some(&mut obs)).expect("run");
    let (_, rows) = swarf::output::csv::read(&dir.join("forces.csv")).expect("forces.csv");
    let late: Vec<_> = rows.iter().filter(|r| r[0] >= 2.0e-6).collect();
    let mean = |k: usize| late.iter().map(|r| r[k]).sum::<f64>() / late.len() as f64;
    let _ = std::fs::remove_dir_all(&dir);
    ([mean(2), mean(3)], vz)
}

/// Issue 24: V0060 extruded by 8 layers in z, periodic in z and held in plane strain, is the 2D cut: F_c and F_f
/// per mm of width within 5 % of the 2D run's (the tolerance) over 2–3 µs of a coarse cut (Δx = 20 µm),
/// and no particle ever moves in z, the 3D scene's artificial stress at the 2D strength (the test below). Measured:
/// F_c +0.70 %, F_f +2.90 % (+0.7 %, +3.1 % at ε = 0.3). (With 4 free layers instead, F_c was 11 % and F_f 16 %
/// low: the z faces truncate the kernel.)
#[test]
fn extruded_cut_in_plane_strain_matches_2d() {
    let (f2, _) = cut("cases/cutting/v0060.toml", &coarse(false), "2d");
    let (f3, vz) = cut("cases/3d/orthogonal-v0060.toml", &coarse(true), "3d");
    let d = [f3[0] / f2[0] - 1.0, f3[1] / f2[1] - 1.0];
    eprintln!(
        "extruded V0060: 2D F_c {:.2} F_f {:.2}, 3D {:.2} {:.2} N/mm ({:+.2} %, {:+.2} %), max |v_z| {vz:e}",
        f2[0],
        f2[1],
        f3[0],
        f3[1],
        100.0 * d[0],
        100.0 * d[1]
    );
    assert!(f2[0] > 100.0 && f2[1] > 20.0, "the 2D tool must be cutting ({f2:?})");
    assert!(d[0].abs() <= 0.05 && d[1].abs() <= 0.05, "3D against 2D: F_c {:+.3}, F_f {:+.3}", d[0], d[1]);
    assert_eq!(vz, 0.0, "plane strain: v_z stays 0");
}

/// The artificial stress under extrusion (docs/3d.md, "The artificial stress under extrusion"): its pair term
/// f_ij^n (R_i + R_j)·∇W_ij with f_ij = W(r)/W(Δx) (kernels/src/sph/interact.rs), summed for a particle on the
/// surface of a lattice half-space under a uniform R, is in the 8-layer extrusion 0.509 of the 2D sum (f^4 all but
/// removes the neighbours of the other layers, whose mass the 2D kernel carries), so the extruded scene's ε is
/// V0060's over 0.509. Asserted: the factor (0.509 ± 0.002, from this lattice sum in Python and here) and the two
/// scenes' ε · sum equal within 0.1 % (the scene rounds ε to 3 digits).
#[test]
fn the_extruded_scene_carries_the_2d_artificial_stress_strength() {
    use swarf::kernels::sph::CubicSpline;
    let s2 = Scene::load("cases/cutting/v0060.toml", &[]).expect("2D scene");
    let s3 = Scene::load("cases/3d/orthogonal-v0060.toml", &[]).expect("3D scene");
    let (dx, h) = (s3.discretisation.dx, s3.discretisation.h_over_dx * s3.discretisation.dx);
    assert_eq!((dx, h), (s2.discretisation.dx, s2.discretisation.h_over_dx * s2.discretisation.dx));
    let layers = (s3.discretisation.period_z.expect("a period") / dx).round() as i32;
    let eps = |s: &Scene| {
        let a = s.stabilisation.artificial_stress.as_ref().expect("artificial stress");
        (a.epsilon, a.exponent)
    };
    let ((e2, n), (e3, n3)) = (eps(&s2), eps(&s3));
    assert_eq!(n, n3, "the exponent is the 2D model's");
    // Σ_j V_j f_ij^n ∂W/∂y over the half-space y_j ≥ y_i (V_j = Δx^dim, ρ and R uniform): the surface particle's
    // acceleration per unit R/ρ. In 3D the layers z = kΔx, nearest images of the period.
    let sum = |dim: usize| {
        let k = CubicSpline::<f64>::new(h, dim);
        let inv_w_dx = 1.0 / k.w(dx);
        let reach = (2.0 * h / dx).ceil() as i32;
        let zs: Vec<i32> = if dim == 3 { (-layers / 2..layers - layers / 2).collect() } else { vec![0] };
        let mut a = 0.0;
        for i in -reach..=reach {
            for j in 0..=reach {
                for &kz in &zs {
                    let d = [i as f64 * dx, j as f64 * dx, kz as f64 * dx];
                    let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                    if r > 0.0 {
                        let f = swarf::kernels::sph::interact::power(k.w(r) * inv_w_dx, n);
                        a += dx.powi(dim as i32) * f * k.dw_dr(r) * d[1] / r;
                    }
                }
            }
        }
        a
    };
    let (a2, a3) = (sum(2), sum(3));
    let factor = a3 / a2;
    eprintln!("artificial stress, extruded over 2D: {factor:.5}; eps 3D {e3} against {:.4}", e2 / factor);
    assert!((factor - 0.509).abs() < 0.002, "the extrusion factor {factor}");
    assert!((e3 * a3 / (e2 * a2) - 1.0).abs() < 1e-3, "eps {e3} does not give the 2D strength ({})", e2 / factor);
}

/// The Verlet list's wide (32-bit) offsets (docs/neighbour-search.md, "Wide offsets") list the same candidates in the
/// same order as the packed 16-bit ones, so a run is bitwise the same with either, with one lane per particle and
/// with eight: the coarse extruded cut (periodic in z, so its seam's pairs cross the period), 60 steps on the CPU
/// (tests/gpu.rs builds both layouts on a GPU).
#[test]
fn wide_verlet_offsets_give_the_packed_run_bit_for_bit() {
    use swarf::solver::Solver;
    let b = CpuBackend::new();
    for lanes in [1, 8] {
        let run = |bits: u32| {
            let mut o = coarse(true);
            o.push(format!("discretisation.verlet_offsets={bits}"));
            let scene = Scene::load("cases/3d/orthogonal-v0060.toml", &o).expect("scene");
            let s = swarf::run::setup::<f64, Dim3>(&scene).expect("setup");
            assert_eq!(s.grid.list_wide, u32::from(bits == 32), "verlet_offsets = {bits} did not reach the grid");
            let mut sv = Solver::<_, f64, Dim3>::new(&b, &s).expect("solver");
            sv.lanes = lanes;
            sv.advance(&b, s.dt, 60).expect("steps");
            sv.download(&b).expect("state")
        };
        let (packed, wide) = (run(16), run(32));
        assert!(wide.bitwise_eq(&packed), "{lanes} lane(s): the wide list's run differs from the packed one's");
    }
}

/// A 12 × 12 × 8 lattice (Δx = 1 mm, h = 1.5 Δx), elastic steel-like, periodic in z (P = 8 Δx), with
/// `plane_strain` over the whole body when `held`.
fn sheared_slab(held: bool) -> Scene {
    let hold =
        "\n[[boundary]]\nkind = \"plane_strain\"\nbody = \"slab\"\nmin = [-1.0, -1.0, -1.0]\nmax = [1.0, 1.0, 1.0]\n";
    let text = format!(
        "name = \"slab\"\ndim = 3\n\n[discretisation]\ndx = 1.0e-3\nh_over_dx = 1.5\nperiod_z = 8.0e-3\n\n[material]\n\
         density = 7850.0\nyoungs_modulus = 2.0e11\npoisson_ratio = 0.3\n\n[[body]]\nname = \"slab\"\nshape = \"box\"\n\
         lattice = \"nodes\"\nmin = [0.0, 0.0, 0.0]\nmax = [1.1e-2, 1.1e-2, 7.0e-3]\n{}\n[time]\nend = 1.0e-5\ncfl = 0.3\n",
        if held { hold } else { "" }
    );
    Scene::from_str(&text, "slab.toml", &[]).expect("scene")
}

/// The largest |S_xz| and |S_yz| over the slab's particles, and the largest |S_xy|, after 20 steps from the
/// velocity field v = (u sin(2π z/P), u sin(2π x/L), 0), u = 1 m/s: the layers shear across one another in x (the
/// way the layers of an extruded cut do once they part by rounding) while the body also shears in plane.
fn out_of_plane_shear(scene: &Scene) -> (f64, f64) {
    use swarf::kernels::{Dim, SymTensor};
    type V = <Dim3 as Dim>::Vec<f64>;
    let mut s = swarf::run::setup::<f64, Dim3>(scene).expect("setup");
    let (p, l) = (8.0e-3, 1.2e-2);
    let tau = 2.0 * std::f64::consts::PI;
    for (v, x) in s.particles.vel.iter_mut().zip(&s.particles.pos) {
        *v = V::new([(tau * x.get(2) / p).sin(), (tau * x.get(0) / l).sin(), 0.0]);
    }
    let b = CpuBackend::new();
    let mut sv = swarf::solver::Solver::<_, f64, Dim3>::new(&b, &s).expect("solver");
    for _ in 0..20 {
        sv.step(&b, s.dt).expect("step");
    }
    let st = sv.download(&b).expect("state");
    st.stress.iter().fold((0.0f64, 0.0f64), |(o, i), t| {
        let c = t.components(); // xx, xy, xz, yy, yz, zz
        (o.max(c[2].abs()).max(c[4].abs()), i.max(c[1].abs()))
    })
}

/// Plane strain's velocity gradient (kernels/src/sph/tensor.rs `TensorOps::plane_strain`; docs/3d.md): a particle
/// held in plane strain has ∂v/∂z = 0 and ∂v_z/∂x = ∂v_z/∂y = 0, so its S_xz and S_yz stay exactly 0, the 2D
/// solver's state, even where its layers move differently in x. Asserted: exactly 0 over the held slab, while the
/// in-plane shear stress is built (|S_xy| > 1 MPa); the same slab not held (the control) carries out-of-plane shear
/// of the same order (> 10 % of its |S_xy|), so the test sees the constraint. Without it the most stressed tenth of
/// the extruded V0060 carried 10–12 % of S:S out of plane after 0.3 mm of cut, once its layers had parted
/// (docs/3d.md).
#[test]
fn plane_strain_carries_no_out_of_plane_shear() {
    let (held_out, held_in) = out_of_plane_shear(&sheared_slab(true));
    let (free_out, free_in) = out_of_plane_shear(&sheared_slab(false));
    eprintln!("sheared slab: held |S_xz|,|S_yz| {held_out:e}, |S_xy| {held_in:e}; not held {free_out:e}, {free_in:e}");
    assert!(held_in > 1.0e6, "the in-plane shear must build ({held_in:e} Pa)");
    assert_eq!(held_out, 0.0, "out-of-plane shear stress in plane strain");
    assert!(free_out > 0.1 * free_in, "the control must shear out of plane ({free_out:e} against {free_in:e})");
}
