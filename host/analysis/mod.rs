//! Analyses of particle states used by tests and reports.

pub mod neck;

use crate::backend::CpuBackend;
use crate::grid::{bounding_box, grid_with_cell};
use crate::kernels::neighbour::GridParams;
use crate::kernels::neighbour::search::for_each_neighbour;
use crate::kernels::vector::V3f64;
use crate::kernels::{Dim3, Real};
use crate::neighbour::CellList;
use crate::{Error, Result};

/// Number of connected components of each group (body) of particles, where two particles of the same group are
/// connected when closer than `radius`. Numerical fracture shows as a body splitting into several components
/// (roethlin-solver.md AT-68/AT-69). Positions are 3-vectors (z = 0 in 2D); the search reuses the cell list.
pub fn components_per_group(pos: &[[f64; 3]], group: &[u32], radius: f64) -> Result<Vec<usize>> {
    if pos.len() != group.len() {
        return Err(Error::Length { op: "components_per_group", expected: pos.len(), got: group.len() });
    }
    let n = pos.len();
    let groups = group.iter().copied().max().map_or(0, |g| g as usize + 1);
    if n == 0 {
        return Ok(vec![0; groups]);
    }
    // Union–find over original indices.
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(p: &mut [usize], mut a: usize) -> usize {
        while p[a] != a {
            p[a] = p[p[a]];
            a = p[a];
        }
        a
    }
    for_each_close_pair(pos, radius, |i, j, _| {
        if group[i] == group[j] {
            let (a, c) = (find(&mut parent, i), find(&mut parent, j));
            if a != c {
                parent[a] = c;
            }
        }
    })?;
    let mut roots = vec![Vec::new(); groups];
    for i in 0..n {
        let r = find(&mut parent, i);
        roots[group[i] as usize].push(r);
    }
    Ok(roots
        .into_iter()
        .map(|mut r| {
            r.sort_unstable();
            r.dedup();
            r.len()
        })
        .collect())
}

/// Widens a run's positions to f64 3-vectors.
pub fn positions_f64<R: Real, V: crate::kernels::Vector<R>>(pos: &[V]) -> Vec<[f64; 3]> {
    pos.iter().map(|p| std::array::from_fn(|k| p.get(k).to_f64())).collect()
}

/// Calls `f(i, j, r²)` once for every pair i ≠ j (indices into `pos`) closer than `radius`. The pairs are found by
/// the kernels' stencil walk (`kernels::neighbour::search::for_each_neighbour`) over the cell list, each from the
/// side of the particle that sorts first, without storing a neighbour list: both callers are symmetric in i and j,
/// and the two passes of a stored list at 2h took most of `swarf neck`'s 7–10 s per 522 000-particle 3D frame.
fn for_each_close_pair(pos: &[[f64; 3]], radius: f64, mut f: impl FnMut(usize, usize, f64)) -> Result<()> {
    if pos.is_empty() {
        return Ok(());
    }
    let b = CpuBackend::new();
    let p: Vec<V3f64> = pos.iter().map(|x| V3f64([x[0], x[1], x[2], 0.0])).collect();
    let (lo, hi, cell) = search_box(&p, GridParams::cell_for(radius, 2));
    let grid = grid_with_cell(lo, hi, 3, cell, 2)?;
    let mut cl = CellList::new(&b, grid, p.len())?;
    cl.build::<f64, Dim3>(&b, &p)?;
    let sorted: Vec<V3f64> = cl.perm.iter().map(|&i| p[i as usize]).collect();
    let support2 = radius * radius;
    for (s, a) in sorted.iter().enumerate() {
        // SAFETY: `starts` is the prefix array `cl.build` made for `cl.grid` over `sorted`.
        unsafe {
            for_each_neighbour::<f64, V3f64, _>(&cl.grid, cl.starts.as_ptr(), a, |t| {
                let t = t as usize;
                if t > s {
                    // The grid has no period: dist2 is Σ (a_k − c_k)², summed x, y, z.
                    let r2 = cl.grid.dist2::<f64, V3f64>(a, &sorted[t]);
                    if r2 < support2 {
                        f(cl.perm[s] as usize, cl.perm[t] as usize, r2);
                    }
                }
            })
        };
    }
    Ok(())
}

/// Cells per point above which the pair search's grid is bounded ([`search_box`]).
const CELLS_PER_POINT: f64 = 64.0;

/// Cells of a grid of cell `cell` over the box `lo`..`hi`.
fn cell_count(lo: &[f64; 3], hi: &[f64; 3], cell: f64) -> f64 {
    (0..3).map(|k| ((hi[k] - lo[k]) / cell).floor() + 1.0).product()
}

/// The box and cell of the pair search over `p` with cells of at least `cell`: the bounding box of the finite
/// positions, unless that would take more than [`CELLS_PER_POINT`] cells per point (and a million): then, per axis,
/// the range between the `f` and 1 − `f` quantiles of the positions for the smallest `f` of 0.1 %, 1 %, 5 % and 25 %
/// that fits, its cell grown where none does. Particles outside the box are clamped into its boundary cells, which
/// keeps the search exact (docs/neighbour-search.md). An unstable run ejects a few particles far from the rest, and
/// the bounding box alone then made every output step build a grid of billions of cells: the multi-grain runs at
/// CFL 0.5 stopped answering (issue 24; tests/stability_solids.rs, `ejected_particles_do_not_blow_up_the_contact_search`).
fn search_box(p: &[V3f64], cell: f64) -> ([f64; 3], [f64; 3], f64) {
    let budget = CELLS_PER_POINT * p.len() as f64 + f64::from(1u32 << 20);
    let (lo, hi) = bounding_box::<f64, V3f64>(p);
    if cell_count(&lo, &hi, cell) <= budget {
        return (lo, hi, cell);
    }
    let mut axes: Vec<Vec<f64>> =
        (0..3).map(|k| p.iter().map(|x| x.0[k]).filter(|x| x.is_finite()).collect()).collect();
    for a in &mut axes {
        a.sort_unstable_by(f64::total_cmp);
    }
    let mut last = (lo, hi);
    for f in [1e-3, 1e-2, 5e-2, 0.25] {
        let q = |a: &Vec<f64>, t: f64| a[((t * (a.len() - 1) as f64).round() as usize).min(a.len() - 1)];
        let l: [f64; 3] = std::array::from_fn(|k| q(&axes[k], f));
        let h: [f64; 3] = std::array::from_fn(|k| q(&axes[k], 1.0 - f));
        last = (l, h);
        if cell_count(&l, &h, cell) <= budget {
            return (l, h, cell);
        }
    }
    let (l, h) = last;
    (l, h, cell * (cell_count(&l, &h, cell) / budget).cbrt())
}

/// The closest pair of particles that started apart (see [`min_pair_distances`]): where the contact is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosestPair {
    /// Their distance.
    pub distance: f64,
    /// Their stable ids (`HostParticles::id`), the smaller first.
    pub ids: [u32; 2],
    /// The midpoint of the two (z = 0 in 2D): locates the contact (tool face, chip back, fixed boundary, ...).
    pub midpoint: [f64; 3],
}

/// The smallest distances between two distinct particles among those with `include[i]`, searched within
/// `radius` (None when no two included particles are that close), in one pass:
/// - over all pairs: pairing and interpenetration show as pairs far closer than the lattice spacing;
/// - over the pairs that started at least `radius` apart (`initial`: every particle's position at t = 0, in the
///   order of `pos`): the closest approach of material that was not in contact at the start, i.e. a chip touching
///   itself, the workpiece or another body (issue 8, chip self-contact), with the pair's ids (`id`, in the order
///   of `pos`) and midpoint so that the output says where. Equal distances go to the smaller ids, so the pair
///   does not depend on the particles' order or the search's.
pub fn min_pair_distances(
    pos: &[[f64; 3]],
    include: &[bool],
    radius: f64,
    initial: &[[f64; 3]],
    id: &[u32],
) -> Result<(Option<f64>, Option<ClosestPair>)> {
    for (op, got) in [
        ("min_pair_distances: include", include.len()),
        ("min_pair_distances: initial", initial.len()),
        ("min_pair_distances: id", id.len()),
    ] {
        if got != pos.len() {
            return Err(Error::Length { op, expected: pos.len(), got });
        }
    }
    let idx: Vec<usize> = (0..pos.len()).filter(|&i| include[i]).collect();
    let p: Vec<[f64; 3]> = idx.iter().map(|&i| pos[i]).collect();
    let d2 = |a: &[f64; 3], c: &[f64; 3]| (a[0] - c[0]).powi(2) + (a[1] - c[1]).powi(2) + (a[2] - c[2]).powi(2);
    let mut all = f64::INFINITY;
    // (r², ids, index into pos of each) of the closest pair that started apart.
    let mut apart: Option<(f64, [u32; 2], [usize; 2])> = None;
    for_each_close_pair(&p, radius, |i, j, r2| {
        all = all.min(r2);
        let (a, c) = (idx[i], idx[j]);
        if d2(&initial[a], &initial[c]) >= radius * radius {
            let (ids, at) = if id[a] <= id[c] { ([id[a], id[c]], [a, c]) } else { ([id[c], id[a]], [c, a]) };
            if apart.is_none_or(|(best, best_ids, _)| (r2, ids) < (best, best_ids)) {
                apart = Some((r2, ids, at));
            }
        }
    })?;
    let closest = apart.map(|(r2, ids, [a, c])| ClosestPair {
        distance: r2.sqrt(),
        ids,
        midpoint: std::array::from_fn(|k| 0.5 * (pos[a][k] + pos[c][k])),
    });
    Ok((all.is_finite().then(|| all.sqrt()), closest))
}
