//! The cubic-spline kernel of the theses (roethlin-solver.md §3.1, (4.31)), support radius 2h:
//!
//! W(q) = n_c (1 − 1.5 q² + 0.75 q³) for 0 ≤ q < 1,  n_c · 0.25 (2 − q)³ for 1 ≤ q < 2,  0 beyond; q = r/h.
//! dW/dr = (n_c/h)(−3q + 2.25q²) for q < 1,  (n_c/h)(−0.75 (2 − q)²) for 1 ≤ q < 2.
//! W'(r)/r = (n_c/h²)(−3 + 2.25q) for q < 1 (no division),  (n_c/h)(−0.75 (2 − q)²)/r for 1 ≤ q < 2.
//!
//! n_c = 10/(7π h²) in 2D, 1/(π h³) in 3D ([C2D]/[C3D]). The old 2D code computed 0.25(2 − q)⁶ for q > 1
//! (erratum 24); [`CubicSpline::w`] is the correct cube, [`CubicSpline::w_c2d`] the old code's value, kept only to
//! reproduce it (`model = "mfree_iwf"`, docs/validation.md).

use crate::real::Real;
use bytemuck::{Pod, Zeroable};

/// Kernel constants for one smoothing length, precomputed on the host.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CubicSpline<R: Real> {
    pub h: R,
    pub inv_h: R,
    /// Normalisation n_c.
    pub norm: R,
    /// Squared support radius (2h)².
    pub support2: R,
}

// SAFETY: four fields of one float type: no padding, every bit pattern valid.
unsafe impl<R: Real> Zeroable for CubicSpline<R> {}
unsafe impl<R: Real> Pod for CubicSpline<R> {}

impl<R: Real> CubicSpline<R> {
    pub fn new(h: f64, dim: usize) -> Self {
        let pi = core::f64::consts::PI;
        let norm = if dim == 3 { 1.0 / (pi * h * h * h) } else { 10.0 / (7.0 * pi * h * h) };
        CubicSpline {
            h: R::from_f64(h),
            inv_h: R::from_f64(1.0 / h),
            norm: R::from_f64(norm),
            support2: R::from_f64(4.0 * h * h),
        }
    }

    /// W(r).
    #[inline(always)]
    pub fn w(&self, r: R) -> R {
        let q = r * self.inv_h;
        let one = R::ONE;
        let two = R::from_f64(2.0);
        if q < one {
            self.norm * (one - R::from_f64(1.5) * q * q + R::from_f64(0.75) * q * q * q)
        } else if q < two {
            let t = two - q;
            self.norm * R::from_f64(0.25) * t * t * t
        } else {
            R::ZERO
        }
    }

    /// W(r) as Röthlin's 2D code [C2D] computes it (`kernels.cuh`, `cubic_spline`): n_c (1 − 1.5 q² + 0.75 q³) for
    /// q ≤ 1, n_c · 0.25 (2 − q)⁶ for 1 < q < 2 (**a bug**, roethlin-solver.md §11 erratum 24: the sixth power where
    /// the spline has the cube), 0 beyond. The two branches agree at q = 1 (both 0.25 n_c), so the bug only lowers
    /// W on 1 < q < 2, by the factor (2 − q)³. The code uses this value only where it needs W itself, XSPH and the
    /// artificial stress's f_ij = W/W(Δx) (with W(Δx) on q < 1, unaffected); its gradient is the correct cube's.
    /// Reproduced under `model = "mfree_iwf"` ([`super::params::model::C2D_KERNEL_W`]), never by default.
    #[inline(always)]
    pub fn w_c2d(&self, r: R) -> R {
        let q = r * self.inv_h;
        let one = R::ONE;
        let two = R::from_f64(2.0);
        if q < one {
            self.norm * (one - R::from_f64(1.5) * q * q + R::from_f64(0.75) * q * q * q)
        } else if q < two {
            let t = two - q;
            let t3 = t * t * t;
            self.norm * R::from_f64(0.25) * t3 * t3
        } else {
            R::ZERO
        }
    }

    /// dW/dr(r); the gradient with respect to x_i is dW/dr · x_ij / r.
    #[inline(always)]
    pub fn dw_dr(&self, r: R) -> R {
        let q = r * self.inv_h;
        let one = R::ONE;
        let two = R::from_f64(2.0);
        let c = self.norm * self.inv_h;
        if q < one {
            c * (R::from_f64(-3.0) * q + R::from_f64(2.25) * q * q)
        } else if q < two {
            let t = two - q;
            c * R::from_f64(-0.75) * t * t
        } else {
            R::ZERO
        }
    }

    /// W'(r)/r, the factor of ∇W_ij = W'(r)/r · x_ij (roethlin-solver.md §3.1 (4.31) divided by r = q h):
    /// (n_c/h²)(−3 + 2.25 q) for q < 1, (n_c/h)(−0.75 (2 − q)²)/r for 1 ≤ q < 2, 0 beyond. The inner branch
    /// needs no division (costly in f64 on the GPU); it holds about a quarter of the pairs in 2D and an eighth in
    /// 3D (area or volume fraction of the support). The outer one divides as `dw_dr(r) / r` does, bit for bit.
    /// Equal to `dw_dr(r) / r` to rounding; only IEEE +, −, ×, ÷, so CPU and GPU agree.
    #[inline(always)]
    pub fn dw_dr_over_r(&self, r: R) -> R {
        let q = r * self.inv_h;
        let one = R::ONE;
        let two = R::from_f64(2.0);
        if q < one {
            // n_c/h² from the fields (no new field: the struct is Pod inside other repr(C) parameter blocks).
            self.norm * self.inv_h * self.inv_h * (R::from_f64(-3.0) + R::from_f64(2.25) * q)
        } else if q < two {
            let t = two - q;
            self.norm * self.inv_h * R::from_f64(-0.75) * t * t / r
        } else {
            R::ZERO
        }
    }
}
