//! Ductile damage (klippel-constitutive.md §2.6; Klippel §3.6, §7.4, §8.2.2): initiation by a fracture strain
//! (Johnson–Cook, JC-GG, Rice–Tracey) with linear accumulation of ω, then Hillerborg's energy-regularised
//! evolution of D with the exponential degradation, and the interaction mask of fully damaged neighbours in
//! tension. Weak coupling: the plastic update runs first and [`damage_step`] after it, from its Δε̄ and σ_y
//! (`sph::plastic`).
//!
//! Conventions (docs/damage.md):
//! - The particles' stored deviatoric stress is the **undamaged** (effective) stress S̄ (the Jaumann update and the
//!   radial return act on it, Eq. 7.29's effective-stress concept); the stress the momentum equation sees is
//!   degraded in the pre-pass ([`multiplier`], [`degraded_pressure`]).
//! - D is Klippel's "D" of Eqs. 7.23–7.25, the dissipated energy over G_f; the stress multiplier is exp(−D), and
//!   full damage is D ≥ −ln 0.01 ([`FULL_DAMAGE`]), the digest's consistent reading of Eqs. 7.26/7.27 ([NOTE] §2.6).
//! - Triaxiality σ* = σ_H/σ_y = −p/σ_y (tension positive) with the current yield stress, as the VUMAT.
//! - D3: the fracture strain uses exp(−|D3| σ*), so the library's D3 are stored as printed (Ti6Al4V +0.48, 50SiB8
//!   ±1.5643) and both give a strain that falls with triaxiality (§2.6 [NOTE — sign of D3]).

use crate::real::Real;
use bytemuck::{Pod, Zeroable};

/// The fracture-strain model of [`DamageParams::model`].
pub mod model {
    /// Johnson–Cook, Eq. 3.165.
    pub const JC: u32 = 0;
    /// Johnson–Cook with Gerstgrasser's temperature polynomial, Eqs. 7.35–7.36.
    pub const JC_GG: u32 = 1;
    /// Rice–Tracey, Eq. 3.163.
    pub const RICE_TRACEY: u32 = 2;
}

/// The bits of [`DamageParams::flags`].
pub mod switches {
    /// The interaction mask of fully damaged neighbours in tension (Eqs. 7.30–7.34).
    pub const MASK: u32 = 1;
    /// Fully damaged particles leave the interactions and keep their last position (SHTB, §7.4.3).
    pub const DELETE: u32 = 2;
}

/// D at which a particle is fully damaged: −ln 0.01, 99 % of G_f dissipated (Eq. 3.171; the digest's [NOTE] on
/// Eqs. 7.26/7.27).
pub const FULL_DAMAGE: f64 = 4.605_170_185_988_091;

/// The floor of the fracture strain (the VUMAT's guard: ε_f ≤ 0 → 1e-9).
pub const MIN_FRACTURE_STRAIN: f64 = 1e-9;

/// The cap of the JC-GG temperature term (Eq. 7.36; the VUMAT caps at 2.5, `min`, not the printed `max`).
pub const JC_GG_T_CAP: f64 = 2.5;

/// The mask value of a deleted particle (the mask field holds 1 (interacting), 0 (masked) or this).
pub const DELETED: f64 = -1.0;

/// Damage constants of a run (one block, read by the plastic pass and the pre-pass). `#[repr(C)]`, two u32 then
/// f64s only: no padding (144 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct DamageParams {
    /// [`model`].
    pub model: u32,
    /// [`switches`].
    pub flags: u32,
    /// D1..D8 of JC / JC-GG (D6..D8 JC-GG only); Rice–Tracey: d[0] = D_RT1, d[1] = D_RT2.
    pub d: [f64; 8],
    /// ε̇0 of ε̇* = ε̄̇/ε̇0 [1/s].
    pub ref_rate: f64,
    /// T_ref and T_melt of T* = (T − T_ref)/(T_melt − T_ref) [K].
    pub ref_temp: f64,
    pub melt_temp: f64,
    /// Fracture energy G_f [J/m²]; 0: no softening, full damage at initiation (ω = 1).
    pub fracture_energy: f64,
    /// c0² and ρ0 of the EOS p = c0²(ρ − ρ0(T)), for the triaxiality in the plastic pass.
    pub c0sq: f64,
    pub rho0: f64,
    /// The run's volumetric thermal expansion 3α [1/K] (0: none) and its reference temperature T0 [K]: ρ0(T) of
    /// `material::eos::reference_density`, the pre-pass's EOS.
    pub expansion: f64,
    pub expansion_t0: f64,
    /// Dimension (2 or 3) of L_char: √V in 2D, ∛V in 3D.
    pub dim: f64,
    /// The bulk modulus K [Pa] of the volumetric elastic energy p²/(2K) ([`released_density`]).
    pub bulk: f64,
}

/// Stress triaxiality σ* = σ_H/σ_eq = −p/σ_eq (Eq. 3.164, tension positive; p positive in compression). 0 where
/// σ_eq ≤ 0 (no deviatoric stress: the accumulation it feeds has Δε̄ = 0 there).
#[inline(always)]
pub fn triaxiality(pressure: f64, sigma_eq: f64) -> f64 {
    if sigma_eq > 0.0 { -pressure / sigma_eq } else { 0.0 }
}

/// ε̇* = ε̄̇/ε̇0 with the VUMAT's guard ε̇* < 1 → 1.
#[inline(always)]
fn rate_ratio(p: &DamageParams, rate: f64) -> f64 {
    let r = rate / p.ref_rate;
    if r > 1.0 { r } else { 1.0 }
}

/// T* = (T − T_ref)/(T_melt − T_ref) (not clamped: JC-GG's polynomial is fitted over it, the VUMAT does not clamp).
#[inline(always)]
fn homologous(p: &DamageParams, temp: f64) -> f64 {
    (temp - p.ref_temp) / (p.melt_temp - p.ref_temp)
}

/// The triaxiality part D1 + D2 exp(−|D3| σ*) (Eq. 3.165 with the sign convention of the module doc).
#[inline(always)]
fn stress_part(p: &DamageParams, triax: f64) -> f64 {
    p.d[0] + p.d[1] * libm::exp(-libm::fabs(p.d[2]) * triax)
}

/// The guard ε_f ≤ 0 → 1e-9 (VUMAT).
#[inline(always)]
fn floor(e: f64) -> f64 {
    if e > MIN_FRACTURE_STRAIN { e } else { MIN_FRACTURE_STRAIN }
}

/// Johnson–Cook fracture strain (Eq. 3.165): ε_f = (D1 + D2 exp(−|D3| σ*))(1 + D4 ln ε̇*)(1 + D5 T*), with the
/// VUMAT's guards ε̇* < 1 → 1 and ε_f ≤ 0 → 1e-9.
#[inline(always)]
pub fn jc_fracture_strain(p: &DamageParams, triax: f64, rate: f64, temp: f64) -> f64 {
    let rate_part = 1.0 + p.d[3] * libm::log(rate_ratio(p, rate));
    floor(stress_part(p, triax) * rate_part * (1.0 + p.d[4] * homologous(p, temp)))
}

/// JC-GG's temperature term (Eq. 7.36): min(1 + D5 T* + D6 T*² + D7 T*³ + D8 T*⁴, 2.5).
#[inline(always)]
pub fn jc_gg_temperature_term(p: &DamageParams, temp: f64) -> f64 {
    let t = homologous(p, temp);
    let v = 1.0 + t * (p.d[4] + t * (p.d[5] + t * (p.d[6] + t * p.d[7])));
    if v > JC_GG_T_CAP { JC_GG_T_CAP } else { v }
}

/// JC-GG fracture strain (Eq. 7.35): (D1 + D2 exp(−|D3| σ*))(1 + D4 ln ε̇*) T_term, the guards as
/// [`jc_fracture_strain`].
#[inline(always)]
pub fn jc_gg_fracture_strain(p: &DamageParams, triax: f64, rate: f64, temp: f64) -> f64 {
    let rate_part = 1.0 + p.d[3] * libm::log(rate_ratio(p, rate));
    floor(stress_part(p, triax) * rate_part * jc_gg_temperature_term(p, temp))
}

/// Rice–Tracey fracture strain (Eq. 3.163): ε_f = D_RT1 exp(D_RT2 σ*) (D_RT2 < 0 for a strain falling with
/// triaxiality; taken as given), floored at 1e-9.
#[inline(always)]
pub fn rice_tracey_fracture_strain(p: &DamageParams, triax: f64) -> f64 {
    floor(p.d[0] * libm::exp(p.d[1] * triax))
}

/// The fracture strain of the run's model.
#[inline(always)]
pub fn fracture_strain(p: &DamageParams, triax: f64, rate: f64, temp: f64) -> f64 {
    match p.model {
        model::JC_GG => jc_gg_fracture_strain(p, triax, rate, temp),
        model::RICE_TRACEY => rice_tracey_fracture_strain(p, triax),
        _ => jc_fracture_strain(p, triax, rate, temp),
    }
}

/// The characteristic length of a particle of volume V (Eq. 7.24): √V in 2D (V per unit depth, an area), ∛V in 3D.
#[inline(always)]
pub fn char_length(vol: f64, dim: f64) -> f64 {
    // `Real::sqrt`: correctly rounded on both sides (libm's generic sqrt reads a table the PTX cannot link).
    if dim > 2.5 { libm::cbrt(vol) } else { Real::sqrt(vol) }
}

/// The state of one particle's damage: ω (initiation, Eq. 3.166) and D (evolution, Eq. 7.25).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DamageState {
    pub omega: f64,
    pub d: f64,
}

/// One step's damage update after the plastic update (weak coupling, §7.4.2), from the step's plastic strain
/// increment Δε̄ ≥ 0, the return's flow stress σ_y, the triaxiality, ε̄̇, T and the particle volume V:
/// - before initiation, ω += Δε̄/ε_f (Eq. 3.166), capped at 1;
/// - after it (ω = 1), ΔD = L_char σ_y Δε̄/G_f (Eq. 7.23) with L_char from V ([`char_length`]), D capped at
///   [`FULL_DAMAGE`]; with G_f = 0, D = [`FULL_DAMAGE`] at initiation.
///
/// The step that completes ω gives its remaining increment to D (the part of Δε̄ beyond ω = 1).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn damage_step(
    p: &DamageParams,
    s: DamageState,
    d_eps: f64,
    flow_stress: f64,
    triax: f64,
    rate: f64,
    temp: f64,
    vol: f64,
) -> DamageState {
    if d_eps.is_nan() || d_eps <= 0.0 || s.d >= FULL_DAMAGE {
        return s;
    }
    let mut out = s;
    let mut rest = d_eps;
    if s.omega < 1.0 {
        let ef = fracture_strain(p, triax, rate, temp);
        let dw = d_eps / ef;
        if s.omega + dw < 1.0 {
            out.omega = s.omega + dw;
            return out;
        }
        // The part of Δε̄ that completes ω; the rest drives D.
        rest = d_eps - (1.0 - s.omega) * ef;
        out.omega = 1.0;
    }
    if p.fracture_energy.is_nan() || p.fracture_energy <= 0.0 {
        out.d = FULL_DAMAGE;
        return out;
    }
    let dd = char_length(vol, p.dim) * flow_stress * rest / p.fracture_energy;
    let d = out.d + if dd > 0.0 { dd } else { 0.0 };
    out.d = if d < FULL_DAMAGE { d } else { FULL_DAMAGE };
    out
}

/// The stress multiplier 1 − d = exp(−D) (the consistent reading of Eqs. 7.26/7.27), 0 at full damage.
#[inline(always)]
pub fn multiplier(d: f64) -> f64 {
    if d >= FULL_DAMAGE {
        0.0
    } else if d > 0.0 {
        libm::exp(-d)
    } else {
        1.0
    }
}

/// True at full damage.
#[inline(always)]
pub fn is_full(d: f64) -> bool {
    d >= FULL_DAMAGE
}

/// The degraded stress of Eqs. 3.172–3.175/7.27–7.28: the deviatoric part times `m` ([`multiplier`]) and the
/// pressure (positive in compression) times `m` only in tension (p < 0): this returns the degraded pressure, the
/// caller scales the deviator by m.
#[inline(always)]
pub fn degraded_pressure<R: Real>(m: R, pressure: R) -> R {
    if pressure < R::ZERO { m * pressure } else { pressure }
}

/// The elastic energy per unit volume of a particle acting with multiplier k ([`multiplier`]), stored deviator
/// S:S = `ss` and undamaged pressure p (positive in compression), in the effective-stress reading (Lemaitre's
/// continuum damage: the degraded stress kS̄ is the stress of the damaged moduli kG, kK):
///   ψ = k S̄:S̄/(4G) + k_p p²/(2K),  k_p = k in tension (p < 0), 1 in compression.
/// Its rate is the power of the degraded stress on the elastic strain rate plus (dk/dt) times the undamaged
/// energies, which the degradation releases ([`released_density`]; docs/damage.md, "Energy"). k = 1 gives the
/// undamaged energy per unit volume S̄:S̄/(4G) + p²/(2K) bit for bit.
#[inline(always)]
pub fn elastic_density<R: Real>(k: R, ss: R, shear: R, pressure: R, bulk: R) -> R {
    let kp = if pressure < R::ZERO { k } else { R::ONE };
    k * ss / (R::from_f64(4.0) * shear) + kp * pressure * pressure / (R::from_f64(2.0) * bulk)
}

/// The elastic energy per unit volume the degradation releases when the multiplier falls from `k_old` to `k_new`
/// at fixed stress: ψ(k_old) − ψ(k_new) of [`elastic_density`] = (k_old − k_new)(S̄:S̄/(4G) + [p < 0] p²/(2K)),
/// ≥ 0 since D never falls. Booked as dissipation in the energy balance (energy.csv's `damage_dissipation`).
#[inline(always)]
pub fn released_density(k_old: f64, k_new: f64, ss: f64, shear: f64, pressure: f64, bulk: f64) -> f64 {
    let vol = if pressure < 0.0 { pressure * pressure / (2.0 * bulk) } else { 0.0 };
    (k_old - k_new) * (ss / (4.0 * shear) + vol)
}

/// The interaction mask F_j (Eqs. 7.30–7.34) of a particle with damage D and undamaged pressure p: 0 for a fully
/// damaged particle in tension (p < 0), else 1; with deletion on, [`DELETED`] for any fully damaged particle.
#[inline(always)]
pub fn mask_value(flags: u32, d: f64, pressure: f64) -> f64 {
    if !is_full(d) {
        1.0
    } else if flags & switches::DELETE != 0 {
        DELETED
    } else if flags & switches::MASK != 0 && pressure < 0.0 {
        0.0
    } else {
        1.0
    }
}

/// G_f from the fracture toughness (Eq. 3.169, plane strain): K_1C² (1 − ν²)/E.
#[inline(always)]
pub fn fracture_energy_from_toughness(k1c: f64, young: f64, poisson: f64) -> f64 {
    k1c * k1c * (1.0 - poisson * poisson) / young
}
