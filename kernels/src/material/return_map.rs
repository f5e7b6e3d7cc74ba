//! Radial return mapping for J2 plasticity with isotropic, rate- and temperature-dependent hardening
//! (roethlin-solver.md §2.4 steps 1–5; klippel-constitutive.md §2.2), and the plastic heating (roethlin §2.5).
//!
//! Scaling (roethlin erratum 8, [C3D]): the unknown Δλ is the stress-norm multiplier,
//! g(Δλ) = ‖S_trial‖ − 2GΔλ − √(2/3)·σ_y(ε̄ + √(2/3)Δλ, √(2/3)Δλ/Δt, T) = 0,
//! S = S_trial(1 − 2GΔλ/‖S_trial‖), Δε̄ = √(2/3)Δλ, ε̄̇ = Δε̄/Δt. (Klippel's Δλ is Δε̄ itself.)
//! ‖S‖ is the Frobenius norm with the factor 2 on the off-diagonal products (erratum 8: [C2D]'s missing factor is a
//! bug and is not copied; `ReturnOptions::c2d_norm` reproduces it for `model = "mfree_iwf"`, and
//! `super::c2d_return` the whole of [C2D]'s return).
//!
//! Elastic check: √(3/2)‖S_trial‖ ≤ σ_y(ε̄_old, 0, T), i.e. with the rate factor 1 (klippel §2.2, the VUMAT's
//! elastic check, and §8 H5: "the elastic check uses rate term = 1"). Röthlin's [C2D] uses ε̄̇_old instead. With
//! rate 0 the check is exactly g(0) ≤ 0, so a plastic step always has g(0) > 0 ≥ g(‖S_trial‖/2G), a bracket.
//!
//! Solvers (both with the theses' guards, klippel §2.2 and roethlin §2.4): a negative iterate is replaced by 0.1×
//! the current one; at most [`MAX_ITERATIONS`]; a relative tolerance on Δλ. On top of that a bracket
//! [lo, hi] ⊂ [0, Δλ_max = ‖S_trial‖/(2G)] with g(lo) > 0 ≥ g(hi) is kept from every evaluation; an iterate outside
//! it, or one that does not halve the step of two iterations before (the safeguard of Numerical Recipes' rtsafe),
//! is replaced by bisection. So the result is always finite with Δλ ∈ [0, Δλ_max] (0: no change; Δλ_max: the
//! zero-strength bound, S = 0).
//!
//! Stopping rule: Δλ_k is accepted when |g(Δλ_k)|/(2G) ≤ rel_tol·Δλ_k + 64ε·Δλ_max. |g|/2G is the step of a
//! Newton iteration with the smallest slope g can have (|g'| ≥ 2G while σ_y does not soften along the path), so
//! it bounds both the theses' |Δλ_{k+1} − Δλ_k| and the error |Δλ_k − Δλ*|; unlike the bare step test it cannot be
//! fooled by an over-estimated secant slope (a tiny step far from the root: seen with Secant B at Δt = 1e-20 s).
//! The 64ε·Δλ_max floor is the resolution of g, a difference of terms of size ‖S_trial‖. The accepted iterate is
//! the result, with the σ_y of its own evaluation (no further Newton step: its σ_y would cost one more evaluation of
//! the flow stress, two logarithms and an exponential for Johnson–Cook). A bracket narrower than the
//! tolerance also ends the iteration: that is how it ends where g has no root (a jump of σ_y: the Uintah rate form
//! at ε̄̇ = ε̄̇0) or is too steep to resolve (ε̄̇ = Δε̄/Δt with a tiny Δt).
//!
//! Consistency achieved: |√(3/2)‖S_new‖ − σ_y(new)| = √(3/2)|g| ≤ rel_tol·(σ_eq,trial − σ_eq,new) + 64ε·σ_eq,trial
//! (the AT-27 states of tests/return_mapping.rs stay within 1e-11·σ_y), except at the bracket exits above, where
//! Δλ is within the tolerance of a sign change of g instead.

// `!(a > b)` is deliberate: it is true for NaN, which must take the safe branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::{FlowStress, fmin, sqrt};

/// Iteration cap of both solvers (Klippel's VUMAT, [C2D]).
pub const MAX_ITERATIONS: u32 = 100;
/// Default relative tolerance on Δλ.
pub const REL_TOL: f64 = 1e-12;
/// Secant B's support-point ratio ε_RR (klippel §2.2, Eqs. 7.18–7.19).
pub const SECANT_B_RATIO: f64 = 1.01;
/// The absolute floor of the stopping rule in units of ε·Δλ_max (the resolution of g).
pub const NOISE_FLOOR_ULPS: f64 = 64.0;
/// Set in [`ReturnResult::packed_iterations`] when the iteration cap was reached.
pub const CAPPED_FLAG: u32 = 1 << 31;

/// √(2/3).
pub const SQRT_2_3: f64 = 0.816496580927726;
/// √(3/2).
pub const SQRT_3_2: f64 = 1.224744871391589;

/// Root finder for g(Δλ) = 0.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Solver {
    /// Newton with the model's analytic derivative g'(Δλ) = −2G − (2/3)(∂σ_y/∂ε̄ + (∂σ_y/∂ε̄̇)/Δt)
    /// (klippel Eq. 7.1, 7.10–7.15).
    Newton = 0,
    /// Klippel's "Secant B" (Eqs. 7.18–7.19): the slope from g(Δλ_k) and g(ε_RR·Δλ_k), ε_RR = 1.01:
    /// Δλ_{k+1} = Δλ_k − g(Δλ_k)(Δλ_k − ε_RR Δλ_k)/(g(Δλ_k) − g(ε_RR Δλ_k)). Two evaluations per iteration.
    SecantB = 1,
}

/// Settings of one return.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReturnOptions {
    pub solver: Solver,
    /// Relative tolerance on Δλ (see the module doc for the absolute floor added to it).
    pub rel_tol: f64,
    pub max_iterations: u32,
    /// Δλ₀ (stress-norm scaling, i.e. √(3/2)·Δε̄₀). ≤ 0 or non-finite: automatic, √(3/2)·ε̄̇_old·Δt (the previous
    /// step's increment, as [C2D]) when ε̄̇_old > 0, else the perfectly plastic estimate
    /// (‖S_trial‖ − √(2/3)σ_y)/(2G) (klippel Eq. 3.154). A guess outside [0, Δλ_max] is replaced by Δλ_max/2.
    pub initial_guess: f64,
    /// Scale by [C2D]'s trial norm, without the factor 2 on the off-diagonal products (**a bug**, roethlin-solver.md
    /// §11 erratum 25a; `model = "mfree_iwf"`): g and S = S_trial(1 − 2GΔλ/n) use n, the elastic check still the
    /// true von Mises stress. Where g(0) ≤ 0 with it (a shear-dominated state just past the check) the return is
    /// Δλ = 0. False by default.
    pub c2d_norm: bool,
}

impl ReturnOptions {
    /// Newton, rel_tol 1e-12, 100 iterations, automatic initial guess.
    pub const DEFAULT: ReturnOptions = ReturnOptions {
        solver: Solver::Newton,
        rel_tol: REL_TOL,
        max_iterations: MAX_ITERATIONS,
        initial_guess: 0.0,
        c2d_norm: false,
    };
    /// Secant B, otherwise as [`ReturnOptions::DEFAULT`].
    pub const SECANT_B: ReturnOptions = ReturnOptions { solver: Solver::SecantB, ..ReturnOptions::DEFAULT };

    /// These options with the initial guess Δλ₀ (stress-norm scaling).
    pub const fn with_initial_guess(self, initial_guess: f64) -> ReturnOptions {
        ReturnOptions { initial_guess, ..self }
    }
}

impl Default for ReturnOptions {
    fn default() -> Self {
        ReturnOptions::DEFAULT
    }
}

/// How a return ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReturnStatus {
    /// √(3/2)‖S_trial‖ ≤ σ_y(ε̄_old, 0, T): S, ε̄ unchanged, ε̄̇ = 0.
    Elastic,
    /// Plastic, converged within the tolerance.
    Converged,
    /// Plastic, iteration cap reached: the result is the last iterate, inside the bracket (finite, within bounds).
    Capped,
}

/// The outcome of [`radial_return`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReturnResult {
    /// S_new (xx, xy, xz, yy, yz, zz) [Pa].
    pub stress: [f64; 6],
    /// ε̄_new.
    pub eps: f64,
    /// ε̄̇_new = Δε̄/Δt [1/s] (0 for an elastic step).
    pub rate: f64,
    /// Δλ (stress-norm scaling): Δε̄ = √(2/3)Δλ.
    pub delta_lambda: f64,
    /// Solver iterations (0 for an elastic step). Secant B evaluates g twice per iteration, Newton once (with the
    /// derivative).
    pub iterations: u32,
    pub status: ReturnStatus,
    /// σ_y(ε̄_new, ε̄̇_new, T) at the return's temperature, bit for bit [`FlowStress::sigma_y`]'s (an elastic step's is
    /// the check's own σ_y(ε̄_old, 0, T)): what the plastic heating, the plastic work and the friction cap read.
    pub flow_stress: f64,
    /// [`FlowStress::strength_part`] at (ε̄_new, ε̄̇_new) and [`FlowStress::thermal_part`] at T (NaN for the models
    /// that do not split), for σ_y at the same state and another temperature ([`FlowStress::sigma_y_parts`]).
    pub strength: f64,
    pub thermal: f64,
}

impl ReturnResult {
    /// The iteration count with [`CAPPED_FLAG`] set when the cap was reached (the GPU probe's `iters_out`).
    #[inline(always)]
    pub fn packed_iterations(&self) -> u32 {
        if self.status == ReturnStatus::Capped { self.iterations | CAPPED_FLAG } else { self.iterations }
    }
}

/// ‖S‖ = √(S:S) of a symmetric tensor stored (xx, xy, xz, yy, yz, zz), off-diagonals counted twice.
#[inline(always)]
pub fn deviatoric_norm(s: &[f64; 6]) -> f64 {
    let [xx, xy, xz, yy, yz, zz] = *s;
    sqrt(xx * xx + yy * yy + zz * zz + 2.0 * (xy * xy + xz * xz + yz * yz))
}

/// von Mises stress √(3/2)‖S‖ = √(3 J2) of a deviatoric S.
#[inline(always)]
pub fn von_mises(s: &[f64; 6]) -> f64 {
    SQRT_3_2 * deviatoric_norm(s)
}

/// Plastic heating ΔT = t_q σ_y Δε̄/(ρ c_p) [K] (roethlin-solver.md §2.5 (3.122), [C2D]: σ_y the flow stress after
/// the return, applied directly after it; t_q the Taylor–Quinney coefficient, 0.9 in [C2D]/[C3D] and Klippel).
#[inline(always)]
pub fn plastic_heating(taylor_quinney: f64, sigma_y: f64, d_eps: f64, density: f64, specific_heat: f64) -> f64 {
    taylor_quinney * sigma_y * d_eps / (density * specific_heat)
}

/// T + ΔT capped at the melt temperature (klippel §2.2: "ΔT … capped at T_m", the VUMAT's cap).
#[inline(always)]
pub fn heated_temperature(temp: f64, d_temp: f64, melt: f64) -> f64 {
    fmin(temp + d_temp, melt)
}

/// Keeps g(lo) > 0 ≥ g(hi) with an evaluation (x, g) strictly inside the bracket; NaN carries no information.
#[inline(always)]
fn tighten(lo: &mut f64, hi: &mut f64, x: f64, g: f64) {
    if x > *lo && x < *hi {
        if g > 0.0 {
            *lo = x;
        } else if g <= 0.0 {
            *hi = x;
        }
    }
}

/// The radial return of one material point (module doc). `s_trial`: deviatoric trial stress (xx, xy, xz, yy, yz,
/// zz) [Pa], plane strain with xz = yz = 0 and zz carried; `eps`, `rate`: ε̄ and ε̄̇ of the previous step (the rate
/// only seeds the initial guess); `temp` [K], frozen during the return; `shear` G > 0 [Pa]; `dt` > 0 [s].
///
/// Always inlined: as a PTX call (LLVM kept one for Johnson–Cook) the trial stress and the result went through
/// local memory and every particle, the elastic ones included, paid for the call.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn radial_return<M: FlowStress + ?Sized>(
    model: &M,
    s_trial: &[f64; 6],
    eps: f64,
    rate: f64,
    temp: f64,
    shear: f64,
    dt: f64,
    opts: &ReturnOptions,
) -> ReturnResult {
    let true_norm = deviatoric_norm(s_trial);
    // The norm of the scaling: the true one, or [C2D]'s (`c2d_norm`, the bug of erratum 25a).
    let norm = if opts.c2d_norm { sqrt(super::c2d_return::c2d_norm_squared(s_trial, true)) } else { true_norm };
    // The temperature is frozen during the return: its part of σ_y (Johnson–Cook's 1 − θᵐ) is evaluated once, for
    // the elastic check, every iteration and the flow stress of the result.
    let thermal = model.thermal_part(temp);
    let strength0 = model.strength_part(eps, 0.0);
    let sy0 = model.sigma_y_parts(eps, 0.0, temp, strength0, thermal);
    if !(SQRT_3_2 * true_norm > sy0) {
        return ReturnResult {
            stress: *s_trial,
            eps,
            rate: 0.0,
            delta_lambda: 0.0,
            iterations: 0,
            status: ReturnStatus::Elastic,
            flow_stress: sy0,
            strength: strength0,
            thermal,
        };
    }
    let two_g = 2.0 * shear;
    let lam_max = norm / two_g;
    let g0 = norm - SQRT_2_3 * sy0;
    let floor = NOISE_FLOOR_ULPS * f64::EPSILON * lam_max;
    let residual =
        |dl: f64| norm - two_g * dl - SQRT_2_3 * model.sigma_y(eps + SQRT_2_3 * dl, SQRT_2_3 * dl / dt, temp);
    // Converged at x when the Newton step with the smallest slope g can have, |g|/2G (an upper bound of |x − Δλ*|
    // for a non-softening σ_y), is within the tolerance.
    let small = |gx: f64, x: f64| {
        let e = gx / two_g;
        let e = if e < 0.0 { -e } else { e };
        e <= opts.rel_tol * x + floor
    };

    let mut x = if opts.initial_guess > 0.0 && opts.initial_guess.is_finite() {
        opts.initial_guess
    } else if rate > 0.0 {
        SQRT_3_2 * rate * dt
    } else {
        g0 / two_g
    };
    if !(x > 0.0 && x <= lam_max) {
        x = 0.5 * lam_max;
    }
    let mut lo = 0.0;
    let mut hi = lam_max;
    let mut iterations = 0;
    let mut converged = !(g0 > 0.0);
    if converged {
        // The trial exceeds σ_y only by rounding: nothing to return.
        x = 0.0;
    }
    // Steps of the last two iterations (rtsafe's dx, dxold).
    let mut step_old = lam_max;
    let mut step_last = lam_max;
    // σ_y and its strength part at the accepted Newton iterate (NaN strength: evaluate them after the loop).
    let mut at_result = (f64::NAN, f64::NAN);
    while !converged && iterations < opts.max_iterations {
        iterations += 1;
        let candidate = match opts.solver {
            Solver::Newton => {
                let (f, strength) = model.flow_and_strength_at(eps + SQRT_2_3 * x, SQRT_2_3 * x / dt, temp, thermal);
                let gx = norm - two_g * x - SQRT_2_3 * f.sigma;
                if small(gx, x) {
                    // x is within the tolerance: the result, with this evaluation's σ_y and strength (no further
                    // step, whose σ_y would cost another evaluation).
                    at_result = (f.sigma, strength);
                    converged = true;
                    break;
                }
                let slope = -two_g - (2.0 / 3.0) * f.path_slope(dt);
                tighten(&mut lo, &mut hi, x, gx);
                x - gx / slope
            }
            Solver::SecantB => {
                let gx = residual(x);
                if small(gx, x) {
                    converged = true;
                    break;
                }
                tighten(&mut lo, &mut hi, x, gx);
                let x2 = SECANT_B_RATIO * x;
                let g2 = residual(x2);
                tighten(&mut lo, &mut hi, x2, g2);
                x - gx * (x - x2) / (gx - g2)
            }
        };
        // The theses' guard against a negative prediction.
        let mut next = if candidate < 0.0 { 0.1 * x } else { candidate };
        let mut step = next - x;
        if step < 0.0 {
            step = -step;
        }
        // The bracket's guard: outside it, or not converging fast enough → bisection.
        if !(next >= lo && next <= hi) || 2.0 * step > step_old {
            next = 0.5 * (lo + hi);
            step = next - x;
            if step < 0.0 {
                step = -step;
            }
        }
        step_old = step_last;
        step_last = step;
        x = next;
        if hi - lo <= opts.rel_tol * hi + floor {
            // The bracket has collapsed (only reachable where g has no root: a jump of σ_y, e.g. the Uintah rate
            // form at ε̄̇ = ε̄̇0, or a σ_y that cannot be resolved any further).
            converged = true;
        }
    }

    let factor = 1.0 - two_g * x / norm;
    let [xx, xy, xz, yy, yz, zz] = *s_trial;
    let (eps_new, rate_new) = (eps + SQRT_2_3 * x, SQRT_2_3 * x / dt);
    // The accepted Newton iterate was evaluated at these very (ε̄, ε̄̇): its σ_y is `sigma_y`'s bit for bit
    // (`FlowStress::flow_and_strength_at`) wherever the model splits off its strength part.
    let (flow_stress, strength) = if at_result.1.is_nan() {
        let strength = model.strength_part(eps_new, rate_new);
        (model.sigma_y_parts(eps_new, rate_new, temp, strength, thermal), strength)
    } else {
        at_result
    };
    ReturnResult {
        stress: [xx * factor, xy * factor, xz * factor, yy * factor, yz * factor, zz * factor],
        eps: eps_new,
        rate: rate_new,
        delta_lambda: x,
        iterations,
        status: if converged { ReturnStatus::Converged } else { ReturnStatus::Capped },
        flow_stress,
        strength,
        thermal,
    }
}
