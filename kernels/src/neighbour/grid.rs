//! The hash grid. Its arithmetic is in f64 whatever the run's precision (positions widen exactly), so that a
//! particle's cell is the same on the host and the GPU and in f32 and f64 runs of the same positions.

use crate::real::{Real, floor_f64};
use crate::vector::Vector;
use bytemuck::{Pod, Zeroable};

/// Grid geometry, passed to GPU kernels through a small device buffer.
///
/// Cells are numbered x fastest: key = (iz·ny + iy)·nx + ix (roethlin-solver.md §6.3, thesis form).
/// Key `n_cells` is the "void" bucket that collects particles with a non-finite position: they sort to the end
/// and belong to no cell, so they never appear as neighbours.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GridParams {
    pub origin: [f64; 3],
    /// Edge length of a cell; at least (support radius)/stencil, see `GridParams::cell_for`.
    pub cell_size: f64,
    pub inv_cell: f64,
    /// The skin s: how far a particle may move from where the cell list binned it before the list must be
    /// rebuilt (`GridParams::beyond_skin`). The solver's grid has cells of (2h + s)/2 for its ±2 stencil, so
    /// that every pair within 2h of the current positions stays within the stencil of the binned ones.
    /// 0 rebuilds whenever a particle moved at all.
    pub skin: f64,
    /// The period P of a domain periodic in z (3D; 0: not periodic) and 1/P. The z cells then tile the period
    /// exactly (dims[2] · cell_size = P), a particle's z cell wraps modulo dims[2], the stencil wraps with it, and
    /// every pair's z displacement is its nearest image, d_z − P ⌊d_z/P + ½⌋ ([`GridParams::displacement`]).
    pub period: f64,
    pub inv_period: f64,
    /// Cells along x, y, z (z = 1 in 2D).
    pub dims: [u32; 3],
    pub n_cells: u32,
    /// Cells searched on each side of a particle's own cell: 2 for cell = h, 1 for cell = 2h.
    pub stencil: u32,
    pub dim: u32,
    /// Most neighbours the Verlet list holds per particle (`neighbour::verlet`); 0: no list, the pair loops walk
    /// the stencil and the rebuild waits for a displacement of s instead of s/2.
    pub list_capacity: u32,
    /// The list's row length (the particle count it was sized for): particle i's count is at i, its candidates k
    /// and k + 1 (k even) share the word at (k/2 + 1)·stride + i (`neighbour::verlet`).
    pub list_stride: u32,
    /// 0: the list stores 16-bit offsets j − i, two to a word; 1 ("wide"): 32-bit offsets, candidate k alone in
    /// the word at (k + 1)·stride + i, for 3D domains whose stencil spans more than `verlet::MAX_OFFSET` sorted
    /// places (docs/neighbour-search.md, "Wide offsets").
    pub list_wide: u32,
    pub _pad: u32,
}

/// The blanking's active box [lo, hi] at one step (roethlin-solver.md §7.6.3; the original code's
/// `src/blanking.cpp`): particles outside it are frozen unless they move faster than the rest speed (docs/3d.md,
/// "Blanking"). `on` 0: no blanking.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BlankBox {
    pub lo: [f64; 3],
    pub hi: [f64; 3],
    /// The square of the rest speed [m²/s²]: a particle outside the box is frozen only when |v|² ≤ this (+∞: every
    /// particle outside, the original code's box). A chip thrown out of the box keeps moving, so it stays active
    /// rather than freeze in the path of the material behind it.
    pub rest_speed2: f64,
    pub on: u32,
    pub _pad: u32,
}

impl BlankBox {
    /// Whether a particle at `p` moving at `v` is blanked: blanking on, p outside [lo, hi] and |v|² ≤
    /// `rest_speed2` (compared in f64, positions and velocities widen exactly; a non-finite position is never
    /// blanked, so that it reaches the void bucket and stops the run; nor is a non-finite velocity).
    #[inline(always)]
    pub fn blanks<R: Real, V: Vector<R>>(&self, p: &V, v: &V) -> bool {
        if self.on == 0 {
            return false;
        }
        let mut outside = false;
        let mut speed2 = 0.0f64;
        let mut k = 0;
        while k < V::DIM {
            let (x, u) = (p.get(k).to_f64(), v.get(k).to_f64());
            // SAFETY: k < DIM <= 3.
            let (lo, hi) = unsafe { (*self.lo.get_unchecked(k), *self.hi.get_unchecked(k)) };
            // NaN compares false: not outside.
            outside |= x < lo || x > hi;
            speed2 += u * u;
            k += 1;
        }
        // NaN compares false: not at rest.
        outside && speed2 <= self.rest_speed2
    }
}

/// Relative enlargement of the cell over (support radius)/stencil. The pair test r² < (2h)² is evaluated in the
/// run's precision (f32 or f64) and the cell coordinate in f64; the margin covers both roundings, so that every
/// pair the test accepts lies within the stencil (proof in docs/neighbour-search.md).
pub const CELL_MARGIN: f64 = 1.0 / 65536.0;

/// |a − b|² in f64 whatever the run's precision (positions widen exactly), summed over the dimension's components in
/// order: the skin test's and the Verlet list's distance, the same bits on the host and the GPU.
#[inline(always)]
pub fn dist2_f64<R: Real, V: Vector<R>>(a: &V, b: &V) -> f64 {
    let mut d2 = 0.0;
    let mut k = 0;
    while k < V::DIM {
        let d = a.get(k).to_f64() - b.get(k).to_f64();
        d2 += d * d;
        k += 1;
    }
    d2
}

/// A z difference d reduced to its nearest periodic image, d − P ⌊d/P + ½⌋ (inv = 1/P), in the precision of d:
/// the one formula of the pair tests, the Verlet list and the pair terms.
#[inline(always)]
pub fn nearest_image<R: Real>(d: R, p: R, inv: R) -> R {
    d - p * (d * inv + R::from_f64(0.5)).floor()
}

/// A grid's z period in the run's precision, read once per particle before its pair loop, so that the loop can be
/// unswitched on it (`on` false: the plain loop, instruction for instruction).
#[derive(Clone, Copy)]
pub struct Period<R: Real> {
    /// A 3D grid with a period.
    pub on: bool,
    p: R,
    inv: R,
}

/// `$body` compiled twice, with the const `$c` true where the period `$per` is on and false elsewhere: the pair
/// loops unswitched on the period, so that a run without one runs its plain loop, instruction for instruction.
macro_rules! unswitch_period {
    ($per:expr, $c:ident => $body:expr) => {
        if $per.on {
            const $c: bool = true;
            $body
        } else {
            const $c: bool = false;
            $body
        }
    };
}
pub(crate) use unswitch_period;

impl<R: Real> Period<R> {
    /// The period of `grid` for a run of dimension `D` (off in 2D, whatever the grid says).
    #[inline(always)]
    pub fn of<D: crate::vector::Dim>(grid: &GridParams) -> Self {
        let on = D::D == 3 && grid.period > 0.0;
        Period { on, p: R::from_f64(grid.period), inv: R::from_f64(grid.inv_period) }
    }

    /// a − b with z reduced to the nearest image, d_z − P ⌊d_z/P + ½⌋ (as [`GridParams::displacement`]).
    #[inline(always)]
    pub fn displacement<V: Vector<R>>(&self, a: &V, b: &V) -> V {
        V::new([a.get(0) - b.get(0), a.get(1) - b.get(1), nearest_image(a.get(2) - b.get(2), self.p, self.inv)])
    }
}

impl GridParams {
    /// a − b in R, its z component reduced to the nearest periodic image when the grid is periodic in z:
    /// d_z − P ⌊d_z/P + ½⌋. Without a period, the plain difference.
    #[inline(always)]
    pub fn displacement<R: Real, V: Vector<R>>(&self, a: &V, b: &V) -> V {
        let mut d = [R::ZERO; 3];
        let mut k = 0;
        while k < V::DIM {
            // SAFETY: k < DIM <= 3.
            unsafe { *d.get_unchecked_mut(k) = a.get(k) - b.get(k) };
            k += 1;
        }
        if V::DIM == 3 && self.period > 0.0 {
            d[2] = nearest_image(d[2], R::from_f64(self.period), R::from_f64(self.inv_period));
        }
        V::new(d)
    }

    /// |a − b|² in R with the nearest periodic image in z (the pair test's distance); without a period,
    /// `Vector::dist2`, bit for bit.
    #[inline(always)]
    pub fn dist2<R: Real, V: Vector<R>>(&self, a: &V, b: &V) -> R {
        if V::DIM == 3 && self.period > 0.0 { self.displacement::<R, V>(a, b).dist2(&V::default()) } else { a.dist2(b) }
    }

    /// [`dist2_f64`] with the nearest periodic image in z (the Verlet list's distance).
    #[inline(always)]
    pub fn dist2_f64<R: Real, V: Vector<R>>(&self, a: &V, b: &V) -> f64 {
        if V::DIM != 3 || self.period <= 0.0 {
            return dist2_f64::<R, V>(a, b);
        }
        let mut d2 = 0.0;
        let mut k = 0;
        while k < 3 {
            let mut d = a.get(k).to_f64() - b.get(k).to_f64();
            if k == 2 {
                d = nearest_image(d, self.period, self.inv_period);
            }
            d2 += d * d;
            k += 1;
        }
        d2
    }

    /// The cell size for a support radius and stencil half-width.
    #[inline]
    pub fn cell_for(support_radius: f64, stencil: u32) -> f64 {
        support_radius / stencil as f64 * (1.0 + CELL_MARGIN)
    }

    /// The Verlet list's rows (`neighbour::verlet`): a row of counts and one row for each two candidates of the
    /// capacity (each candidate, with wide offsets); 0 without a list.
    #[inline(always)]
    pub fn list_rows(&self) -> usize {
        let cap = self.list_capacity as usize;
        if cap == 0 {
            0
        } else if self.list_wide != 0 {
            cap + 1
        } else {
            cap.div_ceil(2) + 1
        }
    }

    /// The Verlet list's length in words: [`GridParams::list_rows`] rows of `list_stride` words.
    #[inline(always)]
    pub fn list_words(&self) -> usize {
        self.list_rows() * self.list_stride as usize
    }

    /// How far a particle may move from where it was binned before the lists must be rebuilt: the skin s for the
    /// cell list alone, s/2 with the Verlet list (both ends of a pair move).
    #[inline(always)]
    pub fn rebuild_distance(&self) -> f64 {
        if self.list_capacity > 0 { 0.5 * self.skin } else { self.skin }
    }

    /// The squared radius of the Verlet list: a hair inside the stencil's reach, stencil · cell (which the
    /// stencil covers whatever the particle's place in its cell), and still beyond 2h + s by more than the
    /// roundings of the pair test (cell_size carries CELL_MARGIN = 2^-16, this takes 2^-18 back).
    #[inline(always)]
    pub fn list_radius2(&self) -> f64 {
        let r = self.stencil as f64 * self.cell_size * (1.0 - 1.0 / 262_144.0);
        r * r
    }

    /// Whether a particle at `x`, binned at `x_ref` when the cell list was built, has moved farther than
    /// [`GridParams::rebuild_distance`], so that the lists must be rebuilt before they are searched again. For a
    /// pair at r < 2h now, |x_i − x_j,ref| ≤ 2h + |x_j − x_j,ref|, which the stencil covers while every
    /// displacement is ≤ s; |x_i,ref − x_j,ref| ≤ 2h + |x_i − x_i,ref| + |x_j − x_j,ref|, which the Verlet list
    /// covers while every displacement is ≤ s/2 (docs/neighbour-search.md, "Skin", "Verlet list"). In f64
    /// (positions widen exactly); a non-finite position counts as moved, so that the rebuild sends it to the void
    /// bucket.
    #[inline(always)]
    pub fn beyond_skin<R: Real, V: Vector<R>>(&self, x: &V, x_ref: &V) -> bool {
        let d2 = dist2_f64::<R, V>(x, x_ref);
        // NaN compares false: a non-finite position is beyond every skin.
        let s = self.rebuild_distance();
        d2.is_nan() || d2 > s * s
    }

    /// Cell coordinate along axis `k`, clamped into the grid. Clamping keeps the search exact: it never increases
    /// the difference of two coordinates, so two particles within the stencil stay within it (docs).
    #[inline(always)]
    pub fn coord(&self, x: f64, k: usize) -> u32 {
        // SAFETY: k < 3 at every call site (loops over the dimension).
        let (o, n) = unsafe { (*self.origin.get_unchecked(k), *self.dims.get_unchecked(k)) };
        let c = floor_f64((x - o) * self.inv_cell);
        if k == 2 && self.period > 0.0 {
            // Periodic in z: the cell modulo dims[2] (exact in f64 for any finite cell count).
            let m = c - n as f64 * floor_f64(c / n as f64);
            return if m >= 0.0 && m < n as f64 { m as u32 } else { 0 };
        }
        if c <= 0.0 {
            0
        } else if c >= n as f64 {
            n - 1
        } else {
            c as u32
        }
    }

    /// The cell key of a position; `n_cells` (the void bucket) if any component is non-finite.
    #[inline(always)]
    pub fn key<R: Real, V: Vector<R>>(&self, p: &V) -> u32 {
        let c = self.coords(p);
        if c[0] == u32::MAX {
            return self.n_cells;
        }
        (c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0]
    }

    /// The cell-list key of a particle at `p` moving at `*v` with blanking (docs/3d.md, "Blanking"): the buckets
    /// are the n_cells cells of the active particles, then the n_cells cells of the blanked ones (key n_cells +
    /// cell), then the void bucket (2 n_cells). Blanked particles thus sort after every active one, cell by cell
    /// (so that their order is fixed by the same per-cell sort), no neighbour walk lists them, and
    /// `starts[n_cells]` counts the active ones. A null `blank` (no blanking): [`GridParams::key`], `v` unread.
    ///
    /// # Safety
    /// A non-null `blank` points at a live box and `v` at the particle's velocity.
    #[inline(always)]
    pub unsafe fn key_blanked<R: Real, V: Vector<R>>(&self, p: &V, v: *const V, blank: *const BlankBox) -> u32 {
        let k = self.key(p);
        if blank.is_null() {
            return k;
        }
        if k == self.n_cells {
            return 2 * self.n_cells;
        }
        if unsafe { (*blank).blanks(p, &*v) } { self.n_cells + k } else { k }
    }

    /// Cell coordinates of a position; `[u32::MAX; 3]` if a component is non-finite.
    #[inline(always)]
    pub fn coords<R: Real, V: Vector<R>>(&self, p: &V) -> [u32; 3] {
        let mut c = [0u32; 3];
        let mut k = 0;
        while k < V::DIM {
            let x = p.get(k);
            if !x.is_finite() {
                return [u32::MAX; 3];
            }
            // SAFETY: k < DIM <= 3.
            unsafe { *c.get_unchecked_mut(k) = self.coord(x.to_f64(), k) };
            k += 1;
        }
        c
    }
}
