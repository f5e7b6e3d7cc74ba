//! The neighbour gather shared by both backends: visit every particle of the (2s+1)^d stencil cells around a
//! particle's cell, in a fixed order (z, then y, then the contiguous run of x cells), so that sums over
//! neighbours are evaluated in the same order on the host and the GPU.

use super::grid::GridParams;
use crate::real::Real;
use crate::vector::Vector;

/// Calls `f(a, b)` for each row of the (2s+1)^d stencil cells around position `p`, in a fixed order (z, then y):
/// the cells x0..=x1 of one row are consecutive keys, so their particles are the one contiguous range a..b.
/// `starts` is the prefix array of the sorted keys: cell `c` holds particles `starts[c] .. starts[c + 1]`; it has
/// `n_cells + 2` entries (the last bucket is the void bucket). A non-finite position has no rows.
///
/// # Safety
/// `starts` must be the cell prefix array built for `grid` (length `n_cells + 2`, non-decreasing).
#[inline(always)]
pub unsafe fn for_each_row<R: Real, V: Vector<R>, F: FnMut(u32, u32)>(
    grid: &GridParams,
    starts: *const u32,
    p: &V,
    mut f: F,
) {
    let c = grid.coords::<R, V>(p);
    if c[0] == u32::MAX {
        return; // a non-finite particle has no neighbours
    }
    let s = grid.stencil;
    let [nx, ny, nz] = grid.dims;
    let x0 = c[0].saturating_sub(s);
    let x1 = if c[0] + s < nx { c[0] + s } else { nx - 1 };
    let y0 = c[1].saturating_sub(s);
    let y1 = if c[1] + s < ny { c[1] + s } else { ny - 1 };
    // Periodic in z: the 2s + 1 rows c − s ..= c + s modulo nz (distinct: the host keeps nz ≥ 2s + 1).
    let wrap = V::DIM == 3 && grid.period > 0.0;
    let (z0, z1) = if wrap {
        (c[2] + nz - s, c[2] + nz + s)
    } else if V::DIM == 3 {
        (c[2].saturating_sub(s), if c[2] + s < nz { c[2] + s } else { nz - 1 })
    } else {
        (0, 0)
    };
    let mut zw = z0;
    while zw <= z1 {
        // zw < c + nz + s < 3 nz: at most two subtractions, no division (no panic path on the GPU).
        let z = if !wrap {
            zw
        } else if zw >= 2 * nz {
            zw - 2 * nz
        } else if zw >= nz {
            zw - nz
        } else {
            zw
        };
        let mut y = y0;
        while y <= y1 {
            let row = (z * ny + y) * nx;
            let (a, b) = unsafe { (*starts.add((row + x0) as usize), *starts.add((row + x1 + 1) as usize)) };
            f(a, b);
            y += 1;
        }
        zw += 1;
    }
}

/// Calls `f(j)` for every sorted particle `j` in the stencil of cells around position `p` (including the
/// particle itself if it is in `pos`), in the order of [`for_each_row`], so that sums over neighbours are
/// evaluated in the same order on the host and the GPU.
///
/// # Safety
/// As [`for_each_row`].
#[inline(always)]
pub unsafe fn for_each_neighbour<R: Real, V: Vector<R>, F: FnMut(u32)>(
    grid: &GridParams,
    starts: *const u32,
    p: &V,
    mut f: F,
) {
    unsafe {
        for_each_row::<R, V, _>(grid, starts, p, |a, b| {
            let mut j = a;
            while j < b {
                f(j);
                j += 1;
            }
        })
    }
}

/// Writes the neighbours j ≠ i of sorted particle i with |x_ij|² < support2 to `list[offsets[i]..]`, in gather
/// order, and returns their count. With `offsets` null the neighbours are only counted (first pass of a CSR
/// build); the caller sizes `list` from the scanned counts.
///
/// # Safety
/// `pos` holds the sorted particles, `i` is in range, `starts` belongs to `grid`, and with `offsets` non-null
/// `list` has room for the counts of the first pass.
#[inline(always)]
pub unsafe fn neighbour_row<R: Real, V: Vector<R>>(
    grid: &GridParams,
    starts: *const u32,
    pos: *const V,
    i: u32,
    support2: R,
    offsets: *const u32,
    list: *mut u32,
) -> u32 {
    let pi = unsafe { *pos.add(i as usize) };
    let out =
        if offsets.is_null() { core::ptr::null_mut() } else { unsafe { list.add(*offsets.add(i as usize) as usize) } };
    let mut c = 0u32;
    unsafe {
        for_each_neighbour::<R, V, _>(grid, starts, &pi, |j| {
            if j != i && grid.dist2::<R, V>(&pi, &*pos.add(j as usize)) < support2 {
                if !out.is_null() {
                    *out.add(c as usize) = j;
                }
                c += 1;
            }
        })
    };
    c
}

/// Calls `f(j)` for the share of `lane` (of `lanes`) of the candidates [`for_each_neighbour`] visits: the
/// candidates numbered k ≡ lane (mod lanes) in that visiting order, in increasing k. The lanes together visit
/// every candidate once, in balanced shares, so that `lanes` threads can sum over one particle's neighbours;
/// with `lanes` = 1 this is `for_each_neighbour`.
///
/// # Safety
/// As [`for_each_neighbour`]; `lane < lanes`.
#[inline(always)]
pub unsafe fn for_each_neighbour_strided<R: Real, V: Vector<R>, F: FnMut(u32)>(
    grid: &GridParams,
    starts: *const u32,
    p: &V,
    lane: u32,
    lanes: u32,
    mut f: F,
) {
    if lanes == 0 {
        return;
    }
    // `skip`: how many candidates of the next row precede this lane's first one.
    let mut skip = lane;
    unsafe {
        for_each_row::<R, V, _>(grid, starts, p, |a, b| {
            let len = b - a;
            if skip >= len {
                skip -= len;
            } else {
                let mut j = a + skip;
                while j < b {
                    f(j);
                    j += lanes;
                }
                // j − b candidates of the next row belong to earlier lanes' turns before ours.
                skip = j - b;
            }
        })
    }
}
