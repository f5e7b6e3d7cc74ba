//! swarf's physics, written once: plain `#[inline]` functions over plain data, compiled for the host (the CPU
//! backend calls them in loops) and to PTX (the entry points in `ptx/` are thin wrappers around the same
//! functions). Nothing here may panic: on nvptx a panic leaves an unresolved `.extern` symbol that the driver
//! refuses (../shared/GPU.md, "Rules for kernel code"), so indexing is bounds-checked explicitly by the callers
//! and done with unchecked accessors.
#![no_std]
// Index loops over fixed-size arrays mirror the tensor index notation of the equations they implement.
#![allow(clippy::needless_range_loop)]
#![cfg_attr(target_arch = "nvptx64", feature(abi_ptx, stdarch_nvptx, core_float_math, asm_experimental_arch))]

pub mod cohesive;
pub mod contact;
pub mod damage;
pub mod load;
pub mod material;
pub mod mpm;
pub mod neighbour;
pub mod pass;
pub mod real;
pub mod sph;
pub mod vector;

#[cfg(target_arch = "nvptx64")]
pub mod ptx;

pub use real::Real;
pub use vector::{Dim, Dim2, Dim3, SymTensor, Vector};

#[cfg(target_arch = "nvptx64")]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    // Unreachable by construction; `trap` aborts the kernel and surfaces as a launch error on the host.
    unsafe { core::arch::nvptx::trap() }
}
