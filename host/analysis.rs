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
    let b = CpuBackend::new();
    let p: Vec<V3f64> = pos.iter().map(|x| V3f64([x[0], x[1], x[2], 0.0])).collect();
    let (lo, hi) = bounding_box::<f64, V3f64>(&p);
    let grid = grid_for_support(lo, hi, 3, radius, 2)?;
    let mut cl = CellList::new(&b, grid, n)?;
    cl.build::<f64, Dim3>(&b, &p)?;
    let sorted: Vec<V3f64> = cl.perm.iter().map(|&i| p[i as usize]).collect();
    let (_, off, list) = cl.csr_neighbours::<f64, Dim3>(&b, &sorted, radius * radius)?;
    // Union–find over original indices.
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(p: &mut [usize], mut a: usize) -> usize {
        while p[a] != a {
            p[a] = p[p[a]];
            a = p[a];
        }
        a
    }
    for s in 0..n {
        let i = cl.perm[s] as usize;
        for &t in &list[off[s] as usize..off[s + 1] as usize] {
            let j = cl.perm[t as usize] as usize;
            if group[i] == group[j] {
                let (a, c) = (find(&mut parent, i), find(&mut parent, j));
                if a != c {
                    parent[a] = c;
                }
            }
        }
    }
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

/// The smallest distance between two distinct particles among those with `include[i]`, searched within `radius`
/// (None when no two included particles are that close). Interpenetration of a chip curling onto itself or onto
/// the workpiece shows as pairs far closer than the lattice spacing (issue 8).
///
/// With `initial` (every particle's position at t = 0, in the same order as `pos`), only pairs that started at
/// least `radius` apart count: the closest approach of material that was not in contact at the start, i.e. a chip
/// touching itself, the workpiece or another body (issue 8, chip self-contact).
pub fn min_pair_distance(
    pos: &[[f64; 3]],
    include: &[bool],
    radius: f64,
    initial: Option<&[[f64; 3]]>,
) -> Result<Option<f64>> {
    if pos.len() != include.len() || initial.is_some_and(|p| p.len() != pos.len()) {
        return Err(Error::Length { op: "min_pair_distance", expected: pos.len(), got: include.len() });
    }
    let idx: Vec<usize> = (0..pos.len()).filter(|&i| include[i]).collect();
    let p: Vec<V3f64> = idx.iter().map(|&i| V3f64([pos[i][0], pos[i][1], pos[i][2], 0.0])).collect();
    if p.len() < 2 {
        return Ok(None);
    }
    let b = CpuBackend::new();
    let (lo, hi) = bounding_box::<f64, V3f64>(&p);
    let grid = grid_for_support(lo, hi, 3, radius, 2)?;
    let mut cl = CellList::new(&b, grid, p.len())?;
    cl.build::<f64, Dim3>(&b, &p)?;
    let sorted: Vec<V3f64> = cl.perm.iter().map(|&i| p[i as usize]).collect();
    let (_, off, list) = cl.csr_neighbours::<f64, Dim3>(&b, &sorted, radius * radius)?;
    let d2 = |a: &[f64; 3], c: &[f64; 3]| (a[0] - c[0]).powi(2) + (a[1] - c[1]).powi(2) + (a[2] - c[2]).powi(2);
    let mut best = f64::INFINITY;
    for i in 0..sorted.len() {
        for &j in &list[off[i] as usize..off[i + 1] as usize] {
            if let Some(init) = initial {
                let (oi, oj) = (idx[cl.perm[i] as usize], idx[cl.perm[j as usize] as usize]);
                if d2(&init[oi], &init[oj]) < radius * radius {
                    continue;
                }
            }
            let (a, c) = (sorted[i].0, sorted[j as usize].0);
            best = best.min(d2(&[a[0], a[1], a[2]], &[c[0], c[1], c[2]]));
        }
    }
    Ok(best.is_finite().then(|| best.sqrt()))
}
