//! Bilinear J2 plasticity: linear isotropic hardening (the Taylor-bar benchmark material).

use super::{Flow, FlowStress};
use bytemuck::{Pod, Zeroable};

/// Linear isotropic hardening: σ_y = σ_y0 + H ε̄, clamped ≥ 0 (H < 0 softens down to zero strength).
///
/// H is the **plastic modulus** dσ_y/dε̄ (the slope of stress against *plastic* strain), not the tangent modulus
/// E_t of the uniaxial stress–total-strain curve; the two are related by H = E E_t/(E − E_t), E_t = E H/(E + H).
/// The Taylor-bar benchmark (E = 117 GPa, ν = 0.35, σ_y0 = 400 MPa, H = 100 MPa) quotes the plastic modulus.
/// σ_y depends neither on the rate nor on the temperature; `melt_temp` only reports the melt (for the heating
/// cap), +∞ when none is given.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Bilinear {
    /// σ_y0: initial yield stress [Pa].
    pub yield_stress: f64,
    /// H: plastic (hardening) modulus dσ_y/dε̄ [Pa].
    pub plastic_modulus: f64,
    /// Melt temperature [K] (reported only).
    pub melt_temp: f64,
}

impl Bilinear {
    /// The tangent modulus E_t = E H/(E + H) of the uniaxial stress–strain curve for Young's modulus `e` [Pa].
    #[inline(always)]
    pub fn tangent_modulus(&self, e: f64) -> f64 {
        e * self.plastic_modulus / (e + self.plastic_modulus)
    }
}

impl FlowStress for Bilinear {
    #[inline]
    fn sigma_y(&self, eps: f64, _rate: f64, _temp: f64) -> f64 {
        let s = self.yield_stress + self.plastic_modulus * eps;
        if s < 0.0 { 0.0 } else { s }
    }

    #[inline]
    fn flow(&self, eps: f64, _rate: f64, _temp: f64) -> Flow {
        Flow { sigma: self.yield_stress + self.plastic_modulus * eps, d_eps: self.plastic_modulus, d_rate: 0.0 }
            .clamped()
    }

    #[inline(always)]
    fn melt_temperature(&self) -> f64 {
        self.melt_temp
    }
}
