//! The corrector's arguments (`sph::step::correct_particle`), alone or followed by the plastic update of the same
//! particle (`sph::plastic::plastic_particle`) and the tool's contact pass (`contact::penalty::contact_particle`).

use super::ModelEntry;
use super::launch::{Grid, Pass, Span};
use super::table::{entry_index, model_variant};
use crate::contact::penalty::{ContactArrays, ContactParams, ToolSet, contact_particle};
use crate::contact::{Tool2d, ToolState};
use crate::material::FlowStress;
use crate::real::Real;
use crate::sph::TensorOps;
use crate::sph::heat::ThermalMaterial;
use crate::sph::plastic::{DamageArrays, PlasticArrays, PlasticConsts, plastic_particle};
use crate::sph::step::{StepArrays, StepScalars, correct_particle};
use crate::vector::Dim;
use core::marker::PhantomData;

/// The fields a step integrates, sorted order: the state y, its start-of-step copy y0, the rates ẏ, the
/// temperature (null without heat or plasticity) with its start copy and rate (null without conduction), the
/// dissipation and its rate (null without the viscosity) and the start positions' low parts (null outside the
/// mixed precision).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct StepPtrs<R: Real, D: Dim> {
    pub pos: *mut D::Vec<R>,
    pub vel: *mut D::Vec<R>,
    pub rho: *mut R,
    pub stress: *mut D::Sym<R>,
    pub pos0: *mut D::Vec<R>,
    pub vel0: *mut D::Vec<R>,
    pub rho0: *mut R,
    pub stress0: *mut D::Sym<R>,
    pub pos_t: *const D::Vec<R>,
    pub vel_t: *const D::Vec<R>,
    pub rho_t: *const R,
    pub stress_t: *const D::Sym<R>,
    pub temp: *mut f64,
    pub temp0: *mut f64,
    pub temp_t: *const f64,
    pub diss: *mut f64,
    pub diss_t: *const R,
    pub pos_lo: *mut D::Vec<R>,
}

impl<R: Real, D: Dim> StepPtrs<R, D> {
    /// The step kernels' view.
    #[inline(always)]
    pub fn arrays(&self) -> StepArrays<R, D::Vec<R>, D::Sym<R>> {
        StepArrays {
            pos: self.pos,
            vel: self.vel,
            rho: self.rho,
            stress: self.stress,
            pos0: self.pos0,
            vel0: self.vel0,
            rho0: self.rho0,
            stress0: self.stress0,
            pos_t: self.pos_t,
            vel_t: self.vel_t,
            rho_t: self.rho_t,
            stress_t: self.stress_t,
            temp: self.temp,
            temp0: self.temp0,
            temp_t: self.temp_t,
            diss: self.diss,
            diss_t: self.diss_t,
            pos_lo: self.pos_lo,
        }
    }
}

/// The corrector of an elastic run.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct FinishArgs<R: Real, D: Dim> {
    pub n: Span,
    /// The step's scalars (Δt).
    pub scalars: *const StepScalars,
    pub step: StepPtrs<R, D>,
}

impl<R: Real, D: Dim> FinishArgs<R, D> {
    /// Particle i's corrector.
    ///
    /// # Safety
    /// i < n; every non-null array holds n particles; `scalars` points at the step's scalars.
    #[inline(always)]
    pub unsafe fn particle(&self, i: usize) {
        unsafe { correct_particle(&self.step.arrays(), (*self.scalars).dt, i) }
    }
}

/// The corrector with the plastic update of flow-stress model `M` and, where `contact` is not null, the tool's
/// contact pass, all of one particle in one thread. The model's parameters come by value (on the GPU: in the
/// constant bank, operands of the return map's instructions).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct FinishPlasticArgs<R: Real, D: Dim, M> {
    pub n: Span,
    /// Blocks in reverse order (`ptx::ordered_index`; the GPU's only, no bit depends on it).
    pub reverse: u32,
    /// The step's scalars (Δt, the tool's state).
    pub scalars: *const StepScalars,
    pub model: M,
    pub shear: f64,
    pub taylor_quinney: f64,
    /// `PlasticConsts::flags` (the original code's return under `model = "mfree_iwf"`; 0: swarf's).
    pub return_flags: u32,
    pub _pad: u32,
    pub step: StepPtrs<R, D>,
    pub eps: *mut f64,
    pub rate: *mut f64,
    pub flags: *const u32,
    /// Thermal materials by body (null without plastic heating).
    pub materials: *const ThermalMaterial,
    /// Receives σ_y after the update (null: not kept).
    pub yield_stress: *mut f64,
    /// Accumulates the specific plastic work (null: not tracked).
    pub work: *mut f64,
    /// The damage's arrays ([`DamageArrays::NONE`]: no damage).
    pub damage: DamageArrays<R>,
    /// The contact pass's parameters; null: no contact pass.
    pub contact: *const ContactParams,
    /// The tool's shape and its motion this step (with `contact`).
    pub contact_tool: *const Tool2d,
    pub contact_state: *const ToolState,
    /// The particles' own masses.
    pub mass: *const R,
    pub normal: *mut D::Vec<R>,
    pub friction: *mut D::Vec<R>,
    /// Null without friction heating.
    pub contact_materials: *const ThermalMaterial,
    /// The plastic update's yield stresses (the CURRENT friction cap), else null.
    pub contact_yield: *const f64,
    /// Usui wear-rate output (null: off).
    pub wear: *mut f64,
}

impl<R: Real, D: TensorOps<R>, M: FlowStress + Copy> FinishPlasticArgs<R, D, M> {
    /// Particle i's corrector, plastic update and contact pass, with `model` (the entry's local copy of
    /// `self.model`, so that the GPU passes the model alone, not the whole block, to the flow-stress functions).
    ///
    /// # Safety
    /// i < n; every non-null array holds n particles; `scalars`, and `contact` and `contact_tool` (unless `contact` is
    /// null), point at live values.
    #[inline(always)]
    pub unsafe fn particle<const DMG: bool>(&self, model: &M, i: usize) {
        unsafe {
            let dt = (*self.scalars).dt;
            correct_particle(&self.step.arrays(), dt, i);
            let c = PlasticConsts {
                shear: self.shear,
                dt,
                taylor_quinney: self.taylor_quinney,
                flags: self.return_flags,
                _pad: 0,
            };
            let p = PlasticArrays::<R, D::Sym<R>> {
                stress: self.step.stress,
                rho: self.step.rho,
                eps: self.eps,
                rate: self.rate,
                temp: self.step.temp,
                flags: self.flags,
                materials: self.materials,
                yield_stress: self.yield_stress,
                work: self.work,
                damage: self.damage,
            };
            plastic_particle::<R, D, M, DMG>(model, &c, &p, i);
            if !self.contact.is_null() {
                let ca = ContactArrays::<R, D::Vec<R>> {
                    pos: self.step.pos,
                    vel: self.step.vel,
                    mass: self.mass,
                    rho: self.step.rho,
                    flags: self.flags,
                    normal: self.normal,
                    friction: self.friction,
                    temp: self.step.temp,
                    materials: self.contact_materials,
                    yield_stress: self.contact_yield,
                    wear: self.wear,
                };
                let set = ToolSet {
                    tools: self.contact_tool,
                    params: self.contact,
                    states: self.contact_state,
                    owner: core::ptr::null_mut(),
                    count: 1,
                    _pad: 0,
                };
                contact_particle::<R, D::Vec<R>, *const Tool2d>(&set, &ca, i);
            }
        }
    }
}

/// The corrector pass of an elastic run (`swarf_step_finish_*`).
pub struct Finish<R, D>(PhantomData<(R, D)>);
crate::simple_pass!(Finish<R, D>, FinishArgs<R, D>, entry_index("finish", D::D, size_of::<R>(), 0), Grid::Particles,
    [R: Real, D: Dim]);

/// The corrector with the plastic update of model `M` and, where set, the contact pass
/// (`swarf_step_finish_<model>_*`; with `DMG` the damage after the plastic update, `..._dmg`).
pub struct FinishPlastic<R, D, M, const DMG: bool>(PhantomData<(R, D, M)>);

impl<R: Real, D: TensorOps<R>, M: FlowStress + ModelEntry + Copy, const DMG: bool> Pass
    for FinishPlastic<R, D, M, DMG>
{
    type Args = FinishPlasticArgs<R, D, M>;
    const ENTRY: usize = entry_index("finish_plastic", D::D, size_of::<R>(), model_variant(M::INDEX, DMG));
    const GRID: Grid = Grid::Plastic;
    fn particles(a: &Self::Args) -> usize {
        a.n.n as usize
    }
    fn active(a: &Self::Args) -> *const u32 {
        a.n.active
    }
    fn order(a: &mut Self::Args) -> Option<&mut u32> {
        Some(&mut a.reverse)
    }
    unsafe fn particle(a: &Self::Args, i: usize) -> u32 {
        unsafe { a.particle::<DMG>(&a.model, i) };
        0
    }
}
