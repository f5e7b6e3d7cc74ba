//! The passes' argument structs (`kernels::pass`) built from a backend's buffers. Both backends build them here,
//! so each buffer's length is checked once, by [`check_len`], on the CPU and on the GPU alike; the CPU backend
//! adds the checks that read buffer contents (the cell starts against the grid, the bodies against the
//! materials), which the GPU's memory does not allow.

use super::{Backend, Buffer, Element, FieldsMut, FusedHeat, SphInputs};
use crate::kernels::neighbour::GridParams;
use crate::kernels::pass::RatesArgs;
use crate::kernels::sph::heat::HeatParams;
use crate::kernels::sph::{SphParams, Stabilisers};
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

/// The pair interaction's arguments ([`Backend::sph_rates`]); `reverse` is the GPU's block order. The stabilisers'
/// buffers must be given where they are on (and are passed as null where off).
#[allow(clippy::too_many_arguments)]
pub fn rates_args<B: Backend, R: Real, D: Dim>(
    b: &B,
    n: usize,
    lanes: u32,
    reverse: u32,
    stab: Stabilisers,
    params: &SphParams<R>,
    grid: &B::Buf<GridParams>,
    starts: &B::Buf<u32>,
    list: Option<&B::Buf<u32>>,
    i: &SphInputs<'_, B, R, D>,
    out: FieldsMut<'_, B, R, D>,
    dissipation: Option<&mut B::Buf<R>>,
    heat: Option<FusedHeat<'_, B, R, D>>,
) -> Result<RatesArgs<R, D>> {
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
        n: u32::try_from(n).map_err(|_| Error::Length {
            op: "sph_rates particles",
            expected: u32::MAX as usize,
            got: n,
        })?,
        lanes,
        reverse,
        params: *params,
        hp,
        grid: input(b, "sph_rates grid", 1, grid)?,
        starts: b.address(starts) as *const u32,
        list: input_opt(b, "sph_rates list", 0, list)?,
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
        pos_t: output(b, "pos_t", n, out.pos)?,
        vel_t: output(b, "vel_t", n, out.vel)?,
        rho_t: output(b, "rho_t", n, out.rho)?,
        stress_t: output(b, "stress_t", n, out.stress)?,
        dissipation_t: output_opt(b, "sph_rates dissipation", n, dissipation)?,
        heat_vol,
        temp,
        materials,
        temp_t,
    })
}

fn null<T>() -> *const T {
    std::ptr::null()
}

/// A stabiliser's buffer that is on but was not given.
fn missing(what: &'static str) -> Error {
    Error::Length { op: what, expected: 1, got: 0 }
}
