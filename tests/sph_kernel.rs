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
