//! The tool beside each particle frame: a VTK XML PolyData file (`.vtp`, ASCII) holding one closed polyline (the
//! 2D tool's outline, a few dozen points) or a triangle surface (a 3D mesh tool), listed in the run's `.pvd` as part 1 of the frame's time step, so that ParaView,
//! meshio and VTK show the tool where it was when the particles were written.

use std::fmt::Write as _;
use std::io;
use std::path::Path;

use super::atomic::write_atomic;
use super::text::fmt_f64;

/// Writes the closed polyline through `points` (at least two, every coordinate finite) to `path` atomically, with
/// the time as field data `TimeValue`. Invalid input is refused ([`io::ErrorKind::InvalidInput`]) before any file
/// is created.
pub fn write_outline(path: &Path, time: f64, points: &[[f64; 3]]) -> io::Result<()> {
    if points.len() < 2 {
        return Err(invalid(path, format!("an outline needs at least 2 points, got {}", points.len())));
    }
    // The polyline returns to its first point: closed.
    let ids: Vec<usize> = (0..points.len()).chain(std::iter::once(0)).collect();
    write_polydata(path, time, points, Cells::Lines(&ids))
}

/// Writes the triangles whose corners are `corners` (3 per triangle, every coordinate finite) to `path` atomically
/// as polygons, with the time as field data `TimeValue` (a mesh tool's surface beside a 3D frame).
pub fn write_surface(path: &Path, time: f64, corners: &[[f64; 3]]) -> io::Result<()> {
    if corners.is_empty() || !corners.len().is_multiple_of(3) {
        return Err(invalid(path, format!("a surface needs 3 corners per triangle, got {}", corners.len())));
    }
    let ids: Vec<usize> = (0..corners.len()).collect();
    write_polydata(path, time, corners, Cells::Triangles(&ids))
}

fn invalid(path: &Path, msg: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, format!("{}: {msg}", path.display()))
}

/// The cells of a PolyData piece: one polyline through the ids, or triangles of three ids each.
enum Cells<'a> {
    Lines(&'a [usize]),
    Triangles(&'a [usize]),
}

/// One PolyData piece of `points` and `cells`, ASCII, with the time as field data.
fn write_polydata(path: &Path, time: f64, points: &[[f64; 3]], cells: Cells<'_>) -> io::Result<()> {
    if let Some(i) = points.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
        return Err(invalid(path, format!("point {i} is not finite: {:?}", points[i])));
    }
    if !time.is_finite() {
        return Err(invalid(path, format!("time {time} is not finite")));
    }
    let n = points.len();
    let (tag, ids, offsets): (&str, &[usize], Vec<usize>) = match cells {
        Cells::Lines(ids) => ("Lines", ids, vec![ids.len()]),
        Cells::Triangles(ids) => ("Polys", ids, (1..=ids.len() / 3).map(|k| 3 * k).collect()),
    };
    let (lines, polys) = if tag == "Lines" { (1, 0) } else { (0, offsets.len()) };
    let mut s = String::from("<?xml version=\"1.0\"?>\n");
    s.push_str("<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n");
    s.push_str("  <PolyData>\n    <FieldData>\n");
    // Writing into a String cannot fail.
    let _ = writeln!(
        s,
        "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">{}</DataArray>",
        fmt_f64(time)
    );
    s.push_str("    </FieldData>\n");
    let _ = writeln!(
        s,
        "    <Piece NumberOfPoints=\"{n}\" NumberOfVerts=\"0\" NumberOfLines=\"{lines}\" NumberOfStrips=\"0\" \
         NumberOfPolys=\"{polys}\">"
    );
    s.push_str("      <Points>\n        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n");
    for p in points {
        let _ = writeln!(s, "          {} {} {}", fmt_f64(p[0]), fmt_f64(p[1]), fmt_f64(p[2]));
    }
    let _ = writeln!(s, "        </DataArray>\n      </Points>\n      <{tag}>");
    s.push_str("        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n          ");
    s.push_str(&ids.iter().map(|i| i.to_string()).collect::<Vec<_>>().join(" "));
    s.push_str("\n        </DataArray>\n");
    let offsets = offsets.iter().map(|i| i.to_string()).collect::<Vec<_>>().join(" ");
    let _ = writeln!(s, "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">{offsets}</DataArray>");
    let _ = writeln!(s, "      </{tag}>\n    </Piece>\n  </PolyData>\n</VTKFile>");
    write_atomic(path, s.as_bytes())
}

/// The points of an outline written by [`write_outline`], in order (the closing repeat left out), and its time.
pub fn read_outline(path: &Path) -> io::Result<(f64, Vec<[f64; 3]>)> {
    let text = std::fs::read_to_string(path).map_err(|e| super::atomic::with_path(path, e))?;
    let bad = |msg: &str| io::Error::new(io::ErrorKind::InvalidData, format!("{}: {msg}", path.display()));
    let between = |from: &str, to: &str, after: usize| -> Option<(String, usize)> {
        let a = text[after..].find(from)? + after;
        let start = text[a..].find('>')? + a + 1;
        let end = text[start..].find(to)? + start;
        Some((text[start..end].to_string(), end))
    };
    let (time, at) = between("Name=\"TimeValue\"", "</DataArray>", 0).ok_or_else(|| bad("no TimeValue"))?;
    let time: f64 = time.trim().parse().map_err(|_| bad("TimeValue is not a number"))?;
    let points_at = text[at..].find("<Points>").ok_or_else(|| bad("no <Points>"))? + at;
    let (coords, _) = between("<DataArray", "</DataArray>", points_at).ok_or_else(|| bad("no point coordinates"))?;
    let c: Vec<f64> =
        coords.split_whitespace().map(str::parse).collect::<Result<_, _>>().map_err(|_| bad("bad coordinate"))?;
    if !c.len().is_multiple_of(3) {
        return Err(bad("coordinates are not triples"));
    }
    Ok((time, c.chunks(3).map(|p| [p[0], p[1], p[2]]).collect()))
}
