//! Reading a tool mesh from a file, by its extension: `.stl` (binary or ASCII), `.obj`, and the LS-DYNA keyword
//! formats `.k`, `.key`, `.dyn`. Units are those of the file; scale comes later ([`super::Placement`]).

use super::{MeshError, TriMesh, dyna, obj, stl};
use std::path::Path;

/// Reads the mesh in `path`, choosing the reader by the extension (case-insensitive).
pub fn read(path: &Path) -> Result<TriMesh, MeshError> {
    let file = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|source| MeshError::Io { file: file.clone(), source })?;
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    match ext.as_str() {
        "stl" => stl::parse(&file, &bytes),
        "obj" => obj::parse(&file, text(&file, &bytes)?),
        "k" | "key" | "dyn" => dyna::parse(&file, text(&file, &bytes)?),
        _ => Err(MeshError::Format {
            file,
            what: format!("unknown mesh extension `.{ext}`: expected .stl, .obj, .k, .key or .dyn"),
        }),
    }
}

/// The file as UTF-8 text.
pub(crate) fn text<'a>(file: &str, bytes: &'a [u8]) -> Result<&'a str, MeshError> {
    std::str::from_utf8(bytes).map_err(|e| MeshError::Format {
        file: file.to_string(),
        what: format!("not UTF-8 text (byte {}): expected a text mesh file", e.valid_up_to()),
    })
}

/// A parse error at a 1-based line.
pub(crate) fn parse_error(file: &str, line: usize, expected: &str, found: &str) -> MeshError {
    MeshError::Parse { file: file.to_string(), line, expected: expected.to_string(), found: found.trim().to_string() }
}

/// Parses a finite f64 token.
pub(crate) fn number(file: &str, line: usize, tok: Option<&str>, what: &str) -> Result<f64, MeshError> {
    let tok = tok.ok_or_else(|| parse_error(file, line, what, "end of line"))?;
    match tok.trim().parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(parse_error(file, line, what, tok)),
    }
}

/// Refuses a reader's result without triangles.
pub(crate) fn nonempty(m: TriMesh) -> Result<TriMesh, MeshError> {
    if m.triangles.is_empty() {
        return Err(MeshError::Format { file: m.source, what: "no triangles: expected at least one face".into() });
    }
    Ok(m)
}
