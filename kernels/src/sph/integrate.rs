//! The explicit midpoint predictor–corrector of the theses ("leap frog", roethlin-solver.md §5.2 steps 2, 3, 11;
//! klippel-constitutive.md §1.4): one derivative evaluation per step,
//!   predictor  y½ = y0 + ½Δt ẏ(previous midpoint),
//!   corrector  y1 = y0 + Δt ẏ(y½),
//! applied to x, v, ρ and S.
//!
//! In the mixed precision (f32 state, docs/measurements/notebook.md "Mixed precision") the corrector's position sum is
//! compensated: x is kept as an f32 pair hi + lo (`advance_compensated`), since a step's displacement on the
//! 150k cut is a few ulps of an f32 coordinate and a rounded sum misses up to 10–20 % of it (docs/stability.md).

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
    let (o, t) = (out.components_mut(), yt.components());
    let mut k = 0;
    while k < o.len() && k < t.len() {
        o[k] += c * t[k];
        k += 1;
    }
    out
}

/// Knuth's TwoSum: s = fl(a + b) and the exact error e with a + b = s + e (|e| ≤ ½ ulp(s)), six correctly
/// rounded operations, without a branch on |a| ≥ |b| (Knuth, TAOCP vol. 2, §4.2.2, theorem B). Valid in any
/// IEEE 754 binary format with round-to-nearest; the f32 build flags (`-fp-contract=fast`) fuse only a product
/// into an add, and TwoSum has no product.
#[inline(always)]
pub fn two_sum<R: Real>(a: R, b: R) -> (R, R) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// The compensated y0 + c·ẏ of a vector kept as hi + lo: each component's increment c·ẏ joins the low part,
/// then TwoSum with the high part gives the new pair. The sum hi + lo then carries about twice the format's
/// significand bits (an f32 pair: 48), so each step's displacement is kept to the rounding of the increment
/// itself, ½ ulp(c·ẏ + lo), not to ½ ulp(x).
#[inline(always)]
pub fn advance_compensated<R: Real, V: Vector<R>>(hi: &V, lo: &V, c: R, yt: &V) -> (V, V) {
    let mut h = [R::ZERO; 3];
    let mut l = [R::ZERO; 3];
    let mut k = 0;
    while k < V::DIM {
        (h[k], l[k]) = two_sum(hi.get(k), lo.get(k) + c * yt.get(k));
        k += 1;
    }
    (V::new(h), V::new(l))
}
