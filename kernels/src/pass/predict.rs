//! The predictor's arguments (`sph::step::predict_particle`), with the skin test and, where `out.sig` is not null,
//! the pre-pass of the predicted particle (`sph::interact::prepare_particle`).

use super::StepPtrs;
use super::launch::{Grid, Pass, Span};
use super::table::entry_index;
use crate::neighbour::GridParams;
use crate::real::Real;
use crate::sph::TensorOps;
use crate::sph::interact::{PrepassArrays, PrepassDamage, prepare_particle};
use crate::sph::params::SphParams;
use crate::sph::step::{StepScalars, is_finite_vec, predict_particle};
use crate::vector::Dim;
use core::marker::PhantomData;

/// Everything one launch of the predictor reads and writes, sorted order. The step's dissipation and the start
/// positions' low parts are null (the predictor reads neither).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct PredictArgs<R: Real, D: Dim> {
    pub n: Span,
    /// The step's scalars: Δt in, the rebuild and non-finite flags out.
    pub scalars: *mut StepScalars,
    /// The cell list the skin test measures against.
    pub grid: *const GridParams,
    pub step: StepPtrs<R, D>,
    /// The positions the cell list binned.
    pub pos_ref: *const D::Vec<R>,
    /// The captured step's IF-node handle (0: none; `ptx::sph`, predict_entry).
    pub condition: u64,
    /// The fused pre-pass's parameters (default without it).
    pub params: SphParams<R>,
    /// The fused pre-pass's masses (null without it).
    pub mass: *const R,
    /// `out.sig` null: no fused pre-pass ([`PrepassArrays::NONE`]).
    pub out: PrepassArrays<R, D::Sym<R>>,
    /// The fused pre-pass's damage (D null: none).
    pub damage: PrepassDamage,
}

impl<R: Real, D: TensorOps<R>> PredictArgs<R, D> {
    /// Particle i's prediction followed by its pre-pass where `out.sig` is set (damaged with `DMG`); returns the
    /// predicted position.
    ///
    /// # Safety
    /// i < n; every non-null array holds n particles, `damage`'s with `DMG`; `scalars` points at the step's scalars.
    #[inline(always)]
    pub unsafe fn particle<const DMG: bool>(&self, i: usize) -> D::Vec<R> {
        unsafe {
            let x = predict_particle(&self.step.arrays(), (*self.scalars).dt, i);
            if !self.out.sig.is_null() {
                let (r, m) = (*self.step.rho.add(i), *self.mass.add(i));
                prepare_particle::<R, D, DMG>(
                    &self.params,
                    &self.out,
                    &self.damage,
                    i,
                    r,
                    m,
                    &*self.step.stress.add(i),
                );
            }
            x
        }
    }

    /// Whether particle i, predicted to `x`, makes the step rebuild the cell list: it moved beyond the skin
    /// (`GridParams::beyond_skin`, which a non-finite position is) or it is outside the blanking's box at rest (its
    /// predicted velocity no faster than the box's rest speed: the rebuild's hash then freezes it).
    ///
    /// # Safety
    /// i < n; `grid`, `pos_ref` and `scalars` are live.
    #[inline(always)]
    pub unsafe fn rebuilds(&self, i: usize, x: &D::Vec<R>) -> bool {
        unsafe {
            (*self.grid).beyond_skin::<R, D::Vec<R>>(x, &*self.pos_ref.add(i))
                || (*self.scalars).blank.blanks(x, &*self.step.vel.add(i))
        }
    }
}

/// The predictor pass (`swarf_step_predict_*`). Its CPU twin flags a particle beyond the skin ([`BEYOND_SKIN`])
/// or with a non-finite position ([`NON_FINITE`]) and sets the step's flags once after the loop; the GPU's
/// threads set them themselves (`ptx::sph`, predict_entry). With `DMG` the fused pre-pass is the damaged one
/// (`swarf_step_predict_*_dmg`).
pub struct Predict<R, D, const DMG: bool>(PhantomData<(R, D)>);

/// A predicted particle left the skin of the cell list or the blanking's box.
pub const BEYOND_SKIN: u32 = 1;
/// A predicted position is not finite.
pub const NON_FINITE: u32 = 2;

impl<R: Real, D: TensorOps<R>, const DMG: bool> Pass for Predict<R, D, DMG> {
    type Args = PredictArgs<R, D>;
    const ENTRY: usize = entry_index("predict", D::D, size_of::<R>(), DMG as u32);
    const GRID: Grid = Grid::Particles;
    fn particles(a: &Self::Args) -> usize {
        a.n.n as usize
    }
    fn active(a: &Self::Args) -> *const u32 {
        a.n.active
    }
    unsafe fn particle(a: &Self::Args, i: usize) -> u32 {
        unsafe {
            let x = a.particle::<DMG>(i);
            let beyond = a.rebuilds(i, &x);
            let finite = is_finite_vec::<R, D::Vec<R>>(&x);
            ((beyond as u32) * BEYOND_SKIN) | ((!finite as u32) * NON_FINITE)
        }
    }
    unsafe fn finish(a: &Self::Args, flags: u32) {
        let s = unsafe { &mut *a.scalars };
        if flags & BEYOND_SKIN != 0 {
            s.rebuild = 1;
        }
        if flags & NON_FINITE != 0 {
            s.non_finite = 1;
        }
    }
}
