//! The cohesive crack along the cut plane (nairn-mpm.md §1.5): Needleman's cubic traction law in mode I and mode II
//! (Eq. 3), Yang and Thouless's decoupled failure criterion (Eq. 4), unloading along the secant to the origin, and
//! the law's initial stiffness against closing. Each crack point joins the two particles that faced each other
//! across the plane at t = 0: the MPM's crack points (`mpm::step::crack_point`; docs/mpm.md "Crack points are
//! particle pairs") and the SPH's bonds (`sph::bond`; docs/mpm.md "The cohesive path in SPH") share the law.

use crate::real::Real;
use bytemuck::{Pod, Zeroable};

/// One mode's cubic law: σ = (27/4) σ_c (δ/δ_c)(1 − δ/δ_c)², J_c = (9/16) σ_c δ_c (Eq. 3).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct CubicLaw {
    /// Peak traction σ_c [Pa] (at δ = δ_c/3).
    pub sigma_c: f64,
    /// Critical opening δ_c [m].
    pub delta_c: f64,
}

impl CubicLaw {
    /// The law's toughness J_c = (9/16) σ_c δ_c [J/m²].
    pub fn toughness(&self) -> f64 {
        9.0 / 16.0 * self.sigma_c * self.delta_c
    }

    /// The law of toughness `g_c` and peak `sigma_c`: δ_c = 16 G_c/(9 σ_c).
    pub fn of_toughness(g_c: f64, sigma_c: f64) -> Self {
        CubicLaw { sigma_c, delta_c: 16.0 * g_c / (9.0 * sigma_c) }
    }

    /// The initial stiffness dσ/dδ at 0, 27σ_c/(4δ_c), which also resists closing [Pa/m].
    #[inline(always)]
    pub fn stiffness<R: Real>(&self) -> R {
        R::from_f64(6.75 * self.sigma_c / self.delta_c)
    }

    /// σ(δ) for 0 ≤ δ (0 beyond δ_c).
    #[inline(always)]
    pub fn traction<R: Real>(&self, d: R) -> R {
        let x = d / R::from_f64(self.delta_c);
        if x >= R::ONE {
            return R::ZERO;
        }
        let y = R::ONE - x;
        R::from_f64(6.75 * self.sigma_c) * x * y * y
    }

    /// J(δ) = ∫₀^δ σ = (27/4) σ_c δ_c (x²/2 − 2x³/3 + x⁴/4), x = min(δ/δ_c, 1) (nairn-mpm.md §1.5).
    #[inline(always)]
    pub fn energy<R: Real>(&self, d: R) -> R {
        let x = (d / R::from_f64(self.delta_c)).min(R::ONE);
        let x2 = x * x;
        let poly = x2 * (R::from_f64(0.5) - x * R::from_f64(2.0 / 3.0) + x2 * R::from_f64(0.25));
        R::from_f64(6.75 * self.sigma_c * self.delta_c) * poly
    }
}

/// The two modes' laws.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Cohesive {
    pub mode1: CubicLaw,
    pub mode2: CubicLaw,
}

/// A crack point's history: the largest normal opening and the largest |sliding| reached, whether it has failed
/// (0/1) and, once failed, the mode-I share J_I/(J_I + J_II) at failure (Fig. 16).
pub type CrackState<R> = [R; 4];

/// Index of the failed flag in a [`CrackState`].
pub const FAILED: usize = 2;
/// Index of the mode-I share at failure.
pub const MODE_I: usize = 3;

/// A crack point's tractions (t_tangential, t_normal) on the face above for the opening δ = u_above − u_below
/// (δ_t along x, δ_n along y), with its history updated:
/// - each mode follows its law while its opening grows past its maximum, and the secant to the origin below it;
/// - J_I(δ_n,max)/J_Ic + J_II(δ_t,max)/J_IIc ≥ 1 fails the point, which then carries no tension and no shear;
/// - a closing δ_n < 0 meets the mode-I initial stiffness, failed or not (crack-face contact).
///
/// The returned tractions are the law's (positive opening: positive traction); the force on the face above is
/// their negative.
#[inline(always)]
pub fn traction<R: Real>(c: &Cohesive, st: &mut CrackState<R>, dt_open: R, dn_open: R) -> (R, R) {
    let closing = if dn_open < R::ZERO { c.mode1.stiffness::<R>() * dn_open } else { R::ZERO };
    if st[FAILED] != R::ZERO {
        return (R::ZERO, closing);
    }
    let at = dt_open.abs();
    if dn_open > st[0] {
        st[0] = dn_open;
    }
    if at > st[1] {
        st[1] = at;
    }
    let j1 = c.mode1.energy(st[0]) / R::from_f64(c.mode1.toughness());
    let j2 = c.mode2.energy(st[1]) / R::from_f64(c.mode2.toughness());
    if j1 + j2 >= R::ONE {
        st[FAILED] = R::ONE;
        st[MODE_I] = if j1 + j2 > R::ZERO { j1 / (j1 + j2) } else { R::ZERO };
        return (R::ZERO, closing);
    }
    let tn = if dn_open > R::ZERO { secant(&c.mode1, st[0], dn_open) } else { closing };
    let tt_abs = if at > R::ZERO { secant(&c.mode2, st[1], at) } else { R::ZERO };
    (if dt_open < R::ZERO { -tt_abs } else { tt_abs }, tn)
}

/// The law at 0 < d ≤ dmax: the envelope at d = dmax, the secant σ(dmax) d/dmax below it.
#[inline(always)]
fn secant<R: Real>(law: &CubicLaw, dmax: R, d: R) -> R {
    let t = law.traction(dmax);
    if d >= dmax { t } else { t * d / dmax }
}
