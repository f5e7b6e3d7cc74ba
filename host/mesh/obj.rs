//! Wavefront OBJ: `v x y z [w]` and `f` with 1-based vertex indices (negative: relative to the vertices read so far,
//! −1 the last), in the forms `i`, `i/t`, `i//n`, `i/t/n`; a polygon of n corners is fanned into n − 2 triangles
//! (0, k, k + 1), which is exact for the convex faces OBJ exporters write. Other statements (vt, vn, g, o, s,
//! usemtl, mtllib, l) are skipped.

use super::read::{nonempty, number, parse_error};
use super::{MeshError, TriMesh};

/// Parses an OBJ file's text.
pub fn parse(file: &str, s: &str) -> Result<TriMesh, MeshError> {
    let mut m = TriMesh { source: file.to_string(), ..Default::default() };
    for (i, raw) in s.lines().enumerate() {
        let line = i + 1;
        let mut tok = raw.split_whitespace();
        match tok.next() {
            Some("v") => {
                let mut v = [0.0; 3];
                for (c, x) in v.iter_mut().enumerate() {
                    *x = number(file, line, tok.next(), &format!("vertex coordinate {}", ["x", "y", "z"][c]))?;
                }
                m.vertices.push(v);
            }
            Some("f") => {
                let idx = tok.map(|t| index(file, line, t, m.vertices.len())).collect::<Result<Vec<u32>, _>>()?;
                if idx.len() < 3 {
                    return Err(parse_error(file, line, "a face of at least 3 vertices", raw));
                }
                for k in 1..idx.len() - 1 {
                    m.triangles.push([idx[0], idx[k], idx[k + 1]]);
                }
            }
            _ => {}
        }
    }
    nonempty(m)
}

/// The 0-based vertex index of a face corner `i[/t[/n]]`.
fn index(file: &str, line: usize, tok: &str, count: usize) -> Result<u32, MeshError> {
    let expected = || format!("a vertex index in 1..={count} or -{count}..=-1 (i, i/t, i//n or i/t/n)");
    let head = tok.split('/').next().unwrap_or("");
    let i: i64 = head.parse().map_err(|_| parse_error(file, line, &expected(), tok))?;
    let zero_based = if i > 0 { i - 1 } else { count as i64 + i };
    if i == 0 || zero_based < 0 || zero_based >= count as i64 {
        return Err(parse_error(file, line, &expected(), tok));
    }
    Ok(zero_based as u32)
}
