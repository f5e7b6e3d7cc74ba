//! Steinberg–Cochran–Guinan–Lund flow stress with the SCG shear-modulus and melt models
//! (klippel-constitutive.md §2.4, Eqs. 8.26–8.32, Tabs 8.15–8.17: OFHC copper).

// `!(a > b)` is deliberate: it is true for NaN, which must take the safe branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::{Flow, FlowStress, fmax, fmin, pow};
use bytemuck::{Pod, Zeroable};

/// Bisection steps for σ_th on [0, σ_p]: 2^-64·σ_p ≈ 1e-12 Pa for σ_p = 20 MPa; the loop also stops when the
/// interval cannot be halved any more.
pub const SCGL_BISECTION_STEPS: u32 = 64;

/// SCGL (klippel-constitutive.md §2.4):
///
/// * Flow stress (Eqs. 8.28–8.30): σ_y = (min(σ_a f(ε̄), σ_max) + σ_th(ε̄̇, T))·μ(p, T)/μ0,
///   f(ε̄) = (1 + β(ε̄ + ε_i))ⁿ, with σ_th ∈ [0, σ_p] the root of
///   ε̄̇ = [ (1/C1) exp((2U_k/(k_B T))(1 − σ_th/σ_p)²) + C2/σ_th ]⁻¹, found by bisection on [0, σ_p]
///   (§8.3.3.4). If even σ_th = σ_p gives a lower rate, σ_th = σ_p (the cap of Eq. 8.29).
/// * Shear modulus (Eq. 8.26): μ(p, T) = μ0 + (∂μ/∂p)·p/η^(1/3) + (∂μ/∂T)(T − T_ref), clamped ≥ 0; ∂μ/∂T is
///   negative (the thesis' Tab 8.16 prints it positive, klippel [NOTE], erratum 13).
/// * Melt (Eq. 8.27): T_f(η) = T_m0 exp(2a(1 − 1/η)) η^(2(Γ0 − a − 1/3)) for η ≥ 1, T_m0 for η < 1.
///   At T ≥ T_f the shear modulus is 0, so σ_y = 0 (the SCG melt rule: this model's melt treatment, instead of the
///   T ≤ T_m − 1 K clamp of the JC family). T is floored at 1 K in the thermal-activation term.
/// * Low rates: σ_th → 0 as ε̄̇ → 0 (the C2/σ_th drag term dominates); ε̄̇ ≤ 0 gives σ_th = 0 and the limiting
///   slope ∂σ_th/∂ε̄̇ = C2.
/// * State: μ and T_f need the particle's pressure p and compression η = ρ/ρ0; they are fields of this block
///   (frozen during the return, like T). [`Scgl::at_state`] returns a copy for one particle; the library sets
///   p = 0, η = 1.
/// * The activation energy is stored as U_k/k_B [K].
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Scgl {
    /// σ_a: athermal yield stress [Pa].
    pub sigma_a: f64,
    /// σ_max: cap of σ_a f(ε̄) [Pa].
    pub sigma_max: f64,
    /// β: hardening coefficient [-].
    pub beta: f64,
    /// ε_i: initial plastic strain [-].
    pub eps_i: f64,
    /// n: hardening exponent [-].
    pub n: f64,
    /// C1: [1/s].
    pub c1: f64,
    /// U_k/k_B: activation energy over Boltzmann's constant [K].
    pub uk_over_kb: f64,
    /// σ_p: Peierls stress, the cap of σ_th [Pa].
    pub sigma_p: f64,
    /// C2: drag coefficient [Pa·s].
    pub c2: f64,
    /// μ0: shear modulus at the reference state [Pa].
    pub mu0: f64,
    /// ∂μ/∂p [-].
    pub dmu_dp: f64,
    /// ∂μ/∂T [Pa/K] (negative).
    pub dmu_dt: f64,
    /// Reference temperature of μ(T) [K] (300 K in Eq. 8.26).
    pub ref_temp: f64,
    /// T_m0: melt temperature at η = 1 [K].
    pub melt_temp0: f64,
    /// Γ0: Grüneisen coefficient [-].
    pub gamma0: f64,
    /// a: the SCG melt model's coefficient [-].
    pub melt_a: f64,
    /// Pressure p (positive in compression) [Pa]: particle state.
    pub pressure: f64,
    /// η = ρ/ρ0 [-]: particle state.
    pub eta: f64,
}

impl Scgl {
    /// A copy with the particle's pressure [Pa] and compression η = ρ/ρ0.
    #[inline(always)]
    pub fn at_state(&self, pressure: f64, eta: f64) -> Scgl {
        Scgl { pressure, eta, ..*self }
    }

    /// SCG melt temperature T_f(η) (Eq. 8.27) [K].
    #[inline(always)]
    pub fn melt_at(&self, eta: f64) -> f64 {
        if eta < 1.0 {
            self.melt_temp0
        } else {
            self.melt_temp0
                * libm::exp(2.0 * self.melt_a * (1.0 - 1.0 / eta))
                * pow(eta, 2.0 * (self.gamma0 - self.melt_a - 1.0 / 3.0))
        }
    }

    /// SCG shear modulus μ(p, T) (Eq. 8.26) [Pa]: 0 at T ≥ T_f, clamped ≥ 0.
    #[inline(always)]
    pub fn shear_modulus(&self, temp: f64) -> f64 {
        if temp >= self.melt_at(self.eta) {
            return 0.0;
        }
        let mu = self.mu0 + self.dmu_dp * self.pressure / libm::cbrt(self.eta) + self.dmu_dt * (temp - self.ref_temp);
        if mu < 0.0 { 0.0 } else { mu }
    }

    /// The rate at which the thermal stress is σ: ε̄̇(σ) = 1/Q(σ), Q(σ) = exp(K(1 − σ/σ_p)²)/C1 + C2/σ
    /// with K = 2U_k/(k_B T). Returns Q(σ) [s].
    #[inline(always)]
    fn inverse_rate(&self, sigma: f64, k: f64) -> f64 {
        let y = 1.0 - sigma / self.sigma_p;
        libm::exp(k * y * y) / self.c1 + self.c2 / sigma
    }

    /// σ_th(ε̄̇, T) and ∂σ_th/∂ε̄̇ (Eq. 8.30; implicit differentiation: dσ/dε̄̇ = Q²/(−Q'(σ))).
    #[inline]
    pub fn thermal_stress(&self, rate: f64, temp: f64) -> (f64, f64) {
        if !(rate > 0.0) {
            return (0.0, self.c2);
        }
        let t = fmax(temp, 1.0);
        let k = 2.0 * self.uk_over_kb / t;
        let target = 1.0 / rate;
        if self.inverse_rate(self.sigma_p, k) >= target {
            return (self.sigma_p, 0.0);
        }
        // Q decreases in σ on (0, σ_p]: Q(lo) > target ≥ Q(hi).
        let mut lo = 0.0;
        let mut hi = self.sigma_p;
        let mut i = 0;
        while i < SCGL_BISECTION_STEPS {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            if self.inverse_rate(mid, k) > target {
                lo = mid;
            } else {
                hi = mid;
            }
            i += 1;
        }
        let s = hi;
        let y = 1.0 - s / self.sigma_p;
        let dq = -libm::exp(k * y * y) / self.c1 * 2.0 * k * y / self.sigma_p - self.c2 / (s * s);
        let slope = target * target / -dq;
        (s, if slope.is_finite() { slope } else { 0.0 })
    }

    /// Athermal part min(σ_a (1 + β(ε̄ + ε_i))ⁿ, σ_max) and its ε̄-derivative (0 where capped).
    #[inline(always)]
    pub fn athermal(&self, eps: f64) -> (f64, f64) {
        let base = 1.0 + self.beta * (fmax(eps, 0.0) + self.eps_i);
        let f = self.sigma_a * pow(base, self.n);
        if f < self.sigma_max {
            (f, self.sigma_a * self.n * self.beta * pow(base, self.n - 1.0))
        } else {
            (fmin(f, self.sigma_max), 0.0)
        }
    }
}

impl FlowStress for Scgl {
    #[inline]
    fn sigma_y(&self, eps: f64, rate: f64, temp: f64) -> f64 {
        self.flow(eps, rate, temp).sigma
    }

    #[inline]
    fn flow(&self, eps: f64, rate: f64, temp: f64) -> Flow {
        let ratio = self.shear_modulus(temp) / self.mu0;
        if ratio == 0.0 {
            return Flow::ZERO;
        }
        let (ath, dath) = self.athermal(eps);
        let (th, dth) = self.thermal_stress(rate, temp);
        Flow { sigma: (ath + th) * ratio, d_eps: dath * ratio, d_rate: dth * ratio }.clamped()
    }

    #[inline(always)]
    fn melt_temperature(&self) -> f64 {
        self.melt_at(self.eta)
    }
}
