//! Density by summation, ρ_i = Σ_j m_j W(|x_i − x_j|, h), self-contribution included (roethlin-solver.md §3.1,
//! (4.12) with f = ρ). The solver evolves ρ by the continuity equation; this sum is the simplest full pass over
//! the neighbours and serves as the workload that measures the neighbour-search layouts (cell h or 2h).

use super::kernel::CubicSpline;
use crate::neighbour::{GridParams, for_each_neighbour};
use crate::real::Real;
use crate::vector::Vector;

/// # Safety
/// `pos` and `mass` hold the sorted particles, `i` is in range and `starts` belongs to `grid`.
#[inline(always)]
pub unsafe fn density_sum<R: Real, V: Vector<R>>(
    grid: &GridParams,
    starts: *const u32,
    kernel: &CubicSpline<R>,
    pos: *const V,
    mass: *const R,
    i: u32,
) -> R {
    let pi = unsafe { *pos.add(i as usize) };
    let mut rho = R::ZERO;
    unsafe {
        for_each_neighbour::<R, V, _>(grid, starts, &pi, |j| {
            let d2 = grid.dist2::<R, V>(&pi, &*pos.add(j as usize));
            if d2 < kernel.support2 {
                rho += *mass.add(j as usize) * kernel.w(d2.sqrt());
            }
        })
    };
    rho
}
