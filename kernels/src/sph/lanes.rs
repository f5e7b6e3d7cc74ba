//! Lanes: several threads sum one particle's neighbour terms, each its share of the candidates
//! (`neighbour::for_each_neighbour_strided`), and the shares are combined by a butterfly: stage s = 1, 2, 4, …
//! adds the partner lane ^ s. On the GPU the partners are warp shuffles; the CPU replays the same tree, so the
//! sums are bitwise equal on both (IEEE addition is commutative, so every lane of the butterfly holds the same
//! bits). One lane is the plain sequential sum.

/// Most lanes per particle.
pub const MAX_LANES: usize = 8;

/// A partial sum that lanes combine.
pub trait LaneSum: Copy + Default {
    fn add(&self, o: &Self) -> Self;
}

impl LaneSum for f64 {
    #[inline(always)]
    fn add(&self, o: &Self) -> Self {
        *self + *o
    }
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
