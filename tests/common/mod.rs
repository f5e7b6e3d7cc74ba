//! Helpers shared by the tests: particle sets and the grid-free brute-force reference of the neighbour-search
//! tests (CPU and GPU) here; test folders, scenes, MPM fragments and the synthetic chip station in submodules.
#![allow(dead_code)]

pub mod files;
pub mod mpm_fragment;
pub mod scenes;
pub mod station;

use rayon::prelude::*;
use swarf::backend::Backend;
use swarf::kernels::neighbour::GridParams;
use swarf::kernels::{Dim, Real, Vector};
use swarf::neighbour::CellList;
use swarf::rng::SplitMix64;
use swarf::state::{HostParticles, Particles};

/// Uniform random in the unit box; spacing ≈ N^(-1/d).
pub fn uniform<R: Real, D: Dim>(n: usize, seed: u64) -> Vec<D::Vec<R>> {
    let mut rng = SplitMix64::new(seed);
    (0..n).map(|_| D::Vec::<R>::new(std::array::from_fn(|_| R::from_f64(rng.uniform())))).collect()
}

/// 30 Gaussian clusters of very different widths plus a 10 % uniform background: dense cells with hundreds of
/// particles next to empty ones.
pub fn clustered<R: Real, D: Dim>(n: usize, seed: u64) -> Vec<D::Vec<R>> {
    let mut rng = SplitMix64::new(seed);
    let centres: Vec<([f64; 3], f64)> =
        (0..30).map(|k| (std::array::from_fn(|_| 0.2 + 0.6 * rng.uniform()), 0.004 * (1.0 + k as f64))).collect();
    (0..n)
        .map(|_| {
            if rng.uniform() < 0.1 {
                D::Vec::<R>::new(std::array::from_fn(|_| R::from_f64(rng.uniform())))
            } else {
                let (c, s) = centres[(rng.next_u64() % 30) as usize];
                D::Vec::<R>::new(std::array::from_fn(|k| R::from_f64(c[k] + s * rng.normal())))
            }
        })
        .collect()
}

/// A lattice of spacing `dx` from the origin, shuffled.
pub fn lattice<R: Real, D: Dim>(per_side: usize, dx: f64, seed: u64) -> Vec<D::Vec<R>> {
    let n = per_side.pow(D::D as u32);
    let mut v: Vec<D::Vec<R>> = (0..n)
        .map(|i| {
            let idx = [i % per_side, (i / per_side) % per_side, i / (per_side * per_side)];
            D::Vec::<R>::new(std::array::from_fn(|k| R::from_f64(idx[k] as f64 * dx)))
        })
        .collect();
    SplitMix64::new(seed).shuffle(&mut v);
    v
}

/// Sorted neighbour lists (j ≠ i with |x_ij|² < support2, evaluated exactly as the kernels do, `Vector::dist2`),
/// found without the cell list: strips in x, swept on y. The finite particles go into strips of width w = 1.01·s
/// (s = √support2, in f64) by ⌊(x − x_min)/w⌋, each strip sorted by y; a particle tests its own and the two
/// adjacent strips, from its y outwards until fl(Δy)² ≥ support2. Nothing is lost: a pair within the support has
/// fl(Δx)² ≤ dist2 < support2, so |Δx| < s and the two strip indices differ by at most one (the 1 % margin is far
/// above the rounding of the index); and `dist2` ≥ fl(Δy)² (one of its terms, the others non-negative, under
/// monotone rounding), which grows monotonically along each strip's y order. The same predicate as an O(N²) double
/// loop, at a fraction of its cost.
pub fn brute_force<R: Real, V: Vector<R>>(pos: &[V], support2: R) -> Vec<Vec<u32>> {
    let finite: Vec<usize> = (0..pos.len()).filter(|&i| (0..V::DIM).all(|k| pos[i].get(k).is_finite())).collect();
    let x0 = finite.iter().map(|&i| pos[i].get(0).to_f64()).fold(f64::INFINITY, f64::min);
    let w = 1.01 * support2.to_f64().sqrt();
    let strip_of = |i: usize| ((pos[i].get(0).to_f64() - x0) / w).floor() as i64;
    let mut strips: std::collections::BTreeMap<i64, Vec<usize>> = std::collections::BTreeMap::new();
    for &i in &finite {
        strips.entry(strip_of(i)).or_default().push(i);
    }
    for v in strips.values_mut() {
        v.sort_by(|&a, &b| pos[a].get(1).to_f64().total_cmp(&pos[b].get(1).to_f64()));
    }
    let found: Vec<(usize, Vec<u32>)> = finite
        .par_iter()
        .map(|&i| {
            let pi = pos[i];
            let near_y = |j: usize| {
                let d = pos[j].get(1) - pi.get(1);
                d * d < support2
            };
            let mut l = Vec::new();
            let k = strip_of(i);
            for v in (k - 1..=k + 1).filter_map(|k| strips.get(&k)) {
                let at = v.partition_point(|&j| pos[j].get(1) < pi.get(1));
                let up = v[at..].iter().take_while(|&&j| near_y(j));
                let down = v[..at].iter().rev().take_while(|&&j| near_y(j));
                l.extend(up.chain(down).filter(|&&j| j != i && pi.dist2(&pos[j]) < support2).map(|&j| j as u32));
            }
            l.sort_unstable();
            (i, l)
        })
        .collect();
    let mut lists = vec![Vec::new(); pos.len()];
    for (i, l) in found {
        lists[i] = l;
    }
    lists
}

/// Neighbour lists from the cell list on backend `b`, mapped back to the input indices and sorted. Also
/// returns the sorted state, the permutation and the cell starts for further checks.
pub struct Searched<R: Real, D: Dim> {
    pub lists: Vec<Vec<u32>>,
    pub sorted: HostParticles<R, D>,
    pub perm: Vec<u32>,
    pub starts: Vec<u32>,
    pub keys: Vec<u32>,
    /// Neighbour lists in sorted indices, in gather order, as the kernel wrote them (CSR).
    pub raw_counts: Vec<u32>,
    pub raw_list: Vec<u32>,
    /// The Verlet list as built (`neighbour::verlet` layout), empty when the grid has no list capacity.
    pub verlet: Vec<u32>,
}

/// CSR neighbour lists on backend `b` (`CellList::csr_neighbours`, which also checks that its counting and filling
/// passes agree).
pub fn csr_lists<B: Backend, R: Real, D: Dim>(
    b: &B,
    pos: &B::Buf<D::Vec<R>>,
    cl: &CellList<B>,
    support2: R,
) -> (Vec<u32>, Vec<u32>, Vec<u32>) {
    cl.csr_neighbours::<R, D>(b, pos, support2).expect("neighbour lists")
}

pub fn search<B: Backend, R: Real, D: Dim>(b: &B, pos: &[D::Vec<R>], grid: GridParams, support2: R) -> Searched<R, D> {
    let n = pos.len();
    let host = HostParticles::<R, D>::at_rest(pos.to_vec(), R::ONE, R::ONE);
    let mut p = Particles::<B, R, D>::upload(b, &host).expect("upload");
    let mut cl = CellList::new(b, grid, n).expect("cell list");
    cl.build::<R, D>(b, &p.pos.cur).expect("build");
    let keys = b.read(&cl.keys).expect("keys");
    p.reorder(b, &cl.perm).expect("reorder");
    let (raw_counts, offsets, raw_list) = csr_lists::<B, R, D>(b, &p.pos.cur, &cl, support2);
    cl.build_list::<R, D>(b, &p.pos.cur, None).expect("Verlet list");
    let verlet = cl.list.as_ref().map(|l| b.read(l).expect("Verlet list")).unwrap_or_default();
    let sorted = p.download(b).expect("download");
    let mut lists = vec![Vec::new(); n];
    for i in 0..n {
        let row = &raw_list[offsets[i] as usize..offsets[i + 1] as usize];
        let mut l: Vec<u32> = row.iter().map(|&j| sorted.id[j as usize]).collect();
        l.sort_unstable();
        lists[sorted.id[i] as usize] = l;
    }
    Searched {
        lists,
        sorted,
        perm: b.read(&cl.perm).expect("perm"),
        starts: b.read(&cl.starts).expect("starts"),
        keys,
        raw_counts,
        raw_list,
        verlet,
    }
}

/// Asserts two sets of neighbour lists are equal, naming the first difference.
pub fn assert_same_pairs(a: &[Vec<u32>], b: &[Vec<u32>], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}: particle counts differ");
    let total: usize = a.iter().map(|l| l.len()).sum();
    for i in 0..a.len() {
        assert_eq!(a[i], b[i], "{what}: neighbours of particle {i} differ");
    }
    assert!(total > 0 || a.is_empty(), "{what}: no pairs at all, the test is vacuous");
}

/// The backend of the physics suites (tests/stability_*.rs): the CPU, or the GPU with `SWARF_TEST_BACKEND=gpu`
/// (ci/gpu-run.sh part `hard` runs the same tests, with the same criteria, on a GPU).
pub fn test_backend() -> swarf::backend::AnyBackend {
    use swarf::backend::{AnyBackend, BackendChoice};
    let choice = match std::env::var("SWARF_TEST_BACKEND").as_deref() {
        Ok("gpu") => BackendChoice::Gpu,
        _ => BackendChoice::Cpu,
    };
    AnyBackend::select(choice).expect("the test backend (SWARF_TEST_BACKEND)").0
}

/// `$f(&backend, args…)` on [`test_backend`]'s backend, for tests that drive a `Solver` of their own (generic
/// over the backend).
#[macro_export]
macro_rules! on_test_backend {
    ($f:ident($($a:expr),*)) => {
        match common::test_backend() {
            swarf::backend::AnyBackend::Cpu(b) => $f(&b, $($a),*),
            swarf::backend::AnyBackend::Cuda(b) => $f(&*b, $($a),*),
        }
    };
}
