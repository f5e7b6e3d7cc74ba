//! PTX entry points. Each is thin: compute the thread's index, bounds-check, call the shared function, store.
//! The block-cooperative pieces (prefix scan, the scatter of the counting sort) are the only GPU code with logic
//! of its own; each has a CPU twin in the host crate that it is tested against.

mod intrinsics;
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
