//! STL, binary and ASCII. Binary: an 80-byte header, a little-endian u32 count, and 50 bytes per triangle (normal,
//! three vertices as f32, a u16 attribute). A file whose size is exactly 84 + 50·count is binary, whatever its
//! header says (binary files often begin with "solid"); any other is read as ASCII (`solid` … `facet normal` …
//! `outer loop`, three `vertex x y z`, `endloop`, `endfacet` … `endsolid`). The stored normals are ignored: the
//! orientation is the vertex order. Every triangle has its own three vertices; [`super::weld`] joins them.

use super::read::{nonempty, number, parse_error, text};
use super::{MeshError, TriMesh};

/// Parses an STL file's bytes.
pub fn parse(file: &str, bytes: &[u8]) -> Result<TriMesh, MeshError> {
    if bytes.len() >= 84 {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        if n.checked_mul(50).and_then(|b| b.checked_add(84)) == Some(bytes.len()) {
            return binary(file, &bytes[84..], n);
        }
    }
    if std::str::from_utf8(bytes).is_err() {
        let count = bytes.get(80..84).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]));
        return Err(MeshError::Format {
            file: file.into(),
            what: format!(
                "neither ASCII nor binary STL: {} bytes, header count {count:?}: expected 84 + 50·count bytes",
                bytes.len()
            ),
        });
    }
    ascii(file, text(file, bytes)?)
}

fn binary(file: &str, body: &[u8], n: usize) -> Result<TriMesh, MeshError> {
    let mut m = TriMesh { source: file.to_string(), ..Default::default() };
    for (t, rec) in body.chunks_exact(50).take(n).enumerate() {
        for k in 0..3 {
            let mut v = [0.0; 3];
            for (c, x) in v.iter_mut().enumerate() {
                let o = 12 + 12 * k + 4 * c;
                *x = f32::from_le_bytes([rec[o], rec[o + 1], rec[o + 2], rec[o + 3]]) as f64;
            }
            if v.iter().any(|x| !x.is_finite()) {
                return Err(MeshError::Format { file: file.into(), what: format!("triangle {t}: non-finite vertex") });
            }
            m.vertices.push(v);
        }
        let b = 3 * t as u32;
        m.triangles.push([b, b + 1, b + 2]);
    }
    nonempty(m)
}

fn ascii(file: &str, s: &str) -> Result<TriMesh, MeshError> {
    let mut m = TriMesh { source: file.to_string(), ..Default::default() };
    let mut corners = 0usize;
    let mut started = false;
    for (i, raw) in s.lines().enumerate() {
        let line = i + 1;
        let mut tok = raw.split_whitespace();
        let Some(key) = tok.next() else { continue };
        match key.to_ascii_lowercase().as_str() {
            "solid" if !started => started = true,
            _ if !started => {
                return Err(parse_error(file, line, "`solid` (an ASCII STL) or a binary STL of 84 + 50·n bytes", raw));
            }
            "vertex" => {
                let mut v = [0.0; 3];
                for (c, x) in v.iter_mut().enumerate() {
                    *x = number(file, line, tok.next(), &format!("vertex coordinate {}", ["x", "y", "z"][c]))?;
                }
                m.vertices.push(v);
                corners += 1;
            }
            "endloop" => {
                if corners != 3 {
                    return Err(parse_error(file, line, "3 vertices per facet", &format!("{corners} vertices")));
                }
                let b = m.vertices.len() as u32 - 3;
                m.triangles.push([b, b + 1, b + 2]);
                corners = 0;
            }
            "facet" | "outer" | "endfacet" | "endsolid" | "solid" => {}
            _ => return Err(parse_error(file, line, "facet, outer loop, vertex, endloop, endfacet or endsolid", raw)),
        }
    }
    if corners != 0 {
        return Err(parse_error(file, s.lines().count(), "`endloop` closing the last facet", "end of file"));
    }
    nonempty(m)
}
