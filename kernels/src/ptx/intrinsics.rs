//! Warp-level primitives and atomics that `core::arch::nvptx` does not provide, as inline PTX.

use core::arch::asm;

/// Lane index within the warp (0..32).
#[inline(always)]
pub fn lane_id() -> u32 {
    let r: u32;
    unsafe { asm!("mov.u32 {r}, %laneid;", r = out(reg32) r) };
    r
}

/// `shfl.sync.up`: the value of lane (lane − delta), or the own value for lanes below `delta`.
#[inline(always)]
pub fn shfl_up(v: u32, delta: u32) -> u32 {
    let r: u32;
    unsafe { asm!("shfl.sync.up.b32 {r}, {v}, {d}, 0, -1;", r = out(reg32) r, v = in(reg32) v, d = in(reg32) delta) };
    r
}

/// `shfl.sync.idx`: the value of lane `src`.
#[inline(always)]
pub fn shfl_idx(v: u32, src: u32) -> u32 {
    let r: u32;
    unsafe { asm!("shfl.sync.idx.b32 {r}, {v}, {s}, 31, -1;", r = out(reg32) r, v = in(reg32) v, s = in(reg32) src) };
    r
}

/// Inclusive prefix sum over the 32 lanes of a full warp (Kogge–Stone, 5 shuffles).
#[inline(always)]
pub fn warp_inclusive_scan(mut v: u32) -> u32 {
    let lane = lane_id();
    let mut d = 1;
    while d < 32 {
        let up = shfl_up(v, d);
        if lane >= d {
            v += up;
        }
        d <<= 1;
    }
    v
}

/// Atomic add on a global u32, returning the previous value.
#[inline(always)]
pub unsafe fn atomic_add_u32(p: *mut u32, v: u32) -> u32 {
    use core::sync::atomic::{AtomicU32, Ordering};
    unsafe { AtomicU32::from_ptr(p).fetch_add(v, Ordering::Relaxed) }
}

/// `shfl.sync.bfly`: the value of lane (lane ^ mask).
#[inline(always)]
pub fn shfl_xor(v: u32, mask: u32) -> u32 {
    let r: u32;
    unsafe { asm!("shfl.sync.bfly.b32 {r}, {v}, {m}, 31, -1;", r = out(reg32) r, v = in(reg32) v, m = in(reg32) mask) };
    r
}

unsafe extern "C" {
    /// The device runtime's `cudaGraphSetConditional(handle, value)` (CUDA 12.3+): sets the condition of a graph's
    /// conditional node. The driver resolves it when it compiles the PTX (the one `.extern` of the module:
    /// tests/ptx.rs; `backend::cuda` strips its calls where a driver cannot).
    fn cudaGraphSetConditional(handle: u64, value: u32);
}

/// Sets a conditional graph node's handle (`handle` ≠ 0: the launch is part of a graph that holds the node).
#[inline(always)]
pub fn graph_set_conditional(handle: u64, value: u32) {
    unsafe { cudaGraphSetConditional(handle, value) }
}
