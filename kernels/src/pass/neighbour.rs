//! The neighbour passes' arguments: the cell list's hash, count, scatter and per-cell sort, the gathers of a
//! reorder, the Verlet list and the CSR neighbour list. The gated ones carry the step's rebuild flag (`gate`;
//! null: always run).

use super::launch::{Grid, Pass, Span};
use super::table::entry_index;
use crate::neighbour::search::neighbour_row;
use crate::neighbour::verlet::verlet_row;
use crate::neighbour::{BlankBox, GatherField, GridParams};
use crate::real::Real;
use crate::vector::Dim;
use core::marker::PhantomData;

/// keys[i] = cell key of pos[i] moving at vel[i] (`GridParams::key_blanked`).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct HashArgs<R: Real, D: Dim> {
    pub n: u32,
    pub pos: *const D::Vec<R>,
    /// The velocities, read with blanking only (its rest speed; null without).
    pub vel: *const D::Vec<R>,
    pub grid: *const GridParams,
    /// The blanking's box (null: no blanking).
    pub blank: *const BlankBox,
    pub keys: *mut u32,
}

impl<R: Real, D: Dim> HashArgs<R, D> {
    /// Particle i's cell key.
    ///
    /// # Safety
    /// i < n; `pos` and `keys` hold n particles, and `vel` with a `blank`; `grid` points at the grid.
    #[inline(always)]
    pub unsafe fn particle(&self, i: usize) {
        unsafe {
            let v = self.vel.wrapping_add(i);
            *self.keys.add(i) = (*self.grid).key_blanked::<R, D::Vec<R>>(&*self.pos.add(i), v, self.blank)
        }
    }
}

/// The hash pass (`swarf_hash_*`).
pub struct Hash<R, D>(PhantomData<(R, D)>);
crate::simple_pass!(Hash<R, D>, HashArgs<R, D>, entry_index("hash", D::D, size_of::<R>(), 0), Grid::Particles,
    [R: Real, D: Dim]);

/// The counting pass of a gated rebuild: keys[i] = cell key of pos[i] moving at vel[i] (`GridParams::key_blanked`),
/// slots[i] = its arrival order in the cell, counts[cell] += 1 (counts zeroed before).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct HashCountArgs<R: Real, D: Dim> {
    pub gate: *const u32,
    pub n: u32,
    pub pos: *const D::Vec<R>,
    /// The velocities, read with blanking only (null without).
    pub vel: *const D::Vec<R>,
    pub grid: *const GridParams,
    /// The blanking's box (null: no blanking).
    pub blank: *const BlankBox,
    pub keys: *mut u32,
    pub counts: *mut u32,
    pub slots: *mut u32,
}

/// Neighbours j ≠ i with |x_i − x_j|² < support2, in gather order, written to list[offsets[i]..] (CSR); with
/// `offsets` null only counted.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct NeighbourListArgs<R: Real, D: Dim> {
    pub n: Span,
    pub pos: *const D::Vec<R>,
    pub grid: *const GridParams,
    pub starts: *const u32,
    pub support2: R,
    pub offsets: *const u32,
    pub counts: *mut u32,
    pub list: *mut u32,
}

impl<R: Real, D: Dim> NeighbourListArgs<R, D> {
    /// Particle i's row: its neighbour count, the row itself where `offsets` is set.
    ///
    /// # Safety
    /// i < n; the arrays hold n sorted particles of the cell list; `list` holds the rows `offsets` names.
    #[inline(always)]
    pub unsafe fn particle(&self, i: usize) {
        unsafe {
            let c = neighbour_row::<R, D::Vec<R>>(
                &*self.grid,
                self.starts,
                self.pos,
                i as u32,
                self.support2,
                self.offsets,
                self.list,
            );
            *self.counts.add(i) = c;
        }
    }
}

/// The CSR neighbour list pass (`swarf_neighbour_list_*`).
pub struct NeighbourList<R, D>(PhantomData<(R, D)>);
crate::simple_pass!(NeighbourList<R, D>, NeighbourListArgs<R, D>,
    entry_index("neighbour_list", D::D, size_of::<R>(), 0), Grid::Particles, [R: Real, D: Dim]);

/// The Verlet list of the sorted particles at `pos` (`neighbour::verlet::verlet_row`).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct VerletArgs<R: Real, D: Dim> {
    pub gate: *const u32,
    pub n: Span,
    pub grid: *const GridParams,
    pub starts: *const u32,
    pub pos: *const D::Vec<R>,
    pub list: *mut u32,
}

impl<R: Real, D: Dim> VerletArgs<R, D> {
    /// Particle i's row (the words (m + 1)·stride + i and i).
    ///
    /// # Safety
    /// i < n; `pos` holds n sorted particles of the cell list; `list` has the grid's layout.
    #[inline(always)]
    pub unsafe fn particle(&self, i: usize) {
        unsafe { verlet_row::<R, D::Vec<R>>(&*self.grid, self.starts, self.pos, i as u32, self.list) }
    }
}

/// The Verlet list pass (`swarf_verlet_build_*`), gated.
pub struct Verlet<R, D>(PhantomData<(R, D)>);

impl<R: Real, D: Dim> Pass for Verlet<R, D> {
    type Args = VerletArgs<R, D>;
    const ENTRY: usize = entry_index("verlet_build", D::D, size_of::<R>(), 0);
    const GRID: Grid = Grid::Strided;
    fn particles(a: &Self::Args) -> usize {
        a.n.n as usize
    }
    fn active(a: &Self::Args) -> *const u32 {
        a.n.active
    }
    fn gate(a: &Self::Args) -> *const u32 {
        a.gate
    }
    unsafe fn particle(a: &Self::Args, i: usize) -> u32 {
        unsafe { a.particle(i) };
        0
    }
}

/// data[i] = 0 for i < n (the cell counts before a gated rebuild); the first thread also counts the rebuild in
/// rebuilds[0] (null: not counted).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct ZeroArgs {
    pub gate: *const u32,
    pub n: u32,
    pub data: *mut u32,
    pub rebuilds: *mut u32,
}

/// perm[starts[keys[i]] + slots[i]] = i.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct ScatterArgs {
    pub gate: *const u32,
    pub n: u32,
    pub keys: *const u32,
    pub slots: *const u32,
    pub starts: *const u32,
    pub perm: *mut u32,
}

/// Each bucket's slice of `perm` sorted ascending (one thread per bucket): the stable permutation.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct SortArgs {
    pub gate: *const u32,
    pub n_buckets: u32,
    pub starts: *const u32,
    pub perm: *mut u32,
}

/// dst[i] = src[perm[i]] for elements of `k` units of type `T` (one thread per unit).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct GatherArgs<T> {
    pub n: u32,
    pub k: u32,
    pub perm: *const u32,
    pub src: *const T,
    pub dst: *mut T,
}

/// dst_f[i] = src_f[perm[i]] for every field f of the `rows` of `table` (null `perm`: a copy).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct GatherFieldsArgs {
    pub gate: *const u32,
    pub n: u32,
    pub rows: u32,
    pub perm: *const u32,
    pub table: *const GatherField,
}

/// The scan's reduce pass: tile_sums[t] = Σ input[t·TILE .. (t+1)·TILE] (`ptx::scan`).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct ScanReduceArgs {
    pub gate: *const u32,
    pub n: u32,
    pub input: *const u32,
    pub tile_sums: *mut u32,
}

/// The scan's apply pass: output[i] = tile_offsets[t] + Σ input[t·TILE .. i] (null `tile_offsets`: one tile).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct ScanApplyArgs {
    pub gate: *const u32,
    pub n: u32,
    pub input: *const u32,
    pub output: *mut u32,
    pub tile_offsets: *const u32,
}
