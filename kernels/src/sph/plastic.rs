//! The plastic update of one particle after the corrector (roethlin-solver.md §5.2 step 13; klippel §2.2): the
//! radial return of the trial deviatoric stress (always f64, `material::return_map`), the equivalent plastic
//! strain and its rate, and the plastic heating ΔT = t_q σ_y Δε̄/(ρ c_p) capped at the melt temperature. Under
//! `model = "mfree_iwf"` ([`PlasticConsts::flags`]) the return is Röthlin's 2D code's (`material::c2d_return`).

use super::heat::ThermalMaterial;
use super::params::flags;
use super::tensor::TensorOps;
use crate::damage::{DamageParams, DamageState, damage_step, released_density, triaxiality};
use crate::material::eos::reference_density;
use crate::material::{
    FlowStress, ReturnOptions, ReturnResult, ReturnStatus, c2d_return, heated_temperature, plastic_heating,
    radial_return,
};
use crate::real::Real;
use crate::vector::SymTensor;

/// Constants of the plastic update.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PlasticConsts {
    /// Shear modulus G [Pa].
    pub shear: f64,
    /// Time step Δt [s] (the plastic strain rate is Δε̄/Δt).
    pub dt: f64,
    /// Taylor–Quinney coefficient t_q; 0 switches plastic heating off.
    pub taylor_quinney: f64,
    /// Parts of the original code's return ([`return_flags`]; 0: swarf's), set from the scene's `model` only.
    pub flags: u32,
    pub _pad: u32,
}

/// The bits of [`PlasticConsts::flags`]: Röthlin's 2D code's radial return, reproduced under `model = "mfree_iwf"`
/// (docs/validation.md, "The original model").
pub mod return_flags {
    /// [C2D]'s procedure (`material::c2d_return`): the elastic check at the previous step's ε̄̇, its secant
    /// iteration with an absolute tolerance, its f32 roundings.
    pub const C2D_RETURN: u32 = 1;
    /// The trial norm without the factor 2 on S_xy² (**a bug**, roethlin-solver.md §11 erratum 25a), in
    /// whichever procedure runs.
    pub const C2D_NORM: u32 = 2;
}

/// Converts the stored deviatoric stress (2D: xx, xy, yy, zz; 3D: xx, xy, xz, yy, yz, zz) to the 3D layout of the
/// return map and back.
#[inline(always)]
fn to6<R: Real, S: SymTensor<R>>(s: &S) -> [f64; 6] {
    let c = s.components();
    if S::COMPONENTS == 4 {
        [c[0].to_f64(), c[1].to_f64(), 0.0, c[2].to_f64(), 0.0, c[3].to_f64()]
    } else {
        let mut o = [0.0; 6];
        let mut k = 0;
        while k < 6 && k < c.len() {
            o[k] = c[k].to_f64();
            k += 1;
        }
        o
    }
}

#[inline(always)]
fn from6<R: Real, S: SymTensor<R>>(v: &[f64; 6], s: &mut S) {
    let c = s.components_mut();
    if S::COMPONENTS == 4 {
        let m = [v[0], v[1], v[3], v[5]];
        let mut k = 0;
        while k < 4 && k < c.len() {
            c[k] = R::from_f64(m[k]);
            k += 1;
        }
    } else {
        let mut k = 0;
        while k < 6 && k < c.len() {
            c[k] = R::from_f64(v[k]);
            k += 1;
        }
    }
}

/// The plastic update of one particle with swarf's return (`C2D` false; the norm flag read at run time) or [C2D]'s
/// (true). `cp` is the specific heat of its material (unused when t_q = 0); `carried` the fraction of the stress
/// the particle acts with (1, or a damaged particle's exp(−D), `damage::multiplier`): the heating is
/// η_TQ · carried · σ_y Δε̄ (Eq. 3.72 with the stress the particle does work with, docs/damage.md).
/// Returns the return's result (its flow stress at the temperature before the heating).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn update_with<R: Real, D: TensorOps<R>, M: FlowStress, const C2D: bool>(
    model: &M,
    c: &PlasticConsts,
    s: &mut D::Sym<R>,
    eps: &mut f64,
    rate: &mut f64,
    temp: &mut f64,
    rho: R,
    fl: u32,
    cp: f64,
    carried: f64,
) -> ReturnResult {
    let trial = to6::<R, _>(s);
    let c2d_norm = c.flags & return_flags::C2D_NORM != 0;
    let r = if C2D {
        c2d_return(model, &trial, *eps, *rate, *temp, c.shear, c.dt, c2d_norm)
    } else {
        let opts = ReturnOptions { c2d_norm, ..ReturnOptions::DEFAULT };
        radial_return(model, &trial, *eps, *rate, *temp, c.shear, c.dt, &opts)
    };
    let d_eps = r.eps - *eps;
    if r.status != ReturnStatus::Elastic {
        from6::<R, _>(&r.stress, s);
    }
    if c.taylor_quinney > 0.0 && d_eps > 0.0 && fl & flags::FIXED_TEMPERATURE == 0 {
        // σ_y(ε̄_new, ε̄̇_new, T) before the heating: the return's own flow stress.
        *temp = heated_temperature(
            *temp,
            plastic_heating(c.taylor_quinney, carried * r.flow_stress, d_eps, rho.to_f64(), cp),
            model.melt_temperature(),
        );
    }
    *eps = r.eps;
    *rate = r.rate;
    r
}

/// Per-particle arrays of the plastic pass (sorted order).
#[derive(Clone, Copy)]
pub struct PlasticArrays<R: Real, S> {
    pub stress: *mut S,
    pub rho: *const R,
    pub eps: *mut f64,
    pub rate: *mut f64,
    pub temp: *mut f64,
    pub flags: *const u32,
    /// Thermal materials by body (null when plastic heating is off).
    pub materials: *const ThermalMaterial,
    /// The flow stress σ_y(ε̄, ε̄̇, T) after the update (null unless the contact's friction cap needs it).
    pub yield_stress: *mut f64,
    /// Accumulated specific plastic work w = Σ σ_y Δε̄ / ρ [J/kg] (null unless the run balances its energy).
    pub work: *mut f64,
    /// The damage's arrays (read only by the damaged entries: `DMG`).
    pub damage: DamageArrays<R>,
}

/// The damage's per-particle arrays in the plastic pass, one block in the standalone plastic pass's arguments and
/// in the fused corrector's ([`PlasticArrays::damage`]); [`DamageArrays::NONE`] without damage.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct DamageArrays<R> {
    /// The damage constants (one element).
    pub params: *const DamageParams,
    /// Damage initiation ω and evolution D (`damage::damage_step`).
    pub omega: *mut f64,
    pub damage: *mut f64,
    /// The particles' full masses (the volume m/ρ of L_char).
    pub mass: *const R,
    /// Accumulated specific elastic energy the degradation has released, Σ `damage::released_density`/ρ [J/kg]
    /// (null: not tracked).
    pub work: *mut f64,
}

impl<R> DamageArrays<R> {
    /// No damage: every pointer null.
    pub const NONE: Self = DamageArrays {
        params: core::ptr::null(),
        omega: core::ptr::null_mut(),
        damage: core::ptr::null_mut(),
        mass: core::ptr::null(),
        work: core::ptr::null_mut(),
    };
}

/// The plastic update of sorted particle i, reading and writing the arrays; with `DMG` the damage after it.
///
/// # Safety
/// All arrays hold at least i + 1 particles; `materials` covers every body index when t_q > 0; the damage's
/// arrays are set with `DMG`.
#[inline(always)]
pub unsafe fn plastic_particle<R: Real, D: TensorOps<R>, M: FlowStress + Copy, const DMG: bool>(
    model: &M,
    c: &PlasticConsts,
    a: &PlasticArrays<R, D::Sym<R>>,
    i: usize,
) {
    if c.flags & return_flags::C2D_RETURN != 0 {
        // [C2D]'s return: a function of its own, called with copies, so that the default's corrector neither grows
        // by a second solver nor keeps the model, the trial stress and the result in local memory for the call.
        unsafe { c2d_particle::<R, D, M, DMG>(*model, *c, *a, i) }
    } else {
        unsafe { particle_with::<R, D, M, false, DMG>(model, c, a, i) }
    }
}

/// [`plastic_particle`] with [C2D]'s return (`model = "mfree_iwf"`), never inlined.
///
/// # Safety
/// As [`plastic_particle`].
#[inline(never)]
unsafe fn c2d_particle<R: Real, D: TensorOps<R>, M: FlowStress, const DMG: bool>(
    model: M,
    c: PlasticConsts,
    a: PlasticArrays<R, D::Sym<R>>,
    i: usize,
) {
    unsafe { particle_with::<R, D, M, true, DMG>(&model, &c, &a, i) }
}

/// [`plastic_particle`]'s body with swarf's return (`C2D` false) or [C2D]'s (true).
///
/// # Safety
/// As [`plastic_particle`].
#[inline(always)]
unsafe fn particle_with<R: Real, D: TensorOps<R>, M: FlowStress, const C2D: bool, const DMG: bool>(
    model: &M,
    c: &PlasticConsts,
    a: &PlasticArrays<R, D::Sym<R>>,
    i: usize,
) {
    unsafe {
        let fl = *a.flags.add(i);
        let cp = if c.taylor_quinney > 0.0 && !a.materials.is_null() {
            (*a.materials.add((fl >> flags::BODY_SHIFT) as usize)).specific_heat
        } else {
            1.0
        };
        let (e0, t0) = (*a.eps.add(i), *a.temp.add(i));
        let (mut e, mut r, mut t) = (e0, *a.rate.add(i), t0);
        let rho = *a.rho.add(i);
        // The fraction of the stress the particle acted with this step: the pre-pass degraded σ with the D it read,
        // the one before this step's damage update (1 without damage; exactly 1.0, so undamaged entries round
        // as before).
        let carried = if DMG { crate::damage::multiplier(*a.damage.damage.add(i)) } else { 1.0 };
        let ret =
            update_with::<R, D, M, C2D>(model, c, &mut *a.stress.add(i), &mut e, &mut r, &mut t, rho, fl, cp, carried);
        if !a.work.is_null() && e > e0 {
            // The dissipation of the step, carried · σ_y Δε̄ per unit volume, at the flow stress the plastic heating
            // uses (σ_y(ε̄_new, ε̄̇_new, T_old), the return's).
            *a.work.add(i) += carried * ret.flow_stress * (e - e0) / rho.to_f64();
        }
        if DMG && e > e0 {
            let dm = &a.damage;
            let d0 = *dm.damage.add(i);
            let p = damage_after_return::<R>(dm, i, rho.to_f64(), e - e0, ret.flow_stress, r, t0);
            let d1 = *dm.damage.add(i);
            if !dm.work.is_null() && d1 != d0 {
                // The elastic energy the step's degradation releases at the stress after the return.
                let ss = D::double_dot(&*a.stress.add(i)).to_f64();
                let (k0, k1) = (crate::damage::multiplier(d0), crate::damage::multiplier(d1));
                let bulk = (*dm.params).bulk;
                *dm.work.add(i) += released_density(k0, k1, ss, c.shear, p, bulk) / rho.to_f64();
            }
        }
        *a.eps.add(i) = e;
        *a.rate.add(i) = r;
        *a.temp.add(i) = t;
        if !a.yield_stress.is_null() {
            // σ_y(ε̄_new, ε̄̇_new, T_new): the return's where the temperature did not change (every elastic step),
            // else its strength part at the new thermal part (the same bits as evaluating σ_y whole).
            *a.yield_stress.add(i) = if t.to_bits() == t0.to_bits() {
                ret.flow_stress
            } else {
                model.sigma_y_parts(e, r, t, ret.strength, model.thermal_part(t))
            };
        }
    }
}

/// The damage after the plastic update of particle i (weak coupling, klippel §2.6, §7.4.2), from its Δε̄ `de` and
/// σ_y, the triaxiality −p/σ_y of the undamaged pressure (the pre-pass's EOS, with ρ0(T) where the run models
/// thermal expansion), ε̄̇ and T before the heating. Returns that pressure p.
/// Only the damaged entries (`DMG`) run it: a run without damage keeps its corrector's code and registers.
///
/// # Safety
/// `a`'s arrays hold i + 1 elements; `a.params` points at the constants.
#[inline(always)]
unsafe fn damage_after_return<R: Real>(
    a: &DamageArrays<R>,
    i: usize,
    rho: f64,
    de: f64,
    flow_stress: f64,
    rate: f64,
    temp: f64,
) -> f64 {
    unsafe {
        let dp = &*a.params;
        let rho0 = reference_density(dp.rho0, dp.expansion, dp.expansion_t0, temp);
        let pressure = dp.c0sq * (rho - rho0);
        let triax = triaxiality(pressure, flow_stress);
        let vol = (*a.mass.add(i)).to_f64() / rho;
        let st = DamageState { omega: *a.omega.add(i), d: *a.damage.add(i) };
        let st = damage_step(dp, st, de, flow_stress, triax, rate, temp, vol);
        *a.omega.add(i) = st.omega;
        *a.damage.add(i) = st.d;
        pressure
    }
}
