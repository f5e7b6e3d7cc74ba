//! The radial return of Röthlin's 2D code [C2D] (MFREE_IWF, `do_plasticity_johnson_cook` and `solve_secant` of
//! its `actions_gpu.cu` / `plasticity.cuh`), reproduced for `model = "mfree_iwf"` (docs/validation.md, "The
//! original model"). swarf's own return is [`super::radial_return`]; nothing here runs by default.
//!
//! The procedure, as that code computes it (our own code, from the formulas; the original is GPLv3):
//! 1. the trial norm n = √(S_xx² + S_yy² + S_zz² + S_xy²), **without the factor 2 on S_xy²** (a bug,
//!    roethlin-solver.md §11 erratum 25a) where `c2d_norm` is set, else the true ‖S‖ (to isolate the bug);
//!    the square root is taken in f32 (`sqrtf` of a double), as the code does;
//! 2. the elastic check σ_vm < σ_y(ε̄, **ε̄̇ of the previous step**, T) with σ_vm = √(3 J2) of σ = S − pI, also in
//!    f32 (p cancels in J2 and is left out here); swarf checks at ε̄̇ = 0 (klippel §8 H5). Elastic: ε̄̇ = 0;
//! 3. Δλ from g(Δλ) = n − 2GΔλ − √(2/3) σ_y(ε̄ + √(2/3) max(Δλ, 0), √(2/3) max(Δλ, 0)/Δt, T) = 0 by the code's
//!    secant iteration: from Δλ₀ = max(ε̄̇_old Δt √(2/3), 1e-8), slope (g(Δλ) − g(1.01 Δλ))/(Δλ − 1.01 Δλ), a negative
//!    iterate replaced by −0.1 × itself, stopped when |Δλ_{k+1} − Δλ_k| < 1e-6 (absolute) or after 102 updates
//!    (the updated iterate is returned either way). No bracket: where g(0) ≤ 0 (possible with the norm bug on a
//!    shear-dominated state that passed the von Mises check) the iteration settles on a small positive Δλ, as the
//!    code's does;
//! 4. S ← S − (S/n) Δλ 2G, the scaling 1 − 2GΔλ/n with the same n (so with the bug a pure shear state returns to
//!    √2 σ_y in von Mises, not σ_y);
//! 5. ε̄ ← ε̄ + √(2/3) max(Δλ, 0) and ε̄̇ = √(2/3) max(Δλ, 0)/Δt with `sqrtf(2.0/3.0)` and `fmaxf(Δλ, 0)`, i.e. both
//!    factors rounded to f32, as the code writes them (the stress scaling uses the f64 Δλ).
//!
//! The plastic heating that follows (t_q σ_y(ε̄_new, ε̄̇_new, T) Δε̄/(ρ c_p)) is `sph::plastic`'s, the same formula
//! as the code's. Not reproduced (docs/validation.md lists them): nvcc's FMA contraction and summation order, the
//! code's flow stress without swarf's clamps (θ < 0 and T ≥ T_m are not reached in the cuts compared), the missing
//! melt cap of its heating.

use super::{FlowStress, ReturnResult, ReturnStatus};
use crate::real::Real;

/// The code's absolute stopping tolerance on the Δλ step.
pub const C2D_TOLERANCE: f64 = 1e-6;
/// The code's iteration limit (`max_iter`): it returns after the update in which the counter, 0 at the first, exceeds
/// it (the 102nd).
pub const C2D_MAX_ITER: u32 = 100;
/// The code's secant support ratio.
pub const C2D_SECANT_RATIO: f64 = 1.01;
/// The code's smallest initial Δλ.
pub const C2D_MIN_GUESS: f64 = 1e-8;

/// `sqrtf(x)` of a double as CUDA C evaluates it: x rounded to f32, the correctly rounded f32 root, widened.
#[inline(always)]
pub fn sqrt_f32(x: f64) -> f64 {
    <f32 as Real>::sqrt(x as f32) as f64
}

/// `fmax(x, 0)`: x where x > 0, else 0 (NaN gives 0, as CUDA's fmax).
#[inline(always)]
fn pos(x: f64) -> f64 {
    if x > 0.0 { x } else { 0.0 }
}

/// The square of the trial norm of step 1: xx² + yy² + zz² + xy² + xz² + yz² with `c2d_norm` (the off-diagonals
/// once: erratum 25a; the 2D code has only xy), else ‖S‖² with them twice.
#[inline(always)]
pub fn c2d_norm_squared(s: &[f64; 6], c2d_norm: bool) -> f64 {
    let [xx, xy, xz, yy, yz, zz] = *s;
    let off = xy * xy + xz * xz + yz * yz;
    let off = if c2d_norm { off } else { 2.0 * off };
    xx * xx + yy * yy + zz * zz + off
}

/// σ_vm of step 2: √(xx² + yy² + zz² − xx yy − xx zz − yy zz + 3 (xy² + xz² + yz²)), the root in f32.
#[inline(always)]
pub fn c2d_von_mises(s: &[f64; 6]) -> f64 {
    let [xx, xy, xz, yy, yz, zz] = *s;
    sqrt_f32((xx * xx + yy * yy + zz * zz) - xx * yy - xx * zz - yy * zz + 3.0 * (xy * xy + xz * xz + yz * yz))
}

/// The return of one material point as [C2D] computes it (module doc). Arguments as [`super::radial_return`]'s:
/// `s_trial` (xx, xy, xz, yy, yz, zz) [Pa], `eps`, `rate` of the previous step, `temp` [K], `shear` G [Pa], `dt`
/// [s]; `c2d_norm` selects the norm without the factor 2 (the bug). The result's `flow_stress` (and `strength`,
/// `thermal`) is σ_y at (ε̄_new, ε̄̇_new, T), as swarf's; an elastic step's at (ε̄, 0, T).
///
/// Inlined into `sph::plastic`'s particle update for the original model, which is itself a function of its own
/// (`c2d_particle`, never inlined): inlined into the default's corrector it nearly doubled
/// `swarf_step_finish_jc_2d_f64` (3901 to 7335 PTX lines); called from it, the model, the trial stress and the
/// result went through local memory on every particle.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn c2d_return<M: FlowStress + ?Sized>(
    model: &M,
    s_trial: &[f64; 6],
    eps: f64,
    rate: f64,
    temp: f64,
    shear: f64,
    dt: f64,
    c2d_norm: bool,
) -> ReturnResult {
    let s23 = super::sqrt(2.0 / 3.0);
    let norm = sqrt_f32(c2d_norm_squared(s_trial, c2d_norm));
    let svm = c2d_von_mises(s_trial);
    let thermal = model.thermal_part(temp);
    if svm < model.sigma_y(eps, rate, temp) {
        let strength = model.strength_part(eps, 0.0);
        return ReturnResult {
            stress: *s_trial,
            eps,
            rate: 0.0,
            delta_lambda: 0.0,
            iterations: 0,
            status: ReturnStatus::Elastic,
            flow_stress: model.sigma_y_parts(eps, 0.0, temp, strength, thermal),
            strength,
            thermal,
        };
    }
    let g = |dl: f64| {
        let d = pos(dl);
        norm - 2.0 * shear * dl - s23 * model.sigma_y(eps + s23 * d, s23 * d / dt, temp)
    };
    let mut x = {
        let guess = rate * dt * s23;
        if guess > C2D_MIN_GUESS { guess } else { C2D_MIN_GUESS }
    };
    let mut iter = 0u32;
    let capped = loop {
        let gx = g(x);
        let x1 = x * C2D_SECANT_RATIO;
        let g1 = g(x1);
        let slope = (gx - g1) / (x - x1);
        let old = x;
        x -= gx / slope;
        if x < 0.0 {
            x *= -0.1;
        }
        let step = x - old;
        if (if step < 0.0 { -step } else { step }) < C2D_TOLERANCE {
            break false;
        }
        if iter > C2D_MAX_ITER {
            break true;
        }
        iter += 1;
    };
    // `sqrtf(2.0/3.0) * fmaxf(delta_lambda, 0.)`: both factors in f32.
    let s23f = sqrt_f32(2.0 / 3.0);
    let d = (pos(x) as f32) as f64;
    let (eps_new, rate_new) = (eps + s23f * d, s23f * d / dt);
    let mut stress = *s_trial;
    for c in stress.iter_mut() {
        *c -= *c / norm * x * 2.0 * shear;
    }
    let strength = model.strength_part(eps_new, rate_new);
    ReturnResult {
        stress,
        eps: eps_new,
        rate: rate_new,
        delta_lambda: x,
        iterations: iter + 1,
        status: if capped { ReturnStatus::Capped } else { ReturnStatus::Converged },
        flow_stress: model.sigma_y_parts(eps_new, rate_new, temp, strength, thermal),
        strength,
        thermal,
    }
}
