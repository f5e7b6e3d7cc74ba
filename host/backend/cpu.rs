//! The CPU backend: the reference. Per-particle kernels run as rayon loops over the kernel crate's functions;
//! the counting sort runs sequentially, which makes its arrival order the index order, so its permutation is
//! the stable one by construction (the GPU restores the same order with `sort_cells`).

use super::{
    Backend, Buffer, CellBuffers, ContactInputs, DeviceInfo, Element, FieldsMut, FusedContact, FusedHeat, FusedPrepare,
    HeatInputs, PlasticInputs, PlasticPass, ScalarsAt, ScalarsMut, SkinTest, SphInputs, StepFields,
};
use crate::kernels::contact::Tool2d;
use crate::kernels::contact::penalty::ContactParams;
use crate::kernels::neighbour::{GatherField, GridParams, sort::sort_cell};
use crate::kernels::pass::{HashArgs, NeighbourListArgs, VerletArgs};
use crate::kernels::sph::heat::{HeatParams, heat_rate};
use crate::kernels::sph::interact::{rates, rates_heat};
use crate::kernels::sph::plastic::PlasticConsts;
use crate::kernels::sph::step::{StepScalars, is_finite_vec};
use crate::kernels::sph::{CubicSpline, SphParams, Stabilisers, TensorOps};
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
}

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
        let a =
            Shared(HashArgs::<R, D> { n: n as u32, pos: pos.as_ptr(), grid: grid.as_ptr(), keys: keys.as_mut_ptr() });
        (0..n).into_par_iter().for_each(|i| {
            // SAFETY: lengths checked above; each key i is written by one task only.
            unsafe { a.get().particle(i) }
        });
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
        let (offsets, list) = match offsets {
            None => (std::ptr::null(), std::ptr::null_mut()),
            Some(off) => {
                check("neighbour_list offsets", n + 1, off.len())?;
                check("neighbour_list list", off[n] as usize, list.len())?;
                (off.as_ptr(), list.as_mut_ptr())
            }
        };
        let a = Shared(NeighbourListArgs::<R, D> {
            n: n as u32,
            pos: pos.as_ptr(),
            grid: grid.as_ptr(),
            starts: starts.as_ptr(),
            support2,
            offsets,
            counts: counts.as_mut_ptr(),
            list,
        });
        (0..n).into_par_iter().for_each(|i| {
            // SAFETY: lengths checked above; row i is list[off[i] .. off[i+1]], disjoint from every other row, and
            // counts[i] is written by task i only.
            unsafe { a.get().particle(i) }
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
        check("density grid", 1, grid.len())?;
        check("density starts", grid[0].n_cells as usize + 2, starts.len())?;
        let a = Shared(super::args::density_args::<_, R, D>(self, n, pos, mass, grid, starts, kernel, rho)?);
        (0..n).into_par_iter().for_each(|i| {
            // SAFETY: `density_args` checked the lengths, starts belong to the grid (above); pos/mass are the
            // sorted particles of this cell list; each particle i is written by one task only.
            unsafe { a.get().particle(i) }
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
        let q = super::args::PrepareBufs::<_, R, D> { params, rho, mass, stress, sig, art, sound, vol, temp };
        // The gate was read above (the GPU reads it in the entry).
        let a = Shared(super::args::prepare_args(self, n, stab, q, None)?);
        macro_rules! go {
            ($av:literal, $as:literal) => {
                (0..n).into_par_iter().for_each(|i| {
                    // SAFETY: `prepare_args` checked the lengths and that the stabilisers' buffers exist where
                    // they are on; each particle i is written by one task only.
                    unsafe { a.get().particle::<$av, $as>(i) }
                })
            };
        }
        match (stab.viscosity, stab.stress) {
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
                        let (arr, nb) = (a.arrays, a.neighbours());
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
        check("heat_rates grid", 1, grid.len())?;
        check("heat_rates starts", grid[0].n_cells as usize + 2, starts.len())?;
        list_ptr("heat_rates list", n, &grid[0], list)?;
        check_bodies("heat_rates materials", &input.flags[..n.min(input.flags.len())], input.materials.len())?;
        let a = Shared(super::args::heat_args(self, n, lanes, pse, hp, params, grid, starts, list, input, temp_t)?);
        (0..n).into_par_iter().for_each(|i| {
            let a = a.get();
            // SAFETY: `heat_args` checked the lengths, the grid's starts and list and the bodies are checked
            // above; each particle i is written by one task only.
            unsafe {
                let (arr, nb) = (a.arrays(), a.neighbours());
                *a.temp_t.add(i) = if pse {
                    heat_rate::<R, D::Vec<R>, true>(&a.hp, &a.params.kernel, &nb, &arr, i as u32, a.lanes)
                } else {
                    heat_rate::<R, D::Vec<R>, false>(&a.hp, &a.params.kernel, &nb, &arr, i as u32, a.lanes)
                };
            }
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
        let a = Shared(super::args::predict_args(self, n, s, f, skin, prepare)?);
        let moved = (0..n).into_par_iter().map(|i| {
            let a = a.get();
            // SAFETY: `predict_args` checked the lengths; each particle i is touched by one task only (the
            // scalars are only read in the loop).
            unsafe {
                let x = a.particle(i);
                let xr = &*a.pos_ref.add(i);
                ((*a.grid).beyond_skin::<R, D::Vec<R>>(&x, xr), is_finite_vec::<R, D::Vec<R>>(&x))
            }
        });
        // Every particle is predicted (no short-circuit), as on the GPU.
        let (beyond, finite) = moved.reduce(|| (false, true), |a, b| (a.0 || b.0, a.1 && b.1));
        // SAFETY: `predict_args` checked the index; the loop has ended.
        let entry = unsafe { &mut *a.get().scalars };
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
        let a = Shared(VerletArgs::<R, D> {
            gate: std::ptr::null(),
            n: n as u32,
            grid: grid.as_ptr(),
            starts: starts.as_ptr(),
            pos: pos.as_ptr(),
            list: out.get(),
        });
        (0..n).into_par_iter().for_each(|i| {
            // SAFETY: sizes checked above; task i writes only row i (the words (m + 1)·stride + i and i).
            unsafe { a.get().particle(i) }
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
        check("flags", n, a.flags.len())?;
        if let Some(m) = a.materials {
            check_bodies("contact materials", &a.flags[..n], m.len())?;
        }
        let a = Shared(super::args::contact_args(self, n, params, shape, &s, a)?);
        (0..n).into_par_iter().for_each(|i| {
            // SAFETY: `contact_args` checked the lengths; each particle i is touched by one task only.
            unsafe { a.get().particle(i) }
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
        check("flags", n, a.flags.len())?;
        if c.taylor_quinney > 0.0 {
            check_bodies("plastic_step materials", &a.flags[..n], a.materials.map_or(0, |m| m.len()))?;
        }
        with_model!(model, M, m => {
            let a = Shared(super::args::plastic_args::<_, R, D, M>(self, n, *m, c, a)?);
            (0..n).into_par_iter().for_each(|i| {
                let a = a.get();
                // SAFETY: `plastic_args` checked the lengths; each particle i is touched by one task only.
                unsafe { a.particle(&a.model, i) }
            });
        });
        Ok(())
    }
}
