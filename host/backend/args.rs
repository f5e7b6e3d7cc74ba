//! The passes' argument structs (`kernels::pass`) built from a backend's buffers. Both backends build them here,
//! so each buffer's length is checked once, by [`check_len`], on the CPU and on the GPU alike; the CPU backend
//! adds the checks that read buffer contents (the cell starts against the grid, the bodies against the
//! materials), which the GPU's memory does not allow.

use super::{
    Backend, BondBufs, Buffer, ContactInputs, DamageBufs, Element, FieldsMut, FusedContact, FusedHeat, FusedPrepare,
    HeatInputs, PlasticInputs, PlasticPass, PrepassBufs, PrepassDamageBufs, ScalarsAt, ScalarsMut, SkinTest, SphInputs,
    StepFields, ToolStatesAt, tool::DeviceTools,
};
use crate::kernels::contact::penalty::ToolSet;
use crate::kernels::contact::{ToolArg, ToolState};
use crate::kernels::neighbour::{BlankBox, GridParams};
use crate::kernels::pass::{
    BondArgs, BondIndexArgs, BondOpenArgs, ContactArgs, CorrectionArgs, DensityArgs, FinishArgs, FinishPlasticArgs,
    HashArgs, HeatArgs, NeighbourListArgs, PlasticArgs, PredictArgs, PrepareArgs, RatesArgs, Span, StepPtrs,
    VerletArgs,
};
use crate::kernels::sph::correction::CorrectionArrays;
use crate::kernels::sph::heat::HeatParams;
use crate::kernels::sph::interact::{Arrays, PrepassArrays, PrepassDamage};
use crate::kernels::sph::plastic::{DamageArrays, PlasticConsts};
use crate::kernels::sph::step::StepScalars;
use crate::kernels::sph::{CubicSpline, SphParams, Stabilisers, TensorOps};
use crate::kernels::{Dim, Real};
use crate::{Error, Result};

/// An error unless a buffer of `len` elements holds the `n` a pass reads or writes.
pub fn check_len(what: &'static str, n: usize, len: usize) -> Result<()> {
    if len < n { Err(Error::Length { op: what, expected: n, got: len }) } else { Ok(()) }
}

/// The address of a buffer of at least `n` elements, for reading.
fn input<B: Backend, T: Element>(b: &B, what: &'static str, n: usize, buf: &B::Buf<T>) -> Result<*const T> {
    check_len(what, n, buf.len())?;
    Ok(b.address(buf) as *const T)
}

/// The address of a buffer of at least `n` elements, for writing.
fn output<B: Backend, T: Element>(b: &B, what: &'static str, n: usize, buf: &mut B::Buf<T>) -> Result<*mut T> {
    check_len(what, n, buf.len())?;
    Ok(b.address_mut(buf) as *mut T)
}

/// The address of an optional input (null where off).
fn input_opt<B: Backend, T: Element>(b: &B, what: &'static str, n: usize, buf: Option<&B::Buf<T>>) -> Result<*const T> {
    buf.map_or(Ok(std::ptr::null()), |buf| input(b, what, n, buf))
}

/// The address of an optional output (null where off).
fn output_opt<B: Backend, T: Element>(
    b: &B,
    what: &'static str,
    n: usize,
    buf: Option<&mut B::Buf<T>>,
) -> Result<*mut T> {
    buf.map_or(Ok(std::ptr::null_mut()), |buf| output(b, what, n, buf))
}

/// The pair interaction's arguments ([`super::Passes::sph_rates`]). The stabilisers'
/// buffers must be given where they are on (and are passed as null where off).
#[allow(clippy::too_many_arguments)]
pub fn rates_args<B: Backend, R: Real, D: Dim>(
    b: &B,
    c: super::Count<'_, B>,
    lanes: u32,
    stab: Stabilisers,
    params: &SphParams<R>,
    grid: &B::Buf<GridParams>,
    starts: &B::Buf<u32>,
    list: Option<&B::Buf<u32>>,
    i: &SphInputs<'_, B, R, D>,
    out: FieldsMut<'_, B, R, D>,
    dissipation: Option<&mut B::Buf<R>>,
    av_switch: Option<&mut B::Buf<R>>,
    heat: Option<FusedHeat<'_, B, R, D>>,
) -> Result<RatesArgs<R, D>> {
    let n = c.n;
    viscosity_for_switch(stab, av_switch.is_some(), "sph_rates (the Balsara switch without the viscosity)")?;
    let art = if stab.stress { input(b, "sph_rates art", n, i.art.ok_or(missing("sph_rates art"))?)? } else { null() };
    let sound = if stab.viscosity {
        input(b, "sph_rates sound", n, i.sound.ok_or(missing("sph_rates sound"))?)?
    } else {
        null()
    };
    let (hp, heat_vol, temp, materials, temp_t) = match heat {
        Some(h) => (
            *h.params,
            input(b, "vol", n, h.input.vol)?,
            input(b, "temp", n, h.input.temp)?,
            b.address(h.input.materials) as *const _,
            output(b, "sph_rates temp_t", n, h.temp_t)?,
        ),
        None => (HeatParams::default(), null(), null(), null(), std::ptr::null_mut()),
    };
    Ok(RatesArgs {
        n: span(b, &c)?,
        lanes,
        // The GPU backend sets the block order at the launch (`Pass::order`).
        reverse: 0,
        params: *params,
        hp,
        grid: input(b, "sph_rates grid", 1, grid)?,
        starts: b.address(starts) as *const u32,
        list: input_opt(b, "sph_rates list", 0, list)?,
        arrays: Arrays {
            pos: input(b, "pos", n, i.pos)?,
            vel: input(b, "vel", n, i.vel)?,
            rho: input(b, "rho", n, i.rho)?,
            mass: input(b, "mass", n, i.mass)?,
            vol: input(b, "vol", n, i.vol)?,
            stress: input(b, "stress", n, i.stress)?,
            sig: input(b, "sig", n, i.sig)?,
            art,
            sound,
            flags: input(b, "flags", n, i.flags)?,
            bc_vel: b.address(i.bc_vel) as *const _,
            normal: input_opt(b, "contact normal", n, i.contact.map(|c| c.0))?,
            friction: input_opt(b, "contact friction", n, i.contact.map(|c| c.1))?,
            mask: input_opt(b, "damage mask", n, i.mask)?,
            correction: input_opt(b, "cspm correction", n, i.correction)?,
        },
        pos_t: output(b, "pos_t", n, out.pos)?,
        vel_t: output(b, "vel_t", n, out.vel)?,
        rho_t: output(b, "rho_t", n, out.rho)?,
        stress_t: output(b, "stress_t", n, out.stress)?,
        dissipation_t: output_opt(b, "sph_rates dissipation", n, dissipation)?,
        av_switch: output_opt(b, "sph_rates av_switch", n, av_switch)?,
        heat_vol,
        temp,
        materials,
        temp_t,
    })
}

/// The correction pass's arguments ([`super::Passes::sph_correction`]).
#[allow(clippy::too_many_arguments)]
pub fn correction_args<B: Backend, R: Real, D: Dim>(
    b: &B,
    c: super::Count<'_, B>,
    lanes: u32,
    params: &SphParams<R>,
    (min_det, path_only): (R, bool),
    grid: &B::Buf<GridParams>,
    starts: &B::Buf<u32>,
    list: Option<&B::Buf<u32>>,
    i: &SphInputs<'_, B, R, D>,
    out: &mut B::Buf<D::Sym<R>>,
) -> Result<CorrectionArgs<R, D>> {
    let n = c.n;
    Ok(CorrectionArgs {
        n: span(b, &c)?,
        lanes,
        // The GPU backend sets the block order at the launch (`Pass::order`).
        reverse: 0,
        path_only: path_only as u32,
        kernel: params.kernel,
        min_r2: params.min_r2,
        min_det,
        grid: input(b, "sph_correction grid", 1, grid)?,
        starts: b.address(starts) as *const u32,
        list: input_opt(b, "sph_correction list", 0, list)?,
        arrays: CorrectionArrays {
            pos: input(b, "pos", n, i.pos)?,
            mass: input(b, "mass", n, i.mass)?,
            vol: input(b, "vol", n, i.vol)?,
            flags: input(b, "flags", n, i.flags)?,
        },
        out: output(b, "cspm correction", n, out)?,
    })
}

fn null<T>() -> *const T {
    std::ptr::null()
}

/// A stabiliser's buffer that is on but was not given.
fn missing(what: &'static str) -> Error {
    Error::Length { op: what, expected: 1, got: 0 }
}

/// The Balsara switch's factors scale the viscosity's sound speed: given without the viscosity, they would be
/// written or read for nothing (a set-up error).
fn viscosity_for_switch(stab: Stabilisers, switch: bool, op: &'static str) -> Result<()> {
    if switch && !stab.viscosity {
        return Err(Error::Length { op, expected: 0, got: 1 });
    }
    Ok(())
}

/// The address of the step's scalars (entry `s.index` of `s.buf`).
pub fn scalars_ptr<B: Backend>(b: &B, s: &ScalarsAt<'_, B>) -> Result<*const StepScalars> {
    check_len("step scalars", s.index + 1, s.buf.len())?;
    Ok((b.address(s.buf) as *const StepScalars).wrapping_add(s.index))
}

/// The address of a step's tool states (`count` of them).
pub fn states_ptr<B: Backend>(b: &B, s: &ToolStatesAt<'_, B>) -> Result<*const ToolState> {
    check_len("tool states", (s.index + 1) * s.count, s.buf.len())?;
    Ok((b.address(s.buf) as *const ToolState).wrapping_add(s.index * s.count))
}

/// The addresses of the fields a step integrates, each checked to hold n particles.
pub fn step_ptrs<B: Backend, R: Real, D: Dim>(b: &B, n: usize, f: StepFields<'_, B, R, D>) -> Result<StepPtrs<R, D>> {
    let (temp, temp0, temp_t) = match (f.temp, f.conduction) {
        (Some(t), Some((t0, tt))) => (
            output(b, "step temperature", n, t)?,
            output(b, "step temperature", n, t0)?,
            input(b, "step temperature", n, tt)?,
        ),
        (Some(t), None) => (output(b, "step temperature", n, t)?, std::ptr::null_mut(), null()),
        _ => (std::ptr::null_mut(), std::ptr::null_mut(), null()),
    };
    let (diss, diss_t) = match f.dissipation {
        Some((d, dt)) => (output(b, "step dissipation", n, d)?, input(b, "step dissipation", n, dt)?),
        None => (std::ptr::null_mut(), null()),
    };
    Ok(StepPtrs {
        pos: output(b, "step fields", n, f.y.pos)?,
        vel: output(b, "step fields", n, f.y.vel)?,
        rho: output(b, "step fields", n, f.y.rho)?,
        stress: output(b, "step fields", n, f.y.stress)?,
        pos0: output(b, "step fields", n, f.y0.pos)?,
        vel0: output(b, "step fields", n, f.y0.vel)?,
        rho0: output(b, "step fields", n, f.y0.rho)?,
        stress0: output(b, "step fields", n, f.y0.stress)?,
        pos_t: input(b, "step fields", n, f.rates.pos)?,
        vel_t: input(b, "step fields", n, f.rates.vel)?,
        rho_t: input(b, "step fields", n, f.rates.rho)?,
        stress_t: input(b, "step fields", n, f.rates.stress)?,
        temp,
        temp0,
        temp_t,
        diss,
        diss_t,
        pos_lo: output_opt(b, "step position low parts", n, f.pos_lo)?,
    })
}

/// The corrector's arguments ([`super::Passes::step_finish`] without plasticity).
pub fn finish_args<B: Backend, R: Real, D: Dim>(
    b: &B,
    c: super::Count<'_, B>,
    s: &ScalarsAt<'_, B>,
    f: StepFields<'_, B, R, D>,
) -> Result<FinishArgs<R, D>> {
    let n = c.n;
    Ok(FinishArgs { n: span(b, &c)?, scalars: scalars_ptr(b, s)?, step: step_ptrs(b, n, f)? })
}

/// The arguments of the corrector with the plastic update of `model` (the kernel type of `p.model`) and, with
/// `contact`, the tool's contact pass ([`super::Passes::step_finish`]).
#[allow(clippy::too_many_arguments)]
pub fn finish_plastic_args<B: Backend, R: Real, D: Dim, M>(
    b: &B,
    c: super::Count<'_, B>,
    s: &ScalarsAt<'_, B>,
    f: StepFields<'_, B, R, D>,
    p: PlasticPass<'_, B, R>,
    model: M,
    contact: Option<FusedContact<'_, B, R, D>>,
) -> Result<FinishPlasticArgs<R, D, M>> {
    let n = c.n;
    if f.temp.is_none() {
        return Err(Error::Length { op: "step_finish (plasticity needs temperature)", expected: n, got: 0 });
    }
    if p.taylor_quinney > 0.0 && p.materials.is_none() {
        return Err(Error::Length { op: "step_finish (thermal materials missing)", expected: 1, got: 0 });
    }
    let yield_stress = output_opt(b, "yield_stress", n, p.yield_stress)?;
    let mut a = FinishPlasticArgs {
        n: span(b, &c)?,
        reverse: 0,
        scalars: scalars_ptr(b, s)?,
        model,
        shear: p.shear,
        taylor_quinney: p.taylor_quinney,
        return_flags: p.return_flags,
        _pad: 0,
        step: step_ptrs(b, n, f)?,
        eps: output(b, "eps", n, p.eps)?,
        rate: output(b, "rate", n, p.rate)?,
        flags: input(b, "flags", n, p.flags)?,
        materials: p.materials.map_or(null(), |m| b.address(m) as *const _),
        yield_stress,
        work: output_opt(b, "plastic work", n, p.work)?,
        damage: p.damage.map_or(Ok(DamageArrays::NONE), |d| damage_arrays(b, n, d))?,
        contact: null(),
        contact_tool: null(),
        contact_state: null(),
        mass: null(),
        normal: std::ptr::null_mut(),
        friction: std::ptr::null_mut(),
        contact_materials: null(),
        contact_yield: null(),
        wear: std::ptr::null_mut(),
    };
    if let Some(c) = contact {
        if c.yield_stress && yield_stress.is_null() {
            return Err(Error::Length { op: "step_finish (the friction cap's yield stresses)", expected: 1, got: 0 });
        }
        a.contact = input(b, "contact parameters", 1, c.params)?;
        a.contact_tool = input(b, "the tool's shape", 1, c.tool)?;
        a.contact_state = states_ptr(b, &c.state)?;
        a.mass = input(b, "mass", n, c.mass)?;
        a.normal = output(b, "normal", n, c.normal)?;
        a.friction = output(b, "friction", n, c.friction)?;
        a.contact_materials = c.materials.map_or(null(), |m| b.address(m) as *const _);
        a.contact_yield = if c.yield_stress { yield_stress } else { null() };
        a.wear = output_opt(b, "wear", n, c.wear)?;
    }
    Ok(a)
}

/// The damage's addresses in the plastic pass (constants, ω, D, masses, released energy), each checked.
fn damage_arrays<B: Backend, R: Real>(b: &B, n: usize, d: DamageBufs<'_, B, R>) -> Result<DamageArrays<R>> {
    Ok(DamageArrays {
        params: input(b, "damage parameters", 1, d.params)?,
        omega: output(b, "damage omega", n, d.omega)?,
        damage: output(b, "damage", n, d.damage)?,
        mass: input(b, "damage mass", n, d.mass)?,
        work: output_opt(b, "damage work", n, d.work)?,
    })
}

/// The pre-pass's damage view (null: off).
fn prepass_damage<B: Backend>(b: &B, n: usize, d: Option<PrepassDamageBufs<'_, B>>) -> Result<PrepassDamage> {
    let Some(d) = d else { return Ok(PrepassDamage::OFF) };
    Ok(PrepassDamage {
        damage: input(b, "damage", n, d.damage)?,
        mask: output(b, "damage mask", n, d.mask)?,
        flags: d.flags,
        _pad: 0,
    })
}

/// A pass's particles as the kernels take them: the count, and with blanking the address of the active count
/// (checked to lie in its buffer).
fn span<B: Backend>(b: &B, c: &super::Count<'_, B>) -> Result<Span> {
    let mut s = Span::all(count(c.n)?);
    if let Some((buf, index)) = c.active {
        check_len("active count", index + 1, buf.len())?;
        s.active = (b.address(buf) as *const u32).wrapping_add(index);
    }
    Ok(s)
}

/// A particle count as the kernels take it.
fn count(n: usize) -> Result<u32> {
    u32::try_from(n).map_err(|_| Error::Length {
        op: "particles (at most 2^32 - 1)",
        expected: u32::MAX as usize,
        got: n,
    })
}

/// The address of the step's rebuild flag (`StepScalars::rebuild`), the gate of a rebuild's launches (null:
/// always run).
pub fn gate_ptr<B: Backend>(b: &B, s: Option<&ScalarsAt<'_, B>>) -> Result<*const u32> {
    let Some(s) = s else { return Ok(null()) };
    let at = scalars_ptr(b, s)? as *const u8;
    Ok(at.wrapping_add(std::mem::offset_of!(StepScalars, rebuild)) as *const u32)
}

/// The density sum's arguments ([`super::Passes::density`]).
#[allow(clippy::too_many_arguments)]
pub fn density_args<B: Backend, R: Real, D: Dim>(
    b: &B,
    c: super::Count<'_, B>,
    pos: &B::Buf<D::Vec<R>>,
    mass: &B::Buf<R>,
    grid: &B::Buf<GridParams>,
    starts: &B::Buf<u32>,
    kernel: &B::Buf<CubicSpline<R>>,
    rho: &mut B::Buf<R>,
) -> Result<DensityArgs<R, D>> {
    let n = c.n;
    Ok(DensityArgs {
        n: span(b, &c)?,
        pos: input(b, "density pos", n, pos)?,
        mass: input(b, "density mass", n, mass)?,
        grid: input(b, "density grid", 1, grid)?,
        starts: b.address(starts) as *const u32,
        kernel: input(b, "density kernel", 1, kernel)?,
        rho: output(b, "density rho", n, rho)?,
    })
}

/// The arguments of the cohesive path's three passes: the id map, the bonds, the opening.
pub type BondPassArgs<R, D> = (BondIndexArgs<R, D>, BondArgs<R, D>, BondOpenArgs<R, D>);

/// The bond pass's, the id map's and the opening pass's arguments ([`super::Passes::bonds`]) for `n` sorted
/// particles.
pub fn bond_args<B: Backend, R: Real, D: TensorOps<R>>(
    b: &B,
    n: usize,
    k: BondBufs<'_, B, R, D>,
    vel_t: &mut B::Buf<D::Vec<R>>,
) -> Result<BondPassArgs<R, D>> {
    let count =
        u32::try_from(n).map_err(|_| Error::Length { op: "bonds count", expected: u32::MAX as usize, got: n })?;
    let index = output(b, "bond index", n, k.index)?;
    let map = BondIndexArgs {
        n: count,
        _pad: 0,
        id: input(b, "bond ids", n, k.id)?,
        index,
        _marker: std::marker::PhantomData,
    };
    let onset = output(b, "bond onsets", n, k.onset)?;
    let arrays = crate::kernels::sph::bond::BondArrays {
        index: index as *const u32,
        partner: input(b, "bond partners", n, k.partner)?,
        reference: input(b, "bond reference offsets", n, k.reference)?,
        state: output(b, "bond states", n, k.state)?,
        onset,
        work: output(b, "bond work", n, k.work)?,
        damping: output(b, "bond damping", n, k.damping)?,
        pos: input(b, "bond pos", n, k.pos)?,
        vel: input(b, "bond vel", n, k.vel)?,
        mass: input(b, "bond mass", n, k.mass)?,
        flags: input(b, "bond flags", n, k.flags)?,
        sig: input(b, "bond stress over density squared", n, k.sig)?,
        rho: input(b, "bond density", n, k.rho)?,
        vel_t: output(b, "bond accelerations", n, vel_t)?,
    };
    let open = BondOpenArgs {
        n: count,
        _pad: 0,
        index: index as *const u32,
        column: input(b, "bond columns", n, k.column)?,
        onset: onset as *const _,
        flags: output(b, "bond flags", n, k.flags)?,
        _marker: std::marker::PhantomData,
    };
    Ok((map, BondArgs { n: count, _pad: 0, params: k.params, arrays }, open))
}

/// The pre-pass's buffers ([`super::Passes::sph_prepare`]).
pub struct PrepareBufs<'a, B: Backend, R: Real, D: Dim> {
    pub params: &'a B::Buf<SphParams<R>>,
    pub rho: &'a B::Buf<R>,
    pub mass: &'a B::Buf<R>,
    pub stress: &'a B::Buf<D::Sym<R>>,
    pub out: PrepassBufs<'a, B, R, D>,
    pub temp: Option<&'a B::Buf<f64>>,
    pub damage: Option<PrepassDamageBufs<'a, B>>,
}

/// The pre-pass's arguments; the stabilisers' buffers must be given where they are on (null where off).
pub fn prepare_args<B: Backend, R: Real, D: Dim>(
    b: &B,
    c: super::Count<'_, B>,
    stab: Stabilisers,
    q: PrepareBufs<'_, B, R, D>,
    gate: Option<&ScalarsAt<'_, B>>,
) -> Result<PrepareArgs<R, D>> {
    let n = c.n;
    Ok(PrepareArgs {
        gate: gate_ptr(b, gate)?,
        n: span(b, &c)?,
        params: input(b, "sph_prepare params", 1, q.params)?,
        rho: input(b, "sph_prepare rho", n, q.rho)?,
        mass: input(b, "sph_prepare mass", n, q.mass)?,
        stress: input(b, "sph_prepare stress", n, q.stress)?,
        out: prepass_arrays(b, n, stab, q.out, "sph_prepare")?,
        temp: input_opt(b, "sph_prepare temp", n, q.temp)?,
        damage: prepass_damage(b, n, q.damage)?,
    })
}

/// The pre-pass's arrays for `op`: σ/ρ² and V always; the artificial stress's and the viscosity's outputs required
/// where their stabiliser is on and null where off; the Balsara factors only with the viscosity (they scale its
/// sound speed).
fn prepass_arrays<B: Backend, R: Real, D: Dim>(
    b: &B,
    n: usize,
    stab: Stabilisers,
    q: PrepassBufs<'_, B, R, D>,
    op: &'static str,
) -> Result<PrepassArrays<R, D::Sym<R>>> {
    let missing = || Error::Length { op, expected: n, got: 0 };
    viscosity_for_switch(stab, q.av_switch.is_some(), "pre-pass (the Balsara switch without the viscosity)")?;
    let art = if stab.stress { output(b, "art", n, q.art.ok_or_else(missing)?)? } else { std::ptr::null_mut() };
    let sound =
        if stab.viscosity { output(b, "sound", n, q.sound.ok_or_else(missing)?)? } else { std::ptr::null_mut() };
    Ok(PrepassArrays {
        sig: output(b, "sig", n, q.sig)?,
        art,
        sound,
        vol: output(b, "vol", n, q.vol)?,
        av_switch: input_opt(b, "av_switch", n, q.av_switch)?,
    })
}

/// The conduction's arguments ([`super::Passes::heat_rates`]); PSE reaches beyond a Verlet list, so it takes none.
#[allow(clippy::too_many_arguments)]
pub fn heat_args<B: Backend, R: Real, D: Dim>(
    b: &B,
    c: super::Count<'_, B>,
    lanes: u32,
    pse: bool,
    hp: &HeatParams,
    params: &SphParams<R>,
    grid: &B::Buf<GridParams>,
    starts: &B::Buf<u32>,
    list: Option<&B::Buf<u32>>,
    i: &HeatInputs<'_, B, R, D>,
    temp_t: &mut B::Buf<f64>,
) -> Result<HeatArgs<R, D>> {
    let n = c.n;
    if pse && list.is_some() {
        return Err(Error::Length { op: "heat_rates (PSE reaches beyond the Verlet list)", expected: 0, got: 1 });
    }
    Ok(HeatArgs {
        n: span(b, &c)?,
        lanes,
        hp: *hp,
        params: *params,
        grid: input(b, "heat_rates grid", 1, grid)?,
        starts: b.address(starts) as *const u32,
        list: input_opt(b, "heat_rates list", 0, list)?,
        pos: input(b, "pos", n, i.pos)?,
        rho: input(b, "rho", n, i.rho)?,
        vol: input(b, "vol", n, i.vol)?,
        temp: input(b, "temp", n, i.temp)?,
        flags: input(b, "flags", n, i.flags)?,
        materials: b.address(i.materials) as *const _,
        temp_t: output(b, "heat_rates temp_t", n, temp_t)?,
    })
}

/// The predictor's arguments ([`super::Passes::step_predict`]), with the fused pre-pass where `prepare` is given.
pub fn predict_args<B: Backend, R: Real, D: Dim>(
    b: &B,
    c: super::Count<'_, B>,
    s: ScalarsMut<'_, B>,
    f: StepFields<'_, B, R, D>,
    skin: SkinTest<'_, B, R, D>,
    prepare: Option<FusedPrepare<'_, B, R, D>>,
) -> Result<PredictArgs<R, D>> {
    let n = c.n;
    check_len("step scalars", s.index + 1, s.buf.len())?;
    let scalars = (b.address_mut(s.buf) as *mut StepScalars).wrapping_add(s.index);
    let mut step = step_ptrs(b, n, f)?;
    // The predictor reads neither (its entry passed them null before the struct).
    (step.diss, step.diss_t, step.pos_lo) = (std::ptr::null_mut(), null(), std::ptr::null_mut());
    let mut a = PredictArgs {
        n: span(b, &c)?,
        scalars,
        grid: input(b, "step_predict grid", 1, skin.grid)?,
        step,
        pos_ref: input(b, "step_predict pos_ref", n, skin.pos_ref)?,
        condition: skin.condition,
        params: SphParams::default(),
        mass: null(),
        out: PrepassArrays::NONE,
        damage: PrepassDamage::OFF,
    };
    if let Some(q) = prepare {
        a.params = *q.params;
        a.mass = input(b, "step_predict mass", n, q.mass)?;
        a.out = prepass_arrays(b, n, q.stab, q.out, "step_predict")?;
        a.damage = prepass_damage(b, n, q.damage)?;
    }
    Ok(a)
}

/// The standalone plastic update's arguments ([`super::Passes::plastic_step`]) for `model` (the kernel type of the
/// host's `FlowModel`).
pub fn plastic_args<B: Backend, R: Real, D: Dim, M>(
    b: &B,
    c: super::Count<'_, B>,
    model: M,
    consts: PlasticConsts,
    a: PlasticInputs<'_, B, R, D>,
) -> Result<PlasticArgs<R, D, M>> {
    let n = c.n;
    if consts.taylor_quinney > 0.0 && a.materials.is_none() {
        return Err(Error::Length { op: "plastic_step (thermal materials missing)", expected: 1, got: 0 });
    }
    Ok(PlasticArgs {
        n: span(b, &c)?,
        model,
        consts,
        stress: output(b, "stress", n, a.stress)?,
        rho: input(b, "rho", n, a.rho)?,
        eps: output(b, "eps", n, a.eps)?,
        rate: output(b, "rate", n, a.rate)?,
        temp: output(b, "temp", n, a.temp)?,
        flags: input(b, "flags", n, a.flags)?,
        materials: a.materials.map_or(null(), |m| b.address(m) as *const _),
        yield_stress: output_opt(b, "yield_stress", n, a.yield_stress)?,
        work: output_opt(b, "plastic work", n, a.work)?,
        damage: a.damage.map_or(Ok(DamageArrays::NONE), |d| damage_arrays(b, n, d))?,
    })
}

/// The standalone contact pass's arguments ([`super::Passes::contact`]) with the tools' argument `shapes` (the
/// address of their array), for the entry of dimension `E`: the scene's `D` (parametric tools) or `Dim3` (mesh
/// tools, whose entries are 3D only); the vectors' pointers are cast after the dimensions are checked equal.
#[allow(clippy::too_many_arguments)]
pub fn contact_args<B: Backend, R: Real, D: Dim, E: Dim, T: ToolArg>(
    b: &B,
    c: super::Count<'_, B>,
    tools: &DeviceTools<B>,
    shapes: T,
    states: &ToolStatesAt<'_, B>,
    owner: Option<&mut B::Buf<u32>>,
    a: ContactInputs<'_, B, R, D>,
) -> Result<ContactArgs<R, E, T>> {
    let n = c.n;
    if D::D != E::D {
        return Err(Error::Length { op: "contact (a mesh tool is 3D)", expected: E::D, got: D::D });
    }
    if states.count != tools.count() || (tools.count() > 1) != owner.is_some() {
        return Err(Error::Length {
            op: "contact (tool states and owners)",
            expected: tools.count(),
            got: states.count,
        });
    }
    Ok(ContactArgs {
        n: span(b, &c)?,
        set: ToolSet {
            tools: shapes,
            params: input(b, "contact parameters", tools.count(), &tools.params)?,
            states: states_ptr(b, states)?,
            owner: output_opt(b, "contact owner", n, owner)?,
            count: count(tools.count())?,
            _pad: 0,
        },
        pos: input(b, "pos", n, a.pos)?.cast(),
        vel: input(b, "vel", n, a.vel)?.cast(),
        mass: input(b, "mass", n, a.mass)?,
        rho: input(b, "rho", n, a.rho)?,
        flags: input(b, "flags", n, a.flags)?,
        normal: output(b, "normal", n, a.normal)?.cast(),
        friction: output(b, "friction", n, a.friction)?.cast(),
        temp: output_opt(b, "temp", n, a.temp)?,
        materials: a.materials.map_or(null(), |m| b.address(m) as *const _),
        yield_stress: input_opt(b, "yield_stress", n, a.yield_stress)?,
        wear: output_opt(b, "wear", n, a.wear)?,
    })
}

/// The address of the blanking box in a step's scalars (null: no blanking).
pub fn blank_ptr<B: Backend>(b: &B, s: Option<&ScalarsAt<'_, B>>) -> Result<*const BlankBox> {
    match s {
        None => Ok(null()),
        Some(s) => {
            // Entry `index` exists (checked); the field lies inside it. Byte arithmetic: the address may be the
            // device's.
            let base = scalars_ptr(b, s)? as *const u8;
            Ok(base.wrapping_add(std::mem::offset_of!(StepScalars, blank)) as *const BlankBox)
        }
    }
}

/// The velocities a blanked hash reads for the box's rest speed: `vel` with a box (required), null without.
pub fn blank_vel<B: Backend, V: Element>(
    b: &B,
    blank: Option<&ScalarsAt<'_, B>>,
    vel: Option<&B::Buf<V>>,
) -> Result<*const V> {
    match (blank, vel) {
        (None, _) => Ok(null()),
        (Some(_), Some(v)) => Ok(b.address(v) as *const V),
        (Some(_), None) => Err(Error::Grid("a blanked hash needs the velocities (the box's rest speed)".into())),
    }
}

/// The hash pass's arguments ([`super::Passes::hash`]), with the blanking box of `blank`'s scalars and the
/// velocities `vel` its rest speed reads.
pub fn hash_args<B: Backend, R: Real, D: Dim>(
    b: &B,
    n: usize,
    pos: &B::Buf<D::Vec<R>>,
    vel: Option<&B::Buf<D::Vec<R>>>,
    grid: &B::Buf<GridParams>,
    blank: Option<&ScalarsAt<'_, B>>,
    keys: &mut B::Buf<u32>,
) -> Result<HashArgs<R, D>> {
    if let Some(v) = vel {
        input(b, "hash vel", n, v)?;
    }
    Ok(HashArgs {
        n: count(n)?,
        pos: input(b, "hash pos", n, pos)?,
        vel: blank_vel(b, blank, vel)?,
        grid: input(b, "hash grid", 1, grid)?,
        blank: blank_ptr(b, blank)?,
        keys: output(b, "hash keys", n, keys)?,
    })
}

/// The CSR neighbour list's arguments ([`super::Passes::neighbour_list`]); without `offsets` only counted (the
/// list is then not touched).
#[allow(clippy::too_many_arguments)]
pub fn neighbour_list_args<B: Backend, R: Real, D: Dim>(
    b: &B,
    c: super::Count<'_, B>,
    pos: &B::Buf<D::Vec<R>>,
    grid: &B::Buf<GridParams>,
    starts: &B::Buf<u32>,
    support2: R,
    offsets: Option<&B::Buf<u32>>,
    counts: &mut B::Buf<u32>,
    list: &mut B::Buf<u32>,
) -> Result<NeighbourListArgs<R, D>> {
    let n = c.n;
    let (offsets, list) = match offsets {
        None => (null(), std::ptr::null_mut()),
        Some(o) => (input(b, "neighbour_list offsets", n + 1, o)?, output(b, "neighbour_list list", 0, list)?),
    };
    Ok(NeighbourListArgs {
        n: span(b, &c)?,
        pos: input(b, "neighbour_list pos", n, pos)?,
        grid: input(b, "neighbour_list grid", 1, grid)?,
        starts: b.address(starts) as *const u32,
        support2,
        offsets,
        counts: output(b, "neighbour_list counts", n, counts)?,
        list,
    })
}

/// The Verlet list's arguments ([`super::Passes::verlet_build`]), gated where `gate` is given.
pub fn verlet_args<B: Backend, R: Real, D: Dim>(
    b: &B,
    c: super::Count<'_, B>,
    gate: Option<&ScalarsAt<'_, B>>,
    grid: &B::Buf<GridParams>,
    starts: &B::Buf<u32>,
    pos: &B::Buf<D::Vec<R>>,
    list: &mut B::Buf<u32>,
) -> Result<VerletArgs<R, D>> {
    let n = c.n;
    Ok(VerletArgs {
        gate: gate_ptr(b, gate)?,
        n: span(b, &c)?,
        grid: input(b, "verlet_build grid", 1, grid)?,
        starts: b.address(starts) as *const u32,
        pos: input(b, "verlet_build pos", n, pos)?,
        list: output(b, "verlet_build list", n, list)?,
    })
}
