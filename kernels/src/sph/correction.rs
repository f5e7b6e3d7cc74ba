//! The Randles–Libersky kernel-gradient correction, which the thesis calls CSPM (roethlin-solver.md §3.2, Eqs.
//! 4.46–4.48 and 4.53–4.57; [C3D] `interactions_gpu.cu` under `#define CSPM`):
//!   B_i = Σ_j V_j (x_j − x_i) ⊗ ∇_i W_ij = −Σ_j V_j W'(r)/r x_ij ⊗ x_ij,
//! symmetric, the identity on an interior lattice, and ∇W̃_ij = B_i⁻¹ ∇W_ij, with which the difference gradient
//! Σ_j V_j (f_j − f_i) ⊗ ∇W̃_ij is exact for every linear f (acceptance test AT-04). The pair interaction then uses
//! ∇W̃ in every gradient term (velocity gradient, momentum, viscosity), as [C3D] does; W itself (XSPH, the
//! artificial stress's f_ij) and the conduction stay uncorrected. Corrected gradients give up ∇W̃_ij = −∇W̃_ji, so
//! linear momentum is no longer conserved exactly; in exchange a rigid rotation keeps its angular momentum
//! (AT-63), which the uncorrected scheme reverses (AT-64).
//!
//! Only mechanical neighbours enter B (the tool's thermal-only particles have no mechanical mass), as in [C3D].
//! Across a cohesive path (`interact::cut_apart`) no pair enters B either: each face's rows are corrected over
//! their own side, as the `_cspm_cut` interaction then uses them (docs/mpm.md, "CSPM on the faces").
//! Where det B ≤ `min_det` (a particle with too few neighbours, or neighbours on a line), B⁻¹ is the identity:
//! the uncorrected gradient ([C3D]: det B > 1e-8).
//!
//! With `path_only` the correction acts only where the path truncates the kernel: a particle with no neighbour
//! across the path within its support keeps B⁻¹ = I (the plain gradient), so that the bulk and the free surfaces
//! run the uncorrected scheme and only the faces' rows within 2h of the path are corrected (docs/mpm.md, "CSPM on
//! the path's faces only"). The faces are then as stiff as the continuum they were cut from, and the corrected
//! scheme's loss of pair antisymmetry stays in those rows.

use super::interact::cut_apart;
use super::lanes::{LaneSum, all_lanes, lane_share, map_real};
use super::params::flags;
use super::tensor::TensorOps;
use crate::load::read;
use crate::neighbour::Neighbours;
use crate::neighbour::grid::{Period, unswitch_period};
use crate::real::Real;
use crate::sph::kernel::CubicSpline;
use crate::vector::{Dim, SymTensor, Vector};

/// What the correction reads, in sorted order.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct CorrectionArrays<R: Real, D: Dim> {
    pub pos: *const D::Vec<R>,
    /// Mechanical masses (zero for the tool's thermal-only particles, which take no part).
    pub mass: *const R,
    /// V = m/ρ of the pre-pass.
    pub vol: *const R,
    pub flags: *const u32,
}

/// The pair sum of B (or one lane's share of it).
#[derive(Clone, Copy, Default)]
pub struct CorrectionSum<R: Real, D: Dim> {
    pub b: D::Sym<R>,
    /// The neighbours across the cohesive path within the support (a small whole number: exact in either real).
    pub cut: R,
}

impl<R: Real, D: Dim> LaneSum for CorrectionSum<R, D> {
    #[inline(always)]
    fn add(&self, o: &Self) -> Self {
        let mut out = *self;
        for (a, b) in out.b.components_mut().iter_mut().zip(o.b.components()) {
            *a += *b;
        }
        out.cut += o.cut;
        out
    }
    #[inline(always)]
    fn map_words<F: FnMut(u32) -> u32>(&self, f: &mut F) -> Self {
        let mut out = *self;
        for a in out.b.components_mut() {
            *a = map_real(*a, f);
        }
        out.cut = map_real(out.cut, f);
        out
    }
}

/// Adds pair (i, j)'s term −V_j W'(r)/r x_ij ⊗ x_ij to `s` (nothing for j = i, beyond the support, closer than
/// the skip distance `min_r2`, or a massless j). A j across the cohesive path from i (whose side is `side_i`)
/// adds no term; with `count_cut` (`scope = "path"`) it is counted in `s.cut` when within the support, otherwise it
/// is left before its data are read, as it was before the count existed.
///
/// # Safety
/// The arrays of `a` hold j + 1 elements.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
unsafe fn add_pair<R: Real, D: TensorOps<R>, const PER: bool>(
    k: &CubicSpline<R>,
    min_r2: R,
    per: &Period<R>,
    a: &CorrectionArrays<R, D>,
    xi: &D::Vec<R>,
    side_i: u32,
    count_cut: bool,
    i: u32,
    j: u32,
    s: &mut CorrectionSum<R, D>,
) {
    let ju = j as usize;
    // A particle off the path (side 0) is never cut apart: only a sided i reads j's flags.
    let across = side_i != 0 && cut_apart(side_i, unsafe { read(a.flags.add(ju)) } & flags::CUT_MASK);
    if across && !count_cut {
        return;
    }
    let (xj, m, v) = unsafe { (read(a.pos.add(ju)), read(a.mass.add(ju)), read(a.vol.add(ju))) };
    let xij = if PER {
        per.displacement(xi, &xj)
    } else {
        D::Vec::<R>::new([xi.get(0) - xj.get(0), xi.get(1) - xj.get(1), xi.get(2) - xj.get(2)])
    };
    let mut r2 = xij.get(0) * xij.get(0) + xij.get(1) * xij.get(1);
    if D::D == 3 {
        r2 += xij.get(2) * xij.get(2);
    }
    if j == i || r2 >= k.support2 || r2 < min_r2 || m == R::ZERO {
        return;
    }
    if across {
        s.cut += R::ONE;
        return;
    }
    D::sym_outer_add(&mut s.b, -(v * k.dw_dr_over_r(r2.sqrt())), &xij);
}

/// Whether sorted particle i gets a correction (the tool's thermal-only particles do not: their mechanical rates
/// are discarded).
///
/// # Safety
/// `a.flags` holds i + 1 elements.
#[inline(always)]
unsafe fn corrected<R: Real, D: Dim>(a: &CorrectionArrays<R, D>, i: u32) -> bool {
    unsafe { *a.flags.add(i as usize) & flags::THERMAL_ONLY == 0 }
}

/// Lane `lane` of `lanes`' share of B of sorted particle i (the GPU's threads; `sph::lanes`).
///
/// # Safety
/// The arrays hold the sorted particles of the cell list (and Verlet list) `nb`; i is in range.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub unsafe fn correction_share<R: Real, D: TensorOps<R>>(
    k: &CubicSpline<R>,
    min_r2: R,
    path_only: bool,
    nb: &Neighbours,
    a: &CorrectionArrays<R, D>,
    i: u32,
    lane: u32,
    lanes: u32,
) -> CorrectionSum<R, D> {
    unsafe {
        if !corrected(a, i) {
            return CorrectionSum::default();
        }
        let (xi, side) = (*a.pos.add(i as usize), *a.flags.add(i as usize) & flags::CUT_MASK);
        let per = Period::<R>::of::<D>(nb.grid);
        unswitch_period!(per, PER =>
            lane_share::<R, D::Vec<R>, _, _>(nb, &xi, i, lane, lanes, |j, s| {
                add_pair::<R, D, PER>(k, min_r2, &per, a, &xi, side, path_only, i, j, s)
            })
        )
    }
}

/// B_i⁻¹ from the lanes' combined sum: the identity where det B ≤ `min_det`, which includes a thermal-only
/// particle (its sum is zero), and, with `path_only`, where no neighbour lies across the path.
#[inline(always)]
pub fn correction_finish<R: Real, D: TensorOps<R>>(s: &CorrectionSum<R, D>, min_det: R, path_only: bool) -> D::Sym<R> {
    if path_only && s.cut == R::ZERO {
        // det 0 ≤ min_det (≥ 0): the identity, by the same function as every other uncorrected particle.
        return D::sym_inverse_or_identity(&CorrectionSum::<R, D>::default().b, min_det);
    }
    D::sym_inverse_or_identity(&s.b, min_det)
}

/// B_i⁻¹ of sorted particle i, summed by `lanes` lanes combined as the GPU combines them.
///
/// # Safety
/// As [`correction_share`].
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub unsafe fn correction<R: Real, D: TensorOps<R>>(
    k: &CubicSpline<R>,
    min_r2: R,
    min_det: R,
    path_only: bool,
    nb: &Neighbours,
    a: &CorrectionArrays<R, D>,
    i: u32,
    lanes: u32,
) -> D::Sym<R> {
    unsafe {
        let s = if !corrected(a, i) {
            CorrectionSum::default()
        } else {
            let (xi, side) = (*a.pos.add(i as usize), *a.flags.add(i as usize) & flags::CUT_MASK);
            let per = Period::<R>::of::<D>(nb.grid);
            unswitch_period!(per, PER =>
                all_lanes::<R, D::Vec<R>, _, _>(nb, &xi, i, lanes, |j, s| {
                    add_pair::<R, D, PER>(k, min_r2, &per, a, &xi, side, path_only, i, j, s)
                })
            )
        };
        correction_finish(&s, min_det, path_only)
    }
}
