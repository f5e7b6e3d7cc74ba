//! Neighbour search on the CPU backend against a grid-free brute force (sweep and prune on x,
//! `common::brute_force`; roethlin-solver.md AT-50, AT-51): the set of pairs within the support radius must be
//! identical, for 10⁵ particles uniform, clustered and on a lattice with particles exactly on cell faces, in 2D and
//! 3D, with both grid layouts (cell h / ±2, cell 2h / ±1).

use crate::common;

use common::*;
use swarf::backend::CpuBackend;
use swarf::grid::{bounding_box, grid_for_support, grid_with_cell};
use swarf::kernels::neighbour::GridParams;
use swarf::kernels::{Dim, Dim2, Dim3, Real, Vector};

const N: usize = 100_000;

/// Smoothing length for a mean spacing dx (h = 1.7 dx as in the theses' benchmarks).
fn h_for(n: usize, d: usize) -> f64 {
    1.7 * (n as f64).powf(-1.0 / d as f64)
}

fn check_against_brute_force<R: Real, D: Dim>(pos: &[D::Vec<R>], h: f64, what: &str) {
    let b = CpuBackend::new();
    let support = 2.0 * h;
    let support2 = R::from_f64(support * support);
    let reference = brute_force::<R, D::Vec<R>>(pos, support2);
    let (lo, hi) = bounding_box::<R, D::Vec<R>>(pos);
    for stencil in [2, 1] {
        let grid = grid_for_support(lo, hi, D::D, support, stencil).expect("grid");
        let s = search::<_, R, D>(&b, pos, grid, support2);
        assert_same_pairs(&s.lists, &reference, &format!("{what}, stencil ±{stencil}"));
    }
}

#[test]
fn uniform_2d_matches_brute_force() {
    check_against_brute_force::<f64, Dim2>(&uniform::<f64, Dim2>(N, 1), h_for(N, 2), "uniform 2D f64");
}

#[test]
fn uniform_2d_f32_matches_brute_force() {
    check_against_brute_force::<f32, Dim2>(&uniform::<f32, Dim2>(N, 2), h_for(N, 2), "uniform 2D f32");
}

#[test]
fn uniform_3d_matches_brute_force() {
    check_against_brute_force::<f64, Dim3>(&uniform::<f64, Dim3>(N, 3), h_for(N, 3), "uniform 3D f64");
}

#[test]
fn clustered_2d_matches_brute_force() {
    check_against_brute_force::<f64, Dim2>(&clustered::<f64, Dim2>(N, 4), h_for(N, 2), "clustered 2D");
}

#[test]
fn clustered_3d_matches_brute_force() {
    check_against_brute_force::<f32, Dim3>(&clustered::<f32, Dim3>(N, 5), h_for(N, 3), "clustered 3D f32");
}

/// Lattice of spacing cell/2 from the grid origin: every other particle lies exactly on a cell face, and the
/// support radius is just below 4 spacings so that lattice distances straddle it. Cell size and spacing are
/// powers of two, so the positions and faces are exact in binary.
fn lattice_on_faces<D: Dim>(per_side: usize) {
    let b = CpuBackend::new();
    let cell = 1.0 / 64.0;
    let dx = cell / 2.0;
    let pos = lattice::<f64, D>(per_side, dx, 6);
    for stencil in [2u32, 1] {
        // Largest support the grid admits: cell·stencil/(1 + margin), slightly below 4dx (stencil 2) or 2dx.
        let support = cell * stencil as f64 / (1.0 + swarf::kernels::neighbour::grid::CELL_MARGIN);
        let support2 = support * support;
        let reference = brute_force::<f64, D::Vec<f64>>(&pos, support2);
        let hi = [(per_side - 1) as f64 * dx; 3];
        let grid = grid_with_cell([0.0; 3], hi, D::D, cell, stencil).expect("grid");
        // Faces: x = k·cell exactly for even lattice indices.
        let on_face = pos.iter().filter(|p| (p.get(0) / cell).fract() == 0.0).count();
        assert!(on_face * 3 > pos.len(), "the lattice must put many particles exactly on faces");
        let s = search::<_, f64, D>(&b, &pos, grid, support2);
        assert_same_pairs(&s.lists, &reference, &format!("lattice on faces {}D ±{stencil}", D::D));
    }
}

#[test]
fn lattice_on_cell_faces_2d_matches_brute_force() {
    lattice_on_faces::<Dim2>(317); // 100 489 particles
}

#[test]
fn lattice_on_cell_faces_3d_matches_brute_force() {
    lattice_on_faces::<Dim3>(47); // 103 823 particles
}

/// The sorted state is a permutation of the input: every field of sorted particle i equals the input's at
/// id[i]; the permutation is the stable sort by key; starts partition [0, N) and each particle is in its cell.
#[test]
fn sorted_state_is_a_stable_permutation() {
    let b = CpuBackend::new();
    let n = 20_000;
    let pos = clustered::<f64, Dim3>(n, 9);
    let mut host = swarf::state::HostParticles::<f64, Dim3>::at_rest(pos.clone(), 1.0, 1.0);
    for (i, v) in host.vel.iter_mut().enumerate() {
        *v = <Dim3 as Dim>::Vec::<f64>::new([i as f64, -(i as f64), 0.5 * i as f64]);
    }
    for (i, m) in host.mass.iter_mut().enumerate() {
        *m = 1.0 + i as f64;
    }
    for (i, r) in host.rho.iter_mut().enumerate() {
        *r = 2.0 * i as f64;
    }
    for (i, s) in host.stress.iter_mut().enumerate() {
        s.0 = std::array::from_fn(|k| (i * 6 + k) as f64);
    }
    for (i, f) in host.flags.iter_mut().enumerate() {
        *f = (i as u32).wrapping_mul(2654435761);
    }
    let (lo, hi) = bounding_box::<f64, _>(&pos);
    let grid = grid_for_support(lo, hi, 3, 0.02, 2).unwrap();
    let mut p = swarf::state::Particles::<_, f64, Dim3>::upload(&b, &host).unwrap();
    let mut cl = swarf::neighbour::CellList::new(&b, grid, n).unwrap();
    cl.build::<f64, Dim3>(&b, &p.pos.cur).unwrap();
    p.reorder(&b, &cl.perm).unwrap();
    let sorted = p.download(&b).unwrap();
    // Permutation of the ids.
    let mut ids = sorted.id.clone();
    ids.sort_unstable();
    assert!(ids.iter().enumerate().all(|(i, &v)| v as usize == i), "ids are not a permutation");
    // Every field moved with its particle.
    for i in 0..n {
        let o = sorted.id[i] as usize;
        assert_eq!(sorted.pos[i], host.pos[o]);
        assert_eq!(sorted.vel[i], host.vel[o]);
        assert_eq!(sorted.mass[i], host.mass[o]);
        assert_eq!(sorted.rho[i], host.rho[o]);
        assert_eq!(sorted.stress[i], host.stress[o]);
        assert_eq!(sorted.flags[i], host.flags[o]);
    }
    // Stable sort by key.
    let keys = cl.keys.clone();
    let mut expect: Vec<u32> = (0..n as u32).collect();
    expect.sort_by_key(|&i| keys[i as usize]);
    assert_eq!(cl.perm, expect, "the permutation is not the stable sort by cell key");
    // Cell ranges.
    let starts = &cl.starts;
    assert_eq!(starts.len(), grid.n_cells as usize + 2);
    assert_eq!(starts[0], 0);
    assert_eq!(*starts.last().unwrap() as usize, n);
    assert!(starts.windows(2).all(|w| w[0] <= w[1]));
    for i in 0..n {
        let k = grid.key::<f64, _>(&sorted.pos[i]) as usize;
        assert!(starts[k] as usize <= i && i < starts[k + 1] as usize, "particle {i} outside its cell {k}");
    }
}

/// Particles outside the grid's box are clamped into the boundary cells; clamping never increases the cell
/// distance of two particles, so the search stays exact. Here the box covers only the middle third.
#[test]
fn particles_outside_the_box_are_clamped_and_still_found() {
    let b = CpuBackend::new();
    let n = 30_000;
    let pos = uniform::<f64, Dim2>(n, 12);
    let h = h_for(n, 2);
    let support2 = 4.0 * h * h;
    let reference = brute_force::<f64, _>(&pos, support2);
    let grid = grid_for_support([0.33, 0.33, 0.0], [0.66, 0.66, 0.0], 2, 2.0 * h, 2).unwrap();
    let s = search::<_, f64, Dim2>(&b, &pos, grid, support2);
    assert_same_pairs(&s.lists, &reference, "box covering the middle third");
}

/// A box far larger than the particles: most cells are empty (start = end) and the search is still exact.
#[test]
fn empty_cells_are_skipped() {
    let b = CpuBackend::new();
    let n = 20_000;
    let pos = clustered::<f64, Dim2>(n, 13);
    let h = h_for(n, 2);
    let support2 = 4.0 * h * h;
    let reference = brute_force::<f64, _>(&pos, support2);
    let grid = grid_for_support([-3.0, -3.0, 0.0], [4.0, 4.0, 0.0], 2, 2.0 * h, 2).unwrap();
    let s = search::<_, f64, Dim2>(&b, &pos, grid, support2);
    let empty = s.starts.windows(2).filter(|w| w[0] == w[1]).count();
    assert!(empty as f64 > 0.9 * grid.n_cells as f64, "most cells must be empty in this test");
    assert_same_pairs(&s.lists, &reference, "mostly empty grid");
}

/// Non-finite positions go to the void bucket after all cells: they are nobody's neighbour and have none.
#[test]
fn non_finite_positions_are_excluded() {
    let b = CpuBackend::new();
    let n = 10_000;
    let mut pos = uniform::<f64, Dim3>(n, 14);
    let bad = [3usize, 77, 4000, 9999];
    pos[3].0[0] = f64::NAN;
    pos[77].0[1] = f64::INFINITY;
    pos[4000].0[2] = f64::NEG_INFINITY;
    pos[9999].0 = [f64::NAN; 4];
    let h = h_for(n, 3);
    let support2 = 4.0 * h * h;
    let reference = brute_force::<f64, _>(&pos, support2);
    let grid = grid_for_support([0.0; 3], [1.0; 3], 3, 2.0 * h, 2).unwrap();
    let s = search::<_, f64, Dim3>(&b, &pos, grid, support2);
    assert_same_pairs(&s.lists, &reference, "with non-finite positions");
    let nc = grid.n_cells as usize;
    assert_eq!((s.starts[nc + 1] - s.starts[nc]) as usize, bad.len(), "void bucket size");
    let tail: Vec<u32> = s.sorted.id[n - bad.len()..].to_vec();
    // In input order on the CPU (its count is sequential); the GPU leaves the void bucket in arrival order.
    assert_eq!(tail, bad.map(|i| i as u32).to_vec(), "non-finite particles sort to the end, in input order");
    for &i in &bad {
        assert_eq!(s.keys[i], grid.n_cells);
    }
}

/// The per-cell sort the GPU runs after its atomic scatter (`kernels::neighbour::sort::sort_cell`: insertion sort
/// up to `INSERTION_MAX`, heap sort above) orders any slice ascending, as `slice::sort` does: shuffled, reversed
/// and already sorted slices of every size around the switch and up to a 27 000-particle cell, with repeated
/// values, inside a larger array whose other elements it must not touch.
#[test]
fn per_cell_sort_orders_any_slice() {
    use swarf::kernels::neighbour::sort::{INSERTION_MAX, sort_cell};
    let mut rng = swarf::rng::SplitMix64::new(41);
    let m = INSERTION_MAX as usize;
    let sizes = (0..=2 * m + 3).chain([100, 1000, 4097, 27_000]);
    for k in sizes {
        let shuffled: Vec<u32> = (0..k).map(|_| (rng.next_u64() % (k as u64 + 1) * 3) as u32).collect();
        let reversed: Vec<u32> = (0..k as u32).rev().collect();
        let sorted: Vec<u32> = (0..k as u32).collect();
        for (what, cell) in [("shuffled", shuffled), ("reversed", reversed), ("sorted", sorted)] {
            let mut v = vec![u32::MAX; 5];
            v.extend(&cell);
            v.extend([7, 7, 7]);
            let a = 5u32;
            // SAFETY: v[a .. a + k] is in bounds.
            unsafe { sort_cell(v.as_mut_ptr(), a, a + k as u32) };
            let mut expect = cell.clone();
            expect.sort();
            assert_eq!(&v[5..5 + k], &expect[..], "{what} cell of {k}");
            assert_eq!((&v[..5], &v[5 + k..]), (&[u32::MAX; 5][..], &[7, 7, 7][..]), "{what} cell of {k}: outside");
        }
    }
}

#[test]
fn grid_construction_refuses_bad_input() {
    let lo = [0.0; 3];
    let hi = [1.0; 3];
    for (res, what) in [
        (grid_for_support(lo, hi, 2, 0.0, 2), "zero support"),
        (grid_for_support(lo, hi, 2, f64::NAN, 2), "NaN support"),
        (grid_for_support(lo, hi, 4, 0.1, 2), "dimension 4"),
        (grid_for_support(lo, hi, 2, 0.1, 4), "stencil 4"),
        (grid_for_support(lo, [1.0, -1.0, 0.0], 2, 0.1, 2), "inverted box"),
        (grid_for_support(lo, [1e6; 3], 3, 1e-3, 2), "too many cells"),
    ] {
        assert!(matches!(res, Err(swarf::Error::Grid(_))), "{what} must be refused, got {res:?}");
    }
    let g: GridParams = grid_for_support(lo, hi, 2, 0.1, 2).unwrap();
    assert!(g.cell_size >= 0.05, "cell must be at least support/stencil");
}

/// CPU twin of the GPU scan against a naive sum, including wrap-around (the GPU test compares the two).
#[test]
fn exclusive_scan_twin() {
    let mut rng = swarf::rng::SplitMix64::new(3);
    for n in [0usize, 1, 2, 1023, 1024, 1025, 100_000] {
        let v: Vec<u32> = (0..n).map(|_| (rng.next_u64() % 7) as u32).collect();
        let mut s = v.clone();
        swarf::backend::cpu::exclusive_scan(&mut s);
        let mut acc = 0u32;
        for i in 0..n {
            assert_eq!(s[i], acc);
            acc += v[i];
        }
    }
    let mut w = vec![u32::MAX, 2, 5];
    swarf::backend::cpu::exclusive_scan(&mut w);
    assert_eq!(w, vec![0, u32::MAX, 1]);
}

/// Each binned position moved in a random direction by up to 0.999 `reach` (a quarter of them by 0.999 `reach`
/// exactly), and how many moved that far. Where `reach` is within the grid's rebuild distance, a displacement that
/// rounds (in R) beyond it is undone: that particle would trigger a rebuild, so it stays where it was binned.
fn displaced<R: Real, D: Dim>(
    binned: &[D::Vec<R>],
    grid: &GridParams,
    reach: f64,
    seed: u64,
) -> (Vec<D::Vec<R>>, usize) {
    let mut rng = swarf::rng::SplitMix64::new(seed ^ 0x5eed);
    let mut moved_far = 0;
    let moved = binned
        .iter()
        .map(|x| {
            let d: [f64; 3] = std::array::from_fn(|k| if k < D::D { rng.normal() } else { 0.0 });
            let len = d.iter().map(|v| v * v).sum::<f64>().sqrt().max(1e-300);
            let frac = if rng.uniform() < 0.25 { 0.999 } else { 0.999 * rng.uniform() };
            let y =
                D::Vec::<R>::new(std::array::from_fn(|k| R::from_f64(x.get(k).to_f64() + frac * reach * d[k] / len)));
            if reach <= grid.rebuild_distance() && grid.beyond_skin::<R, D::Vec<R>>(&y, x) {
                return *x;
            }
            if frac > 0.99 {
                moved_far += 1;
            }
            y
        })
        .collect();
    (moved, moved_far)
}

/// The skin (docs/neighbour-search.md, "Skin"): a cell list built on positions X0 over cells sized for the support
/// plus the skin s still finds every pair within the support after each particle has moved up to s, because the
/// search takes the stencil around each particle's current position and every partner is at most s from where it
/// was binned. Checked against the grid-free search on the moved positions, with displacements drawn up to 0.999 s in
/// random directions and a quarter of the particles moved almost exactly s; 2D and 3D, f32 and f64.
fn stale_list_is_exact_within_the_skin<R: Real, D: Dim>(n: usize, seed: u64) {
    use swarf::backend::Backend;
    use swarf::grid::grid_with_skin;
    use swarf::state::{HostParticles, Particles};
    let b = CpuBackend::new();
    let h = h_for(n, D::D);
    let skin = 0.3 * h;
    let pos = uniform::<R, D>(n, seed);
    let (lo, hi) = bounding_box::<R, D::Vec<R>>(&pos);
    let grid = grid_with_skin(lo, hi, D::D, 2.0 * h, skin).expect("grid");
    let host = HostParticles::<R, D>::at_rest(pos, R::ONE, R::ONE);
    let mut p = Particles::<CpuBackend, R, D>::upload(&b, &host).expect("upload");
    let mut cl = swarf::neighbour::CellList::new(&b, grid, n).expect("cell list");
    cl.build::<R, D>(&b, &p.pos.cur).expect("build");
    p.reorder(&b, &cl.perm).expect("reorder");
    let binned = p.download(&b).expect("download");
    let (moved, moved_far) = displaced::<R, D>(&binned.pos, &grid, skin, seed);
    assert!(moved_far > n / 5, "only {moved_far} of {n} particles moved close to the skin");
    let buf = b.upload(&moved, "moved").expect("upload");
    let support2 = R::from_f64(4.0 * h * h);
    let (_, offsets, list) = csr_lists::<CpuBackend, R, D>(&b, &buf, &cl, support2);
    let stale: Vec<Vec<u32>> = (0..n)
        .map(|i| {
            let mut l = list[offsets[i] as usize..offsets[i + 1] as usize].to_vec();
            l.sort_unstable();
            l
        })
        .collect();
    assert_same_pairs(&stale, &brute_force(&moved, support2), "stale cell list within the skin");
}

#[test]
fn stale_list_within_the_skin_2d_matches_brute_force() {
    stale_list_is_exact_within_the_skin::<f64, Dim2>(4000, 21);
    stale_list_is_exact_within_the_skin::<f32, Dim2>(4000, 22);
}

#[test]
fn stale_list_within_the_skin_3d_matches_brute_force() {
    stale_list_is_exact_within_the_skin::<f64, Dim3>(3000, 23);
    stale_list_is_exact_within_the_skin::<f32, Dim3>(3000, 24);
}

/// The skin test itself: a displacement of exactly s is within it, the next f64 beyond is not, and a non-finite
/// position always asks for a rebuild (which sends it to the void bucket).
#[test]
fn skin_test_bounds_and_non_finite_positions() {
    use swarf::kernels::vector::V2f64;
    let mut g = grid_for_support([0.0; 3], [1.0; 3], 2, 0.1, 2).expect("grid");
    g.skin = 0.25;
    let x0 = V2f64::new([0.5, 0.5, 0.0]);
    assert!(!g.beyond_skin::<f64, V2f64>(&V2f64::new([0.75, 0.5, 0.0]), &x0));
    assert!(g.beyond_skin::<f64, V2f64>(&V2f64::new([0.75f64.next_up(), 0.5, 0.0]), &x0));
    assert!(g.beyond_skin::<f64, V2f64>(&V2f64::new([f64::NAN, 0.5, 0.0]), &x0));
    assert!(g.beyond_skin::<f64, V2f64>(&V2f64::new([0.5, f64::INFINITY, 0.0]), &x0));
    g.skin = 0.0;
    assert!(!g.beyond_skin::<f64, V2f64>(&x0, &x0), "an unmoved particle never asks for a rebuild");
}

/// The cell list and Verlet list of `pos` on `grid` (with its capacity), built as the solver builds them (bin,
/// reorder, list), and the positions in their sorted order.
fn verlet_list_on<R: Real, D: Dim>(
    b: &CpuBackend,
    pos: &[D::Vec<R>],
    grid: GridParams,
) -> (swarf::neighbour::CellList<CpuBackend>, Vec<D::Vec<R>>) {
    use swarf::state::{HostParticles, Particles};
    let host = HostParticles::<R, D>::at_rest(pos.to_vec(), R::ONE, R::ONE);
    let mut p = Particles::<CpuBackend, R, D>::upload(b, &host).expect("upload");
    let mut cl = swarf::neighbour::CellList::new(b, grid, pos.len()).expect("cell list");
    cl.build::<R, D>(b, &p.pos.cur).expect("build");
    p.reorder(b, &cl.perm).expect("reorder");
    cl.build_list::<R, D>(b, &p.pos.cur, None).expect("Verlet list");
    (cl, p.download(b).expect("download").pos)
}

/// The pairs within the support that the Verlet list (or, past its capacity, the stencil) offers sorted particle
/// i at `x`, sorted (`kernels::neighbour::for_each_candidate`, the pair loops' walk).
fn listed_pairs<R: Real, D: Dim>(
    cl: &swarf::neighbour::CellList<CpuBackend>,
    pos: &[D::Vec<R>],
    support2: R,
) -> Vec<Vec<u32>> {
    use swarf::kernels::neighbour::{Neighbours, for_each_candidate};
    let nb = Neighbours { grid: &cl.grid, starts: cl.starts.as_ptr(), list: cl.list.as_ref().expect("list").as_ptr() };
    (0..pos.len() as u32)
        .map(|i| {
            let xi = pos[i as usize];
            let mut l = Vec::new();
            let mut last = None;
            // SAFETY: the cell list and its Verlet list were built for these sorted particles.
            unsafe {
                for_each_candidate::<R, D::Vec<R>, _>(&nb, &xi, i, |j| {
                    assert!(last.is_none_or(|p| p < j), "candidates of {i} not in increasing order");
                    last = Some(j);
                    if j != i && xi.dist2(&pos[j as usize]) < support2 {
                        l.push(j);
                    }
                })
            };
            l
        })
        .collect()
}

/// The Verlet list (docs/neighbour-search.md, "Verlet list"): built on the binned positions X0 with the radius
/// 2h + s, it still holds every pair within the support after each particle has moved up to s/2 (the list's
/// `rebuild_distance`), because both ends of a pair move. Checked against the grid-free search on the moved positions
/// (displacements up to 0.999 s/2, a quarter at almost exactly s/2), 2D and 3D, f32 and f64; with a capacity of 3
/// nearly every particle overflows and walks the stencil, with the same pairs. Moving up to 0.999 s instead (what
/// the cell list alone allows) loses pairs, which shows that the check can fail. Both layouts: 16-bit offsets two to
/// a word, and wide 32-bit ones (`GridParams::list_wide`).
fn verlet_list_is_exact_within_half_the_skin<R: Real, D: Dim>(n: usize, seed: u64) {
    for wide in [0, 1] {
        verlet_list_is_exact_within_half_the_skin_in::<R, D>(n, seed, wide);
    }
}

fn verlet_list_is_exact_within_half_the_skin_in<R: Real, D: Dim>(n: usize, seed: u64, wide: u32) {
    use swarf::grid::grid_with_skin;
    let b = CpuBackend::new();
    let h = h_for(n, D::D);
    let skin = 0.3 * h;
    let pos = uniform::<R, D>(n, seed);
    let (lo, hi) = bounding_box::<R, D::Vec<R>>(&pos);
    let mut grid = grid_with_skin(lo, hi, D::D, 2.0 * h, skin).expect("grid");
    let spacing = (n as f64).powf(-1.0 / D::D as f64);
    let support2 = R::from_f64(4.0 * h * h);
    let full = swarf::neighbour::verlet_capacity(&grid, spacing);
    grid.list_wide = wide;
    for capacity in [full, 3] {
        grid.list_capacity = capacity;
        let (cl, binned) = verlet_list_on::<R, D>(&b, &pos, grid);
        let list = cl.list.as_ref().expect("list");
        let overflows = (0..n).filter(|&i| list[i] > capacity).count();
        if capacity == full {
            assert_eq!(overflows, 0, "{} of {n} particles overflow a capacity of {capacity}", overflows);
        } else {
            assert!(overflows > n * 9 / 10, "only {overflows} of {n} particles overflow a capacity of 3");
        }
        let (half, _) = displaced::<R, D>(&binned, &cl.grid, 0.5 * skin, seed);
        let what = format!("Verlet list (capacity {capacity}, wide {wide}) within half the skin");
        assert_same_pairs(&listed_pairs::<R, D>(&cl, &half, support2), &brute_force(&half, support2), &what);
        if capacity == full {
            let (far, _) = displaced::<R, D>(&binned, &cl.grid, skin, seed);
            let found: usize = listed_pairs::<R, D>(&cl, &far, support2).iter().map(Vec::len).sum();
            let all: usize = brute_force(&far, support2).iter().map(Vec::len).sum();
            assert!(found < all, "moves of up to s lost no pair ({found} of {all}): the check could not fail");
        }
    }
}

#[test]
fn verlet_list_within_half_the_skin_2d_matches_brute_force() {
    verlet_list_is_exact_within_half_the_skin::<f64, Dim2>(4000, 31);
    verlet_list_is_exact_within_half_the_skin::<f32, Dim2>(4000, 32);
}

#[test]
fn verlet_list_within_half_the_skin_3d_matches_brute_force() {
    verlet_list_is_exact_within_half_the_skin::<f64, Dim3>(3000, 33);
    verlet_list_is_exact_within_half_the_skin::<f32, Dim3>(3000, 34);
}

/// With a Verlet list the rebuild waits for half the skin (both ends of a pair move), without one for the skin.
#[test]
fn rebuild_distance_is_half_the_skin_with_a_verlet_list() {
    use swarf::kernels::vector::V2f64;
    let mut g = swarf::grid::grid_with_skin([0.0; 3], [1.0; 3], 2, 0.1, 0.25).expect("grid");
    g.list_capacity = 40;
    let x0 = V2f64::new([0.5, 0.5, 0.0]);
    assert_eq!(g.rebuild_distance(), 0.125);
    assert!(!g.beyond_skin::<f64, V2f64>(&V2f64::new([0.625, 0.5, 0.0]), &x0));
    assert!(g.beyond_skin::<f64, V2f64>(&V2f64::new([0.625f64.next_up(), 0.5, 0.0]), &x0));
    // The list's radius: within the stencil's reach, beyond the support plus the skin by more than f32 rounding.
    let reach = g.stencil as f64 * g.cell_size;
    let r = g.list_radius2().sqrt();
    assert!(r < reach && r > 0.35 * (1.0 + 1e-6), "list radius {r} against reach {reach} and 2h + s = 0.35");
}

/// The Verlet list stores candidates as 16-bit offsets j − i (`kernels::neighbour::verlet`): a row with a candidate
/// more than `MAX_OFFSET` sorted places away is marked `FAR` and walks the stencil. A strip three particles tall and
/// 40 000 wide (a cell row of it holds 40 000–80 000 particles, so every candidate in the next cell row is that far
/// away) beside a small separate block (whose candidates are a few places away): the strip's rows are far, the
/// block's are listed, and every particle gets exactly the pairs within the support that the stencil gives.
#[test]
fn verlet_rows_beyond_the_offset_range_walk_the_stencil() {
    let (cl, list, n) = far_strip(0);
    let far = (0..n).filter(|&i| list[i] == swarf::kernels::neighbour::verlet::FAR).count();
    let listed = (0..n).filter(|&i| list[i] <= cl.grid.list_capacity).count();
    assert!(far >= 100_000, "only {far} of the strip's 120 000 rows are marked far (offsets beyond 32 767)");
    assert!(listed >= 100, "only {listed} rows are listed: the block's 100 must be");
    assert_eq!(far + listed, n, "rows neither far nor listed: the capacity {} overflowed", cl.grid.list_capacity);
}

/// With wide (32-bit) offsets (`GridParams::list_wide`, docs/neighbour-search.md "Wide offsets") the same strip's
/// rows are all listed, none far, and every particle gets exactly the stencil's pairs.
#[test]
fn wide_verlet_offsets_list_the_rows_beyond_the_16_bit_range() {
    let (cl, list, n) = far_strip(1);
    let listed = (0..n).filter(|&i| list[i] <= cl.grid.list_capacity).count();
    assert_eq!(listed, n, "{} of {n} rows are not listed with 32-bit offsets", n - listed);
    assert_eq!(cl.grid.list_words(), (cl.grid.list_capacity as usize + 1) * n, "one word per candidate");
}

/// The far strip of the two tests above, listed with `wide`; checks every particle's listed pairs against the
/// stencil's and returns the cell list, its Verlet list's words and the particle count.
fn far_strip(wide: u32) -> (swarf::neighbour::CellList<CpuBackend>, Vec<u32>, usize) {
    use swarf::grid::grid_with_skin;
    use swarf::kernels::neighbour::{Neighbours, for_each_candidate};
    use swarf::kernels::vector::V2f64;
    let b = CpuBackend::new();
    let (h, dx) = (1.5, 1.0);
    let mut pos: Vec<V2f64> = Vec::new();
    for y in 0..3 {
        for x in 0..40_000 {
            pos.push(V2f64::new([x as f64 * dx, y as f64 * dx, 0.0]));
        }
    }
    for y in 0..10 {
        for x in 0..10 {
            pos.push(V2f64::new([100.0 + x as f64 * dx, 100.0 + y as f64 * dx, 0.0]));
        }
    }
    let n = pos.len();
    let (lo, hi) = bounding_box::<f64, V2f64>(&pos);
    let mut grid = grid_with_skin(lo, hi, 2, 2.0 * h, 0.1 * h).expect("grid");
    grid.list_capacity = swarf::neighbour::verlet_capacity(&grid, dx);
    grid.list_wide = wide;
    let (cl, sorted) = verlet_list_on::<f64, Dim2>(&b, &pos, grid);
    let list = cl.list.as_ref().expect("list").to_vec();
    let support2 = 4.0 * h * h;
    let with_list = listed_pairs::<f64, Dim2>(&cl, &sorted, support2);
    // The same walk with no list: the stencil's pairs.
    let nb = Neighbours { grid: &cl.grid, starts: cl.starts.as_ptr(), list: std::ptr::null() };
    for (i, l) in with_list.iter().enumerate() {
        let xi = sorted[i];
        let mut s = Vec::new();
        // SAFETY: the cell list was built for these sorted particles.
        unsafe {
            for_each_candidate::<f64, V2f64, _>(&nb, &xi, i as u32, |j| {
                if j != i as u32 && xi.dist2(&sorted[j as usize]) < support2 {
                    s.push(j);
                }
            })
        };
        assert_eq!(
            l, &s,
            "particle {i} (count word {}, wide {wide}): the list's pairs differ from the stencil's",
            list[i]
        );
    }
    (cl, list, n)
}
