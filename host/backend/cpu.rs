//! The CPU backend: the reference. Per-particle kernels run as rayon loops over the kernel crate's functions;
//! the counting sort runs sequentially, which makes its arrival order the index order, so its permutation is
//! the stable one by construction (the GPU restores the same order with `sort_cells`).

use super::{
    Backend, Buffer, CellBuffers, ContactInputs, DeviceInfo, Element, FieldsMut, FusedContact, FusedHeat, FusedPrepare,
    HeatInputs, PlasticInputs, PlasticPass, ScalarsAt, ScalarsMut, SkinTest, SphInputs, StepFields,
};
use crate::kernels::contact::Tool2d;
use crate::kernels::contact::penalty::{ContactArrays, ContactParams, contact_particle};
use crate::kernels::neighbour::search::neighbour_row;
use crate::kernels::neighbour::{GatherField, GridParams, Neighbours, sort::sort_cell, verlet::verlet_row};
use crate::kernels::sph::heat::{HeatArrays, HeatParams, heat_rate};
use crate::kernels::sph::interact::{PrepassArrays, prepare, prepare_particle, rates, rates_heat};
use crate::kernels::sph::plastic::{PlasticArrays, PlasticConsts, plastic_particle};
use crate::kernels::sph::step::{StepArrays, StepScalars, is_finite_vec, predict_particle};
use crate::kernels::sph::{CubicSpline, SphParams, Stabilisers, TensorOps, density::density_sum};
use crate::kernels::{Dim, Real};
use crate::material::FlowModel;
use crate::{Error, Result};
use rayon::prelude::*;

impl<T: Send + Sync> Buffer<T> for Vec<T> {
    fn len(&self) -> usize {
        Vec::len(self)
    }
}

pub struct CpuBackend {
    info: DeviceInfo,
    /// Bytes handed out by `alloc` and `upload` so far (the memory estimate's test compares with it).
    allocated: std::sync::atomic::AtomicUsize,
}

impl Default for CpuBackend {
    fn default() -> Self {
        Self::new()
    }
}

impl CpuBackend {
    pub fn new() -> Self {
        CpuBackend {
            info: DeviceInfo {
                backend: "cpu",
                name: cpu_model(),
                memory_bytes: mem_total(),
                units: rayon::current_num_threads(),
                ..Default::default()
            },
            allocated: Default::default(),
        }
    }

    /// Bytes of every buffer `alloc` and `upload` have made so far (never decremented: buffers are plain `Vec`s).
    pub fn allocated_bytes(&self) -> usize {
        self.allocated.load(std::sync::atomic::Ordering::Relaxed)
    }
}

/// The conduction inputs as kernel views, after checking that each holds `n` particles and that every
/// body has a material.
fn heat_arrays<R: Real, D: Dim>(
    n: usize,
    input: &HeatInputs<'_, CpuBackend, R, D>,
    op: &'static str,
) -> Result<SendHeat<R, D::Vec<R>>> {
    for (what, len) in [
        ("pos", input.pos.len()),
        ("rho", input.rho.len()),
        ("vol", input.vol.len()),
        ("temp", input.temp.len()),
        ("flags", input.flags.len()),
    ] {
        check(what, n, len)?;
    }
    check_bodies(op, &input.flags[..n], input.materials.len())?;
    Ok(SendHeat(HeatArrays::<R, D::Vec<R>> {
        pos: input.pos.as_ptr(),
        rho: input.rho.as_ptr(),
        vol: input.vol.as_ptr(),
        temp: input.temp.as_ptr(),
        flags: input.flags.as_ptr(),
        materials: input.materials.as_ptr(),
    }))
}

fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| std::env::consts::ARCH.to_string())
}

fn mem_total() -> usize {
    std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("MemTotal:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|kb| kb.parse::<usize>().ok())
        })
        .map(|kb| kb * 1024)
        .unwrap_or(0)
}

/// A raw pointer shared by parallel tasks that write disjoint ranges.
#[derive(Clone, Copy)]
struct SendPtr(*mut u32);
// SAFETY: only used for disjoint writes (CSR rows) or reads.
unsafe impl Send for SendPtr {}
unsafe impl Sync for SendPtr {}
impl SendPtr {
    fn get(self) -> *mut u32 {
        self.0
    }
    fn from_opt(p: Option<*mut u32>) -> Self {
        SendPtr(p.unwrap_or(std::ptr::null_mut()))
    }
    fn is_null(self) -> bool {
        self.0.is_null()
    }
}

/// The plastic pass's array views: each task writes only its own particle.
struct SendPlastic<R: Real, S>(PlasticArrays<R, S>);
// SAFETY: disjoint per-index writes, buffers outlive the loop.
unsafe impl<R: Real, S> Send for SendPlastic<R, S> {}
unsafe impl<R: Real, S> Sync for SendPlastic<R, S> {}

struct SendPrepass<R: Real, S>(PrepassArrays<R, S>);
// SAFETY: disjoint per-index writes, buffers outlive the loop.
unsafe impl<R: Real, S> Send for SendPrepass<R, S> {}
unsafe impl<R: Real, S> Sync for SendPrepass<R, S> {}

struct SendContact<R: Real, V>(ContactArrays<R, V>);
// SAFETY: disjoint per-index writes, buffers outlive the loop.
unsafe impl<R: Real, V> Send for SendContact<R, V> {}
unsafe impl<R: Real, V> Sync for SendContact<R, V> {}

/// The conduction pass's array views, shared by parallel tasks that only read through them.
struct SendHeat<R: Real, V: crate::kernels::Vector<R>>(HeatArrays<R, V>);
// SAFETY: read-only views of buffers that outlive the parallel loop.
unsafe impl<R: Real, V: crate::kernels::Vector<R>> Send for SendHeat<R, V> {}
unsafe impl<R: Real, V: crate::kernels::Vector<R>> Sync for SendHeat<R, V> {}

/// A pass's argument struct (`kernels::pass`), shared by parallel tasks that write disjoint particles.
struct Shared<T>(T);
// SAFETY: the structs' pointers name buffers that outlive the parallel loop; each task writes its own particles.
unsafe impl<T> Send for Shared<T> {}
unsafe impl<T> Sync for Shared<T> {}
impl<T> Shared<T> {
    /// The struct (a method, so that a closure captures the whole wrapper, not its field).
    fn get(&self) -> &T {
        &self.0
    }
}

struct SendStep<R: Real, D: Dim>(StepArrays<R, D::Vec<R>, D::Sym<R>>);

unsafe impl<R: Real, D: Dim> Send for SendStep<R, D> {}
unsafe impl<R: Real, D: Dim> Sync for SendStep<R, D> {}

/// The single element of a one-element buffer.
fn one<'a, T>(buf: &'a [T], op: &'static str) -> Result<&'a T> {
    buf.first().ok_or(Error::Length { op, expected: 1, got: 0 })
}

/// The step's scalars at `s.index`.
fn scalars(s: &ScalarsAt<'_, CpuBackend>) -> Result<StepScalars> {
    s.buf.get(s.index).copied().ok_or(Error::Length { op: "step scalars", expected: s.index + 1, got: s.buf.len() })
}

/// The Verlet list's address after checking its size against the grid's layout (null without a list).
fn list_ptr(op: &'static str, n: usize, g: &GridParams, list: Option<&Vec<u32>>) -> Result<SendPtr> {
    let Some(l) = list else { return Ok(SendPtr(std::ptr::null_mut())) };
    let stride = g.list_stride as usize;
    if g.list_capacity == 0 || stride < n {
        return Err(Error::Length { op, expected: n, got: stride });
    }
    check(op, g.list_words(), l.len())?;
    Ok(SendPtr(l.as_ptr() as *mut u32))
}

/// Raw views of the step's fields after checking that every one holds n particles.
fn step_arrays<R: Real, D: Dim>(n: usize, f: StepFields<'_, CpuBackend, R, D>) -> Result<SendStep<R, D>> {
    let lens = [
        f.y.pos.len(),
        f.y.vel.len(),
        f.y.rho.len(),
        f.y.stress.len(),
        f.y0.pos.len(),
        f.y0.vel.len(),
        f.y0.rho.len(),
        f.y0.stress.len(),
        f.rates.pos.len(),
        f.rates.vel.len(),
        f.rates.rho.len(),
        f.rates.stress.len(),
    ];
    check("step fields", n, lens.into_iter().min().unwrap_or(0))?;
    let (temp, temp0, temp_t) = match (f.temp, f.conduction) {
        (Some(t), Some((t0, tt))) => {
            check("step temperature", n, t.len().min(t0.len()).min(tt.len()))?;
            (t.as_mut_ptr(), t0.as_mut_ptr(), tt.as_ptr())
        }
        (Some(t), None) => (t.as_mut_ptr(), std::ptr::null_mut(), std::ptr::null()),
        _ => (std::ptr::null_mut(), std::ptr::null_mut(), std::ptr::null()),
    };
    let (diss, diss_t) = match f.dissipation {
        Some((d, dt)) => {
            check("step dissipation", n, d.len().min(dt.len()))?;
            (d.as_mut_ptr(), dt.as_ptr())
        }
        None => (std::ptr::null_mut(), std::ptr::null()),
    };
    let pos_lo = match f.pos_lo {
        Some(l) => {
            check("step position low parts", n, l.len())?;
            l.as_mut_ptr()
        }
        None => std::ptr::null_mut(),
    };
    Ok(SendStep(StepArrays {
        pos: f.y.pos.as_mut_ptr(),
        vel: f.y.vel.as_mut_ptr(),
        rho: f.y.rho.as_mut_ptr(),
        stress: f.y.stress.as_mut_ptr(),
        pos0: f.y0.pos.as_mut_ptr(),
        vel0: f.y0.vel.as_mut_ptr(),
        rho0: f.y0.rho.as_mut_ptr(),
        stress0: f.y0.stress.as_mut_ptr(),
        pos_t: f.rates.pos.as_ptr(),
        vel_t: f.rates.vel.as_ptr(),
        rho_t: f.rates.rho.as_ptr(),
        stress_t: f.rates.stress.as_ptr(),
        temp,
        temp0,
        temp_t,
        diss,
        diss_t,
        pos_lo,
    }))
}

/// Runs `$body` with `$m` bound to the concrete flow-stress model of `$model` and `$t` naming its type: the host's
/// one map from `FlowModel` to the kernel types (both backends use it; the CUDA backend takes the model's entries
/// from `kernels::pass::ModelEntry`).
macro_rules! with_model {
    ($model:expr, $t:ident, $m:ident => $body:expr) => {{
        use crate::kernels::material as km;
        match $model {
            $crate::material::FlowModel::JohnsonCook($m) => {
                type $t = km::JohnsonCook;
                $body
            }
            $crate::material::FlowModel::Calamaz2008($m) => {
                type $t = km::Calamaz2008;
                $body
            }
            $crate::material::FlowModel::Calamaz2010($m) => {
                type $t = km::Calamaz2010;
                $body
            }
            $crate::material::FlowModel::Calamaz2011($m) => {
                type $t = km::Calamaz2011;
                $body
            }
            $crate::material::FlowModel::SimaOzel1($m) => {
                type $t = km::SimaOzel1;
                $body
            }
            $crate::material::FlowModel::SimaOzel2($m) => {
                type $t = km::SimaOzel2;
                $body
            }
            $crate::material::FlowModel::SimaOzel3($m) => {
                type $t = km::SimaOzel3;
                $body
            }
            $crate::material::FlowModel::Scgl($m) => {
                type $t = km::Scgl;
                $body
            }
            $crate::material::FlowModel::Bilinear($m) => {
                type $t = km::Bilinear;
                $body
            }
        }
    }};
}
pub(crate) use with_model;

/// The address of an optional per-particle output, checked to hold n values (null when absent).
fn out_ptr(b: Option<&mut Vec<f64>>, what: &'static str, n: usize) -> Result<*mut f64> {
    match b {
        Some(y) => {
            check(what, n, y.len())?;
            Ok(y.as_mut_ptr())
        }
        None => Ok(std::ptr::null_mut()),
    }
}

fn check(op: &'static str, expected: usize, got: usize) -> Result<()> {
    if got < expected { Err(Error::Length { op, expected, got }) } else { Ok(()) }
}

/// Checks that a per-body material table of `len` entries covers every body index in `flags`.
fn check_bodies(op: &'static str, flags: &[u32], len: usize) -> Result<()> {
    let bodies = flags.iter().map(|f| (f >> crate::kernels::sph::params::flags::BODY_SHIFT) as usize + 1).max();
    check(op, bodies.unwrap_or(0), len)
}

/// Exclusive prefix sum in place (wrapping, as on the GPU): the CPU twin of the GPU scan.
pub fn exclusive_scan(data: &mut [u32]) {
    let mut acc = 0u32;
    for v in data.iter_mut() {
        let x = *v;
        *v = acc;
        acc = acc.wrapping_add(x);
    }
}

impl Backend for CpuBackend {
    type Buf<T: Element> = Vec<T>;
    type Graph = ();

    fn info(&self) -> &DeviceInfo {
        &self.info
    }

    fn alloc<T: Element>(&self, n: usize, _what: &'static str) -> Result<Vec<T>> {
        self.allocated.fetch_add(n * size_of::<T>(), std::sync::atomic::Ordering::Relaxed);
        Ok(vec![T::zeroed(); n])
    }

    fn upload<T: Element>(&self, data: &[T], _what: &'static str) -> Result<Vec<T>> {
        self.allocated.fetch_add(size_of_val(data), std::sync::atomic::Ordering::Relaxed);
        Ok(data.to_vec())
    }

    fn write<T: Element>(&self, buf: &mut Vec<T>, data: &[T]) -> Result<()> {
        check("write", data.len(), buf.len())?;
        buf[..data.len()].copy_from_slice(data);
        Ok(())
    }

    fn read<T: Element>(&self, buf: &Vec<T>) -> Result<Vec<T>> {
        Ok(buf.clone())
    }

    fn fill_zero<T: Element>(&self, buf: &mut Vec<T>, n: usize) -> Result<()> {
        check("fill_zero", n, buf.len())?;
        buf[..n].fill(T::zeroed());
        Ok(())
    }

    fn synchronize(&self) -> Result<()> {
        Ok(())
    }

    fn time_ms(&self, f: &mut dyn FnMut() -> Result<()>) -> Result<f64> {
        let t = std::time::Instant::now();
        f()?;
        Ok(t.elapsed().as_secs_f64() * 1e3)
    }

    fn hash<R: Real, D: Dim>(
        &self,
        n: usize,
        pos: &Vec<D::Vec<R>>,
        grid: &Vec<GridParams>,
        keys: &mut Vec<u32>,
    ) -> Result<()> {
        check("hash pos", n, pos.len())?;
        check("hash keys", n, keys.len())?;
        check("hash grid", 1, grid.len())?;
        let g = grid[0];
        keys[..n].par_iter_mut().zip(pos[..n].par_iter()).for_each(|(k, p)| *k = g.key::<R, D::Vec<R>>(p));
        Ok(())
    }

    fn count_cells(&self, n: usize, keys: &Vec<u32>, counts: &mut Vec<u32>, slots: &mut Vec<u32>) -> Result<()> {
        check("count_cells keys", n, keys.len())?;
        check("count_cells slots", n, slots.len())?;
        for i in 0..n {
            let k = keys[i] as usize;
            let c = counts.get_mut(k).ok_or(Error::Length { op: "count_cells counts", expected: k + 1, got: 0 })?;
            slots[i] = *c;
            *c += 1;
        }
        Ok(())
    }

    fn exclusive_scan(&self, n: usize, data: &mut Vec<u32>, _levels: &mut [Vec<u32>]) -> Result<()> {
        check("exclusive_scan", n, data.len())?;
        exclusive_scan(&mut data[..n]);
        Ok(())
    }

    fn scatter(
        &self,
        n: usize,
        keys: &Vec<u32>,
        slots: &Vec<u32>,
        starts: &Vec<u32>,
        perm: &mut Vec<u32>,
    ) -> Result<()> {
        check("scatter perm", n, perm.len())?;
        for i in 0..n {
            let dst = (starts[keys[i] as usize] + slots[i]) as usize;
            perm[dst] = i as u32;
        }
        Ok(())
    }

    fn sort_cells(&self, n_buckets: usize, starts: &Vec<u32>, perm: &mut Vec<u32>) -> Result<()> {
        check("sort_cells starts", n_buckets + 1, starts.len())?;
        let total = starts[n_buckets] as usize;
        check("sort_cells perm", total, perm.len())?;
        // SAFETY: starts is non-decreasing with starts[n_buckets] <= perm.len(), checked above.
        let p = perm.as_mut_ptr();
        for c in 0..n_buckets {
            let (a, b) = (starts[c], starts[c + 1]);
            if b > a + 1 {
                unsafe { sort_cell(p, a, b) };
            }
        }
        Ok(())
    }

    fn gather<T: Element>(&self, n: usize, perm: &Vec<u32>, src: &Vec<T>, dst: &mut Vec<T>) -> Result<()> {
        check("gather perm", n, perm.len())?;
        check("gather dst", n, dst.len())?;
        dst[..n].par_iter_mut().zip(perm[..n].par_iter()).for_each(|(d, &j)| *d = src[j as usize]);
        Ok(())
    }

    fn neighbour_list<R: Real, D: Dim>(
        &self,
        n: usize,
        pos: &Vec<D::Vec<R>>,
        grid: &Vec<GridParams>,
        starts: &Vec<u32>,
        support2: R,
        offsets: Option<&Vec<u32>>,
        counts: &mut Vec<u32>,
        list: &mut Vec<u32>,
    ) -> Result<()> {
        check("neighbour_list pos", n, pos.len())?;
        check("neighbour_list counts", n, counts.len())?;
        check("neighbour_list starts", grid[0].n_cells as usize + 2, starts.len())?;
        let g = grid[0];
        let (off_ptr, list_ptr) = match offsets {
            None => (std::ptr::null(), SendPtr(std::ptr::null_mut())),
            Some(off) => {
                check("neighbour_list offsets", n + 1, off.len())?;
                check("neighbour_list list", off[n] as usize, list.len())?;
                (off.as_ptr(), SendPtr(list.as_mut_ptr()))
            }
        };
        let off_ptr = SendPtr(off_ptr as *mut u32);
        counts[..n].par_iter_mut().enumerate().for_each(|(i, c)| {
            // SAFETY: lengths checked above; row i is list[off[i] .. off[i+1]], disjoint from every other row.
            *c = unsafe {
                neighbour_row::<R, D::Vec<R>>(
                    &g,
                    starts.as_ptr(),
                    pos.as_ptr(),
                    i as u32,
                    support2,
                    off_ptr.get(),
                    list_ptr.get(),
                )
            };
        });
        Ok(())
    }

    fn density<R: Real, D: Dim>(
        &self,
        n: usize,
        pos: &Vec<D::Vec<R>>,
        mass: &Vec<R>,
        grid: &Vec<GridParams>,
        starts: &Vec<u32>,
        kernel: &Vec<CubicSpline<R>>,
        rho: &mut Vec<R>,
    ) -> Result<()> {
        check("density pos", n, pos.len())?;
        check("density mass", n, mass.len())?;
        check("density rho", n, rho.len())?;
        check("density starts", grid[0].n_cells as usize + 2, starts.len())?;
        let (g, k) = (grid[0], kernel[0]);
        rho[..n].par_iter_mut().enumerate().for_each(|(i, r)| {
            // SAFETY: lengths checked above; pos/mass are the sorted particles of this cell list.
            *r = unsafe { density_sum::<R, D::Vec<R>>(&g, starts.as_ptr(), &k, pos.as_ptr(), mass.as_ptr(), i as u32) };
        });
        Ok(())
    }

    fn sph_prepare<R: Real, D: TensorOps<R>>(
        &self,
        n: usize,
        stab: Stabilisers,
        params: &Vec<SphParams<R>>,
        rho: &Vec<R>,
        mass: &Vec<R>,
        stress: &Vec<D::Sym<R>>,
        sig: &mut Vec<D::Sym<R>>,
        art: Option<&mut Vec<D::Sym<R>>>,
        sound: Option<&mut Vec<R>>,
        vol: &mut Vec<R>,
        temp: Option<&Vec<f64>>,
        gate: Option<ScalarsAt<'_, Self>>,
    ) -> Result<()> {
        if let Some(g) = gate
            && scalars(&g)?.rebuild == 0
        {
            return Ok(());
        }
        check("sph_prepare rho", n, rho.len())?;
        check("sph_prepare mass", n, mass.len())?;
        check("sph_prepare vol", n, vol.len())?;
        if let Some(t) = temp {
            check("sph_prepare temp", n, t.len())?;
        }
        check("sph_prepare stress", n, stress.len())?;
        check("sph_prepare sig", n, sig.len())?;
        let p = params[0];
        if let Some(a) = &art {
            check("sph_prepare art", n, a.len())?;
        }
        if let Some(c) = &sound {
            check("sph_prepare sound", n, c.len())?;
        }
        if (stab.stress && art.is_none()) || (stab.viscosity && sound.is_none()) {
            return Err(Error::Length { op: "sph_prepare (stabiliser buffer missing)", expected: n, got: 0 });
        }
        let art = SendPtr::from_opt(art.map(|a| a.as_mut_ptr() as *mut u32));
        let sound = SendPtr::from_opt(sound.map(|c| c.as_mut_ptr() as *mut u32));
        macro_rules! go {
            ($av:literal, $as:literal) => {
                sig[..n].par_iter_mut().zip(vol[..n].par_iter_mut()).enumerate().for_each(|(i, (sg, v))| {
                    let q = prepare::<R, D, $av, $as>(&p, rho[i], mass[i], &stress[i], temp.map(|t| t[i]));
                    *sg = q.sig;
                    *v = q.vol;
                    // SAFETY: the buffers exist when their stabiliser is on and hold n elements (checked by the
                    // solver, which allocates them); each index is written by one task.
                    unsafe {
                        if $as {
                            *(art.get() as *mut D::Sym<R>).add(i) = q.art;
                        }
                        if $av {
                            *(sound.get() as *mut R).add(i) = q.c;
                        }
                    }
                })
            };
        }
        match (stab.viscosity && !sound.is_null(), stab.stress && !art.is_null()) {
            (false, false) => go!(false, false),
            (false, true) => go!(false, true),
            (true, false) => go!(true, false),
            (true, true) => go!(true, true),
        }
        Ok(())
    }

    fn sph_rates<R: Real, D: TensorOps<R>>(
        &self,
        n: usize,
        lanes: u32,
        stab: Stabilisers,
        params: &SphParams<R>,
        grid: &Vec<GridParams>,
        starts: &Vec<u32>,
        list: Option<&Vec<u32>>,
        input: &SphInputs<'_, Self, R, D>,
        out: FieldsMut<'_, Self, R, D>,
        dissipation: Option<&mut Vec<R>>,
        heat: Option<FusedHeat<'_, Self, R, D>>,
    ) -> Result<()> {
        check("sph_rates starts", grid[0].n_cells as usize + 2, starts.len())?;
        list_ptr("sph_rates list", n, &grid[0], list)?;
        if let Some(h) = &heat {
            check_bodies(
                "sph_rates (fused conduction)",
                &h.input.flags[..n.min(h.input.flags.len())],
                h.input.materials.len(),
            )?;
        }
        let fused = heat.is_some();
        let args = Shared(super::args::rates_args(
            self,
            n,
            lanes,
            0,
            stab,
            params,
            grid,
            starts,
            list,
            input,
            out,
            dissipation,
            heat,
        )?);
        macro_rules! go {
            ($av:literal, $as:literal, $xs:literal) => {
                (0..n).into_par_iter().for_each(|i| {
                    let a = args.get();
                    // SAFETY: `rates_args` checked that every array holds n sorted particles, starts and the list
                    // belong to the grid (above), and each index i is written by one task only.
                    unsafe {
                        let (arr, nb) = (a.arrays(), a.neighbours());
                        let o = if fused {
                            let (o, tt) = rates_heat::<R, D, $av, $as, $xs>(
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
                            rates::<R, D, $av, $as, $xs>(&a.params, &nb, &arr, i as u32, a.lanes)
                        };
                        a.store(i, &o);
                    }
                })
            };
        }
        match (stab.viscosity, stab.stress, stab.xsph) {
            (false, false, false) => go!(false, false, false),
            (false, false, true) => go!(false, false, true),
            (false, true, false) => go!(false, true, false),
            (false, true, true) => go!(false, true, true),
            (true, false, false) => go!(true, false, false),
            (true, false, true) => go!(true, false, true),
            (true, true, false) => go!(true, true, false),
            (true, true, true) => go!(true, true, true),
        }
        Ok(())
    }

    fn heat_rates<R: Real, D: Dim>(
        &self,
        n: usize,
        lanes: u32,
        pse: bool,
        hp: &HeatParams,
        params: &SphParams<R>,
        grid: &Vec<GridParams>,
        starts: &Vec<u32>,
        list: Option<&Vec<u32>>,
        input: &HeatInputs<'_, Self, R, D>,
        temp_t: &mut Vec<f64>,
    ) -> Result<()> {
        check("heat_rates temp_t", n, temp_t.len())?;
        check("heat_rates starts", grid[0].n_cells as usize + 2, starts.len())?;
        let (h, k, g) = (*hp, params.kernel, grid[0]);
        if pse && list.is_some() {
            return Err(Error::Length { op: "heat_rates (PSE reaches beyond the Verlet list)", expected: 0, got: 1 });
        }
        let lp = list_ptr("heat_rates list", n, &g, list)?;
        let a = heat_arrays::<R, D>(n, input, "heat_rates materials")?;
        let st = SendPtr(starts.as_ptr() as *mut u32);
        temp_t[..n].par_iter_mut().enumerate().for_each(|(i, t)| {
            let a = &a;
            let nb = Neighbours { grid: &g, starts: st.get(), list: lp.get() };
            // SAFETY: lengths checked above; every body index has a material.
            *t = unsafe {
                if pse {
                    heat_rate::<R, D::Vec<R>, true>(&h, &k, &nb, &a.0, i as u32, lanes)
                } else {
                    heat_rate::<R, D::Vec<R>, false>(&h, &k, &nb, &a.0, i as u32, lanes)
                }
            };
        });
        Ok(())
    }

    fn step_predict<R: Real, D: TensorOps<R>>(
        &self,
        n: usize,
        s: ScalarsMut<'_, Self>,
        f: StepFields<'_, Self, R, D>,
        skin: SkinTest<'_, Self, R, D>,
        prepare: Option<FusedPrepare<'_, Self, R, D>>,
    ) -> Result<()> {
        let entry =
            s.buf.get_mut(s.index).ok_or(Error::Length { op: "step scalars", expected: s.index + 1, got: 0 })?;
        let dt = entry.dt;
        let (rho, stress) = (f.y.rho.as_ptr(), f.y.stress.as_ptr());
        let a = step_arrays::<R, D>(n, f)?;
        check("step_predict pos_ref", n, skin.pos_ref.len())?;
        check("step_predict grid", 1, skin.grid.len())?;
        let g = skin.grid[0];
        // The fused pre-pass (as the CUDA entry): the same particle's pre-pass after its prediction.
        let prep = match prepare {
            None => None,
            Some(q) => {
                check("step_predict mass", n, q.mass.len())?;
                check("step_predict sig", n, q.sig.len())?;
                check("step_predict vol", n, q.vol.len())?;
                if let Some(a) = &q.art {
                    check("step_predict art", n, a.len())?;
                }
                if let Some(c) = &q.sound {
                    check("step_predict sound", n, c.len())?;
                }
                let art = if q.stab.stress { q.art.map(|a| a.as_mut_ptr()) } else { None };
                let sound = if q.stab.viscosity { q.sound.map(|c| c.as_mut_ptr()) } else { None };
                if (q.stab.stress && art.is_none()) || (q.stab.viscosity && sound.is_none()) {
                    return Err(Error::Length { op: "step_predict (stabiliser buffer missing)", expected: n, got: 0 });
                }
                Some((
                    *q.params,
                    q.mass.as_ptr() as usize,
                    SendPrepass(PrepassArrays {
                        sig: q.sig.as_mut_ptr(),
                        art: art.unwrap_or(std::ptr::null_mut()),
                        sound: sound.unwrap_or(std::ptr::null_mut()),
                        vol: q.vol.as_mut_ptr(),
                    }),
                ))
            }
        };
        let (rho, stress) = (rho as usize, stress as usize);
        let moved = skin.pos_ref[..n].par_iter().enumerate().map(|(i, xr)| {
            let (a, prep) = (&a, &prep);
            // SAFETY: lengths checked by step_arrays and above; each particle i is touched by one task only.
            let x = unsafe { predict_particle(&a.0, dt, i) };
            if let Some((p, mass, o)) = prep {
                // SAFETY: as above; the predictor wrote particle i's ρ and S.
                unsafe {
                    let (r, m) = (*(rho as *const R).add(i), *(*mass as *const R).add(i));
                    prepare_particle::<R, D>(p, &o.0, i, r, m, &*(stress as *const D::Sym<R>).add(i));
                }
            }
            (g.beyond_skin::<R, D::Vec<R>>(&x, xr), is_finite_vec::<R, D::Vec<R>>(&x))
        });
        // Every particle is predicted (no short-circuit), as on the GPU.
        let (beyond, finite) = moved.reduce(|| (false, true), |a, b| (a.0 || b.0, a.1 && b.1));
        if beyond {
            entry.rebuild = 1;
        }
        if !finite {
            entry.non_finite = 1;
        }
        Ok(())
    }

    fn rebuild_cells<R: Real, D: Dim>(
        &self,
        n: usize,
        gate: ScalarsAt<'_, Self>,
        pos: &Vec<D::Vec<R>>,
        c: CellBuffers<'_, Self>,
    ) -> Result<()> {
        if scalars(&gate)?.rebuild == 0 {
            return Ok(());
        }
        check("rebuild_cells rebuilds", 1, c.rebuilds.len())?;
        c.rebuilds[0] += 1;
        self.fill_zero(c.starts, c.n_buckets + 1)?;
        self.hash::<R, D>(n, pos, c.grid, c.keys)?;
        self.count_cells(n, c.keys, c.starts, c.slots)?;
        self.exclusive_scan(c.n_buckets + 1, c.starts, c.scan)?;
        self.scatter(n, c.keys, c.slots, c.starts, c.perm)?;
        self.sort_cells(c.n_buckets, c.starts, c.perm)
    }

    fn verlet_build<R: Real, D: Dim>(
        &self,
        n: usize,
        gate: Option<ScalarsAt<'_, Self>>,
        grid: &Vec<GridParams>,
        starts: &Vec<u32>,
        pos: &Vec<D::Vec<R>>,
        list: &mut Vec<u32>,
    ) -> Result<()> {
        if let Some(g) = gate
            && scalars(&g)?.rebuild == 0
        {
            return Ok(());
        }
        check("verlet_build pos", n, pos.len())?;
        check("verlet_build grid", 1, grid.len())?;
        let g = grid[0];
        check("verlet_build starts", g.n_cells as usize + 2, starts.len())?;
        let out = list_ptr("verlet_build list", n, &g, Some(list))?;
        let (st, p) = (SendPtr(starts.as_ptr() as *mut u32), SendPtr(pos.as_ptr() as *mut u32));
        (0..n).into_par_iter().for_each(|i| {
            let out = &out;
            // SAFETY: sizes checked above; task i writes only row i (the words (m + 1)·stride + i and i).
            unsafe { verlet_row::<R, D::Vec<R>>(&g, st.get(), p.get() as *const D::Vec<R>, i as u32, out.get()) }
        });
        Ok(())
    }

    fn step_finish<R: Real, D: TensorOps<R>>(
        &self,
        n: usize,
        s: ScalarsAt<'_, Self>,
        f: StepFields<'_, Self, R, D>,
        plastic: Option<PlasticPass<'_, Self>>,
        contact: Option<FusedContact<'_, Self, R, D>>,
    ) -> Result<()> {
        if contact.is_some() && (plastic.is_none() || D::D != 2) {
            return Err(Error::Length {
                op: "step_finish (the fused contact needs plasticity, 2D)",
                expected: 2,
                got: D::D,
            });
        }
        let Some(p) = plastic else {
            let a = Shared(super::args::finish_args(self, n, &s, f)?);
            (0..n).into_par_iter().for_each(|i| {
                // SAFETY: `finish_args` checked the lengths; each particle i is touched by one task only.
                unsafe { a.get().particle(i) }
            });
            return Ok(());
        };
        // The checks that read the flags (the GPU cannot).
        check("flags", n, p.flags.len())?;
        if p.taylor_quinney > 0.0 {
            check_bodies("step_finish materials", &p.flags[..n], p.materials.map_or(0, |m| m.len()))?;
        }
        if let Some(m) = contact.as_ref().and_then(|c| c.materials) {
            check_bodies("contact materials", &p.flags[..n], m.len())?;
        }
        let model = p.model;
        with_model!(model, M, m => {
            let a = Shared(super::args::finish_plastic_args::<_, R, D, M>(self, n, 0, &s, f, p, *m, contact)?);
            (0..n).into_par_iter().for_each(|i| {
                let a = a.get();
                // SAFETY: `finish_plastic_args` checked the lengths; each particle i is touched by one task only.
                unsafe { a.particle(&a.model, i) }
            });
        });
        Ok(())
    }

    fn address<T: Element>(&self, buf: &Vec<T>) -> u64 {
        buf.as_ptr() as u64
    }

    fn address_mut<T: Element>(&self, buf: &mut Vec<T>) -> u64 {
        buf.as_mut_ptr() as u64
    }

    unsafe fn gather_fields(
        &self,
        n: usize,
        perm: Option<&Vec<u32>>,
        fields: &[GatherField],
        gate: Option<ScalarsAt<'_, Self>>,
    ) -> Result<()> {
        if let Some(g) = gate
            && scalars(&g)?.rebuild == 0
        {
            return Ok(());
        }
        if let Some(p) = perm {
            check("gather_fields perm", n, p.len())?;
        }
        for f in fields {
            let b = f.bytes as usize;
            if b == 0 || !b.is_multiple_of(4) {
                return Err(Error::Length { op: "gather_fields (element size)", expected: 4, got: b });
            }
            let (src, dst) = (f.src as usize, f.dst as usize);
            (0..n).into_par_iter().for_each(|i| {
                let j = perm.map_or(i, |p| p[i] as usize);
                // SAFETY: the caller guarantees distinct live buffers of at least n elements of b bytes; each
                // destination element i is written by one task only.
                unsafe { std::ptr::copy_nonoverlapping((src + j * b) as *const u8, (dst + i * b) as *mut u8, b) };
            });
        }
        Ok(())
    }

    fn capture(&self, f: &mut dyn FnMut() -> Result<()>) -> Result<Option<()>> {
        f()?;
        Ok(None)
    }

    fn replay(&self, _g: &()) -> Result<()> {
        Ok(())
    }

    fn contact<R: Real, D: Dim>(
        &self,
        n: usize,
        params: &Vec<ContactParams>,
        shape: &Vec<Tool2d>,
        s: ScalarsAt<'_, Self>,
        a: ContactInputs<'_, Self, R, D>,
    ) -> Result<()> {
        let tool = scalars(&s)?.tool;
        if D::D != 2 {
            return Err(Error::Length { op: "contact (the parametric tool is 2D)", expected: 2, got: D::D });
        }
        for (what, len) in [
            ("pos", a.pos.len()),
            ("vel", a.vel.len()),
            ("mass", a.mass.len()),
            ("rho", a.rho.len()),
            ("flags", a.flags.len()),
            ("normal", a.normal.len()),
            ("friction", a.friction.len()),
        ] {
            check(what, n, len)?;
        }
        for (what, len) in [
            ("temp", a.temp.as_ref().map(|t| t.len())),
            ("yield_stress", a.yield_stress.map(|t| t.len())),
            ("wear", a.wear.as_ref().map(|t| t.len())),
        ] {
            if let Some(len) = len {
                check(what, n, len)?;
            }
        }
        if let Some(m) = a.materials {
            check_bodies("contact materials", &a.flags[..n], m.len())?;
        }
        let c = params[0];
        let shape = one(shape, "contact (the tool's shape)")?;
        let arr = SendContact(ContactArrays::<R, D::Vec<R>> {
            pos: a.pos.as_ptr(),
            vel: a.vel.as_ptr(),
            mass: a.mass.as_ptr(),
            rho: a.rho.as_ptr(),
            flags: a.flags.as_ptr(),
            normal: a.normal.as_mut_ptr(),
            friction: a.friction.as_mut_ptr(),
            temp: a.temp.map_or(std::ptr::null_mut(), |t| t.as_mut_ptr()),
            materials: a.materials.map_or(std::ptr::null(), |m| m.as_ptr()),
            yield_stress: a.yield_stress.map_or(std::ptr::null(), |y| y.as_ptr()),
            wear: a.wear.map_or(std::ptr::null_mut(), |w| w.as_mut_ptr()),
        });
        (0..n).into_par_iter().for_each(|i| {
            let arr = &arr;
            // SAFETY: lengths checked above; each particle i is touched by one task only.
            unsafe { contact_particle::<R, D::Vec<R>, Tool2d>(&c, shape, &tool, &arr.0, i) }
        });
        Ok(())
    }

    fn plastic_step<R: Real, D: TensorOps<R>>(
        &self,
        n: usize,
        model: &FlowModel,
        c: PlasticConsts,
        a: PlasticInputs<'_, Self, R, D>,
    ) -> Result<()> {
        for (what, len) in [
            ("stress", a.stress.len()),
            ("rho", a.rho.len()),
            ("eps", a.eps.len()),
            ("rate", a.rate.len()),
            ("temp", a.temp.len()),
            ("flags", a.flags.len()),
        ] {
            check(what, n, len)?;
        }
        if c.taylor_quinney > 0.0 {
            check_bodies("plastic_step materials", &a.flags[..n], a.materials.map_or(0, |m| m.len()))?;
        }
        let arr = SendPlastic(PlasticArrays::<R, D::Sym<R>> {
            stress: a.stress.as_mut_ptr(),
            rho: a.rho.as_ptr(),
            eps: a.eps.as_mut_ptr(),
            rate: a.rate.as_mut_ptr(),
            temp: a.temp.as_mut_ptr(),
            flags: a.flags.as_ptr(),
            materials: a.materials.map_or(std::ptr::null(), |m| m.as_ptr()),
            yield_stress: out_ptr(a.yield_stress, "yield_stress", n)?,
            work: out_ptr(a.work, "plastic work", n)?,
        });
        with_model!(model, M, m => (0..n).into_par_iter().for_each(|i| {
            let arr = &arr;
            // SAFETY: lengths checked above; each particle i is touched by one task only.
            unsafe { plastic_particle::<R, D, M>(m, &c, &arr.0, i) }
        }));
        Ok(())
    }
}
