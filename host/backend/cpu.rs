//! The CPU backend: the reference. Per-particle kernels run as rayon loops over the kernel crate's functions;
//! the counting sort runs sequentially, which makes its arrival order the index order, so its permutation is
//! the stable one by construction (the GPU restores the same order with `sort_cells`).

use super::{Backend, Buffer, CellBuffers, DeviceInfo, Element, ScalarsAt};
use crate::kernels::neighbour::{GatherField, sort::sort_cell};
use crate::kernels::pass::Pass;
use crate::kernels::sph::step::StepScalars;
use crate::kernels::{Dim, Real};
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

fn check(op: &'static str, expected: usize, got: usize) -> Result<()> {
    if got < expected { Err(Error::Length { op, expected, got }) } else { Ok(()) }
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

    fn read_one<T: Element>(&self, buf: &Vec<T>, i: usize) -> Result<T> {
        check("read_one", i + 1, buf.len())?;
        Ok(buf[i])
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

    fn host_slice<'a, T: Element>(&self, buf: &'a Vec<T>) -> Option<&'a [T]> {
        Some(buf)
    }

    fn address<T: Element>(&self, buf: &Vec<T>) -> u64 {
        buf.as_ptr() as u64
    }

    fn address_mut<T: Element>(&self, buf: &mut Vec<T>) -> u64 {
        buf.as_mut_ptr() as u64
    }

    fn gather<T: Element>(&self, n: usize, perm: &Vec<u32>, src: &Vec<T>, dst: &mut Vec<T>) -> Result<()> {
        check("gather perm", n, perm.len())?;
        check("gather dst", n, dst.len())?;
        dst[..n].par_iter_mut().zip(perm[..n].par_iter()).for_each(|(d, &j)| *d = src[j as usize]);
        Ok(())
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

    unsafe fn launch<P: Pass>(&self, args: &P::Args) -> Result<()> {
        let gate = P::gate(args);
        // SAFETY: a non-null gate points at a live step's rebuild flag (the caller's contract).
        if !gate.is_null() && unsafe { *gate } == 0 {
            return Ok(());
        }
        let a = Shared(*args);
        let active = P::active(args);
        // SAFETY: a non-null count points at the live cell starts (the caller's contract, `args::span`).
        let n = if active.is_null() { P::particles(args) } else { P::particles(args).min(unsafe { *active } as usize) };
        let flags = (0..n)
            .into_par_iter()
            // SAFETY: the caller's contract (live buffers of the pass's sizes); each particle's twin writes only
            // that particle's entries.
            .map(|i| unsafe { P::particle(a.get(), i) })
            .reduce(|| 0, |x, y| x | y);
        // SAFETY: every particle's call has returned.
        unsafe { P::finish(args, flags) };
        Ok(())
    }

    fn bin_cells<R: Real, D: Dim>(
        &self,
        n: usize,
        gate: Option<ScalarsAt<'_, Self>>,
        pos: &Vec<D::Vec<R>>,
        vel: Option<&Vec<D::Vec<R>>>,
        c: CellBuffers<'_, Self>,
    ) -> Result<()> {
        if let Some(g) = &gate
            && scalars(g)?.rebuild == 0
        {
            return Ok(());
        }
        let sorted = c.sorted_buckets();
        if let Some(r) = c.rebuilds {
            check("bin_cells rebuilds", 1, r.len())?;
            r[0] += 1;
        }
        self.fill_zero(c.starts, c.n_buckets + 1)?;
        let h = super::args::hash_args::<_, R, D>(self, n, pos, vel, c.grid, c.blank.as_ref(), c.keys)?;
        // SAFETY: `hash_args` checked the lengths.
        unsafe { self.launch::<crate::kernels::pass::Hash<R, D>>(&h)? };
        count_cells(n, c.keys, c.starts, c.slots)?;
        self.exclusive_scan(c.n_buckets + 1, c.starts, c.scan)?;
        scatter(n, c.keys, c.slots, c.starts, c.perm)?;
        sort_cells(sorted, c.starts, c.perm)
    }

    fn exclusive_scan(&self, n: usize, data: &mut Vec<u32>, _levels: &mut [Vec<u32>]) -> Result<()> {
        check("exclusive_scan", n, data.len())?;
        exclusive_scan(&mut data[..n]);
        Ok(())
    }

    fn capture(&self, f: &mut dyn FnMut() -> Result<()>) -> Result<Option<()>> {
        f()?;
        Ok(None)
    }

    fn replay(&self, _g: &()) -> Result<()> {
        Ok(())
    }
}

/// counts[keys[i]] += 1 and slots[i] = the particle's arrival order in its bucket, sequentially: the arrival
/// order is the index order, so the scatter's permutation is the stable one by construction.
fn count_cells(n: usize, keys: &[u32], counts: &mut [u32], slots: &mut [u32]) -> Result<()> {
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

/// perm[starts[keys[i]] + slots[i]] = i.
fn scatter(n: usize, keys: &[u32], slots: &[u32], starts: &[u32], perm: &mut [u32]) -> Result<()> {
    check("scatter perm", n, perm.len())?;
    for i in 0..n {
        let dst = (starts[keys[i] as usize] + slots[i]) as usize;
        let len = perm.len();
        *perm.get_mut(dst).ok_or(Error::Length { op: "scatter perm", expected: dst + 1, got: len })? = i as u32;
    }
    Ok(())
}

/// Sorts each bucket's slice perm[starts[c] .. starts[c+1]] ascending, c < n_buckets (the GPU's twin; a no-op
/// after the sequential count, kept so that both build the same way; `CellBuffers::sorted_buckets` leaves out
/// the void bucket, which the GPU's atomic scatter leaves in arrival order).
fn sort_cells(n_buckets: usize, starts: &[u32], perm: &mut [u32]) -> Result<()> {
    check("sort_cells starts", n_buckets + 1, starts.len())?;
    let total = starts[n_buckets] as usize;
    check("sort_cells perm", total, perm.len())?;
    let p = perm.as_mut_ptr();
    for c in 0..n_buckets {
        let (a, b) = (starts[c], starts[c + 1]);
        if b > a + 1 {
            // SAFETY: starts is non-decreasing with starts[n_buckets] <= perm.len(), checked above.
            unsafe { sort_cell(p, a, b) };
        }
    }
    Ok(())
}
