//! Analyses of particle states used by tests and reports.

use crate::backend::CpuBackend;
use crate::grid::{bounding_box, grid_for_support};
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

/// Calls `f(i, j, r²)` for every ordered pair of distinct particles closer than `radius` (indices into `pos`),
/// found through the cell list.
fn for_each_close_pair(pos: &[[f64; 3]], radius: f64, mut f: impl FnMut(usize, usize, f64)) -> Result<()> {
    if pos.is_empty() {
        return Ok(());
    }
    let b = CpuBackend::new();
    let p: Vec<V3f64> = pos.iter().map(|x| V3f64([x[0], x[1], x[2], 0.0])).collect();
    let (lo, hi) = bounding_box::<f64, V3f64>(&p);
    let grid = grid_for_support(lo, hi, 3, radius, 2)?;
    let mut cl = CellList::new(&b, grid, p.len())?;
    cl.build::<f64, Dim3>(&b, &p)?;
    let sorted: Vec<V3f64> = cl.perm.iter().map(|&i| p[i as usize]).collect();
    let (_, off, list) = cl.csr_neighbours::<f64, Dim3>(&b, &sorted, radius * radius)?;
    for s in 0..sorted.len() {
        for &t in &list[off[s] as usize..off[s + 1] as usize] {
            let (a, c) = (sorted[s].0, sorted[t as usize].0);
            let r2 = (a[0] - c[0]).powi(2) + (a[1] - c[1]).powi(2) + (a[2] - c[2]).powi(2);
            f(cl.perm[s] as usize, cl.perm[t as usize] as usize, r2);
        }
    }
    Ok(())
}

/// The smallest distances between two distinct particles among those with `include[i]`, searched within
/// `radius` (None when no two included particles are that close), in one pass:
/// - over all pairs: pairing and interpenetration show as pairs far closer than the lattice spacing;
/// - over the pairs that started at least `radius` apart (`initial`: every particle's position at t = 0, in the
///   order of `pos`): the closest approach of material that was not in contact at the start, i.e. a chip touching
///   itself, the workpiece or another body (issue 8, chip self-contact).
pub fn min_pair_distances(
    pos: &[[f64; 3]],
    include: &[bool],
    radius: f64,
    initial: &[[f64; 3]],
) -> Result<(Option<f64>, Option<f64>)> {
    if pos.len() != include.len() || initial.len() != pos.len() {
        return Err(Error::Length { op: "min_pair_distances", expected: pos.len(), got: include.len() });
    }
    let idx: Vec<usize> = (0..pos.len()).filter(|&i| include[i]).collect();
    let p: Vec<[f64; 3]> = idx.iter().map(|&i| pos[i]).collect();
    let d2 = |a: &[f64; 3], c: &[f64; 3]| (a[0] - c[0]).powi(2) + (a[1] - c[1]).powi(2) + (a[2] - c[2]).powi(2);
    let (mut all, mut apart) = (f64::INFINITY, f64::INFINITY);
    for_each_close_pair(&p, radius, |i, j, r2| {
        all = all.min(r2);
        if d2(&initial[idx[i]], &initial[idx[j]]) >= radius * radius {
            apart = apart.min(r2);
        }
    })?;
    let root = |x: f64| x.is_finite().then(|| x.sqrt());
    Ok((root(all), root(apart)))
}
