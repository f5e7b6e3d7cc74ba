//! Triangle-mesh tools (issue 24, item 1): the readers, the checks, the placement, and the grid query against brute
//! force over all triangles and against the analytic distance of the tessellated shapes; the diamond grain of the
//! original 3D code.

use std::f64::consts::PI;
use std::path::PathBuf;
use swarf::kernels::contact::{SurfacePoint, ToolGeometry};
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
    let v =
        vec![[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, -1.0]];
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
    let (all, near, safe) =
        (grid(&m, size, 4.0 * size, false), grid(&m, size, 0.1 * size, false), grid(&m, size, 4.0 * size, true));
    let (all, near, safe) = (all.tool(), near.tool(), safe.tool());
    let mut worst: f64 = 0.0;
    let mut far = 0;
    for p in points(&m, 10_000, 7) {
        let brute = all.query_brute(p);
        let q = all.query(p);
        assert!(
            (q.distance - brute.distance).abs() <= ROUND * size,
            "{} {p:?}: grid {q:?} vs brute {brute:?}",
            m.source
        );
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
        for (j, &uj) in u.iter().enumerate() {
            cum += uj;
            let t = (cum - 1.0) / (j + 1) as f64;
            if uj - t > 0.0 {
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

/// The unit corner tetrahedron's four outward faces.
const TET: [[[f64; 3]; 3]; 4] = [
    [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]],
    [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
    [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
];

/// Reads, welds and checks a file; returns the mesh and its report.
fn read_checked(p: &std::path::Path) -> (TriMesh, mesh::CheckReport) {
    mesh::prepare(&mesh::read(p).unwrap(), 0.0).unwrap()
}

#[test]
fn stl_ascii_and_binary_read_the_same_tetrahedron() {
    let mut ascii = String::from("solid tet\n");
    let mut bin = vec![0u8; 80];
    bin.extend(4u32.to_le_bytes());
    for f in TET {
        ascii += "  facet normal 0 0 0\n    outer loop\n";
        bin.extend([0u8; 12]);
        for v in f {
            ascii += &format!("      vertex {} {} {}\n", v[0], v[1], v[2]);
            v.iter().for_each(|x| bin.extend((*x as f32).to_le_bytes()));
        }
        ascii += "    endloop\n  endfacet\n";
        bin.extend([0u8; 2]);
    }
    ascii += "endsolid tet\n";
    let (a, ra) = read_checked(&write("tet-ascii.stl", ascii.as_bytes()));
    let (b, rb) = read_checked(&write("tet-binary.stl", &bin));
    assert_eq!((a.vertices.clone(), a.triangles.clone()), (b.vertices, b.triangles), "ASCII and binary agree");
    // 12 corners welded into 4 vertices; volume 1/6 (exact in binary: every coordinate is 0 or 1).
    assert_eq!((ra.vertices, ra.triangles, ra.welded), (4, 4, 8));
    assert!((ra.volume - 1.0 / 6.0).abs() < 1e-15 && (rb.volume - ra.volume).abs() == 0.0, "{ra:?}");
    // A broken facet names the file and line.
    let bad = write("bad.stl", b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0\n");
    let e = mesh::read(&bad).unwrap_err().to_string();
    assert!(e.contains("bad.stl") && e.contains("line 4") && e.contains("vertex coordinate z"), "{e}");
    // A truncated binary file: its size and count disagree.
    let e = mesh::read(&write("short.stl", &bin[..bin.len() - 1])).unwrap_err().to_string();
    assert!(e.contains("short.stl") && e.contains("283 bytes") && e.contains("Some(4)"), "{e}");
}

#[test]
fn obj_reads_polygons_negative_indices_and_slash_forms() {
    // The cube [−1, 1]³: faces as quads in the forms i, i/t, i//n, i/t/n and negative (relative) indices.
    let mut s = String::from("# cube\no cube\n");
    let c = cuboid([1.0; 3]);
    for v in &c.vertices {
        s += &format!("v {} {} {}\n", v[0], v[1], v[2]);
    }
    s += "vt 0 0\nvn 0 0 1\n";
    s += "f 1 5 7 3\nf 2/1 4/1 8/1 6/1\nf 1//1 2//1 6//1 5//1\nf 3/1/1 7/1/1 8/1/1 4/1/1\nf -8 -6 -5 -7\nf 5 6 8 7\n";
    let (m, r) = read_checked(&write("cube.obj", s.as_bytes()));
    assert_eq!((m.triangles.len(), r.vertices), (12, 8));
    assert!((r.volume - 8.0).abs() < 1e-14, "{r:?}");
    let e = mesh::read(&write("bad.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 9\n")).unwrap_err().to_string();
    assert!(e.contains("bad.obj") && e.contains("line 5") && e.contains("vertex index in 1..=3"), "{e}");
}

/// The cube [0, 1]³'s vertices as `*NODE` lines, ids 101–108 (bit 0 x, 1 y, 2 z of id − 101).
fn dyna_nodes() -> String {
    let mut s = String::from("*KEYWORD\n$ a comment\n*NODE\n");
    for i in 0..8 {
        s += &format!("{:>8}{:>16}{:>16}{:>16}\n", 101 + i, i & 1, i >> 1 & 1, i >> 2 & 1);
    }
    s
}

#[test]
fn dyna_shells_quads_and_triangles() {
    // The cube as shells: five quads and one face as two triangles (n4 = n3, and 3 nodes only), comma-separated.
    let mut s = dyna_nodes();
    s += "*ELEMENT_SHELL\n1,1,101,105,107,103\n2 1 102 104 108 106\n3 1 101 102 106 105\n4 1 103 107 108 104\n";
    s += "5 1 101 103 104 104\n6 1 101 104 102\n7 1 105 106 108 107\n*END\n";
    let (m, r) = read_checked(&write("cube-shell.k", s.as_bytes()));
    assert_eq!(m.triangles.len(), 12);
    assert!((r.volume - 1.0).abs() < 1e-15, "{r:?}");
}

#[test]
fn dyna_solid_tetrahedra_and_hexahedron_give_their_outward_boundary() {
    // The unit cube as five tetrahedra: the even-parity corners 0, 3, 5, 6 form the inner one, each odd corner
    // a corner one; some in 8-node form with repeated nodes, some of negative orientation, one in 4-node form.
    let mut s = dyna_nodes();
    s += "*ELEMENT_SOLID\n$#   eid     pid      n1      n2      n3      n4      n5      n6      n7      n8\n";
    s += "       1       1     101     104     106     107     107     107     107     107\n";
    s += "       2       1     102     101     104     106     106     106     106     106\n";
    s += "3 1 103 101 107 104 104 104 104 104\n";
    s += "4 1 105 101 106 107\n";
    s += "5 1 108 104 107 106 106 106 106 106\n*END\n";
    let (m, r) = read_checked(&write("cube-tet.k", s.as_bytes()));
    // The boundary: 6 faces × 2 triangles, the inner faces dropped; volume 1 = 1/3 + 4 · 1/6.
    assert_eq!((m.triangles.len(), r.flipped_all), (12, false));
    assert!((r.volume - 1.0).abs() < 1e-15, "{r:?}");
    // One hexahedron of the same cube, nodes in LS-DYNA order (bottom counter-clockwise, then top).
    let hex = dyna_nodes() + "*ELEMENT_SOLID\n1 1 101 102 104 103 105 106 108 107\n";
    let (h, rh) = read_checked(&write("cube-hex.k", hex.as_bytes()));
    assert_eq!(h.triangles.len(), 12);
    assert!((rh.volume - 1.0).abs() < 1e-15, "{rh:?}");
    // An element naming an undefined node: file, line and what was expected.
    let bad = dyna_nodes() + "*ELEMENT_SOLID\n1 1 101 102 104 999 999 999 999 999\n";
    let e = mesh::read(&write("bad.k", bad.as_bytes())).unwrap_err().to_string();
    assert!(
        e.contains("bad.k") && e.contains("line 13") && e.contains("node id defined in *NODE") && e.contains("999"),
        "{e}"
    );
}

fn refused(m: &TriMesh) -> String {
    match mesh::prepare(m, 0.0) {
        Err(e @ MeshError::Broken { .. }) => e.to_string(),
        other => panic!("{}: expected a refusal, got {other:?}", m.source),
    }
}

#[test]
fn checks_refuse_a_hole_a_non_manifold_edge_a_flipped_face_and_a_degenerate_triangle() {
    let mut hole = cuboid([1.0; 3]);
    hole.triangles.remove(11);
    let e = refused(&hole);
    // Triangle 11 was (4, 7, 6): its three edges are left with one triangle each.
    assert!(e.contains("not closed") && e.contains("3 boundary edges"), "{e}");
    assert!(e.contains("edge 4–7 at (0.000000e0, 0.000000e0, 1.000000e0) (triangles 10)"), "{e}");

    // Two tetrahedra sharing the edge 0–1: four triangles at it.
    let mut nm = mesh(
        vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]],
        vec![],
        "two-tets",
    );
    nm.triangles = vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3], [0, 4, 1], [0, 1, 5], [0, 5, 4], [1, 4, 5]];
    let e = refused(&nm);
    assert!(e.contains("non-manifold") && e.contains("edge 0–1") && e.contains("triangles 0, 1, 4, 5"), "{e}");

    let mut flipped = cuboid([1.0; 3]);
    flipped.triangles[5].swap(1, 2);
    let e = refused(&flipped);
    assert!(
        e.contains("inconsistent orientation") && e.contains("1 flipped faces") && e.contains("triangle 5 at"),
        "{e}"
    );

    let mut degenerate = cuboid([1.0; 3]);
    degenerate.triangles.push([0, 0, 1]);
    let e = refused(&degenerate);
    assert!(e.contains("degenerate") && e.contains("triangle 12"), "{e}");
}

#[test]
fn inward_mesh_is_flipped_and_near_vertices_weld_within_tolerance() {
    let mut inward = cuboid([1.0; 3]);
    inward.triangles.iter_mut().for_each(|t| t.swap(1, 2));
    let (m, r) = mesh::prepare(&inward, 0.0).unwrap();
    assert!(r.flipped_all && (r.volume - 8.0).abs() < 1e-14 && m.signed_volume() > 0.0, "{r:?}");

    // A soup of the octahedron's faces, each corner moved by up to 1e-12: exact welding leaves holes, a tolerance
    // of 1e-9 of the diagonal closes it.
    let o = octahedron();
    let mut rng = SplitMix64::new(3);
    let mut soup = mesh(vec![], vec![], "soup");
    for t in &o.triangles {
        for &i in t {
            soup.vertices.push(o.vertices[i as usize].map(|x| x + 1e-12 * (rng.uniform() - 0.5)));
        }
        let b = soup.vertices.len() as u32 - 3;
        soup.triangles.push([b, b + 1, b + 2]);
    }
    assert!(refused(&soup).contains("not closed"));
    let (w, r) = mesh::prepare(&soup, 1e-9).unwrap();
    assert_eq!((w.vertices.len(), r.welded), (6, 18));
    assert!((r.volume - 4.0 / 3.0).abs() < 1e-10, "{r:?}");
}

#[test]
fn placement_scales_rotates_and_translates() {
    // 120° about (1, 1, 1) cycles the axes x → y → z.
    let p = Placement::from_axis_angle(2.0, [3.0, 3.0, 3.0], 2.0 * PI / 3.0, [10.0, 0.0, -1.0]).unwrap();
    let q = p.point([1.0, 0.0, 0.0]);
    for (k, want) in [10.0, 2.0, -1.0].iter().enumerate() {
        assert!((q[k] - want).abs() < 1e-14, "{q:?}");
    }
    let placed = p.apply(&cuboid([1.0; 3]));
    let (_, r) = mesh::prepare(&placed, 0.0).unwrap();
    // Volume × s³, orientation kept.
    assert!(!r.flipped_all && (r.volume - 64.0).abs() < 1e-12, "{r:?}");
    assert_eq!(Placement::IDENTITY.point([1.0, 2.0, 3.0]), [1.0, 2.0, 3.0]);
    let mirror = [[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for bad in [
        Placement::new(1.0, mirror, [0.0; 3]),
        Placement::new(0.0, Placement::IDENTITY.rotation, [0.0; 3]),
        Placement::new(1.0, [[1.0, 0.1, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], [0.0; 3]),
        Placement::from_axis_angle(1.0, [0.0; 3], 1.0, [0.0; 3]),
        Placement::from_axis_angle(1.0, [0.0, 0.0, 1.0], f64::NAN, [0.0; 3]),
    ] {
        assert!(matches!(bad, Err(MeshError::Placement(_))), "{bad:?}");
    }
}

/// The simplified diamond grain of iwf_mfree_gpu_3d (cases/3d/tools/README.md): 96 nodes, 290 tetrahedra, µm.
#[test]
fn diamond_grain_is_closed_and_outward() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases/3d/tools/diamond-grain.k");
    let raw = mesh::read(&path).unwrap();
    let (m, r) = mesh::prepare(&raw, 0.0).unwrap();
    // The independent volume: Σ |tetrahedron volumes| from the file's lines (the elements fill the grain).
    let text = std::fs::read_to_string(&path).unwrap();
    let mut nodes = std::collections::HashMap::new();
    let mut tets = Vec::new();
    let mut block = "";
    for line in text.lines() {
        if line.starts_with('*') {
            block = line.trim();
            continue;
        }
        let f: Vec<f64> = line.split_whitespace().filter_map(|t| t.parse().ok()).collect();
        match (block, f.len()) {
            ("*NODE", 6) => drop(nodes.insert(f[0] as i64, [f[1], f[2], f[3]])),
            ("*ELEMENT_SOLID", 10) => tets.push([f[2], f[3], f[4], f[5]].map(|x| x as i64)),
            _ => {}
        }
    }
    assert_eq!((nodes.len(), tets.len()), (96, 290));
    let vol: f64 = tets
        .iter()
        .map(|t| {
            let [a, b, c, d] = t.map(|i| nodes[&i]);
            let (u, v, w) =
                ([0, 1, 2].map(|k| b[k] - a[k]), [0, 1, 2].map(|k| c[k] - a[k]), [0, 1, 2].map(|k| d[k] - a[k]));
            (u[0] * (v[1] * w[2] - v[2] * w[1])
                + u[1] * (v[2] * w[0] - v[0] * w[2])
                + u[2] * (v[0] * w[1] - v[1] * w[0]))
                .abs()
                / 6.0
        })
        .sum();
    let (lo, hi) = r.bounds;
    eprintln!(
        "diamond grain: {} boundary triangles, {} vertices, volume {:.6e} µm³ (Σ tets {vol:.6e}), box {lo:?} – {hi:?} µm, edges {:.3} – mean {:.3} µm, flipped {}",
        r.triangles, r.vertices, r.volume, r.min_edge, r.mean_edge, r.flipped_all
    );
    assert!((r.volume - vol).abs() <= 1e-9 * vol, "surface volume {} vs Σ tets {vol}", r.volume);
    // The file's header: the grain's underside at z = 670 µm; its top face at z = 1079.80005.
    assert_eq!((lo[2], hi[2]), (670.0, 1079.80005));
    // A point above the middle of the flat top face: its distance is the height above it, exactly to rounding.
    let g = MeshGridData::build(&m, &GridOptions::new(2000.0)).unwrap();
    let q = g.tool().query([186.3, 0.0, 1500.0]);
    assert!((q.distance - (1500.0 - 1079.80005)).abs() < 1e-9, "{q:?}");
    assert!(g.tool().query([186.3, 0.0, 900.0]).distance < 0.0, "the grain's middle is inside");
}
