//! Cell-list construction on the GPU: hash, count (integer atomics), scan (ptx/scan.rs), scatter, per-cell sort,
//! gather, and the Verlet list built on the sorted particles. The atomics only decide the order in which a cell's slice is filled; `sort_cells` then restores the
//! unique stable order, so the permutation is deterministic and equal to the CPU twin's.

use super::intrinsics::atomic_add_u32;
use super::{global_index, grid_threads};
use crate::neighbour::{GatherField, sort::sort_cell};
use crate::pass::{
    GatherArgs, GatherFieldsArgs, HashArgs, HashCountArgs, NeighbourListArgs, ScatterArgs, SortArgs, VerletArgs,
    ZeroArgs,
};
use crate::vector::{Dim, Dim2, Dim3};
use core::num::NonZeroU32;

type Vec_<R, D> = <D as Dim>::Vec<R>;

/// The gated kernels loop over their items with a grid stride: they are launched with a capped grid
/// (`backend::cuda`, GATED_BLOCKS), so that a step that does not rebuild pays for a few hundred blocks that read
/// the flag and return, not for one block per 256 items (the reorder alone has one item per particle and field).
///
/// False when a gated launch has nothing to do: `gate` points at a step's rebuild flag
/// (`sph::step::StepScalars::rebuild`) and it is 0. A null gate always runs (a build outside the step loop).
#[inline(always)]
pub(crate) unsafe fn open(gate: *const u32) -> bool {
    gate.is_null() || unsafe { core::ptr::read_volatile(gate) } != 0
}

/// The per-vector neighbour entries of the pass table (pass::table), each in its own anonymous scope: its exported
/// name is the table's.
macro_rules! per_vector {
    (verlet_build, $sym:expr, $r:ident, $d:ident) => {
        const _: () = {
            /// The Verlet list of the sorted particles at `pos` (`neighbour::verlet::verlet_row`), when the gate
            /// is open; after the reorder of a gated rebuild, or with a null gate after a build outside the step
            /// loop.
            #[unsafe(export_name = $sym)]
            pub unsafe extern "ptx-kernel" fn entry(args: VerletArgs<$r, $d>) {
                if !unsafe { open(args.gate) } {
                    return;
                }
                let mut i = global_index();
                let n = unsafe { args.n.limit() };
                while i < n {
                    unsafe { args.particle(i as usize) };
                    i += grid_threads();
                }
            }
        };
    };
    (hash_count, $sym:expr, $r:ident, $d:ident) => {
        const _: () = {
            /// The counting pass of a gated rebuild: keys[i] = cell key of pos[i], slots[i] = its arrival order
            /// in the cell, counts[cell] += 1 (counts zeroed before), when the gate is open.
            #[unsafe(export_name = $sym)]
            pub unsafe extern "ptx-kernel" fn entry(args: HashCountArgs<$r, $d>) {
                let HashCountArgs { gate, n, pos, vel, grid, blank, keys, counts, slots } = args;
                if !unsafe { open(gate) } {
                    return;
                }
                let mut i = global_index();
                while i < n {
                    unsafe {
                        let v = vel.wrapping_add(i as usize);
                        let k = (*grid).key_blanked::<$r, Vec_<$r, $d>>(&*pos.add(i as usize), v, blank);
                        *keys.add(i as usize) = k;
                        *slots.add(i as usize) = atomic_add_u32(counts.add(k as usize), 1);
                    }
                    i += grid_threads();
                }
            }
        };
    };
    (hash, $sym:expr, $r:ident, $d:ident) => {
        const _: () = {
            /// keys[i] = cell key of pos[i] (`GridParams::key`).
            #[unsafe(export_name = $sym)]
            pub unsafe extern "ptx-kernel" fn entry(args: HashArgs<$r, $d>) {
                let i = global_index();
                if i < args.n {
                    unsafe { args.particle(i as usize) };
                }
            }
        };
    };
    (neighbour_list, $sym:expr, $r:ident, $d:ident) => {
        const _: () = {
            /// Neighbours j ≠ i with |x_i − x_j|² < support2, in gather order, written to list[offsets[i]..]
            /// (CSR); with `offsets` null only counted.
            #[unsafe(export_name = $sym)]
            pub unsafe extern "ptx-kernel" fn entry(args: NeighbourListArgs<$r, $d>) {
                let i = global_index();
                if unsafe { args.n.live(i) } {
                    unsafe { args.particle(i as usize) };
                }
            }
        };
    };
    ($kind:ident, $($rest:tt)*) => {};
}

crate::for_each_entry!(per_vector);

/// data[i] = 0 for i < n when the gate is open (the cell counts before a gated rebuild); the first thread also
/// counts the rebuild in rebuilds[0] (null: not counted).
#[unsafe(no_mangle)]
pub unsafe extern "ptx-kernel" fn swarf_zero_gated(args: ZeroArgs) {
    let ZeroArgs { gate, n, data, rebuilds } = args;
    if !unsafe { open(gate) } {
        return;
    }
    let mut i = global_index();
    if i == 0 && !rebuilds.is_null() {
        unsafe { *rebuilds += 1 };
    }
    while i < n {
        unsafe { *data.add(i as usize) = 0 };
        i += grid_threads();
    }
}

/// perm[starts[keys[i]] + slots[i]] = i (when the gate is open).
#[unsafe(no_mangle)]
pub unsafe extern "ptx-kernel" fn swarf_scatter(args: ScatterArgs) {
    let ScatterArgs { gate, n, keys, slots, starts, perm } = args;
    if !unsafe { open(gate) } {
        return;
    }
    let mut i = global_index();
    while i < n {
        unsafe {
            let k = *keys.add(i as usize);
            let dst = *starts.add(k as usize) + *slots.add(i as usize);
            *perm.add(dst as usize) = i;
        }
        i += grid_threads();
    }
}

/// Sorts each bucket's slice of `perm` ascending (one thread per bucket), making the permutation the stable one
/// (when the gate is open).
#[unsafe(no_mangle)]
pub unsafe extern "ptx-kernel" fn swarf_sort_cells(args: SortArgs) {
    let SortArgs { gate, n_buckets, starts, perm } = args;
    if !unsafe { open(gate) } {
        return;
    }
    let mut c = global_index();
    while c < n_buckets {
        unsafe {
            let a = *starts.add(c as usize);
            let b = *starts.add(c as usize + 1);
            if b > a + 1 {
                sort_cell(perm, a, b);
            }
        }
        c += grid_threads();
    }
}

macro_rules! gather {
    ($name:ident, $t:ty) => {
        /// dst[i] = src[perm[i]] for elements of `k` units of this kernel's unit size (one thread per unit).
        #[unsafe(no_mangle)]
        pub unsafe extern "ptx-kernel" fn $name(args: GatherArgs<$t>) {
            let GatherArgs { n, k, perm, src, dst } = args;
            let Some(kk) = NonZeroU32::new(k) else { return };
            let t = global_index();
            let i = t / kk;
            if i < n {
                let w = t - i * k;
                unsafe {
                    let s = *perm.add(i as usize) as usize * k as usize + w as usize;
                    *dst.add(t as usize) = *src.add(s);
                }
            }
        }
    };
}

/// 16-byte unit for vector loads and stores.
#[repr(C, align(16))]
#[derive(Clone, Copy)]
pub struct B16([u32; 4]);

gather!(swarf_gather_b4, u32);
gather!(swarf_gather_b8, u64);
gather!(swarf_gather_b16, B16);

/// dst_f[i] = src_f[perm[i]] for every field f of the `rows` of `table` (a grid-stride loop over fields ×
/// particles), the whole particle state reordered in one launch. Each element is copied in the widest unit its size allows.
#[unsafe(no_mangle)]
pub unsafe extern "ptx-kernel" fn swarf_gather_fields(args: GatherFieldsArgs) {
    let GatherFieldsArgs { gate, n, rows, perm, table } = args;
    if !unsafe { open(gate) } {
        return;
    }
    // Item t is particle t mod n of field t / n (a grid-stride loop over fields × particles). A nonzero
    // divisor: no division-by-zero panic path (a trap) in the kernel.
    let Some(nn) = core::num::NonZeroU64::new(n as u64) else { return };
    let total = n as u64 * rows as u64;
    let mut t = global_index() as u64;
    while t < total {
        let (row, i) = ((t / nn) as usize, (t % nn) as usize);
        unsafe {
            let f = *table.add(row);
            // A null permutation copies (the copy-back of an in-place reorder).
            let j = if perm.is_null() { i } else { *perm.add(i) as usize };
            let b = f.bytes as usize;
            if b.is_multiple_of(16) {
                copy_units::<B16>(f, b / 16, i, j);
            } else if b.is_multiple_of(8) {
                copy_units::<u64>(f, b / 8, i, j);
            } else {
                copy_units::<u32>(f, b / 4, i, j);
            }
        }
        t += grid_threads() as u64;
    }
}

#[inline(always)]
unsafe fn copy_units<T: Copy>(f: GatherField, k: usize, i: usize, j: usize) {
    let (src, dst) = (f.src as *const T, f.dst as *mut T);
    let mut w = 0;
    while w < k {
        unsafe { *dst.add(i * k + w) = *src.add(j * k + w) };
        w += 1;
    }
}
