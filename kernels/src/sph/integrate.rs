//! The explicit midpoint predictor–corrector of the theses ("leap frog", roethlin-solver.md §5.2 steps 2, 3, 11;
//! klippel-constitutive.md §1.4): one derivative evaluation per step,
//!   predictor  y½ = y0 + ½Δt ẏ(previous midpoint),
//!   corrector  y1 = y0 + Δt ẏ(y½),
//! applied to x, v, ρ and S.

use crate::real::Real;
use crate::vector::{SymTensor, Vector};

/// y0 + c·ẏ for a vector.
#[inline(always)]
pub fn advance_vec<R: Real, V: Vector<R>>(y0: &V, c: R, yt: &V) -> V {
    V::new([y0.get(0) + c * yt.get(0), y0.get(1) + c * yt.get(1), y0.get(2) + c * yt.get(2)])
}

/// y0 + c·ẏ for a symmetric tensor.
#[inline(always)]
pub fn advance_sym<R: Real, S: SymTensor<R>>(y0: &S, c: R, yt: &S) -> S {
    let mut out = *y0;
    // SAFETY: SymTensor types are repr(C) arrays of R.
    let o = unsafe { core::slice::from_raw_parts_mut(&mut out as *mut S as *mut R, S::COMPONENTS) };
    let t = unsafe { core::slice::from_raw_parts(yt as *const S as *const R, S::COMPONENTS) };
    let mut k = 0;
    while k < o.len() && k < t.len() {
        o[k] += c * t[k];
        k += 1;
    }
    out
}
