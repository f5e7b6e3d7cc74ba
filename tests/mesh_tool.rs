//! Triangle-mesh tools (issue 24, item 1): the readers, the checks, the placement, and the grid query against brute
//! force over all triangles and against the analytic distance of the tessellated shapes; the diamond grain of the
//! original 3D code.

use std::f64::consts::PI;
use std::path::PathBuf;
use swarf::kernels::contact::{MeshTool, SurfacePoint, ToolGeometry};
use swarf::mesh::{self, GridOptions, MeshError, MeshGridData, Placement, TriMesh};
use swarf::rng::SplitMix64;

/// A fresh file in the temp folder with these bytes.
fn write(name: &str, bytes: &[u8]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("swarf-mesh-tool-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

fn mesh(vertices: Vec<[f64; 3]>, triangles: Vec<[u32; 3]>, name: &str) -> TriMesh {
    TriMesh { source: name.into(), vertices, triangles }
}

/// The box [−e, e], 12 triangles from 6 quads counter-clockwise seen from outside (vertex i: bit 0 x, 1 y, 2 z).
fn cuboid(e: [f64; 3]) -> TriMesh {
    let v = (0..8).map(|i| [0, 1, 2].map(|k| if i >> k & 1 == 1 { e[k] } else { -e[k] })).collect();
    let quads = [[0, 4, 6, 2], [1, 3, 7, 5], [0, 1, 5, 4], [2, 6, 7, 3], [0, 2, 3, 1], [4, 5, 7, 6]];
    mesh(v, quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect(), "box")
}

/// |x| + |y| + |z| = 1.
fn octahedron() -> TriMesh {
    let v = vec![[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, -1.0]];
    let mut t = Vec::new();
    for s in 0..8u32 {
        let (x, y, z) = (s & 1, 2 + (s >> 1 & 1), 4 + (s >> 2 & 1));
        // An odd number of negative axes mirrors the triangle.
        t.push(if s.count_ones() % 2 == 0 { [x, y, z] } else { [x, z, y] });
    }
    mesh(v, t, "octahedron")
}

/// A UV sphere of radius r: `lat` bands, `lon` segments, vertices on the sphere.
fn sphere(r: f64, lat: u32, lon: u32) -> TriMesh {
    let mut v = vec![[0.0, 0.0, r]];
    for i in 1..lat {
        let th = PI * i as f64 / lat as f64;
        for j in 0..lon {
            let ph = 2.0 * PI * j as f64 / lon as f64;
            v.push([r * th.sin() * ph.cos(), r * th.sin() * ph.sin(), r * th.cos()]);
        }
    }
    v.push([0.0, 0.0, -r]);
    let s = v.len() as u32 - 1;
    let ring = |i: u32, j: u32| 1 + (i - 1) * lon + j % lon;
    let mut t = Vec::new();
    for j in 0..lon {
        t.push([0, ring(1, j), ring(1, j + 1)]);
        for i in 1..lat - 1 {
            let (a, b, c, d) = (ring(i, j), ring(i + 1, j), ring(i + 1, j + 1), ring(i, j + 1));
            t.push([a, b, c]);
            t.push([a, c, d]);
        }
        t.push([s, ring(lat - 1, j + 1), ring(lat - 1, j)]);
    }
    mesh(v, t, "sphere")
}

/// A closed cylinder of radius r and half-height h about z, n segments, caps fanned from their centres.
fn cylinder(r: f64, h: f64, n: u32) -> TriMesh {
    let mut v = Vec::new();
    for z in [-h, h] {
        for j in 0..n {
            let ph = 2.0 * PI * j as f64 / n as f64;
            v.push([r * ph.cos(), r * ph.sin(), z]);
        }
    }
    v.push([0.0, 0.0, -h]);
    v.push([0.0, 0.0, h]);
    let (cb, ct) = (2 * n, 2 * n + 1);
    let mut t = Vec::new();
    for j in 0..n {
        let (b0, b1, t0, t1) = (j, (j + 1) % n, n + j, n + (j + 1) % n);
        t.extend([[b0, b1, t1], [b0, t1, t0], [ct, t0, t1], [cb, b1, b0]]);
    }
    mesh(v, t, "cylinder")
}

/// A grid of the mean edge length, a margin of 5 % of `size`.
fn grid(m: &TriMesh, size: f64, cutoff: f64, safe: bool) -> MeshGridData {
    let o = GridOptions { safe, margin: 0.05 * size, ..GridOptions::new(cutoff) };
    MeshGridData::build(m, &o).unwrap()
}

/// Uniform points in the mesh's bounding box grown by half its size on each side.
fn points(m: &TriMesh, n: usize, seed: u64) -> Vec<[f64; 3]> {
    let (lo, hi) = m.bounds();
    let mut r = SplitMix64::new(seed);
    (0..n).map(|_| [0, 1, 2].map(|k| lo[k] - 0.5 * (hi[k] - lo[k]) + 2.0 * (hi[k] - lo[k]) * r.uniform())).collect()
}

/// Rounding tolerance of a distance, for coordinates of order 1: a few hundred ulps of the geometry.
const ROUND: f64 = 1e-12;

/// Checks one shape: the grid query equals brute force (a large cut-off: every point; a small one: points within
/// it exactly, the rest "far" with the brute-force sign), the distance equals `exact` within `tol`, the sign
/// equals ray parity, and safe mode gives the same signs. Returns the largest |query − exact|.
fn check_shape(m: &TriMesh, exact: impl Fn([f64; 3]) -> f64, tol: f64) -> f64 {
    let (m, report) = mesh::prepare(m, 0.0).unwrap();
    assert!(!report.flipped_all, "{}: built outward", m.source);
    let (lo, hi) = m.bounds();
    let size = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
    let (all, near, safe) = (grid(&m, size, 4.0 * size, false), grid(&m, size, 0.1 * size, false), grid(&m, size, 4.0 * size, true));
    let (all, near, safe) = (all.tool(), near.tool(), safe.tool());
    let mut worst: f64 = 0.0;
    let mut far = 0;
    for p in points(&m, 10_000, 7) {
        let brute = all.query_brute(p);
        let q = all.query(p);
        assert!((q.distance - brute.distance).abs() <= ROUND * size, "{} {p:?}: grid {q:?} vs brute {brute:?}", m.source);
        check_normal(&q, p);
        let e = exact(p);
        worst = worst.max((q.distance - e).abs());
        assert!((q.distance - e).abs() <= tol, "{} {p:?}: {} vs analytic {e}", m.source, q.distance);
        if q.distance.abs() > ROUND * size {
            assert_eq!(q.distance < 0.0, all.inside_by_parity(p), "{} {p:?}: sign vs ray parity", m.source);
            assert_eq!(safe.query(p).distance < 0.0, q.distance < 0.0, "{} {p:?}: safe mode", m.source);
        }
        let n = near.query(p);
        let c = near.grid.cutoff;
        if brute.distance.abs() < c {
            assert!((n.distance - brute.distance).abs() <= ROUND * size, "{} {p:?}: near {n:?} vs {brute:?}", m.source);
        } else {
            far += 1;
            assert_eq!(n.distance.abs(), c, "{} {p:?}: far point reports the cut-off", m.source);
            assert_eq!(n.distance < 0.0, brute.distance < 0.0, "{} {p:?}: far sign", m.source);
        }
    }
    assert!(far > 1000, "{}: the far branch is exercised ({far} points)", m.source);
    worst
}

/// The normal is a unit vector along ±(p − point), outward: p = point + distance · normal.
fn check_normal(q: &SurfacePoint, p: [f64; 3]) {
    let len = q.normal.iter().map(|x| x * x).sum::<f64>().sqrt();
    assert!((len - 1.0).abs() < 1e-12, "unit normal {q:?}");
    for k in 0..3 {
        assert!((q.point[k] + q.distance * q.normal[k] - p[k]).abs() < 1e-9, "{p:?}: p = point + d·n, {q:?}");
    }
}

#[test]
fn box_distance_is_exact() {
    let e = [1.0, 0.7, 0.5];
    let exact = |p: [f64; 3]| {
        let q = [0, 1, 2].map(|k| p[k].abs() - e[k]);
        let out = q.iter().map(|x| x.max(0.0).powi(2)).sum::<f64>().sqrt();
        out + q[0].max(q[1]).max(q[2]).min(0.0)
    };
    let worst = check_shape(&cuboid(e), exact, ROUND);
    eprintln!("box: max |d − analytic| = {worst:e}");
}

#[test]
fn octahedron_distance_is_exact() {
    // Outside: the distance to the projection of |p| on the simplex x ≥ 0, Σx = 1 (sort-based projection, Held et
    // al. 1974); inside: the distance to the nearest face plane, (1 − |p|₁)/√3.
    let exact = |p: [f64; 3]| {
        let q = p.map(f64::abs);
        let s: f64 = q.iter().sum();
        if s <= 1.0 {
            return (s - 1.0) / 3f64.sqrt();
        }
        let mut u = q;
        u.sort_by(|a, b| b.total_cmp(a));
        let (mut cum, mut tau) = (0.0, 0.0);
        for j in 0..3 {
            cum += u[j];
            let t = (cum - 1.0) / (j + 1) as f64;
            if u[j] - t > 0.0 {
                tau = t;
            }
        }
        q.iter().map(|&x| (x - (x - tau).max(0.0)).powi(2)).sum::<f64>().sqrt()
    };
    let worst = check_shape(&octahedron(), exact, ROUND);
    eprintln!("octahedron: max |d − analytic| = {worst:e}");
}

#[test]
fn sphere_within_tessellation_error() {
    let (r, m) = (1.0, sphere(1.0, 16, 32));
    // Every vertex is on the sphere, so the surface lies in the shell between the smallest face-plane distance from
    // the centre and r: the distances to the two surfaces differ by at most the shell's width.
    let inner = m.triangles.iter().map(|t| plane_distance(&m, t)).fold(f64::INFINITY, f64::min);
    let tol = r - inner + ROUND;
    let worst = check_shape(&m, |p| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - r, tol);
    eprintln!("sphere (16 × 32): max |d − analytic| = {worst:e}, bound {tol:e}");
}

#[test]
fn cylinder_within_tessellation_error() {
    let (r, h, n) = (0.5, 1.0, 48);
    // The prism's sides lie between r·cos(π/n) and r; the caps are exact.
    let tol = r * (1.0 - (PI / n as f64).cos()) + ROUND;
    let exact = |p: [f64; 3]| {
        let (dr, dz) = ((p[0] * p[0] + p[1] * p[1]).sqrt() - r, p[2].abs() - h);
        (dr.max(0.0).powi(2) + dz.max(0.0).powi(2)).sqrt() + dr.max(dz).min(0.0)
    };
    let worst = check_shape(&cylinder(r, h, n), exact, tol);
    eprintln!("cylinder ({n} segments): max |d − analytic| = {worst:e}, bound {tol:e}");
}

/// The distance from the origin to a triangle's plane.
fn plane_distance(m: &TriMesh, t: &[u32; 3]) -> f64 {
    let [a, b, c] = m.corners(t);
    let (u, v) = ([0, 1, 2].map(|k| b[k] - a[k]), [0, 1, 2].map(|k| c[k] - a[k]));
    let n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
    let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    (n[0] * a[0] + n[1] * a[1] + n[2] * a[2]).abs() / l
}
