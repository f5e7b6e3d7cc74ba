//! The Verlet list: each particle's candidates within 2h + s of where the cell list binned it, built with every
//! rebuild of the cell list and read by the pair loops until the next (docs/neighbour-search.md, "Verlet list").
//!
//! The stencil walk of a 2D cell list of (2h + s)/2 visits 25 cells, about 62 candidates at h = 1.5 Δx for 24
//! neighbours, and a warp steps through the longest of its threads' walks, running the pair term wherever one of
//! them has a neighbour; the list holds about 28. Its layout: `list[i]` is particle i's count; a candidate j is
//! stored as its offset j − i in 16 bits (two's complement), two to a word: candidates k and k + 1 (k even) in the
//! low and high halves of `list[(k/2 + 1)·stride + i]` (k < capacity). Column-major, so that a warp's threads
//! read consecutive words; packed, because the list is the one array of the pair loop that streams from DRAM
//! every step (20 MB of indices inside the 150k cut as 32-bit words: 28 candidates of 183 199 particles), and one
//! load serves two candidates. Candidates are in increasing sorted index, which is the order of the stencil walk
//! (keys are row-major and the walk visits rows in increasing order, each a contiguous range), so a sum over the
//! list equals the sum over the stencil bit for bit when the pair term skips j beyond the support, as every pair
//! term does. A particle with more candidates than the capacity keeps its true count and walks the stencil
//! instead; so does one with a candidate more than [`MAX_OFFSET`] sorted places away (count [`FAR`]): neighbours
//! sit within a few cell rows in the sorted order, far less than that in every 2D scene, but a 3D stencil spans
//! two layers of cells (nx·ny cells each), so a large 3D domain has far rows. There the host chooses **wide
//! offsets** (`GridParams::list_wide`): candidate k alone in the word at (k + 1)·stride + i as a 32-bit offset,
//! twice the memory and traffic, and no row is ever far.

use super::grid::GridParams;
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

    /// Word m of particle i's row after its count: candidates 2m and 2m + 1, or candidate m with wide offsets.
    ///
    /// # Safety
    /// The word holds at least one of i's listed candidates.
    #[inline(always)]
    unsafe fn word(&self, i: u32, m: u32) -> u32 {
        let at = (m as usize + 1) * self.grid.list_stride as usize + i as usize;
        unsafe { *self.list.add(at) }
    }
}

/// The largest |j − i| the packed list stores (an i16 offset).
pub const MAX_OFFSET: u32 = i16::MAX as u32;

/// The count of a row with a candidate more than [`MAX_OFFSET`] sorted places away: beyond any capacity, so the
/// pair loops walk the stencil for it.
pub const FAR: u32 = u32::MAX;

/// The candidate of particle i whose offset is the low 16 bits of `half`.
#[inline(always)]
fn decode(i: u32, half: u32) -> u32 {
    i.wrapping_add(half as u16 as i16 as i32 as u32)
}

/// Candidate k of a listed row, from the word `w` that holds it: with wide offsets the whole word, else its low
/// (k even) or high (k odd) half.
#[inline(always)]
fn candidate<const WIDE: bool>(i: u32, w: u32, k: u32) -> u32 {
    if WIDE { i.wrapping_add(w) } else { decode(i, if k & 1 == 0 { w } else { w >> 16 }) }
}

/// The word (after the count's) that holds candidate k.
#[inline(always)]
fn slot<const WIDE: bool>(k: u32) -> u32 {
    if WIDE { k } else { k / 2 }
}

/// Calls `f(j)` for the listed candidates k ≡ lane (mod lanes) of a row of `c`, in increasing k, compiled once for
/// each layout so that the packed loop carries no test of the layout.
///
/// The word of the next candidate is loaded before the current pair term runs: the list streams from DRAM, and its
/// load would otherwise stand at the head of every iteration's chain (index → position → term). Packed, with one
/// lane a word serves two iterations, so every other one loads.
///
/// # Safety
/// Particle i's row is listed (`Neighbours::listed` gave `c`).
#[inline(always)]
unsafe fn walk_row<const WIDE: bool, F: FnMut(u32)>(nb: &Neighbours, i: u32, c: u32, lane: u32, lanes: u32, mut f: F) {
    unsafe {
        let mut w = if lane < c { nb.word(i, slot::<WIDE>(lane)) } else { 0 };
        let mut k = lane;
        while k < c {
            let j = candidate::<WIDE>(i, w, k);
            let next = k + lanes;
            if next < c && slot::<WIDE>(next) != slot::<WIDE>(k) {
                w = nb.word(i, slot::<WIDE>(next));
            }
            f(j);
            k = next;
        }
    }
}

/// Calls `f(j)` for every candidate of sorted particle i at `x`: its listed candidates, or (without a list, or
/// beyond its capacity) every particle of the stencil around `x`, i itself included. Both in increasing j.
///
/// # Safety
/// `nb.starts` is the cell list of `nb.grid`; `nb.list` is null or built on it ([`verlet_row`]) with every
/// particle within [`GridParams::rebuild_distance`] of where it was binned; `x` is particle i's position.
#[inline(always)]
pub unsafe fn for_each_candidate<R: Real, V: Vector<R>, F: FnMut(u32)>(nb: &Neighbours, x: &V, i: u32, f: F) {
    unsafe { for_each_candidate_strided::<R, V, F>(nb, x, i, 0, 1, f) }
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
    f: F,
) {
    unsafe {
        match nb.listed(i) {
            Some(c) if nb.grid.list_wide != 0 => walk_row::<true, F>(nb, i, c, lane, lanes, f),
            Some(c) => walk_row::<false, F>(nb, i, c, lane, lanes, f),
            None => for_each_neighbour_strided::<R, V, _>(nb.grid, nb.starts, x, lane, lanes, f),
        }
    }
}

/// Builds sorted particle i's row of the Verlet list: every j ≠ i of the stencil with |x_i − x_j|² <
/// `grid.list_radius2()` (in f64: positions widen exactly), in increasing j; the first `list_capacity` are stored
/// as offsets j − i, two to a word, or one to a word with `grid.list_wide` (module doc); the count is stored whole
/// (a count beyond the capacity sends the pair loops to the stencil), or, packed, [`FAR`] where an offset exceeds
/// [`MAX_OFFSET`] (the words already written for that row are never read).
///
/// # Safety
/// `pos` holds the sorted particles of the cell list `starts`/`grid` (i < n ≤ `grid.list_stride`), and `list` has
/// `grid.list_words()` entries.
#[inline(always)]
pub unsafe fn verlet_row<R: Real, V: Vector<R>>(
    grid: &GridParams,
    starts: *const u32,
    pos: *const V,
    i: u32,
    list: *mut u32,
) {
    let (cap, stride) = (grid.list_capacity, grid.list_stride as usize);
    let wide = grid.list_wide != 0;
    let r2 = grid.list_radius2();
    let iu = i as usize;
    let xi = unsafe { *pos.add(iu) };
    let (mut c, mut far, mut low) = (0u32, false, 0u32);
    unsafe {
        for_each_neighbour::<R, V, _>(grid, starts, &xi, |j| {
            if j != i && grid.dist2_f64::<R, V>(&xi, &*pos.add(j as usize)) < r2 {
                if wide {
                    if c < cap {
                        *list.add((c as usize + 1) * stride + iu) = j.wrapping_sub(i);
                    }
                } else {
                    far |= j.abs_diff(i) > MAX_OFFSET;
                    if c < cap {
                        let half = j.wrapping_sub(i) & 0xffff;
                        let at = (c as usize / 2 + 1) * stride + iu;
                        // An even candidate opens its word (the high half 0 until the next one comes).
                        if c & 1 == 0 {
                            low = half;
                            *list.add(at) = half;
                        } else {
                            *list.add(at) = low | half << 16;
                        }
                    }
                }
                c += 1;
            }
        });
        *list.add(iu) = if far { FAR } else { c };
    }
}
