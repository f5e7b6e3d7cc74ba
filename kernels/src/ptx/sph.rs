//! SPH entry points.

use super::global_index;
use crate::neighbour::GridParams;
use crate::real::Real;
use crate::sph::CubicSpline;
use crate::sph::density::density_sum;
use crate::vector::{V2f32, V2f64, V3f32, V3f64, Vector};

#[inline(always)]
unsafe fn density<R: Real, V: Vector<R>>(
    n: u32,
    pos: *const V,
    mass: *const R,
    grid: *const GridParams,
    starts: *const u32,
    kernel: *const CubicSpline<R>,
    rho: *mut R,
) {
    let i = global_index();
    if i < n {
        unsafe {
            let r = density_sum::<R, V>(&*grid, starts, &*kernel, pos, mass, i);
            *rho.add(i as usize) = r;
        }
    }
}

macro_rules! density_entry {
    ($name:ident, $r:ty, $v:ty) => {
        /// rho[i] = Σ_j m_j W(|x_i − x_j|) (sph::density::density_sum).
        #[unsafe(no_mangle)]
        pub unsafe extern "ptx-kernel" fn $name(
            n: u32,
            pos: *const $v,
            mass: *const $r,
            grid: *const GridParams,
            starts: *const u32,
            kernel: *const CubicSpline<$r>,
            rho: *mut $r,
        ) {
            unsafe { density::<$r, $v>(n, pos, mass, grid, starts, kernel, rho) }
        }
    };
}

density_entry!(swarf_density_2d_f32, f32, V2f32);
density_entry!(swarf_density_2d_f64, f64, V2f64);
density_entry!(swarf_density_3d_f32, f32, V3f32);
density_entry!(swarf_density_3d_f64, f64, V3f64);
