//! The Verlet list: each particle's candidates within 2h + s of where the cell list binned it, built with every
//! rebuild of the cell list and read by the pair loops until the next (docs/neighbour-search.md, "Verlet list").
//!
//! The stencil walk of a 2D cell list of (2h + s)/2 visits 25 cells, about 62 candidates at h = 1.5 Δx for 24
//! neighbours, and a warp steps through the longest of its threads' walks, running the pair term wherever one of
//! them has a neighbour; the list holds about 28. Its layout: `list[i]` is particle i's count and
//! `list[(k + 1)·stride + i]` its k-th candidate (k < capacity), column-major so that a warp's threads read
//! consecutive words. Candidates are in increasing sorted index, which is the order of the stencil walk (keys
//! are row-major and the walk visits rows in increasing order, each a contiguous range), so a sum over the list
//! equals the sum over the stencil bit for bit when the pair term skips j beyond the support, as every pair term
//! does. A particle with more candidates than the capacity keeps its true count and walks the stencil instead.

use super::grid::{GridParams, dist2_f64};
use super::search::{for_each_neighbour, for_each_neighbour_strided};
use crate::real::Real;
use crate::vector::Vector;

/// What a pair loop searches: the cell list, and the Verlet list built on it (null: the stencil walk).
#[derive(Clone, Copy)]
pub struct Neighbours<'a> {
    pub grid: &'a GridParams,
    /// The cell list's prefix array (`search::for_each_row`).
    pub starts: *const u32,
    /// The Verlet list in the layout of this module (`grid.list_capacity`, `grid.list_stride`), or null.
    pub list: *const u32,
}

impl Neighbours<'_> {
    /// Particle i's candidate count when the list holds them all, else None (no list, or an overflow).
    ///
    /// # Safety
    /// `list` is null or built for `grid` with i < stride.
    #[inline(always)]
    unsafe fn listed(&self, i: u32) -> Option<u32> {
        if self.list.is_null() {
            return None;
        }
        let c = unsafe { *self.list.add(i as usize) };
        if c <= self.grid.list_capacity { Some(c) } else { None }
    }

    /// Candidate k of particle i.
    ///
    /// # Safety
    /// i has at least k + 1 listed candidates.
    #[inline(always)]
    unsafe fn entry(&self, i: u32, k: u32) -> u32 {
        let at = (k as usize + 1) * self.grid.list_stride as usize + i as usize;
        unsafe { *self.list.add(at) }
    }
}

/// Calls `f(j)` for every candidate of sorted particle i at `x`: its listed candidates, or (without a list, or
/// beyond its capacity) every particle of the stencil around `x`, i itself included. Both in increasing j.
///
/// # Safety
/// `nb.starts` is the cell list of `nb.grid`; `nb.list` is null or built on it ([`verlet_row`]) with every
/// particle within [`GridParams::rebuild_distance`] of where it was binned; `x` is particle i's position.
#[inline(always)]
pub unsafe fn for_each_candidate<R: Real, V: Vector<R>, F: FnMut(u32)>(nb: &Neighbours, x: &V, i: u32, mut f: F) {
    unsafe {
        match nb.listed(i) {
            Some(c) => {
                // The next index is loaded before the current pair term runs: the list streams from DRAM, and
                // its load would otherwise stand at the head of every iteration's chain (index → position → term).
                let mut next = if c > 0 { nb.entry(i, 0) } else { 0 };
                let mut k = 0;
                while k < c {
                    let j = next;
                    if k + 1 < c {
                        next = nb.entry(i, k + 1);
                    }
                    f(j);
                    k += 1;
                }
            }
            None => for_each_neighbour::<R, V, _>(nb.grid, nb.starts, x, f),
        }
    }
}

/// The share of `lane` (of `lanes`) of [`for_each_candidate`]'s candidates: those numbered k ≡ lane (mod lanes),
/// in increasing k (`search::for_each_neighbour_strided` over the stencil).
///
/// # Safety
/// As [`for_each_candidate`]; `lane < lanes`.
#[inline(always)]
pub unsafe fn for_each_candidate_strided<R: Real, V: Vector<R>, F: FnMut(u32)>(
    nb: &Neighbours,
    x: &V,
    i: u32,
    lane: u32,
    lanes: u32,
    mut f: F,
) {
    unsafe {
        match nb.listed(i) {
            Some(c) => {
                // As in `for_each_candidate`: the next index is in flight while the current term runs.
                let mut next = if lane < c { nb.entry(i, lane) } else { 0 };
                let mut k = lane;
                while k < c {
                    let j = next;
                    if k + lanes < c {
                        next = nb.entry(i, k + lanes);
                    }
                    f(j);
                    k += lanes;
                }
            }
            None => for_each_neighbour_strided::<R, V, _>(nb.grid, nb.starts, x, lane, lanes, f),
        }
    }
}

/// Builds sorted particle i's row of the Verlet list: every j ≠ i of the stencil with |x_i − x_j|² <
/// `grid.list_radius2()` (in f64: positions widen exactly), in increasing j; the first `list_capacity` are stored,
/// the count is stored whole (a count beyond the capacity sends the pair loops to the stencil).
///
/// # Safety
/// `pos` holds the sorted particles of the cell list `starts`/`grid` (i < n ≤ `grid.list_stride`), and `list` has
/// (capacity + 1) · stride entries.
#[inline(always)]
pub unsafe fn verlet_row<R: Real, V: Vector<R>>(
    grid: &GridParams,
    starts: *const u32,
    pos: *const V,
    i: u32,
    list: *mut u32,
) {
    let (cap, stride) = (grid.list_capacity, grid.list_stride as usize);
    let r2 = grid.list_radius2();
    let iu = i as usize;
    let xi = unsafe { *pos.add(iu) };
    let mut c = 0u32;
    unsafe {
        for_each_neighbour::<R, V, _>(grid, starts, &xi, |j| {
            if j != i && dist2_f64::<R, V>(&xi, &*pos.add(j as usize)) < r2 {
                if c < cap {
                    *list.add((c as usize + 1) * stride + iu) = j;
                }
                c += 1;
            }
        });
        *list.add(iu) = c;
    }
}
