//! The kernel-gradient correction's arguments (`sph::correction`: B_i⁻¹ of every sorted particle, before the pair
//! interaction that applies it).

use super::launch::{Grid, Pass, Span};
use super::table::entry_index;
use crate::neighbour::{GridParams, Neighbours};
use crate::real::Real;
use crate::sph::TensorOps;
use crate::sph::correction::{CorrectionArrays, correction};
use crate::sph::kernel::CubicSpline;
use crate::vector::Dim;
use core::marker::PhantomData;

/// Everything one launch of the correction reads and writes, all arrays in sorted order.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct CorrectionArgs<R: Real, D: Dim> {
    pub n: Span,
    /// Lanes per particle (1, 2, 4 or 8; `sph::lanes::clamp_lanes`), as the pair interaction's.
    pub lanes: u32,
    /// Blocks in reverse order (`ptx::ordered_index`; the GPU's only, no bit depends on it).
    pub reverse: u32,
    /// 1: correct only the particles with a neighbour across the cohesive path (`[stabilisation.cspm] scope =
    /// "path"`); 0: every particle.
    pub path_only: u32,
    pub kernel: CubicSpline<R>,
    /// The pair interaction's skip distance (`SphParams::min_r2`).
    pub min_r2: R,
    /// det B at or below which B⁻¹ is the identity (`[stabilisation.cspm] min_determinant`).
    pub min_det: R,
    pub grid: *const GridParams,
    pub starts: *const u32,
    /// The Verlet list of `grid`, or null: walk the stencil.
    pub list: *const u32,
    pub arrays: CorrectionArrays<R, D>,
    /// B_i⁻¹ of each particle.
    pub out: *mut D::Sym<R>,
}

impl<R: Real, D: Dim> CorrectionArgs<R, D> {
    /// The neighbour walk's view of the cell list.
    ///
    /// # Safety
    /// `grid` points at a live `GridParams`.
    #[inline(always)]
    pub unsafe fn neighbours(&self) -> Neighbours<'_> {
        Neighbours { grid: unsafe { &*self.grid }, starts: self.starts, list: self.list }
    }
}

/// The correction pass (`swarf_sph_correction_*`), `lanes` threads per particle on the GPU.
pub struct CorrectionPass<R, D>(PhantomData<(R, D)>);

impl<R: Real, D: TensorOps<R>> Pass for CorrectionPass<R, D> {
    type Args = CorrectionArgs<R, D>;
    const ENTRY: usize = entry_index("correction", D::D, size_of::<R>(), 0);
    const GRID: Grid = Grid::Pair;
    fn particles(a: &Self::Args) -> usize {
        a.n.n as usize
    }
    fn active(a: &Self::Args) -> *const u32 {
        a.n.active
    }
    fn lanes(a: &Self::Args) -> u32 {
        a.lanes
    }
    fn order(a: &mut Self::Args) -> Option<&mut u32> {
        Some(&mut a.reverse)
    }
    unsafe fn particle(a: &Self::Args, i: usize) -> u32 {
        unsafe {
            let nb = a.neighbours();
            *a.out.add(i) =
                correction::<R, D>(&a.kernel, a.min_r2, a.min_det, a.path_only != 0, &nb, &a.arrays, i as u32, a.lanes);
        }
        0
    }
}
