//! The cohesive crack along the cut plane (nairn-mpm.md §1.5): Needleman's cubic traction law in mode I and mode II
//! (Eq. 3), or the triangular law the paper also tried, Yang and Thouless's decoupled failure criterion (Eq. 4), unloading along the secant to the origin, and
//! the law's initial stiffness against closing. Each crack point joins the two particles that faced each other
//! across the plane at t = 0: the MPM's crack points (`mpm::step::crack_point`; docs/mpm.md "Crack points are
//! particle pairs") and the SPH's bonds (`sph::bond`; docs/mpm.md "The cohesive path in SPH") share the law. The
//! SPH bonds that take over from the continuum at an onset (`coupling = "continuum"`) use [`strength_ratio`] and
//! the extrinsic [`softening`] law instead (docs/mpm.md "Continuum until onset").

use crate::real::Real;
use bytemuck::{Pod, Zeroable};

/// [`TractionLaw::shape`]: Needleman's cubic law (nairn-mpm.md §1.5, Eq. 3), the paper's.
pub const CUBIC: u32 = 0;
/// [`TractionLaw::shape`]: the triangular law the paper also tried (§1.5): linear to σ_c at δ_p, linear to zero
/// at δ_c.
pub const TRIANGULAR: u32 = 1;

/// Where the triangular law peaks, δ_p/δ_c = 32/243: its initial stiffness σ_c/δ_p is then the cubic law's
/// 27σ_c/(4δ_c) of the same σ_c and G_c (δ_c,cubic = 16 G_c/(9σ_c), δ_c,triangular = 2 G_c/σ_c), so that the two
/// laws differ only in their shape past the start, and close with the same stiffness (docs/mpm.md "Traction
/// laws"). The paper does not say where its triangular law peaks.
pub const TRIANGULAR_PEAK: f64 = 32.0 / 243.0;

/// One mode's traction law of peak σ_c and critical opening δ_c:
/// - cubic: σ = (27/4) σ_c x(1 − x)², J_c = (9/16) σ_c δ_c (Eq. 3), x = δ/δ_c;
/// - triangular: σ = σ_c x/p for x ≤ p, σ_c (1 − x)/(1 − p) for p < x < 1, J_c = ½ σ_c δ_c, p = [`TRIANGULAR_PEAK`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct TractionLaw {
    /// Peak traction σ_c [Pa].
    pub sigma_c: f64,
    /// Critical opening δ_c [m].
    pub delta_c: f64,
    /// [`CUBIC`] or [`TRIANGULAR`].
    pub shape: u32,
    pub _pad: u32,
}

impl TractionLaw {
    /// J_c/(σ_c δ_c): 9/16 (cubic), 1/2 (triangular).
    fn toughness_factor(shape: u32) -> f64 {
        if shape == TRIANGULAR { 0.5 } else { 9.0 / 16.0 }
    }

    /// The law's toughness J_c [J/m²].
    pub fn toughness(&self) -> f64 {
        Self::toughness_factor(self.shape) * self.sigma_c * self.delta_c
    }

    /// The law of `shape`, toughness `g_c` and peak `sigma_c`: δ_c = G_c/(factor σ_c) (16 G_c/(9 σ_c) cubic,
    /// 2 G_c/σ_c triangular).
    pub fn of_toughness(shape: u32, g_c: f64, sigma_c: f64) -> Self {
        let delta_c = g_c / (Self::toughness_factor(shape) * sigma_c);
        TractionLaw { sigma_c, delta_c, shape, _pad: 0 }
    }

    /// The initial stiffness dσ/dδ at 0, which also resists closing [Pa/m]: 27σ_c/(4δ_c) (cubic),
    /// σ_c/(p δ_c) (triangular).
    #[inline(always)]
    pub fn stiffness<R: Real>(&self) -> R {
        let k = if self.shape == TRIANGULAR { 1.0 / TRIANGULAR_PEAK } else { 6.75 };
        R::from_f64(k * self.sigma_c / self.delta_c)
    }

    /// σ(δ) for 0 ≤ δ (0 beyond δ_c).
    #[inline(always)]
    pub fn traction<R: Real>(&self, d: R) -> R {
        let x = d / R::from_f64(self.delta_c);
        if x >= R::ONE {
            return R::ZERO;
        }
        if self.shape == TRIANGULAR {
            let p = R::from_f64(TRIANGULAR_PEAK);
            let s = R::from_f64(self.sigma_c);
            return if x <= p { s * x / p } else { s * (R::ONE - x) / (R::ONE - p) };
        }
        let y = R::ONE - x;
        R::from_f64(6.75 * self.sigma_c) * x * y * y
    }

    /// J(δ) = ∫₀^δ σ, x = min(δ/δ_c, 1): cubic (27/4) σ_c δ_c (x²/2 − 2x³/3 + x⁴/4) (nairn-mpm.md §1.5);
    /// triangular ½ σ_c δ_c x²/p for x ≤ p, ½ σ_c δ_c p + σ_c δ_c [(x − p) − (x² − p²)/2]/(1 − p) beyond.
    #[inline(always)]
    pub fn energy<R: Real>(&self, d: R) -> R {
        let x = (d / R::from_f64(self.delta_c)).min(R::ONE);
        let half = R::from_f64(0.5);
        if self.shape == TRIANGULAR {
            let (sd, p) = (R::from_f64(self.sigma_c * self.delta_c), R::from_f64(TRIANGULAR_PEAK));
            if x >= R::ONE {
                // The whole J_c, exactly, so that a point opened to δ_c fails whatever the rounding below.
                return half * sd;
            }
            if x <= p {
                return half * sd * x * x / p;
            }
            return half * sd * p + sd * ((x - p) - half * (x * x - p * p)) / (R::ONE - p);
        }
        let x2 = x * x;
        let poly = x2 * (half - x * R::from_f64(2.0 / 3.0) + x2 * R::from_f64(0.25));
        R::from_f64(6.75 * self.sigma_c * self.delta_c) * poly
    }
}

/// The two modes' laws.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Cohesive {
    pub mode1: TractionLaw,
    pub mode2: TractionLaw,
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

/// The strength ratio λ = √(⟨t_n⟩²/σ_c² + t_t²/τ_c²) of a traction (t_t, t_n) on the plane, σ_c and τ_c the two
/// modes' peaks: a [`softening`] bond's onset at λ ≥ 1 (the quadratic criterion of Camacho and Ortiz 1996, which
/// reduces to each mode's peak alone; docs/mpm.md "Continuum until onset").
#[inline(always)]
pub fn strength_ratio<R: Real>(c: &Cohesive, tt: R, tn: R) -> R {
    let n = tn.max(R::ZERO) / R::from_f64(c.mode1.sigma_c);
    let t = tt / R::from_f64(c.mode2.sigma_c);
    (n * n + t * t).sqrt()
}

/// A bond's tractions (t_t, t_n) past its onset, an extrinsic law of linear softening (Camacho and Ortiz 1996):
/// with the normalised opening x = √(ξ_n² + ξ_t²), ξ_n = ⟨u_n⟩/δ_fI, ξ_t = u_t/δ_fII, δ_f = 2 J_c/σ_c of each mode and
/// u the opening since the onset, the traction is t = (τ_c ξ_t, σ_c ξ_n)(1 − x_max)/x_max: on the strength ellipse
/// at the onset, along the opening, falling linearly to zero at x = 1, and along the secant to the onset opening
/// below the largest x reached (st[0]). Each mode's traction does positive work on an opening; a proportional one
/// dissipates J_Ic cos²φ + J_IIc sin²φ (ξ = x (sin φ, cos φ)): pure mode I J_Ic, pure mode II J_IIc. A closing
/// u_n < 0 adds the mode-I law's initial stiffness, failed or not (crack-face contact). x_max ≥ 1 fails the bond
/// (st[FAILED]; the mode-I share is the caller's, from the work).
#[inline(always)]
pub fn softening<R: Real>(c: &Cohesive, st: &mut CrackState<R>, ut: R, un: R) -> (R, R) {
    let closing = if un < R::ZERO { c.mode1.stiffness::<R>() * un } else { R::ZERO };
    if st[FAILED] != R::ZERO {
        return (R::ZERO, closing);
    }
    let fi = R::from_f64(2.0 * c.mode1.toughness() / c.mode1.sigma_c);
    let fii = R::from_f64(2.0 * c.mode2.toughness() / c.mode2.sigma_c);
    let (xn, xt) = (un.max(R::ZERO) / fi, ut / fii);
    let x = (xn * xn + xt * xt).sqrt();
    if x > st[0] {
        st[0] = x;
    }
    if st[0] >= R::ONE {
        st[FAILED] = R::ONE;
        return (R::ZERO, closing);
    }
    if st[0] == R::ZERO {
        // No opening yet: no direction to carry a traction along.
        return (R::ZERO, closing);
    }
    let k = (R::ONE - st[0]) / st[0];
    (R::from_f64(c.mode2.sigma_c) * xt * k, R::from_f64(c.mode1.sigma_c) * xn * k + closing)
}

/// The law at 0 < d ≤ dmax: the envelope at d = dmax, the secant σ(dmax) d/dmax below it.
#[inline(always)]
fn secant<R: Real>(law: &TractionLaw, dmax: R, d: R) -> R {
    let t = law.traction(dmax);
    if d >= dmax { t } else { t * d / dmax }
}
