//! The cubic-spline kernel (roethlin-solver.md §3.1 (4.31), acceptance tests AT-01..AT-03 of §10.1).

use swarf::kernels::sph::CubicSpline;

/// AT-01: ∫W = 1 over the support, 2D and 3D, to 1e-8 (composite Simpson in r on [0, 2h]).
#[test]
fn kernel_is_normalised() {
    for dim in [2usize, 3] {
        let h = 0.37;
        let k = CubicSpline::<f64>::new(h, dim);
        let m = 20_000; // even
        let dr = 2.0 * h / m as f64;
        let shell = |r: f64| if dim == 2 { 2.0 * std::f64::consts::PI * r } else { 4.0 * std::f64::consts::PI * r * r };
        let mut s = 0.0;
        for i in 0..=m {
            let r = i as f64 * dr;
            let w = if i == 0 || i == m {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            s += w * k.w(r) * shell(r);
        }
        s *= dr / 3.0;
        assert!((s - 1.0).abs() < 1e-8, "{dim}D: ∫W = {s}");
    }
}

/// AT-02: Σ_j W_ij Δx^d at an interior particle of an infinite lattice: 1.0017 (2D) and 1.0014 (3D) at
/// h = 1.7Δx; 1.0034 and 1.0018 at h = 1.5Δx; tolerance 1e-4 (values [D] of the digest).
#[test]
fn lattice_sums() {
    for (dim, ratio, expect) in [(2usize, 1.7, 1.0017), (3, 1.7, 1.0014), (2, 1.5, 1.0034), (3, 1.5, 1.0018)] {
        let dx = 1.0;
        let k = CubicSpline::<f64>::new(ratio * dx, dim);
        let m = 5i32;
        let mut s = 0.0;
        for i in -m..=m {
            for j in -m..=m {
                let zs: Vec<i32> = if dim == 3 { (-m..=m).collect() } else { vec![0] };
                for kz in zs {
                    let r = ((i * i + j * j + kz * kz) as f64).sqrt() * dx;
                    s += k.w(r) * dx.powi(dim as i32);
                }
            }
        }
        assert!((s - expect).abs() < 1e-4, "{dim}D h/Δx = {ratio}: Σ W Δx^d = {s}, expected {expect}");
    }
}

/// AT-03: dW/dr against central differences at 1000 points in (0, 2h), relative error below 1e-6 (absolute
/// near the zero of dW/dr at r = 0 and r = 2h, scaled by max|dW/dr|).
#[test]
fn gradient_matches_finite_differences() {
    let mut rng = swarf::rng::SplitMix64::new(1);
    for dim in [2usize, 3] {
        let h = 0.01;
        let k = CubicSpline::<f64>::new(h, dim);
        let scale = (0..1000).map(|i| k.dw_dr(2.0 * h * i as f64 / 1000.0).abs()).fold(0.0, f64::max);
        for _ in 0..1000 {
            let r = 2.0 * h * (1e-3 + (1.0 - 2e-3) * rng.uniform());
            let e = 1e-7 * h;
            let fd = (k.w(r + e) - k.w(r - e)) / (2.0 * e);
            let an = k.dw_dr(r);
            assert!((fd - an).abs() < 1e-6 * scale, "{dim}D r/h = {}: fd {fd}, analytic {an}", r / h);
        }
    }
}

/// W'(r)/r without the division on q < 1 (`CubicSpline::dw_dr_over_r`, (4.31) divided by r = q h) equals
/// dW/dr / r to 1e-14 relative over (0, 2h), bit for bit on 1 ≤ q < 2 (the same division there), and is 0 at and
/// beyond 2h; 2D and 3D.
#[test]
fn gradient_over_r_matches_the_division() {
    let mut rng = swarf::rng::SplitMix64::new(7);
    for dim in [2usize, 3] {
        for h in [0.01, 0.37, 1.7] {
            let k = CubicSpline::<f64>::new(h, dim);
            let grid = (1..2000).map(|i| 2.0 * h * i as f64 / 2000.0);
            let random = (0..2000).map(|_| 2.0 * h * rng.uniform()).filter(|&r| r > 0.0);
            for r in grid.chain(random).chain([1e-6 * h, h, 2.0 * h * (1.0 - 1e-15)]) {
                let (fast, slow) = (k.dw_dr_over_r(r), k.dw_dr(r) / r);
                assert!((fast - slow).abs() <= 1e-14 * slow.abs(), "{dim}D h = {h} r/h = {}: {fast} vs {slow}", r / h);
                if r * k.inv_h >= 1.0 {
                    assert_eq!(fast.to_bits(), slow.to_bits(), "{dim}D h = {h} r/h = {}", r / h);
                }
            }
            for r in [2.0 * h, 2.0 * h * (1.0 + 1e-12), 2.5 * h, 10.0 * h] {
                assert_eq!(k.dw_dr_over_r(r), 0.0, "{dim}D h = {h} r/h = {}", r / h);
            }
        }
    }
}

/// The SPH pre-pass (`sph::interact::prepare` through `Passes::sph_prepare`): the per-particle volume V = m/ρ that
/// the pair terms read instead of dividing per pair is written exactly (the same IEEE division), with every
/// stabiliser combination, in f64 and f32, 2D and 3D.
mod pre_pass {

    use swarf::backend::{CpuBackend, Passes, PrepassBufs};
    use swarf::kernels::sph::{CubicSpline, SphParams, Stabilisers, TensorOps};
    use swarf::kernels::{Dim2, Dim3, Real};
    use swarf::rng::SplitMix64;

    fn volumes_are_exact<R: Real, D: TensorOps<R>>() {
        let b = CpuBackend::new();
        let n = 257;
        let mut rng = SplitMix64::new(11);
        let rho: Vec<R> = (0..n).map(|_| R::from_f64(7800.0 * (0.8 + 0.4 * rng.uniform()))).collect();
        // Masses of a few magnitudes, and a zero one (a massless particle has V = 0).
        let mass: Vec<R> =
            (0..n).map(|i| R::from_f64(if i == 3 { 0.0 } else { 1e-6 * (0.5 + rng.uniform()) })).collect();
        let stress = vec![D::Sym::<R>::default(); n];
        let params = vec![SphParams::<R> {
            kernel: CubicSpline::new(1e-4, D::D),
            rho0: R::from_f64(7800.0),
            c0sq: R::from_f64(2.1e7),
            bulk: R::from_f64(1.6e11),
            as_eps: R::from_f64(0.3),
            ..Default::default()
        }];
        for (viscosity, stress_on) in [(false, false), (false, true), (true, false), (true, true)] {
            let stab = Stabilisers { viscosity, stress: stress_on, xsph: false };
            let mut sig = vec![D::Sym::<R>::default(); n];
            let mut art = vec![D::Sym::<R>::default(); n];
            let mut sound = vec![R::ZERO; n];
            let mut vol = vec![R::from_f64(-1.0); n];
            b.sph_prepare::<R, D>(
                n,
                stab,
                &params,
                &rho,
                &mass,
                &stress,
                PrepassBufs {
                    sig: &mut sig,
                    art: Some(&mut art),
                    sound: Some(&mut sound),
                    vol: &mut vol,
                    av_switch: None,
                },
                None,
                None,
                None,
            )
            .expect("pre-pass");
            for i in 0..n {
                let expect = mass[i] / rho[i];
                assert!(
                    vol[i].to_f64().to_bits() == expect.to_f64().to_bits(),
                    "{}D {} bytes, {stab:?}: vol[{i}] = {} vs m/ρ = {}",
                    D::D,
                    std::mem::size_of::<R>(),
                    vol[i].to_f64(),
                    expect.to_f64()
                );
            }
        }
    }

    #[test]
    fn prepass_writes_the_exact_volume() {
        volumes_are_exact::<f64, Dim2>();
        volumes_are_exact::<f64, Dim3>();
        volumes_are_exact::<f32, Dim2>();
        volumes_are_exact::<f32, Dim3>();
    }
}

/// The artificial stress's f_ijⁿ (roethlin-solver.md §3.6, n = 4) by repeated squaring (`interact::power`): exact
/// for n = 0, 1, 2 and equal to (x²)² bit for bit for n = 4 (the unrolled case); every n ≤ 8 within 4 ulp of
/// `powi` (each of the ≤ 4 multiplications rounds once), f32 and f64, over x ∈ [0, 1.2] (f_ij ≤ W(0)/W(Δx)).
#[test]
fn artificial_stress_power_by_squaring() {
    use swarf::kernels::sph::interact::power;
    for k in 0..=1200 {
        let x = k as f64 * 1e-3;
        assert_eq!(power(x, 0), 1.0);
        assert_eq!(power(x, 1).to_bits(), x.to_bits());
        assert_eq!(power(x, 2).to_bits(), (x * x).to_bits());
        assert_eq!(power(x, 4).to_bits(), ((x * x) * (x * x)).to_bits());
        let xf = x as f32;
        assert_eq!(power(xf, 4).to_bits(), ((xf * xf) * (xf * xf)).to_bits());
        for n in 0..=8u32 {
            let (got, want) = (power(x, n), x.powi(n as i32));
            assert!((got - want).abs() <= 4.0 * f64::EPSILON * want, "x = {x}, n = {n}: {got} against {want}");
            let (got, want) = (power(xf, n), xf.powi(n as i32));
            assert!((got - want).abs() <= 4.0 * f32::EPSILON * want, "x = {xf}, n = {n}: {got} against {want}");
        }
    }
}
