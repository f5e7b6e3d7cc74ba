//! Checks that a tool mesh bounds a solid, before any run: welded vertices, no zero-area triangles, closed (every
//! edge shared by exactly two triangles), manifold (no edge of more than two), consistently oriented (each shared
//! edge traversed in opposite directions) and outward (positive signed volume; a closed, consistent mesh of
//! negative volume is turned inside out by flipping every triangle, and the report says so). A broken mesh is
//! refused with what is wrong and where: triangle indices and a coordinate. These are what the signed distance of
//! `swarf_kernels::contact::mesh` needs to be right (Bærentzen & Aanæs 2005: the pseudo-normal sign holds on a
//! closed, oriented 2-manifold).

use super::{MeshError, TriMesh, at};
use std::collections::{HashMap, VecDeque};

/// What the checks found in an accepted mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct CheckReport {
    pub vertices: usize,
    pub triangles: usize,
    /// Vertices joined by [`weld`] (0 when the checks ran on an already welded mesh).
    pub welded: usize,
    /// Enclosed volume (after any flip), in the file's units cubed.
    pub volume: f64,
    /// Bounding box: lowest and highest corner.
    pub bounds: ([f64; 3], [f64; 3]),
    /// Whether every triangle was flipped because the mesh was oriented inward.
    pub flipped_all: bool,
    /// Shortest and mean edge length.
    pub min_edge: f64,
    pub mean_edge: f64,
}

/// The relative size below which twice a triangle's area, over the squared bounding-box diagonal, is zero.
pub const DEGENERATE_REL: f64 = 1e-18;

/// Joins vertices closer than `rel_tol` × the bounding-box diagonal (0: exactly equal coordinates) and drops the
/// vertices no triangle uses, keeping the order of the rest. Returns the welded mesh and the number of vertices
/// joined. The triangles must name vertices that exist.
pub fn weld(m: &TriMesh, rel_tol: f64) -> (TriMesh, usize) {
    let (lo, hi) = m.bounds();
    let tol = rel_tol * dist(lo, hi);
    let key = |p: [f64; 3]| -> [i64; 3] {
        if tol > 0.0 { p.map(|x| (x / tol).floor() as i64) } else { p.map(|x| (x + 0.0).to_bits() as i64) }
    };
    let mut cells: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    let mut out = TriMesh { source: m.source.clone(), ..Default::default() };
    let mut map: Vec<Option<u32>> = vec![None; m.vertices.len()];
    let mut joined = 0;
    let mut remap = |i: u32, out: &mut TriMesh| -> u32 {
        if let Some(j) = map[i as usize] {
            return j;
        }
        let p = m.vertices[i as usize];
        let k = key(p);
        let reach = if tol > 0.0 { 1 } else { 0 };
        let mut found = None;
        'search: for dx in -reach..=reach {
            for dy in -reach..=reach {
                for dz in -reach..=reach {
                    for &j in cells.get(&[k[0] + dx, k[1] + dy, k[2] + dz]).into_iter().flatten() {
                        if dist(out.vertices[j as usize], p) <= tol {
                            found = Some(j);
                            break 'search;
                        }
                    }
                }
            }
        }
        let j = found.unwrap_or_else(|| {
            out.vertices.push(p);
            let j = out.vertices.len() as u32 - 1;
            cells.entry(k).or_default().push(j);
            j
        });
        if found.is_some() {
            joined += 1;
        }
        map[i as usize] = Some(j);
        j
    };
    // In vertex order, so that a mesh with no near duplicates and no unused vertices keeps its numbering.
    let mut used = vec![false; m.vertices.len()];
    m.triangles.iter().flatten().for_each(|&i| used[i as usize] = true);
    for i in (0..m.vertices.len()).filter(|&i| used[i]) {
        remap(i as u32, &mut out);
    }
    out.triangles = m.triangles.iter().map(|t| t.map(|i| map[i as usize].unwrap_or(0))).collect();
    (out, joined)
}

/// Welds (`rel_tol`, as [`weld`]), checks and orients a mesh: the mesh a grid is built from, and its report.
pub fn prepare(m: &TriMesh, rel_tol: f64) -> Result<(TriMesh, CheckReport), MeshError> {
    in_range(m)?;
    let (mut w, joined) = weld(m, rel_tol);
    let mut report = check(&w)?;
    if report.volume < 0.0 {
        w.triangles.iter_mut().for_each(|t| t.swap(1, 2));
        report.volume = -report.volume;
        report.flipped_all = true;
    }
    report.welded = joined;
    Ok((w, report))
}

/// Checks a welded mesh (see the module doc); a negative volume is reported, not refused ([`prepare`] flips it).
pub fn check(m: &TriMesh) -> Result<CheckReport, MeshError> {
    let broken = |what: String| MeshError::Broken { file: m.source.clone(), what };
    if m.triangles.is_empty() {
        return Err(broken("no triangles".into()));
    }
    in_range(m)?;
    degenerate(m).map_err(broken)?;
    let edges = edge_uses(m);
    closed_manifold(m, &edges).map_err(broken)?;
    consistent(m, &edges).map_err(broken)?;
    let (sum, min) = m
        .triangles
        .iter()
        .flat_map(|t| {
            let c = m.corners(t);
            [dist(c[0], c[1]), dist(c[1], c[2]), dist(c[2], c[0])]
        })
        .fold((0.0, f64::INFINITY), |(s, lo), e| (s + e, lo.min(e)));
    Ok(CheckReport {
        vertices: m.vertices.len(),
        triangles: m.triangles.len(),
        welded: 0,
        volume: m.signed_volume(),
        bounds: m.bounds(),
        flipped_all: false,
        min_edge: min,
        mean_edge: sum / (3 * m.triangles.len()) as f64,
    })
}

/// Refuses a triangle naming a vertex that does not exist.
fn in_range(m: &TriMesh) -> Result<(), MeshError> {
    match m.triangles.iter().position(|t| t.iter().any(|&i| i as usize >= m.vertices.len())) {
        Some(t) => Err(MeshError::Broken {
            file: m.source.clone(),
            what: format!("triangle {t} names a vertex beyond the {} read", m.vertices.len()),
        }),
        None => Ok(()),
    }
}

/// Each undirected edge (lower vertex, higher vertex) and its uses: (triangle, whether it runs low → high).
type Edges = HashMap<(u32, u32), Vec<(usize, bool)>>;

fn edge_uses(m: &TriMesh) -> Edges {
    let mut e: Edges = HashMap::new();
    for (t, tri) in m.triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            e.entry((a.min(b), a.max(b))).or_default().push((t, a < b));
        }
    }
    e
}

/// Lists up to five items and how many more.
fn list(items: &[String]) -> String {
    let more = if items.len() > 5 { format!(" and {} more", items.len() - 5) } else { String::new() };
    format!("{}{more}", items.iter().take(5).cloned().collect::<Vec<_>>().join("; "))
}

fn degenerate(m: &TriMesh) -> Result<(), String> {
    let (lo, hi) = m.bounds();
    let limit = DEGENERATE_REL * dist(lo, hi).powi(2);
    let bad: Vec<String> = (0..m.triangles.len())
        .filter(|&t| {
            let [a, b, c] = m.corners(&m.triangles[t]);
            let n = cross(sub(b, a), sub(c, a));
            let twice_area = dot(n, n).sqrt();
            twice_area.is_nan() || twice_area <= limit
        })
        .map(|t| format!("triangle {t} at {}", at(m.centroid(t))))
        .collect();
    if bad.is_empty() { Ok(()) } else { Err(format!("{} degenerate (zero-area) triangles: {}", bad.len(), list(&bad))) }
}

fn closed_manifold(m: &TriMesh, edges: &Edges) -> Result<(), String> {
    let mut sorted: Vec<_> = edges.iter().collect();
    sorted.sort_unstable_by_key(|(k, _)| **k);
    let describe = |(a, b): (u32, u32), uses: &[(usize, bool)]| {
        let tris = uses.iter().map(|u| u.0.to_string()).collect::<Vec<_>>().join(", ");
        format!("edge {a}–{b} at {} (triangles {tris})", at(mid(m.vertices[a as usize], m.vertices[b as usize])))
    };
    let holes: Vec<String> = sorted.iter().filter(|(_, u)| u.len() == 1).map(|(k, u)| describe(**k, u)).collect();
    if !holes.is_empty() {
        return Err(format!(
            "not closed: {} boundary edges (holes), each of one triangle: {}",
            holes.len(),
            list(&holes)
        ));
    }
    let nm: Vec<String> = sorted.iter().filter(|(_, u)| u.len() > 2).map(|(k, u)| describe(**k, u)).collect();
    if !nm.is_empty() {
        return Err(format!("non-manifold: {} edges shared by more than two triangles: {}", nm.len(), list(&nm)));
    }
    Ok(())
}

/// Propagates an orientation over each connected piece from its first triangle; the triangles that disagree with
/// the majority of their piece are reported as flipped.
fn consistent(m: &TriMesh, edges: &Edges) -> Result<(), String> {
    let n = m.triangles.len();
    let mut flip: Vec<Option<bool>> = vec![None; n];
    let mut flipped = Vec::new();
    let mut adj: Vec<Vec<(usize, bool)>> = vec![Vec::new(); n];
    for uses in edges.values() {
        if let [(t, d), (u, e)] = uses[..] {
            // The same direction in both: the two disagree.
            adj[t].push((u, d == e));
            adj[u].push((t, d == e));
        }
    }
    for seed in 0..n {
        if flip[seed].is_some() {
            continue;
        }
        let mut piece = vec![seed];
        flip[seed] = Some(false);
        let mut queue = VecDeque::from([seed]);
        while let Some(t) = queue.pop_front() {
            let ft = flip[t].unwrap_or(false);
            for &(u, differ) in &adj[t] {
                let want = ft ^ differ;
                match flip[u] {
                    None => {
                        flip[u] = Some(want);
                        piece.push(u);
                        queue.push_back(u);
                    }
                    Some(f) if f != want => {
                        return Err(format!(
                            "not orientable: triangles {t} and {u} at {} cannot agree",
                            at(m.centroid(u))
                        ));
                    }
                    _ => {}
                }
            }
        }
        let ones = piece.iter().filter(|&&t| flip[t] == Some(true)).count();
        let minority = ones * 2 <= piece.len();
        flipped.extend(piece.into_iter().filter(|&t| flip[t] == Some(minority)));
    }
    if flipped.is_empty() {
        return Ok(());
    }
    flipped.sort_unstable();
    let items: Vec<String> = flipped.iter().map(|&t| format!("triangle {t} at {}", at(m.centroid(t)))).collect();
    Err(format!(
        "inconsistent orientation: {} flipped faces (each traverses a shared edge in the same direction as its neighbour): {}",
        flipped.len(),
        list(&items)
    ))
}

pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

pub(crate) fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = sub(a, b);
    dot(d, d).sqrt()
}

fn mid(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0, (a[2] + b[2]) / 2.0]
}
