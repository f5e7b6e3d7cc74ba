//! Lanes: several threads sum one particle's neighbour terms, each its share of the candidates
//! (`neighbour::for_each_candidate_strided`), and the shares are combined by a butterfly: stage s = 1, 2, 4, …
//! adds the partner lane ^ s. On the GPU the partners are warp shuffles; the CPU replays the same tree, so the
//! sums are bitwise equal on both (IEEE addition is commutative, so every lane of the butterfly holds the same
//! bits). One lane is the plain sequential sum.

use crate::neighbour::{Neighbours, for_each_candidate, for_each_candidate_strided};
use crate::real::Real;
use crate::vector::Vector;

/// Most lanes per particle.
pub const MAX_LANES: usize = 8;

/// A partial sum that lanes combine.
pub trait LaneSum: Copy + Default {
    fn add(&self, o: &Self) -> Self;
    /// The sum with each 32-bit word of its values replaced by `f(word)` (the GPU's shuffles move words). Field
    /// by field: padding between fields is never read, which would be undefined behaviour (LLVM turned a
    /// whole-struct copy over padding into a trap).
    fn map_words<F: FnMut(u32) -> u32>(&self, f: &mut F) -> Self;
}

impl LaneSum for f64 {
    #[inline(always)]
    fn add(&self, o: &Self) -> Self {
        *self + *o
    }
    #[inline(always)]
    fn map_words<F: FnMut(u32) -> u32>(&self, f: &mut F) -> Self {
        map_real(*self, f)
    }
}

/// `x` with each 32-bit word replaced by `f(word)` (one word for f32, two for f64).
#[inline(always)]
pub fn map_real<R: Copy, F: FnMut(u32) -> u32>(x: R, f: &mut F) -> R {
    let mut y = x;
    let p = &mut y as *mut R as *mut u32;
    let mut k = 0;
    while k < size_of::<R>() / 4 {
        // SAFETY: R is a float (4 or 8 bytes, every byte initialised); k is within it.
        unsafe { *p.add(k) = f(*p.add(k)) };
        k += 1;
    }
    y
}

/// A vector with each component's words mapped by `f` (only the dimension's components).
#[inline(always)]
pub fn map_vector<R: Real, V: Vector<R>, F: FnMut(u32) -> u32>(v: &V, f: &mut F) -> V {
    let x = map_real(v.get(0), f);
    let y = map_real(v.get(1), f);
    let z = if V::DIM == 3 { map_real(v.get(2), f) } else { R::ZERO };
    V::new([x, y, z])
}

/// The butterfly over `parts` (a power of two of them), as the GPU's shuffles evaluate it: returns lane 0's result,
/// ((p0 + p1) + (p2 + p3)) + ((p4 + p5) + (p6 + p7)) for eight lanes.
#[inline(always)]
pub fn combine<T: LaneSum>(parts: &mut [T]) -> T {
    let n = parts.len();
    let mut s = 1;
    while s < n {
        let mut k = 0;
        while k + s < n {
            parts[k] = parts[k].add(&parts[k + s]);
            k += 2 * s;
        }
        s <<= 1;
    }
    parts.first().copied().unwrap_or_default()
}

/// Lanes per particle clamped to 1 ..= MAX_LANES.
#[inline(always)]
pub fn clamp_lanes(lanes: u32) -> u32 {
    if lanes == 0 {
        1
    } else if lanes as usize > MAX_LANES {
        MAX_LANES as u32
    } else {
        lanes
    }
}

/// Lane `lane` of `lanes`' share of a per-particle neighbour sum: `term(j, &mut share)` for every `lanes`-th
/// candidate of sorted particle i at `x` (`neighbour::for_each_candidate`), from the `lane`-th on (what the GPU
/// thread of that lane sums).
///
/// # Safety
/// `nb` as `neighbour::for_each_candidate` requires; `term` is safe for every candidate it is given.
#[inline(always)]
pub unsafe fn lane_share<R: Real, V: Vector<R>, S: LaneSum, F: FnMut(u32, &mut S)>(
    nb: &Neighbours,
    x: &V,
    i: u32,
    lane: u32,
    lanes: u32,
    mut term: F,
) -> S {
    let mut share = S::default();
    unsafe { for_each_candidate_strided::<R, V, _>(nb, x, i, lane, lanes, |j| term(j, &mut share)) };
    share
}

/// Every lane's share in one pass (candidate k to lane k mod `lanes`, so each share is summed in [`lane_share`]'s
/// order), combined by the butterfly: the CPU twin of [`lane_share`] on each lane followed by the GPU's shuffles.
///
/// # Safety
/// As [`lane_share`].
#[inline(always)]
pub unsafe fn all_lanes<R: Real, V: Vector<R>, S: LaneSum, F: FnMut(u32, &mut S)>(
    nb: &Neighbours,
    x: &V,
    i: u32,
    lanes: u32,
    mut term: F,
) -> S {
    let lanes = clamp_lanes(lanes);
    let mut parts = [S::default(); MAX_LANES];
    let mut k = 0u32;
    unsafe {
        for_each_candidate::<R, V, _>(nb, x, i, |j| {
            term(j, &mut parts[(k % lanes) as usize]);
            k += 1;
        })
    };
    combine(&mut parts[..lanes as usize])
}
