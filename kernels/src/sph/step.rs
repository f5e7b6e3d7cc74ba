//! The streaming (per-particle) halves of a step, fused so that a step is a handful of launches
//! (docs/measurements/notebook.md, "The fused step"):
//!
//! - `predict_particle`: y0 ← y, y ← y0 + ½Δt ẏ for x, v, ρ, S and (with conduction) T; the launch then hashes
//!   the predicted position into its cell and counts it (the cell list's first pass);
//! - `correct_particle`: y ← y0 + Δt ẏ for the same fields; the launch then applies the plastic update
//!   (`sph::plastic`) to the same particle.
//!
//! The integrator is the midpoint predictor–corrector of `sph::integrate` (roethlin-solver.md §5.2 steps 2, 3, 11).
//! The step's scalars (Δt, the tool's state) are read from device memory ([`StepScalars`]) rather than passed by
//! value, so that a step captured once in a CUDA graph replays with each step's values.

use super::integrate::{advance_compensated, advance_sym, advance_vec};
use crate::real::Real;

/// The scalars of one step, written by the host before the step runs.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct StepScalars {
    /// The length of this step Δt [s].
    pub dt: f64,
    /// Nonzero when this step rebuilds the cell list and reorders the particles: written by the host (0, or 1
    /// to force a rebuild), set to 1 by the predictor when a particle moved beyond the grid's skin. The
    /// rebuild's kernels run only when it is set (a captured step holds every launch; the flag decides).
    pub rebuild: u32,
    /// Set to 1 by the predictor when a predicted position is non-finite, so that the run loop stops within one
    /// batch (it reads the flags after each batch) instead of at its next output.
    pub non_finite: u32,
    /// The blanking's active box at this step's end (`on` 0: no blanking; docs/3d.md, "Blanking"): the predictor
    /// asks for a rebuild when an active particle is outside it at rest, the rebuild's hash freezes those particles.
    pub blank: crate::neighbour::BlankBox,
}

/// Whether every component of a position is finite.
#[inline(always)]
pub fn is_finite_vec<R: Real, V: crate::vector::Vector<R>>(x: &V) -> bool {
    let mut k = 0;
    while k < V::DIM {
        if !x.get(k).is_finite() {
            return false;
        }
        k += 1;
    }
    true
}

/// The integrated fields of sorted particles: the state y, its start-of-step copy y0 and the rates ẏ. The
/// temperature joins them when `temp_t` is not null (conduction); `temp` may be set without it (plasticity).
#[derive(Clone, Copy)]
pub struct StepArrays<R: Real, V, S> {
    pub pos: *mut V,
    pub vel: *mut V,
    pub rho: *mut R,
    pub stress: *mut S,
    pub pos0: *mut V,
    pub vel0: *mut V,
    pub rho0: *mut R,
    pub stress0: *mut S,
    pub pos_t: *const V,
    pub vel_t: *const V,
    pub rho_t: *const R,
    pub stress_t: *const S,
    pub temp: *mut f64,
    pub temp0: *mut f64,
    pub temp_t: *const f64,
    /// The artificial viscosity's accumulated dissipation per unit mass [J/kg] and its rate (null without AV
    /// or in the predictor): the corrector adds Δt × the midpoint rate.
    pub diss: *mut f64,
    pub diss_t: *const R,
    /// The low part of the start-of-step position x0 = pos0 + pos_lo (mixed precision, f32 only; null otherwise,
    /// ignored in f64): the corrector's position sum is then compensated (`integrate::advance_compensated`). The predictor leaves it:
    /// the midpoint position is used once and rounded, only x1 accumulates over the steps.
    pub pos_lo: *mut V,
}

/// Predictor of particle i: y0 ← y; y ← y0 + ½Δt ẏ. Returns the predicted position.
///
/// # Safety
/// Every non-null array holds at least i + 1 particles.
#[inline(always)]
pub unsafe fn predict_particle<R: Real, V: crate::vector::Vector<R>, S: crate::vector::SymTensor<R>>(
    a: &StepArrays<R, V, S>,
    dt: f64,
    i: usize,
) -> V {
    let c = R::from_f64(0.5 * dt);
    unsafe {
        let (x, v, r, s) = (*a.pos.add(i), *a.vel.add(i), *a.rho.add(i), *a.stress.add(i));
        *a.pos0.add(i) = x;
        *a.vel0.add(i) = v;
        *a.rho0.add(i) = r;
        *a.stress0.add(i) = s;
        let xp = advance_vec(&x, c, &*a.pos_t.add(i));
        *a.pos.add(i) = xp;
        *a.vel.add(i) = advance_vec(&v, c, &*a.vel_t.add(i));
        *a.rho.add(i) = r + c * *a.rho_t.add(i);
        *a.stress.add(i) = advance_sym(&s, c, &*a.stress_t.add(i));
        if !a.temp_t.is_null() {
            let t = *a.temp.add(i);
            *a.temp0.add(i) = t;
            *a.temp.add(i) = t + 0.5 * dt * *a.temp_t.add(i);
        }
        xp
    }
}

/// Corrector of particle i: y ← y0 + Δt ẏ (x compensated where `pos_lo` is given).
///
/// # Safety
/// As [`predict_particle`].
#[inline(always)]
pub unsafe fn correct_particle<R: Real, V: crate::vector::Vector<R>, S: crate::vector::SymTensor<R>>(
    a: &StepArrays<R, V, S>,
    dt: f64,
    i: usize,
) {
    let c = R::from_f64(dt);
    unsafe {
        // The mixed precision is f32's: in f64 the test folds to false at compile time, so the f64 correctors never
        // load `pos_lo` and keep their registers (they share the entry's parameter list).
        if core::mem::size_of::<R>() != 4 || a.pos_lo.is_null() {
            *a.pos.add(i) = advance_vec(&*a.pos0.add(i), c, &*a.pos_t.add(i));
        } else {
            let (hi, lo) = advance_compensated(&*a.pos0.add(i), &*a.pos_lo.add(i), c, &*a.pos_t.add(i));
            *a.pos.add(i) = hi;
            *a.pos_lo.add(i) = lo;
        }
        *a.vel.add(i) = advance_vec(&*a.vel0.add(i), c, &*a.vel_t.add(i));
        *a.rho.add(i) = *a.rho0.add(i) + c * *a.rho_t.add(i);
        *a.stress.add(i) = advance_sym(&*a.stress0.add(i), c, &*a.stress_t.add(i));
        if !a.temp_t.is_null() {
            *a.temp.add(i) = *a.temp0.add(i) + dt * *a.temp_t.add(i);
        }
        if !a.diss.is_null() {
            *a.diss.add(i) += dt * (*a.diss_t.add(i)).to_f64();
        }
    }
}
