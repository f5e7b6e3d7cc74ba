//! PTX entry points. Each is thin: compute the thread's index, bounds-check, call the shared function, store.
//! The block-cooperative pieces (prefix scan, the scatter of the counting sort) are the only GPU code with logic
//! of its own; each has a CPU twin in the host crate that it is tested against.

mod intrinsics;
mod mpm;
mod neighbour;
mod scan;
mod sph;

/// Threads in the whole grid along x: the stride of a grid-stride loop.
#[inline(always)]
pub(crate) fn grid_threads() -> u32 {
    use core::arch::nvptx::*;
    unsafe { _grid_dim_x() * _block_dim_x() }
}

/// Global thread index along x.
#[inline(always)]
pub(crate) fn global_index() -> u32 {
    use core::arch::nvptx::*;
    unsafe { _block_idx_x() * _block_dim_x() + _thread_idx_x() }
}

/// Global thread index along x with the blocks taken in reverse order when `reverse` ≠ 0: block b covers the
/// threads of block (blocks − 1 − b). The hardware starts blocks in increasing index, so a launch whose costly
/// particles sit at the end of the sorted order (a cut's shear zone and chip, near the top rows of the cell keys)
/// starts them first and fills the multiprocessors with the cheap ones behind them, instead of leaving the costly
/// blocks for a tail on a few multiprocessors (docs/measurements/notebook.md, "Block order"). Each thread's particle and its
/// arithmetic are the same in either order.
#[inline(always)]
pub(crate) fn ordered_index(reverse: u32) -> u32 {
    use core::arch::nvptx::*;
    unsafe {
        let b = if reverse != 0 { _grid_dim_x() - 1 - _block_idx_x() } else { _block_idx_x() };
        b * _block_dim_x() + _thread_idx_x()
    }
}
