//! The uGIMP shape functions of MPM (Bardenhagen & Kober 2004; nairn-mpm.md §1.1): a particle's domain is an
//! undeformed square of half-width l_p that moves with it, and its weight on a node is the hat function of the
//! grid averaged over that square.

use crate::real::Real;

/// The 1D uGIMP weight S(ξ) and its derivative dS/dξ for a particle at ξ = x_p − x_i from a node, cell size Δx
/// and particle half-width l_p < Δx/2 (nairn-mpm.md §1.1, the piecewise form):
///
/// - |ξ| ≤ l_p: S = 1 − (ξ² + l_p²)/(2 Δx l_p);
/// - l_p < |ξ| ≤ Δx − l_p: S = 1 − |ξ|/Δx;
/// - Δx − l_p < |ξ| < Δx + l_p: S = (Δx + l_p − |ξ|)²/(4 Δx l_p);
/// - 0 beyond.
///
/// The weights of the nodes a particle touches sum to 1 and their gradients to 0 (partition of unity; tests/mpm.rs).
#[inline(always)]
pub fn ugimp<R: Real>(xi: R, dx: R, lp: R) -> (R, R) {
    let neg = xi < R::ZERO;
    let a = if neg { -xi } else { xi };
    let (s, d) = if a >= dx + lp {
        (R::ZERO, R::ZERO)
    } else if a > dx - lp {
        let t = dx + lp - a;
        let den = dx * lp;
        (t * t / (R::from_f64(4.0) * den), -t / (R::from_f64(2.0) * den))
    } else if a > lp {
        (R::ONE - a / dx, -R::ONE / dx)
    } else {
        // The centre piece is even in ξ: its derivative carries the sign itself.
        return (R::ONE - (xi * xi + lp * lp) / (R::from_f64(2.0) * dx * lp), -xi / (dx * lp));
    };
    (s, if neg { -d } else { d })
}
