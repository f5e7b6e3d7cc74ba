//! The pair interaction's arguments (`sph::interact::rates`, fused with the Brookshaw conduction in
//! `sph::interact::rates_heat`).

use super::launch::{Grid, Pass, Span};
use super::table::{entry_index, rates_variant};
use crate::neighbour::{GridParams, Neighbours};
use crate::real::Real;
use crate::sph::TensorOps;
use crate::sph::heat::{HeatArrays, HeatParams, ThermalMaterial};
use crate::sph::interact::{Arrays, Rates, rates, rates_heat};
use crate::sph::params::SphParams;
use crate::vector::Dim;
use core::marker::PhantomData;

/// Everything one launch of the pair interaction reads and writes, all arrays in sorted order.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct RatesArgs<R: Real, D: Dim> {
    pub n: Span,
    /// Lanes per particle (1, 2, 4 or 8; `sph::lanes::clamp_lanes`).
    pub lanes: u32,
    /// Blocks in reverse order (`ptx::ordered_index`; the GPU's only, no bit depends on it).
    pub reverse: u32,
    pub params: SphParams<R>,
    /// The conduction's constants (the fused entries only).
    pub hp: HeatParams,
    pub grid: *const GridParams,
    pub starts: *const u32,
    /// The Verlet list of `grid`, or null: walk the stencil.
    pub list: *const u32,
    /// The interaction's read-only arrays (`sph::interact::Arrays`, embedded so its field list is written once).
    pub arrays: Arrays<R, D>,
    pub pos_t: *mut D::Vec<R>,
    pub vel_t: *mut D::Vec<R>,
    pub rho_t: *mut R,
    pub stress_t: *mut D::Sym<R>,
    /// Null: the dissipation rate is not stored.
    pub dissipation_t: *mut R,
    /// The Balsara switch's factor f_i of this step's L_i (`sph::interact::balsara`), which the next pre-pass
    /// reads; null: the switch is off (a uniform branch per particle, after the pair loop).
    pub av_switch: *mut R,
    /// The fused conduction's inputs (volumes from the full masses) and Ṫ; null in the plain entries.
    pub heat_vol: *const R,
    pub temp: *const f64,
    pub materials: *const ThermalMaterial,
    pub temp_t: *mut f64,
}

impl<R: Real, D: Dim> RatesArgs<R, D> {
    /// The fused conduction's read-only arrays.
    #[inline(always)]
    pub fn heat_arrays(&self) -> HeatArrays<R, D::Vec<R>> {
        HeatArrays {
            pos: self.arrays.pos,
            rho: self.arrays.rho,
            vol: self.heat_vol,
            temp: self.temp,
            flags: self.arrays.flags,
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

    /// Stores particle i's rates (the dissipation rate where `dissipation_t` is set, the Balsara factor where
    /// `av_switch` is).
    ///
    /// # Safety
    /// i < n, and the output arrays hold n particles.
    #[inline(always)]
    pub unsafe fn store(&self, i: usize, o: &Rates<R, D>) {
        unsafe {
            *self.pos_t.add(i) = o.pos_t;
            *self.vel_t.add(i) = o.vel_t;
            *self.rho_t.add(i) = o.rho_t;
            *self.stress_t.add(i) = o.stress_t;
            if !self.dissipation_t.is_null() {
                *self.dissipation_t.add(i) = o.dissipation_t;
            }
            if !self.av_switch.is_null() {
                *self.av_switch.add(i) = o.av_switch;
            }
        }
    }
}

/// The pair interaction pass (`swarf_sph_rates_*`; with `HEAT` the fused conduction, `swarf_sph_rates_heat_*`),
/// with the viscosity (`AV`), the artificial stress (`AS`) and XSPH (`XS`), `lanes` threads per particle on the
/// GPU (the CPU sums the lanes' shares in the same order: `sph::lanes`); with `DMG` the damage's interaction mask
/// (`swarf_sph_rates_*_dmg`, `arrays.mask` set); with `CS` the corrected kernel gradient (`swarf_sph_rates_*_cspm`,
/// `arrays.correction` set by the correction pass); with `CUT` no continuum pair across the cohesive path
/// (`swarf_sph_rates_*_cut`, `sph::interact::cut_apart`; with CSPM `_cspm_cut`; without conduction or damage,
/// which the scene refuses with it).
pub struct RatesPass<
    R,
    D,
    const AV: bool,
    const AS: bool,
    const XS: bool,
    const HEAT: bool,
    const DMG: bool,
    const CS: bool,
    const CUT: bool,
>(PhantomData<(R, D)>);

impl<
    R: Real,
    D: TensorOps<R>,
    const AV: bool,
    const AS: bool,
    const XS: bool,
    const HEAT: bool,
    const DMG: bool,
    const CS: bool,
    const CUT: bool,
> Pass for RatesPass<R, D, AV, AS, XS, HEAT, DMG, CS, CUT>
{
    type Args = RatesArgs<R, D>;
    const ENTRY: usize = entry_index("rates", D::D, size_of::<R>(), rates_variant(AV, AS, XS, HEAT, DMG, CS, CUT));
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
    fn order(a: &mut Self::Args) -> Option<&mut u32> {
        Some(&mut a.reverse)
    }
    unsafe fn particle(a: &Self::Args, i: usize) -> u32 {
        unsafe {
            let (arr, nb) = (a.arrays, a.neighbours());
            let o = if HEAT {
                let (o, tt) = rates_heat::<R, D, AV, AS, XS, DMG, CS>(
                    &a.params,
                    &a.hp,
                    &nb,
                    &arr,
                    &a.heat_arrays(),
                    i as u32,
                    a.lanes,
                );
                *a.temp_t.add(i) = tt;
                o
            } else {
                rates::<R, D, AV, AS, XS, DMG, CS, CUT>(&a.params, &nb, &arr, i as u32, a.lanes)
            };
            a.store(i, &o);
        }
        0
    }
}
