//! The tool's outline beside each particle frame: a VTK XML PolyData file (`.vtp`, ASCII: a few dozen points)
//! holding one closed polyline, listed in the run's `.pvd` as part 1 of the frame's time step, so that ParaView,
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
    let bad = |msg: String| io::Error::new(io::ErrorKind::InvalidInput, format!("{}: {msg}", path.display()));
    if points.len() < 2 {
        return Err(bad(format!("an outline needs at least 2 points, got {}", points.len())));
    }
    if let Some(i) = points.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
        return Err(bad(format!("outline point {i} is not finite: {:?}", points[i])));
    }
    if !time.is_finite() {
        return Err(bad(format!("time {time} is not finite")));
    }
    let n = points.len();
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
        "    <Piece NumberOfPoints=\"{n}\" NumberOfVerts=\"0\" NumberOfLines=\"1\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">"
    );
    s.push_str("      <Points>\n        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n");
    for p in points {
        let _ = writeln!(s, "          {} {} {}", fmt_f64(p[0]), fmt_f64(p[1]), fmt_f64(p[2]));
    }
    s.push_str("        </DataArray>\n      </Points>\n      <Lines>\n");
    s.push_str("        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n          ");
    // The polyline returns to its first point: closed.
    let ids: Vec<String> = (0..n).chain(std::iter::once(0)).map(|i| i.to_string()).collect();
    s.push_str(&ids.join(" "));
    s.push_str("\n        </DataArray>\n");
    let _ = writeln!(s, "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">{}</DataArray>", n + 1);
    s.push_str("      </Lines>\n    </Piece>\n  </PolyData>\n</VTKFile>\n");
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
