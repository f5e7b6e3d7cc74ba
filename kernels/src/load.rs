//! Loads that stay where they are written. On the GPU a load placed under a branch waits for the branch's
//! condition; LLVM sinks a load into the block that uses it (InstCombine), which turns loads written together at
//! the head of a pair term back into a chain of dependent latencies (`sph::interact::Partner`). Through inline PTX
//! (which LLVM does not move) the loads issue where the source puts them; on the CPU this is a plain read. They
//! use the read-only data path (`ld.global.nc`): only for arrays that no thread writes during the kernel.

/// `*p`, issued here on the GPU (the module doc).
///
/// # Safety
/// As `*p`; on the GPU, `p` points to global memory that the running kernel does not write.
#[inline(always)]
pub unsafe fn read<T: Copy>(p: *const T) -> T {
    #[cfg(target_arch = "nvptx64")]
    unsafe {
        gpu::read(p)
    }
    #[cfg(not(target_arch = "nvptx64"))]
    unsafe {
        *p
    }
}

#[cfg(target_arch = "nvptx64")]
mod gpu {
    use core::arch::asm;
    use core::mem::{MaybeUninit, align_of, size_of};

    /// `*p` in 16-, 8- or 4-byte words as the type's size and alignment allow (a Pod value of floats and words).
    #[inline(always)]
    pub unsafe fn read<T: Copy>(p: *const T) -> T {
        let mut out = MaybeUninit::<T>::uninit();
        let (size, align) = (size_of::<T>(), align_of::<T>());
        unsafe {
            if align >= 16 && size % 16 == 0 {
                let (src, dst) = (p as *const u64, out.as_mut_ptr() as *mut u64);
                let mut k = 0;
                while k < size / 8 {
                    let (a, b) = ld_v2_b64(src.add(k));
                    *dst.add(k) = a;
                    *dst.add(k + 1) = b;
                    k += 2;
                }
            } else if align >= 8 && size % 8 == 0 {
                let (src, dst) = (p as *const u64, out.as_mut_ptr() as *mut u64);
                let mut k = 0;
                while k < size / 8 {
                    *dst.add(k) = ld_b64(src.add(k));
                    k += 1;
                }
            } else {
                // Every type read this way is a whole number of 4-byte words (f32, u32 and arrays of them).
                let (src, dst) = (p as *const u32, out.as_mut_ptr() as *mut u32);
                let mut k = 0;
                while k < size / 4 {
                    *dst.add(k) = ld_b32(src.add(k));
                    k += 1;
                }
            }
            out.assume_init()
        }
    }

    #[inline(always)]
    unsafe fn ld_v2_b64(p: *const u64) -> (u64, u64) {
        let (a, b): (u64, u64);
        unsafe {
            asm!("ld.global.nc.v2.b64 {{{a}, {b}}}, [{p}];", a = out(reg64) a, b = out(reg64) b, p = in(reg64) p,
                 options(readonly, nostack, preserves_flags))
        };
        (a, b)
    }

    #[inline(always)]
    unsafe fn ld_b64(p: *const u64) -> u64 {
        let a: u64;
        unsafe {
            asm!("ld.global.nc.b64 {a}, [{p}];", a = out(reg64) a, p = in(reg64) p,
                 options(readonly, nostack, preserves_flags))
        };
        a
    }

    #[inline(always)]
    unsafe fn ld_b32(p: *const u32) -> u32 {
        let a: u32;
        unsafe {
            asm!("ld.global.nc.b32 {a}, [{p}];", a = out(reg32) a, p = in(reg64) p,
                 options(readonly, nostack, preserves_flags))
        };
        a
    }
}
