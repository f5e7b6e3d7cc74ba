//! Exclusive prefix sum of u32 over large arrays, in two passes per level (reduce, then scan with offsets):
//! each warp owns a tile of 1024 elements and walks it in 32 coalesced rounds of 32, carrying the running sum
//! in a register, so the scan needs neither shared memory nor block barriers. The host scans the tile sums
//! recursively with the same kernels. CPU twin: `swarf::backend::cpu::exclusive_scan`.

use super::intrinsics::{lane_id, shfl_idx, warp_inclusive_scan};
use super::neighbour::open;
use crate::pass::{ScanApplyArgs, ScanReduceArgs};
use core::arch::nvptx::*;

/// Elements per warp tile.
pub const TILE: u32 = 1024;

#[inline(always)]
fn warp_tile() -> u32 {
    unsafe { (_block_idx_x() * _block_dim_x() + _thread_idx_x()) / 32 }
}

/// Both passes take a gate (`ptx::neighbour::open`): a gated rebuild's scan runs only when its step rebuilds.
///
/// tile_sums[t] = Σ input[t·TILE .. (t+1)·TILE] (wrapping u32 arithmetic).
#[unsafe(no_mangle)]
pub unsafe extern "ptx-kernel" fn swarf_scan_reduce(args: ScanReduceArgs) {
    let ScanReduceArgs { gate, n, input, tile_sums } = args;
    let tile = warp_tile();
    let base = tile as u64 * TILE as u64;
    if base >= n as u64 || !unsafe { open(gate) } {
        return;
    }
    let lane = lane_id();
    let mut s = 0u32;
    let mut r = 0;
    while r < 32 {
        let i = base as u32 + r * 32 + lane;
        if i < n {
            s = s.wrapping_add(unsafe { *input.add(i as usize) });
        }
        r += 1;
    }
    let total = shfl_idx(warp_inclusive_scan(s), 31);
    if lane == 0 {
        unsafe { *tile_sums.add(tile as usize) = total };
    }
}

/// output[i] = tile_offsets[t] + Σ input[t·TILE .. i] (exclusive within the tile). `output` may alias `input`.
#[unsafe(no_mangle)]
pub unsafe extern "ptx-kernel" fn swarf_scan_apply(args: ScanApplyArgs) {
    let ScanApplyArgs { gate, n, input, output, tile_offsets } = args;
    let tile = warp_tile();
    let base = tile as u64 * TILE as u64;
    if base >= n as u64 || !unsafe { open(gate) } {
        return;
    }
    let lane = lane_id();
    // A null `tile_offsets` means one tile: its offset is 0.
    let mut carry = if tile_offsets.is_null() { 0 } else { unsafe { *tile_offsets.add(tile as usize) } };
    let mut r = 0;
    while r < 32 {
        let i = base as u32 + r * 32 + lane;
        let v = if i < n { unsafe { *input.add(i as usize) } } else { 0 };
        let inc = warp_inclusive_scan(v);
        if i < n {
            unsafe { *output.add(i as usize) = carry.wrapping_add(inc).wrapping_sub(v) };
        }
        carry = carry.wrapping_add(shfl_idx(inc, 31));
        r += 1;
    }
}
