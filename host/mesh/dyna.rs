//! The LS-DYNA keyword mesh: `*NODE` (nid x y z), `*ELEMENT_SHELL` (eid pid n1 n2 n3 n4: a triangle when n4 is
//! absent or equals n3, else a quadrilateral split along n1–n3) and `*ELEMENT_SOLID` (eid pid n1 … n8: a
//! tetrahedron as 4 nodes or as 8 with n4 = n5 = … = n8, or a hexahedron of 8 distinct nodes). Of solids only the
//! boundary surface is kept: the faces used by exactly one element, oriented outward (each element's faces are
//! taken outward from its own signed volume, so elements of either handedness give an outward surface). Fields
//! are free format (separated by blanks or commas); a line that does not split into the fields is read in the
//! fixed columns of the manual (8 for ids, 16 for coordinates). `$` lines are comments, other keywords skipped.

use super::read::{nonempty, parse_error};
use super::{MeshError, TriMesh};
use std::collections::HashMap;

/// Which block the lines belong to.
#[derive(Clone, Copy, PartialEq)]
enum Block {
    Node,
    Shell,
    Solid,
    Other,
}

/// Parses a keyword file's text.
pub fn parse(file: &str, s: &str) -> Result<TriMesh, MeshError> {
    let mut block = Block::Other;
    let mut ids: HashMap<i64, u32> = HashMap::new();
    let mut m = TriMesh { source: file.to_string(), ..Default::default() };
    // Element faces as (node ids, line), resolved once every node is read (nodes may follow elements).
    let mut shells: Vec<(Vec<i64>, usize)> = Vec::new();
    let mut solids: Vec<(Vec<i64>, usize)> = Vec::new();
    for (i, raw) in s.lines().enumerate() {
        let line = i + 1;
        if raw.starts_with('$') || raw.trim().is_empty() {
            continue;
        }
        if let Some(key) = raw.strip_prefix('*') {
            block = match key.trim().to_ascii_uppercase().as_str() {
                "NODE" => Block::Node,
                "ELEMENT_SHELL" => Block::Shell,
                "ELEMENT_SOLID" => Block::Solid,
                _ => Block::Other,
            };
            continue;
        }
        match block {
            Block::Node => {
                let f = fields(raw, &[8, 16, 16, 16], 4);
                let nid = int(file, line, f.first(), "a node id")?;
                let mut v = [0.0; 3];
                for (c, x) in v.iter_mut().enumerate() {
                    *x = super::read::number(
                        file,
                        line,
                        f.get(c + 1).map(|s| s.as_str()),
                        &format!("node {nid} coordinate {}", ["x", "y", "z"][c]),
                    )?;
                }
                if ids.insert(nid, m.vertices.len() as u32).is_some() {
                    return Err(parse_error(file, line, "a node id not defined before", &nid.to_string()));
                }
                m.vertices.push(v);
            }
            Block::Shell | Block::Solid => {
                let f = fields(raw, &[8; 10], if block == Block::Shell { 5 } else { 6 });
                let mut n = Vec::new();
                for k in 2..f.len() {
                    n.push(int(file, line, f.get(k), "a node id")?);
                }
                let (min, list) = if block == Block::Shell { (3, &mut shells) } else { (4, &mut solids) };
                if n.len() < min {
                    return Err(parse_error(file, line, &format!("eid, pid and at least {min} node ids"), raw));
                }
                list.push((n, line));
            }
            Block::Other => {}
        }
    }
    let node = |id: i64, line: usize| {
        ids.get(&id).copied().ok_or_else(|| parse_error(file, line, "a node id defined in *NODE", &id.to_string()))
    };
    for (n, line) in &shells {
        let n = n.iter().map(|&id| node(id, *line)).collect::<Result<Vec<_>, _>>()?;
        if n.len() == 3 || n[3] == n[2] {
            m.triangles.push([n[0], n[1], n[2]]);
        } else {
            m.triangles.push([n[0], n[1], n[2]]);
            m.triangles.push([n[0], n[2], n[3]]);
        }
    }
    let mut faces: HashMap<Vec<u32>, (Vec<u32>, usize)> = HashMap::new();
    for (n, line) in &solids {
        let n = n.iter().map(|&id| node(id, *line)).collect::<Result<Vec<_>, _>>()?;
        for face in element_faces(file, *line, &m.vertices, &n)? {
            let mut key = face.clone();
            key.sort_unstable();
            faces.entry(key).or_insert((face, 0)).1 += 1;
        }
    }
    let mut boundary: Vec<Vec<u32>> = faces.into_values().filter(|(_, c)| *c == 1).map(|(f, _)| f).collect();
    // The hash map's order is arbitrary: sort so that the surface is the same on every read.
    boundary.sort_unstable();
    for f in boundary {
        m.triangles.push([f[0], f[1], f[2]]);
        if f.len() == 4 {
            m.triangles.push([f[0], f[2], f[3]]);
        }
    }
    nonempty(m)
}

/// The outward faces of a tetrahedron or hexahedron (node indices).
fn element_faces(file: &str, line: usize, v: &[[f64; 3]], n: &[u32]) -> Result<Vec<Vec<u32>>, MeshError> {
    let tet = n.len() == 4 || (n.len() == 8 && n[4..].iter().all(|&x| x == n[3]));
    let mut faces: Vec<Vec<u32>> = if tet {
        let [a, b, c, d] = [n[0], n[1], n[2], n[3]];
        vec![vec![a, c, b], vec![a, b, d], vec![a, d, c], vec![b, c, d]]
    } else if n.len() == 8 && distinct(n) {
        // Nodes 1–4 the bottom, 5–8 the top above them (LS-DYNA's numbering).
        let q = |i: [usize; 4]| i.iter().map(|&k| n[k]).collect::<Vec<u32>>();
        vec![q([0, 3, 2, 1]), q([4, 5, 6, 7]), q([0, 1, 5, 4]), q([1, 2, 6, 5]), q([2, 3, 7, 6]), q([3, 0, 4, 7])]
    } else {
        let found = n.iter().map(|x| x.to_string()).collect::<Vec<_>>().join(" ");
        return Err(parse_error(
            file,
            line,
            "a tetrahedron (4 nodes, or 8 with n4 = n5 = … = n8) or a hexahedron of 8 distinct nodes",
            &format!("node indices {found}"),
        ));
    };
    if tet && !distinct(&n[..4]) {
        return Err(parse_error(file, line, "4 distinct tetrahedron nodes", "a repeated node"));
    }
    // The element's signed volume from its outward-if-positive faces (divergence theorem over its faces).
    let vol: f64 = faces.iter().map(|f| fan_volume(v, f)).sum();
    if vol < 0.0 {
        faces.iter_mut().for_each(|f| f.reverse());
    }
    Ok(faces)
}

/// 6 × the signed volume of the cone from the origin to a planar polygon, fanned from its first corner.
fn fan_volume(v: &[[f64; 3]], f: &[u32]) -> f64 {
    let p = |i: u32| v[i as usize];
    (1..f.len() - 1)
        .map(|k| {
            let (a, b, c) = (p(f[0]), p(f[k]), p(f[k + 1]));
            a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) + a[2] * (b[0] * c[1] - b[1] * c[0])
        })
        .sum()
}

fn distinct(n: &[u32]) -> bool {
    (0..n.len()).all(|i| (i + 1..n.len()).all(|j| n[i] != n[j]))
}

/// A data line's fields: split on commas or blanks; a line with fewer than `min` such fields is cut into the fixed
/// column widths instead.
fn fields(raw: &str, widths: &[usize], min: usize) -> Vec<String> {
    let free: Vec<String> = if raw.contains(',') {
        raw.split(',').map(|s| s.trim().to_string()).filter(|s| !s.is_empty()).collect()
    } else {
        raw.split_whitespace().map(str::to_string).collect()
    };
    if free.len() >= min {
        return free;
    }
    let mut out = Vec::new();
    let mut at = 0;
    for &w in widths {
        let end = (at + w).min(raw.len());
        if let Some(s) = raw.get(at..end)
            && !s.trim().is_empty()
        {
            out.push(s.trim().to_string());
        }
        at = end;
    }
    out
}

fn int(file: &str, line: usize, tok: Option<&String>, what: &str) -> Result<i64, MeshError> {
    let tok = tok.ok_or_else(|| parse_error(file, line, what, "end of line"))?;
    tok.parse().map_err(|_| parse_error(file, line, what, tok))
}
