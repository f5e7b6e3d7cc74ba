//! Klippel's optimiser benchmark (klippel-constitutive.md §6.3, Eq. 9.13, Tabs. 9.23–9.25): the adiabatic
//! Johnson–Cook flow curve of 50SiB8 at the reference rate, integrated by explicit Euler in the plastic strain
//! (σ_{k+1} = σ_y(ε_{k+1}, ε̇0, T_k), T_{k+1} = T_k + η σ_{k+1} Δε/(ρ c_p)), sampled at ε = 0, 0.3, …, 3.0, and the
//! cost c = Σ_j (σ_j − σ_sample,j)² [MPa²] an optimiser minimises over (A, B, C, m, n).

use crate::kernels::material::{FlowStress, JohnsonCook, plastic_heating};

/// Tab. 9.23: the sampled curve [MPa] at ε_pl = 0, 0.3, …, 3.0.
pub const TAB_9_23: [f64; 11] = [423.5, 911.7, 994.6, 1024.5, 1028.5, 1017.3, 996.3, 968.7, 936.6, 901.7, 864.9];

/// The benchmark's conditions (§6.3): η_TQ, T_init, ρ, c_p, ε̇ = ε̇0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conditions {
    pub taylor_quinney: f64,
    pub initial_temp: f64,
    pub density: f64,
    pub specific_heat: f64,
    /// The strain step of the explicit integration (§6.3: 1e-5).
    pub step: f64,
}

impl Conditions {
    /// Klippel's: η = 0.9, T = 300 K, ρ = 7850 kg/m³, c_p = 466 J/(kg K), Δε = 1e-5.
    pub const KLIPPEL: Conditions =
        Conditions { taylor_quinney: 0.9, initial_temp: 300.0, density: 7850.0, specific_heat: 466.0, step: 1e-5 };
}

/// The curve of `jc` at the samples ε = 0.3 j, j = 0..=10 [MPa], at the reference rate.
pub fn adiabatic_curve(jc: &JohnsonCook, c: &Conditions) -> [f64; 11] {
    let rate = jc.ref_rate;
    let mut t = c.initial_temp;
    let mut out = [0.0; 11];
    out[0] = jc.sigma_y(0.0, rate, t) * 1e-6;
    let per_sample = (0.3 / c.step).round() as u64;
    for k in 1..=10 * per_sample {
        let s = jc.sigma_y(k as f64 * c.step, rate, t);
        t += plastic_heating(c.taylor_quinney, s, c.step, c.density, c.specific_heat);
        if k % per_sample == 0 {
            out[(k / per_sample) as usize] = s * 1e-6;
        }
    }
    out
}

/// Eq. 9.13: Σ_j (σ_j − σ_sample,j)² [MPa²].
pub fn cost(curve: &[f64; 11], samples: &[f64; 11]) -> f64 {
    curve.iter().zip(samples).map(|(a, b)| (a - b) * (a - b)).sum()
}

/// A 50SiB8 Johnson–Cook set with (A, B [Pa], C, m, n) and the library's other constants (ε̇0 = 1e-3/s,
/// T_ref = 293.15 K, T_m = 2006 K, the clamped ln rate form).
pub fn jc_50sib8(a: f64, b: f64, c: f64, m: f64, n: f64) -> JohnsonCook {
    JohnsonCook {
        a,
        b,
        c,
        n,
        m,
        ref_rate: 1e-3,
        ref_temp: 293.15,
        melt_temp: 2006.0,
        rate_form: crate::kernels::material::RATE_FORM_CLAMP,
        _pad: 0,
    }
}
