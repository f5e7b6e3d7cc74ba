//! The arguments of the SPH passes that run alone: the density sum, the pre-pass, the conduction, the plastic
//! update and the tool's contact pass (each also fused into another pass: `RatesArgs`, `FinishPlasticArgs`,
//! `PredictArgs`), and the cohesive path's bonds.

use super::ModelEntry;
use super::launch::{Grid, Pass, Span};
use super::table::{entry_index, model_variant, prepare_variant};
use crate::contact::ToolArg;
use crate::contact::penalty::{ContactArrays, ToolSet, contact_particle};
use crate::material::FlowStress;
use crate::neighbour::{GridParams, Neighbours};
use crate::real::Real;
use crate::sph::CubicSpline;
use crate::sph::TensorOps;
use crate::sph::bond::{BondArrays, BondParams, OnsetState, bond_particle, index_particle, open_particle};
use crate::sph::density::density_sum;
use crate::sph::heat::heat_rate;
use crate::sph::heat::{HeatArrays, HeatParams, ThermalMaterial};
use crate::sph::interact::{PrepassArrays, PrepassDamage, prepare_store};
use crate::sph::params::SphParams;
use crate::sph::plastic::{DamageArrays, PlasticArrays, PlasticConsts, plastic_particle};
use crate::vector::Dim;
use core::marker::PhantomData;

/// The density sum ρ_i = Σ_j m_j W(|x_i − x_j|) (`sph::density::density_sum`).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct DensityArgs<R: Real, D: Dim> {
    pub n: Span,
    pub pos: *const D::Vec<R>,
    pub mass: *const R,
    pub grid: *const GridParams,
    pub starts: *const u32,
    pub kernel: *const CubicSpline<R>,
    pub rho: *mut R,
}

impl<R: Real, D: Dim> DensityArgs<R, D> {
    /// Particle i's density.
    ///
    /// # Safety
    /// i < n; the arrays hold n sorted particles of the cell list `grid`/`starts`.
    #[inline(always)]
    pub unsafe fn particle(&self, i: usize) {
        unsafe {
            let r = density_sum::<R, D::Vec<R>>(&*self.grid, self.starts, &*self.kernel, self.pos, self.mass, i as u32);
            *self.rho.add(i) = r;
        }
    }
}

/// The density sum pass (`swarf_density_*`).
pub struct Density<R, D>(PhantomData<(R, D)>);
crate::simple_pass!(Density<R, D>, DensityArgs<R, D>, entry_index("density", D::D, size_of::<R>(), 0),
    Grid::Particles, [R: Real, D: Dim]);

/// The pre-pass: sig = σ/ρ², art = artificial stress (AS), sound = √(K/ρ) (AV; times the Balsara factor where
/// `av_switch` is set), vol = m/ρ (`mass` the full masses), gated on a step's rebuild flag (`gate`; null: always)
/// where the predictor runs the pre-pass.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct PrepareArgs<R: Real, D: Dim> {
    /// The step's rebuild flag (`StepScalars::rebuild`; the GPU's gate: the CPU reads it before the loop).
    pub gate: *const u32,
    pub n: Span,
    pub params: *const SphParams<R>,
    pub rho: *const R,
    pub mass: *const R,
    pub stress: *const D::Sym<R>,
    /// σ/ρ², V, the stabilisers' outputs (null where off) and the Balsara factors (null: off).
    pub out: PrepassArrays<R, D::Sym<R>>,
    /// Null without temperature.
    pub temp: *const f64,
    /// The damage (D null: none) and its mask's output.
    pub damage: PrepassDamage,
}

impl<R: Real, D: TensorOps<R>> PrepareArgs<R, D> {
    /// Particle i's pre-pass, the viscosity's sound speed with `AV`, the artificial stress with `AS`, the damage's
    /// degradation and mask with `DMG`.
    ///
    /// # Safety
    /// i < n; every array holds n particles, `out.art`/`out.sound` where `AS`/`AV`, `out.av_switch` where not null, `damage`'s
    /// where `DMG`; `params` points at the parameters.
    #[inline(always)]
    pub unsafe fn particle<const AV: bool, const AS: bool, const DMG: bool>(&self, i: usize) {
        unsafe {
            let t = if self.temp.is_null() { None } else { Some(*self.temp.add(i)) };
            let (r, m, s) = (*self.rho.add(i), *self.mass.add(i), &*self.stress.add(i));
            prepare_store::<R, D, AV, AS, DMG>(&*self.params, &self.out, &self.damage, i, r, m, s, t);
        }
    }
}

/// The pre-pass (`swarf_sph_prepare_*`) with the viscosity's sound speed (`AV`), the artificial stress (`AS`)
/// and the damage (`DMG`, `swarf_sph_prepare_*_dmg`), gated where its struct's `gate` is set.
pub struct Prepare<R, D, const AV: bool, const AS: bool, const DMG: bool>(PhantomData<(R, D)>);

impl<R: Real, D: TensorOps<R>, const AV: bool, const AS: bool, const DMG: bool> Pass for Prepare<R, D, AV, AS, DMG> {
    type Args = PrepareArgs<R, D>;
    const ENTRY: usize = entry_index("prepare", D::D, size_of::<R>(), prepare_variant(AV, AS, DMG));
    const GRID: Grid = Grid::Particles;
    fn particles(a: &Self::Args) -> usize {
        a.n.n as usize
    }
    fn active(a: &Self::Args) -> *const u32 {
        a.n.active
    }
    fn gate(a: &Self::Args) -> *const u32 {
        a.gate
    }
    unsafe fn particle(a: &Self::Args, i: usize) -> u32 {
        unsafe { a.particle::<AV, AS, DMG>(i) };
        0
    }
}

/// The conduction Ṫ_i (`sph::heat`), Brookshaw or PSE (PSE with a null `list`), `lanes` threads per particle.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct HeatArgs<R: Real, D: Dim> {
    pub n: Span,
    /// Lanes per particle (1, 2, 4 or 8; `sph::lanes::clamp_lanes`).
    pub lanes: u32,
    pub hp: HeatParams,
    /// The smoothing kernel's parameters (`params.kernel`).
    pub params: SphParams<R>,
    pub grid: *const GridParams,
    pub starts: *const u32,
    /// The Verlet list of `grid`, or null: walk the stencil.
    pub list: *const u32,
    pub pos: *const D::Vec<R>,
    pub rho: *const R,
    pub vol: *const R,
    pub temp: *const f64,
    pub flags: *const u32,
    pub materials: *const ThermalMaterial,
    pub temp_t: *mut f64,
}

impl<R: Real, D: Dim> HeatArgs<R, D> {
    /// The conduction's read-only arrays.
    #[inline(always)]
    pub fn arrays(&self) -> HeatArrays<R, D::Vec<R>> {
        HeatArrays {
            pos: self.pos,
            rho: self.rho,
            vol: self.vol,
            temp: self.temp,
            flags: self.flags,
            materials: self.materials,
        }
    }

    /// The neighbour walk's view of the cell list.
    ///
    /// # Safety
    /// `grid` points at a live `GridParams`.
    #[inline(always)]
    pub unsafe fn neighbours(&self) -> Neighbours<'_> {
        Neighbours { grid: unsafe { &*self.grid }, starts: self.starts, list: self.list }
    }
}

/// The conduction pass (`swarf_heat_brookshaw_*`, `swarf_heat_pse_*` with `PSE`), `lanes` threads per particle on
/// the GPU (the CPU sums the lanes' shares in the same order: `sph::lanes`).
pub struct Heat<R, D, const PSE: bool>(PhantomData<(R, D)>);

impl<R: Real, D: Dim, const PSE: bool> Pass for Heat<R, D, PSE> {
    type Args = HeatArgs<R, D>;
    const ENTRY: usize = entry_index("heat", D::D, size_of::<R>(), PSE as u32);
    const GRID: Grid = Grid::Pair;
    fn particles(a: &Self::Args) -> usize {
        a.n.n as usize
    }
    fn active(a: &Self::Args) -> *const u32 {
        a.n.active
    }
    fn lanes(a: &Self::Args) -> u32 {
        a.lanes
    }
    unsafe fn particle(a: &Self::Args, i: usize) -> u32 {
        unsafe {
            let (arr, nb) = (a.arrays(), a.neighbours());
            *a.temp_t.add(i) = heat_rate::<R, D::Vec<R>, PSE>(&a.hp, &a.params.kernel, &nb, &arr, i as u32, a.lanes);
        }
        0
    }
}

/// The plastic update (radial return + heating) of flow-stress model `M`, its parameters by value.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct PlasticArgs<R: Real, D: Dim, M> {
    pub n: Span,
    pub model: M,
    pub consts: PlasticConsts,
    pub stress: *mut D::Sym<R>,
    pub rho: *const R,
    pub eps: *mut f64,
    pub rate: *mut f64,
    pub temp: *mut f64,
    pub flags: *const u32,
    /// Thermal materials by body (null without plastic heating).
    pub materials: *const ThermalMaterial,
    /// Receives σ_y after the update (null: not kept).
    pub yield_stress: *mut f64,
    /// Accumulates the specific plastic work (null: not tracked).
    pub work: *mut f64,
    /// The damage's arrays ([`DamageArrays::NONE`]: no damage).
    pub damage: DamageArrays<R>,
}

impl<R: Real, D: TensorOps<R>, M: FlowStress + Copy> PlasticArgs<R, D, M> {
    /// Particle i's plastic update with `model` (the struct's, or a local copy of it).
    ///
    /// # Safety
    /// i < n; every non-null array holds n particles; `materials` covers every body where heating is on.
    #[inline(always)]
    pub unsafe fn particle<const DMG: bool>(&self, model: &M, i: usize) {
        let a = PlasticArrays::<R, D::Sym<R>> {
            stress: self.stress,
            rho: self.rho,
            eps: self.eps,
            rate: self.rate,
            temp: self.temp,
            flags: self.flags,
            materials: self.materials,
            yield_stress: self.yield_stress,
            work: self.work,
            damage: self.damage,
        };
        unsafe { plastic_particle::<R, D, M, DMG>(model, &self.consts, &a, i) }
    }
}

/// The standalone plastic update (`swarf_plastic_<model>_*`; with `DMG` the damage after it, `..._dmg`).
pub struct Plastic<R, D, M, const DMG: bool>(PhantomData<(R, D, M)>);

impl<R: Real, D: TensorOps<R>, M: FlowStress + ModelEntry + Copy, const DMG: bool> Pass for Plastic<R, D, M, DMG> {
    type Args = PlasticArgs<R, D, M>;
    const ENTRY: usize = entry_index("plastic", D::D, size_of::<R>(), model_variant(M::INDEX, DMG));
    const GRID: Grid = Grid::Plastic;
    fn particles(a: &Self::Args) -> usize {
        a.n.n as usize
    }
    fn active(a: &Self::Args) -> *const u32 {
        a.n.active
    }
    unsafe fn particle(a: &Self::Args, i: usize) -> u32 {
        unsafe { a.particle::<DMG>(&a.model, i) };
        0
    }
}

/// The tools' contact pass (`contact::penalty::contact_particle`) with the tools `T`: parametric tools (the
/// outline in 2D, the prism of the outline along z in 3D) or, in 3D, triangle meshes ([`ToolArg`]).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct ContactArgs<R: Real, D: Dim, T: ToolArg> {
    pub n: Span,
    /// The tools: their shapes, constants, this step's motions and the particles' owners.
    pub set: ToolSet<T>,
    pub pos: *const D::Vec<R>,
    pub vel: *const D::Vec<R>,
    pub mass: *const R,
    pub rho: *const R,
    pub flags: *const u32,
    pub normal: *mut D::Vec<R>,
    pub friction: *mut D::Vec<R>,
    /// Null: no frictional heating.
    pub temp: *mut f64,
    pub materials: *const ThermalMaterial,
    /// Null: no friction cap.
    pub yield_stress: *const f64,
    /// Null: no wear.
    pub wear: *mut f64,
}

impl<R: Real, D: Dim, T: ToolArg> ContactArgs<R, D, T> {
    /// Particle i's contact forces.
    ///
    /// # Safety
    /// i < n; every non-null array holds n particles; the tool set's arrays hold its `count` live entries.
    #[inline(always)]
    pub unsafe fn particle(&self, i: usize) {
        let a = ContactArrays::<R, D::Vec<R>> {
            pos: self.pos,
            vel: self.vel,
            mass: self.mass,
            rho: self.rho,
            flags: self.flags,
            normal: self.normal,
            friction: self.friction,
            temp: self.temp,
            materials: self.materials,
            yield_stress: self.yield_stress,
            wear: self.wear,
        };
        unsafe { contact_particle::<R, D::Vec<R>, T>(&self.set, &a, i) }
    }
}

/// The standalone contact pass (`swarf_contact_2d_*`, `swarf_contact_3d_*`: the parametric tool;
/// `swarf_contact_mesh_3d_*`: a mesh tool).
pub struct Contact<R, D, T>(PhantomData<(R, D, T)>);
crate::simple_pass!(Contact<R, D, T>, ContactArgs<R, D, T>, entry_index("contact", D::D, size_of::<R>(), T::VARIANT),
    Grid::Particles, [R: Real, D: Dim, T: ToolArg]);

/// The cohesive path's bonds (`sph::bond::bond_particle`): one thread per sorted particle, the bonds' owners act.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct BondArgs<R: Real, D: TensorOps<R>> {
    pub n: u32,
    pub _pad: u32,
    pub params: BondParams,
    pub arrays: BondArrays<R, D>,
}

impl<R: Real, D: TensorOps<R>> BondArgs<R, D> {
    /// # Safety
    /// As `sph::bond::bond_particle`.
    #[inline(always)]
    pub unsafe fn particle(&self, i: usize) {
        unsafe { bond_particle(&self.params, &self.arrays, i) }
    }
}

/// The bond pass (`swarf_sph_bond_*`).
pub struct Bond<R, D>(PhantomData<(R, D)>);
crate::simple_pass!(Bond<R, D>, BondArgs<R, D>, entry_index("bond", D::D, size_of::<R>(), 0), Grid::Particles,
    [R: Real, D: TensorOps<R>]);

/// The map from particle id to sorted index (`sph::bond::index_particle`), rebuilt before the bonds each step.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct BondIndexArgs<R: Real, D: Dim> {
    pub n: u32,
    pub _pad: u32,
    pub id: *const u32,
    pub index: *mut u32,
    pub _marker: PhantomData<(R, D)>,
}

impl<R: Real, D: Dim> BondIndexArgs<R, D> {
    /// # Safety
    /// As `sph::bond::index_particle`.
    #[inline(always)]
    pub unsafe fn particle(&self, i: usize) {
        unsafe { index_particle(self.id, self.index, i) }
    }
}

/// The id-to-index pass (`swarf_sph_bond_index_*`).
pub struct BondIndex<R, D>(PhantomData<(R, D)>);
crate::simple_pass!(BondIndex<R, D>, BondIndexArgs<R, D>, entry_index("bond_index", D::D, size_of::<R>(), 0),
    Grid::Particles, [R: Real, D: Dim]);

/// The columns' opening after the bonds under `coupling = "continuum"` (`sph::bond::open_particle`).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct BondOpenArgs<R: Real, D: Dim> {
    pub n: u32,
    pub _pad: u32,
    /// The bond pass's id-to-index map.
    pub index: *const u32,
    pub column: *const u32,
    pub onset: *const OnsetState<R>,
    pub flags: *mut u32,
    pub _marker: PhantomData<D>,
}

impl<R: Real, D: Dim> BondOpenArgs<R, D> {
    /// # Safety
    /// As `sph::bond::open_particle`.
    #[inline(always)]
    pub unsafe fn particle(&self, i: usize) {
        unsafe { open_particle(self.index, self.column, self.onset, self.flags, i) }
    }
}

/// The opening pass (`swarf_sph_bond_open_*`).
pub struct BondOpen<R, D>(PhantomData<(R, D)>);
crate::simple_pass!(BondOpen<R, D>, BondOpenArgs<R, D>, entry_index("bond_open", D::D, size_of::<R>(), 0),
    Grid::Particles, [R: Real, D: Dim]);
