//! Johnson–Cook flow stress (roethlin-solver.md §2.4 Eq. (3.101); klippel-constitutive.md §2.1 Eq. 3.95), and the
//! rate and temperature factors that the JC extensions of [`super::tanh`] share.

use super::{Flow, FlowStress, STRAIN_FLOOR, clamp_below_melt, fmax, pow, pow_pair};
use bytemuck::{Pod, Zeroable};

/// `rate_form`: the ln form 1 + C ln ε̇* with ε̇* clamped ≥ 1, i.e. no rate effect below ε̇0 (roethlin-solver.md
/// §11 erratum 9's clamp; klippel-constitutive.md §2.1's recommended floor, the Abaqus VUMAT's `Term_B = 1`).
/// Continuous at ε̇* = 1.
pub const RATE_FORM_CLAMP: u32 = 0;
/// `rate_form`: the Uintah form (1 + ε̇*)^C for ε̇* ≤ 1 and 1 + C ln ε̇* above ([C2D]/[C3D], roethlin-solver.md
/// §2.4; Klippel Eq. 7.20). It jumps from 2^C to 1 at ε̇* = 1 (klippel §2.1 [NOTE]); at ε̇* = 1 itself the Uintah
/// branch applies (AT-23: σ_y(0, 1/s, 300 K) = 862·2^0.01 = 868.0 MPa).
pub const RATE_FORM_UINTAH: u32 = 1;

/// Johnson–Cook: σ_y = (A + B ε̄ⁿ)(1 + C ln ε̄̇*)(1 − θᵐ), ε̄̇* = ε̄̇/ε̄̇0, θ = (T − T0)/(Tm − T0)
/// (roethlin-solver.md §2.4 (3.101); klippel-constitutive.md §2.1 Eq. 3.95).
///
/// * θ is clamped to 0 below T0 (klippel §2.1: "θ = 0 if T < T_ref"; no hardening below the reference
///   temperature) and T to ≤ Tm − 1 K, so θ < 1 and 1 − θᵐ > 0 ([C3D]'s clamp).
/// * Low rates: see [`RATE_FORM_CLAMP`] and [`RATE_FORM_UINTAH`]; any other value acts as the clamp. Both give
///   a factor 1 at ε̄̇ = 0. ε̄̇ < 0 is treated as 0.
/// * ε̄ < 0 is treated as 0; ∂σ/∂ε̄ is evaluated at max(ε̄, [`STRAIN_FLOOR`]) (nBε̄ⁿ⁻¹ is infinite at 0 for n < 1).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct JohnsonCook {
    /// A: initial yield stress [Pa].
    pub a: f64,
    /// B: hardening modulus [Pa].
    pub b: f64,
    /// C: strain-rate coefficient [-].
    pub c: f64,
    /// n: hardening exponent [-].
    pub n: f64,
    /// m: thermal-softening exponent [-].
    pub m: f64,
    /// ε̄̇0: reference strain rate [1/s].
    pub ref_rate: f64,
    /// T0 (T_ref): reference temperature [K].
    pub ref_temp: f64,
    /// Tm (T_f): melt temperature [K].
    pub melt_temp: f64,
    /// [`RATE_FORM_CLAMP`] or [`RATE_FORM_UINTAH`].
    pub rate_form: u32,
    pub _pad: u32,
}

impl JohnsonCook {
    /// Rate factor and its derivative ∂/∂ε̄̇ [s].
    #[inline(always)]
    pub fn rate_factor(&self, rate: f64) -> (f64, f64) {
        let r = rate / self.ref_rate;
        if self.rate_form == RATE_FORM_UINTAH && r <= 1.0 {
            let r = fmax(r, 0.0);
            let f = pow(1.0 + r, self.c);
            (f, self.c * f / ((1.0 + r) * self.ref_rate))
        } else if r > 1.0 {
            (1.0 + self.c * libm::log(r), self.c / rate)
        } else {
            (1.0, 0.0)
        }
    }

    /// Thermal factor 1 − θᵐ with the clamps above.
    #[inline(always)]
    pub fn thermal_factor(&self, temp: f64) -> f64 {
        let t = clamp_below_melt(temp, self.melt_temp);
        let theta = (t - self.ref_temp) / (self.melt_temp - self.ref_temp);
        if theta <= 0.0 { 1.0 } else { 1.0 - pow(theta, self.m) }
    }

    /// T/Tm with T clamped to [0, Tm − 1 K]: the absolute temperature ratio of the tanh models (klippel §2.3).
    #[inline(always)]
    pub fn melt_ratio(&self, temp: f64) -> f64 {
        let t = clamp_below_melt(temp, self.melt_temp);
        let t = if t < 0.0 { 0.0 } else { t };
        t / self.melt_temp
    }

    /// Hardening term A + B ε̄ⁿ and its derivative nBε̄ⁿ⁻¹ (at max(ε̄, STRAIN_FLOOR)). Above the floor both
    /// powers share one logarithm (`pow_pair`: the same bits as two `pow`), one `ln` fewer per Newton iteration.
    #[inline(always)]
    pub fn hardening(&self, eps: f64) -> (f64, f64) {
        let e = fmax(eps, 0.0);
        let ed = fmax(eps, STRAIN_FLOOR);
        let (pn, pd) =
            if e == ed { pow_pair(e, self.n, self.n - 1.0) } else { (pow(e, self.n), pow(ed, self.n - 1.0)) };
        (self.a + self.b * pn, self.n * self.b * pd)
    }
}

impl FlowStress for JohnsonCook {
    /// [`FlowStress::sigma_y_parts`] of its own parts, so that a caller holding a part gets these bits.
    #[inline]
    fn sigma_y(&self, eps: f64, rate: f64, temp: f64) -> f64 {
        self.sigma_y_parts(eps, rate, temp, self.strength_part(eps, rate), self.thermal_factor(temp))
    }

    /// (A + B ε̄ⁿ)(1 + C ln ε̄̇*), ε̄ < 0 as 0.
    #[inline(always)]
    fn strength_part(&self, eps: f64, rate: f64) -> f64 {
        let e = fmax(eps, 0.0);
        (self.a + self.b * pow(e, self.n)) * self.rate_factor(rate).0
    }

    /// strength · (1 − θᵐ), clamped ≥ 0.
    #[inline(always)]
    fn sigma_y_parts(&self, _eps: f64, _rate: f64, _temp: f64, strength: f64, thermal: f64) -> f64 {
        let s = strength * thermal;
        if s < 0.0 { 0.0 } else { s }
    }

    #[inline]
    fn flow(&self, eps: f64, rate: f64, temp: f64) -> Flow {
        self.flow_at(eps, rate, temp, self.thermal_factor(temp))
    }

    #[inline(always)]
    fn thermal_part(&self, temp: f64) -> f64 {
        self.thermal_factor(temp)
    }

    /// `th` = 1 − θᵐ at `_temp` ([`JohnsonCook::thermal_factor`]).
    #[inline(always)]
    fn flow_at(&self, eps: f64, rate: f64, temp: f64, th: f64) -> Flow {
        self.flow_and_strength_at(eps, rate, temp, th).0
    }

    /// σ = (h·r)·th with the strength h·r: `strength_part`'s bits (the hardening's ε̄ⁿ is `pow`'s, `pow_pair`), so
    /// σ is `sigma_y_parts`' (σ_y clamped at 0 either way).
    #[inline(always)]
    fn flow_and_strength_at(&self, eps: f64, rate: f64, _temp: f64, th: f64) -> (Flow, f64) {
        let (h, dh) = self.hardening(eps);
        let (r, dr) = self.rate_factor(rate);
        let strength = h * r;
        (Flow { sigma: strength * th, d_eps: dh * r * th, d_rate: h * dr * th }.clamped(), strength)
    }

    #[inline(always)]
    fn melt_temperature(&self) -> f64 {
        self.melt_temp
    }
}
