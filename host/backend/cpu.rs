//! The CPU backend: the reference. Per-particle kernels run as rayon loops over the kernel crate's functions;
//! the counting sort runs sequentially, which makes its arrival order the index order, so its permutation is
//! the stable one by construction (the GPU restores the same order with `sort_cells`).

use super::{Backend, Buffer, DeviceInfo, Element};
use crate::kernels::neighbour::search::neighbour_row;
use crate::kernels::neighbour::{GridParams, sort::sort_cell};
use crate::kernels::sph::{CubicSpline, density::density_sum};
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
        }
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

    fn info(&self) -> &DeviceInfo {
        &self.info
    }

    fn alloc<T: Element>(&self, n: usize, _what: &'static str) -> Result<Vec<T>> {
        Ok(vec![T::zeroed(); n])
    }

    fn upload<T: Element>(&self, data: &[T], _what: &'static str) -> Result<Vec<T>> {
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
}
