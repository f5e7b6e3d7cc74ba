//! Material-point tests of the SPH constitutive pieces (roethlin-solver.md §10.2 AT-20, AT-21; §3.6).
#![allow(clippy::needless_range_loop)] // component-wise comparisons by index

use swarf::kernels::sph::TensorOps;
use swarf::kernels::sph::eigen::sym3_eigen;
use swarf::kernels::vector::{S2f64, S3f64};
use swarf::kernels::{Dim2, Dim3};
use swarf::rng::SplitMix64;
use swarf::solver::params::Elastic;

/// Integrates Ṡ = rate(S) with the solver's midpoint predictor–corrector.
fn integrate<S: Copy>(mut s: S, dt: f64, steps: usize, rate: impl Fn(&S) -> S, axpy: impl Fn(&S, f64, &S) -> S) -> S {
    for _ in 0..steps {
        let half = axpy(&s, 0.5 * dt, &rate(&s));
        s = axpy(&s, dt, &rate(&half));
    }
    s
}

fn axpy2(a: &S2f64, c: f64, b: &S2f64) -> S2f64 {
    S2f64(std::array::from_fn(|k| a.0[k] + c * b.0[k]))
}

fn axpy3(a: &S3f64, c: f64, b: &S3f64) -> S3f64 {
    S3f64(std::array::from_fn(|k| a.0[k] + c * b.0[k]))
}

/// AT-20: a pre-stressed point in rigid rotation, L = W = [[0, −ω], [ω, 0]], ω = 50 rad/s,
/// S0 = diag(100, −100, 0) MPa; after a quarter turn (t = π/(2ω), Δt = 1e-6 s) the Jaumann rate gives
/// S = R S0 Rᵀ = diag(−100, 100, 0) MPa within 1e-6 relative. The spin-free rate keeps S0 (negative control).
#[test]
fn rigid_rotation_rotates_the_stress_2d() {
    let w = 50.0;
    let l = [0.0, -w, w, 0.0];
    let g = 40.74e9;
    let s0 = S2f64([100e6, 0.0, -100e6, 0.0]);
    let t = std::f64::consts::PI / (2.0 * w);
    let dt = 1e-6;
    let steps = (t / dt).round() as usize;
    let dt = t / steps as f64;
    let s = integrate(s0, dt, steps, |s| <Dim2 as TensorOps<f64>>::jaumann(&l, s, g), axpy2);
    let expect = [-100e6, 0.0, 100e6, 0.0];
    for k in 0..4 {
        assert!((s.0[k] - expect[k]).abs() < 1e-6 * 100e6, "component {k}: {} vs {}", s.0[k], expect[k]);
    }
    let naive = integrate(s0, dt, steps, |_| <Dim2 as TensorOps<f64>>::spin_free_rate(&l, g), axpy2);
    assert_eq!(naive, s0, "the spin-free rate must leave the stress fixed in space (the wrong answer)");
    assert!((naive.0[0] - expect[0]).abs() > 1e8, "negative control: the non-objective rate fails AT-20");
}

/// AT-20 in 3D, rotating about z and about x: S(t) = R(ωt) S0 Rᵀ(ωt).
#[test]
fn rigid_rotation_rotates_the_stress_3d() {
    let w = 50.0;
    let g = 40.74e9;
    let s0 = S3f64([100e6, 20e6, -30e6, -100e6, 10e6, 0.0]);
    let t = std::f64::consts::PI / (2.0 * w);
    let steps = 31416;
    let dt = t / steps as f64;
    // About z: quarter turn maps (x, y, z) → (−y, x, z): S'xx = Syy, S'yy = Sxx, S'xy = −Sxy, S'xz = −Syz,
    // S'yz = Sxz, S'zz = Szz.
    let lz = [0.0, -w, 0.0, w, 0.0, 0.0, 0.0, 0.0, 0.0];
    let s = integrate(s0, dt, steps, |s| <Dim3 as TensorOps<f64>>::jaumann(&lz, s, g), axpy3);
    let [xx, xy, xz, yy, yz, zz] = s0.0;
    let expect = [yy, -xy, -yz, xx, xz, zz];
    for k in 0..6 {
        assert!((s.0[k] - expect[k]).abs() < 1e-6 * 100e6, "z: component {k}: {} vs {}", s.0[k], expect[k]);
    }
    // About x: (x, y, z) → (x, −z, y): S'yy = Szz, S'zz = Syy, S'yz = −Syz, S'xy = −Sxz, S'xz = Sxy.
    let lx = [0.0, 0.0, 0.0, 0.0, 0.0, -w, 0.0, w, 0.0];
    let s = integrate(s0, dt, steps, |s| <Dim3 as TensorOps<f64>>::jaumann(&lx, s, g), axpy3);
    let expect = [xx, -xz, xy, zz, -yz, yy];
    for k in 0..6 {
        assert!((s.0[k] - expect[k]).abs() < 1e-6 * 100e6, "x: component {k}: {} vs {}", s.0[k], expect[k]);
    }
}

/// Pure deformation: Ṡ = 2G dev D; in plane strain Ṡzz = −(2/3) G tr D (roethlin-solver.md §2.3).
#[test]
fn deviatoric_rate_of_pure_stretch() {
    let g = 10.0;
    let l = [3.0, 0.0, 0.0, 1.0]; // D = diag(3, 1, 0), tr D = 4
    let s = <Dim2 as TensorOps<f64>>::jaumann(&l, &S2f64::default(), g);
    let expect = [2.0 * g * (3.0 - 4.0 / 3.0), 0.0, 2.0 * g * (1.0 - 4.0 / 3.0), -2.0 / 3.0 * g * 4.0];
    for k in 0..4 {
        assert!((s.0[k] - expect[k]).abs() < 1e-12, "component {k}: {} vs {}", s.0[k], expect[k]);
    }
    assert!(s.0[0] + s.0[2] + s.0[3] < 1e-12, "the rate is deviatoric");
}

/// AT-21: Ti6Al4V (E = 110 GPa, ν = 0.35, ρ = 4430 kg/m³): K = 122.2 GPa, G = 40.74 GPa, c0 = √(K/ρ0) = 5252.6 m/s.
#[test]
fn eos_sound_speed() {
    let m = Elastic { density: 4430.0, youngs_modulus: 110e9, poisson_ratio: 0.35 };
    assert!((m.bulk_modulus() - 122.2e9).abs() < 0.05e9, "K = {}", m.bulk_modulus());
    assert!((m.shear_modulus() - 40.74e9).abs() < 0.005e9, "G = {}", m.shear_modulus());
    let c0 = m.sound_speed();
    assert!((c0 - 5252.6).abs() < 0.05, "c0 = {c0}");
    let independent = (110e9 / (3.0 * (1.0 - 0.7)) / 4430.0_f64).sqrt();
    assert!((c0 / independent - 1.0).abs() < 1e-12);
    // The kernels' EOS p = c0²(ρ − ρ0) has dp/dρ = c0² (= K/ρ0).
    let p = swarf::solver::params::sph_params::<f64>(&m, 1e-5, 1.5e-5, 2, &Default::default());
    let dp = swarf::kernels::sph::interact::pressure(&p, 4431.0) - swarf::kernels::sph::interact::pressure(&p, 4430.0);
    assert!((dp / (c0 * c0) - 1.0).abs() < 1e-9, "dp/dρ = {dp}, c0² = {}", c0 * c0);
}

/// The 3D Jacobi eigen-decomposition reconstructs random symmetric matrices (A = Q Λ Qᵀ, QᵀQ = I) to 1e-13
/// relative, and handles repeated eigenvalues and diagonal input.
#[test]
fn symmetric_eigen_3d() {
    let mut rng = SplitMix64::new(7);
    let mut cases: Vec<[f64; 6]> = (0..2000).map(|_| std::array::from_fn(|_| rng.normal() * 1e8)).collect();
    cases.push([1.0, 0.0, 0.0, 1.0, 0.0, 1.0]);
    cases.push([2.0, 1.0, 1.0, 2.0, 1.0, 2.0]); // eigenvalues 4, 1, 1
    cases.push([0.0; 6]);
    cases.push([-5.0, 0.0, 0.0, 3.0, 0.0, 7.0]);
    for a in cases {
        let (lam, q) = sym3_eigen(a);
        let scale = a.iter().fold(0.0f64, |m, x| m.max(x.abs())).max(1e-300);
        let idx = [[0, 1, 2], [1, 3, 4], [2, 4, 5]];
        for i in 0..3 {
            for j in 0..3 {
                let rec: f64 = (0..3).map(|k| q[i][k] * lam[k] * q[j][k]).sum();
                assert!((rec - a[idx[i][j]]).abs() <= 1e-13 * scale + 1e-300, "reconstruction of {a:?}");
                let orth: f64 = (0..3).map(|k| q[k][i] * q[k][j]).sum();
                assert!((orth - if i == j { 1.0 } else { 0.0 }).abs() < 1e-13, "orthonormality of {a:?}");
            }
        }
    }
}

/// The artificial stress (Gray–Monaghan, roethlin-solver.md §3.6): R = Q diag(R') Qᵀ with R'_k = −ε λ_k/ρ² for
/// tensile principal stresses only. The 2D closed form equals the 3D Jacobi path on in-plane stresses, it
/// vanishes in pure compression, and it is −ε σ/ρ² for a purely tensile state.
#[test]
fn artificial_stress_2d_and_3d_agree() {
    let mut rng = SplitMix64::new(9);
    let (eps, rho) = (0.3, 7830.0);
    for _ in 0..2000 {
        let (sxx, sxy, syy, p) = (rng.normal() * 1e8, rng.normal() * 1e8, rng.normal() * 1e8, rng.normal() * 1e8);
        let r2 = <Dim2 as TensorOps<f64>>::artificial_stress(&S2f64([sxx, sxy, syy, 0.0]), p, rho, eps);
        // In 3D, put a strongly compressive zz so that it contributes nothing.
        let s3 = S3f64([sxx, sxy, 0.0, syy, 0.0, -1e12]);
        let r3 = <Dim3 as TensorOps<f64>>::artificial_stress(&s3, p, rho, eps);
        let scale = eps * 1e9 / (rho * rho);
        for (a, b) in [(r2.0[0], r3.0[0]), (r2.0[1], r3.0[1]), (r2.0[2], r3.0[3])] {
            assert!((a - b).abs() < 1e-10 * scale, "2D {r2:?} vs 3D {r3:?}");
        }
    }
    let comp = <Dim2 as TensorOps<f64>>::artificial_stress(&S2f64([1e6, 2e5, -3e5, 0.0]), 5e7, rho, eps);
    assert_eq!(comp, S2f64::default(), "pure compression gives no artificial stress");
    let ten = <Dim2 as TensorOps<f64>>::artificial_stress(&S2f64([3e6, 1e6, 2e6, 0.0]), -1e7, rho, eps);
    let expect = [-eps * 13e6 / (rho * rho), -eps * 1e6 / (rho * rho), -eps * 12e6 / (rho * rho)];
    for (k, e) in [(0, expect[0]), (1, expect[1]), (2, expect[2])] {
        assert!((ten.0[k] - e).abs() < 1e-12 * e.abs().max(1e-20), "tensile state: {ten:?}");
    }
}
