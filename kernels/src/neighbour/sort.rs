//! The one piece of the counting sort that is per-cell work: after the GPU scatters particle indices into their
//! cells in an arbitrary (atomic) order, each cell's slice is sorted ascending. The result equals a stable sort
//! of the particles by key, so it is unique and the host's sequential counting sort produces the same
//! permutation (the GPU-against-CPU check compares them exactly).

/// Sorts `v[a..b]` ascending in place (insertion sort: cells hold a handful of particles).
///
/// # Safety
/// `a <= b` and `v[a..b]` must be valid for reads and writes.
#[inline(always)]
pub unsafe fn sort_cell(v: *mut u32, a: u32, b: u32) {
    let mut i = a + 1;
    while i < b {
        let x = unsafe { *v.add(i as usize) };
        let mut j = i;
        while j > a {
            let y = unsafe { *v.add((j - 1) as usize) };
            if y <= x {
                break;
            }
            unsafe { *v.add(j as usize) = y };
            j -= 1;
        }
        unsafe { *v.add(j as usize) = x };
        i += 1;
    }
}
