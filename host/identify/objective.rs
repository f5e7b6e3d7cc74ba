//! Klippel's objective (klippel-constitutive.md §6.2, Eqs. 9.14–9.17): per experiment
//! ΔF² = w_c (F_c^sim − F_c^exp)² + w_f (F_f^sim − F_f^exp)² (w_c = w_f = 1 in the thesis; forces per mm of
//! width, so ΔF² is in N²/mm², which the thesis writes N²), plus, beyond the thesis (its §9.8.4 asks for it),
//! w_h (h^sim − h^exp)² with the chip thickness h in µm. Over experiments the terms are summed (Eq. 9.17) or,
//! with `combine = "mean"`, averaged. A term whose measured value has no simulated counterpart (a failed run, a
//! chip too short to measure) makes the objective NaN, which the optimisers rank last.

use super::file::{Measured, Objective};

/// What a run gave: F_c, F_f [N/mm], chip thickness [µm]; None where not measured.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Simulated {
    pub fc: Option<f64>,
    pub ff: Option<f64>,
    pub chip: Option<f64>,
}

/// One experiment's term: Eq. 9.14 (with the chip term where its weight is positive).
pub fn experiment_term(measured: &Measured, sim: &Simulated, w: &Objective) -> f64 {
    let sq = |weight: f64, exp: Option<f64>, sim: Option<f64>| match (exp, weight > 0.0) {
        (Some(e), true) => sim.filter(|s| s.is_finite()).map_or(f64::NAN, |s| weight * (s - e) * (s - e)),
        _ => 0.0,
    };
    sq(w.fc_weight, measured.fc, sim.fc)
        + sq(w.ff_weight, measured.ff, sim.ff)
        + sq(measured.chip_weight, measured.chip, sim.chip)
}

/// The objective over experiments: Eq. 9.17's sum, or the mean. NaN when any term is.
pub fn combine(terms: &[f64], w: &Objective) -> f64 {
    let sum: f64 = terms.iter().sum();
    if w.mean && !terms.is_empty() { sum / terms.len() as f64 } else { sum }
}
