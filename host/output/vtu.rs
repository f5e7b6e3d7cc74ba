//! Particle frames as binary VTK XML unstructured grids (.vtu), which ParaView opens directly.
//!
//! Layout (VTK XML file format version 1.0): every particle is a `VTK_VERTEX` cell (type 1) so that ParaView
//! renders the points without a glyph filter; all arrays are little-endian binary in one `<AppendedData>` block,
//! in one of two [`Encoding`]s:
//!
//! - `raw` (the default): each array prefixed by its byte count as a UInt64 (`header_type="UInt64"`, so frames
//!   above 4 GiB work); the XML `offset` attributes are byte offsets into the block. The fastest form to write and
//!   to read, exact; ParaView and VTK read it, meshio does not.
//! - `base64-zlib`: VTK's compressed layout (`compressor="vtkZLibDataCompressor"`): each array cut into blocks of
//!   32 KiB, each block zlib-compressed; a UInt64 header (number of blocks, block size, size of the last partial
//!   block or 0, each block's compressed size) base64-encoded on its own, then the compressed blocks base64-encoded
//!   together; the offsets count base64 characters. Exact too, smaller, and read by meshio as well.
//!
//! The frame time goes into `<FieldData>` twice: as `TimeValue`, which VTK ≥ 8.2 readers turn into the
//! data set's time (ParaView's file-series reader then orders frames by it), and as `TIME`, the older convention
//! (VisIt, legacy VTK). Both are Float64 with one tuple.
//!
//! [`read`] reads back the files [`write_encoded`] produces (both encodings), for tests and post-processing in
//! Rust; it is not a general VTU reader.

use std::borrow::Cow;
use std::fs;
use std::io::{self, Read, Write};
use std::path::Path;

use bytemuck::Pod;

use super::atomic::{with_path, write_atomic_with};
use super::base64;
use super::text::{escape_attr, tags, unescape_attr};

/// How a frame's appended data is stored (the module's documentation gives both layouts).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub enum Encoding {
    #[default]
    #[serde(rename = "raw")]
    Raw,
    #[serde(rename = "base64-zlib")]
    Base64Zlib,
}

impl Encoding {
    /// The names of the scene key `output.vtu_encoding`.
    pub const NAMES: [&str; 2] = ["raw", "base64-zlib"];

    pub fn from_name(name: &str) -> Option<Encoding> {
        match name {
            "raw" => Some(Encoding::Raw),
            "base64-zlib" => Some(Encoding::Base64Zlib),
            _ => None,
        }
    }
}

/// Uncompressed bytes per zlib block (VTK's default block size).
const ZLIB_BLOCK: usize = 1 << 15;

/// Field-data names written from [`Frame::time`]; a caller's field data may not use them.
pub const RESERVED_FIELD_NAMES: [&str; 2] = ["TimeValue", "TIME"];

/// Borrowed array values. Symmetric tensors are passed as 6 (or 9) components by the caller; ParaView's order for
/// 6 components is xx, yy, zz, xy, yz, xz.
#[derive(Clone, Copy, Debug)]
pub enum Values<'a> {
    F32(&'a [f32]),
    F64(&'a [f64]),
    U32(&'a [u32]),
    I32(&'a [i32]),
}

impl Values<'_> {
    /// Number of scalars (tuples × components).
    pub fn len(&self) -> usize {
        match self {
            Values::F32(v) => v.len(),
            Values::F64(v) => v.len(),
            Values::U32(v) => v.len(),
            Values::I32(v) => v.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn vtk_type(&self) -> &'static str {
        match self {
            Values::F32(_) => "Float32",
            Values::F64(_) => "Float64",
            Values::U32(_) => "UInt32",
            Values::I32(_) => "Int32",
        }
    }

    fn byte_len(&self) -> usize {
        match self {
            Values::F32(v) => size_of_val(*v),
            Values::F64(v) => size_of_val(*v),
            Values::U32(v) => size_of_val(*v),
            Values::I32(v) => size_of_val(*v),
        }
    }

    fn write_to(&self, w: &mut dyn Write) -> io::Result<()> {
        match self {
            Values::F32(v) => write_le(w, v),
            Values::F64(v) => write_le(w, v),
            Values::U32(v) => write_le(w, v),
            Values::I32(v) => write_le(w, v),
        }
    }
}

/// A named per-particle array: `values.len() == n * components`.
#[derive(Clone, Copy, Debug)]
pub struct Array<'a> {
    pub name: &'a str,
    pub components: usize,
    pub values: Values<'a>,
}

/// One output frame of n particles.
#[derive(Clone, Debug)]
pub struct Frame<'a> {
    /// Simulation time, written as the field data `TimeValue` and `TIME`.
    pub time: f64,
    /// Positions, 3 components per particle (2D runs pass z = 0), `F32` or `F64`.
    pub points: Values<'a>,
    pub point_data: Vec<Array<'a>>,
    /// Further per-frame scalars (e.g. `STEP`), written as Float64 field data; not `TIME` or `TimeValue`.
    pub field_data: Vec<(&'a str, f64)>,
}

/// Owned array values, as read back.
#[derive(Clone, Debug, PartialEq)]
pub enum OwnedValues {
    F32(Vec<f32>),
    F64(Vec<f64>),
    U32(Vec<u32>),
    I32(Vec<i32>),
}

impl OwnedValues {
    pub fn len(&self) -> usize {
        self.as_values().len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The values as f64 when they are floating point (`F32` widened exactly); `None` for integers.
    pub fn floats(&self) -> Option<Vec<f64>> {
        match self {
            OwnedValues::F64(v) => Some(v.clone()),
            OwnedValues::F32(v) => Some(v.iter().map(|&x| f64::from(x)).collect()),
            _ => None,
        }
    }

    pub fn as_values(&self) -> Values<'_> {
        match self {
            OwnedValues::F32(v) => Values::F32(v),
            OwnedValues::F64(v) => Values::F64(v),
            OwnedValues::U32(v) => Values::U32(v),
            OwnedValues::I32(v) => Values::I32(v),
        }
    }
}

/// A frame read back by [`read`].
#[derive(Clone, Debug)]
pub struct ReadFrame {
    pub n: usize,
    /// `TimeValue` (or `TIME`) from the field data.
    pub time: Option<f64>,
    pub points: OwnedValues,
    /// (name, components, values), in file order.
    pub point_data: Vec<(String, usize, OwnedValues)>,
    /// Field data other than `TimeValue` and `TIME`, in file order.
    pub field_data: Vec<(String, f64)>,
}

/// One appended block, in file order.
enum Block<'a> {
    Scalar(f64),
    Values(Values<'a>),
    Connectivity,
    Offsets,
    Types,
}

impl Block<'_> {
    /// Its data's bytes, for n points.
    fn byte_len(&self, n: usize) -> usize {
        match self {
            Block::Scalar(_) => 8,
            Block::Values(v) => v.byte_len(),
            Block::Connectivity | Block::Offsets => 8 * n,
            Block::Types => n,
        }
    }

    /// Writes its data (without a length prefix), little-endian.
    fn write_to(&self, w: &mut dyn Write, n: usize) -> io::Result<()> {
        match self {
            Block::Scalar(x) => w.write_all(&x.to_le_bytes()),
            Block::Values(v) => v.write_to(w),
            Block::Connectivity => write_counting(w, 0, n),
            Block::Offsets => write_counting(w, 1, n),
            Block::Types => write_types(w, n),
        }
    }
}

/// Writes `frame` to `path` atomically with raw appended data ([`write_encoded`]).
pub fn write(path: &Path, frame: &Frame) -> io::Result<()> {
    write_encoded(path, frame, Encoding::Raw)
}

/// Writes `frame` to `path` atomically in `encoding`. The frame is validated first, so an invalid frame creates
/// no file: lengths, component counts and names (non-empty, unique) are checked and refused with
/// [`io::ErrorKind::InvalidInput`] naming the array.
pub fn write_encoded(path: &Path, frame: &Frame, encoding: Encoding) -> io::Result<()> {
    const END: &[u8] = b"\n  </AppendedData>\n</VTKFile>\n";
    match encoding {
        Encoding::Raw => {
            let (header, blocks, n) =
                layout(frame, encoding, &mut |_, bytes| 8 + bytes).map_err(|m| invalid_input(path, &m))?;
            write_atomic_with(path, |w| {
                w.write_all(header.as_bytes())?;
                for block in &blocks {
                    w.write_all(&(block.byte_len(n) as u64).to_le_bytes())?;
                    block.write_to(w, n)?;
                }
                w.write_all(END)
            })
        }
        Encoding::Base64Zlib => {
            // The offsets depend on the compressed sizes: compress every block first, then lay the header out.
            let (_, blocks, n) = layout(frame, encoding, &mut |_, bytes| bytes).map_err(|m| invalid_input(path, &m))?;
            let mut raw = Vec::new();
            let mut coded = Vec::with_capacity(blocks.len());
            for block in &blocks {
                raw.clear();
                block.write_to(&mut raw, n)?;
                coded.push(zlib_base64(&raw)?);
            }
            let (header, _, _) =
                layout(frame, encoding, &mut |k, _| coded[k].len()).map_err(|m| invalid_input(path, &m))?;
            write_atomic_with(path, |w| {
                w.write_all(header.as_bytes())?;
                coded.iter().try_for_each(|c| w.write_all(c))?;
                w.write_all(END)
            })
        }
    }
}

/// One array in VTK's zlib layout: the UInt64 header (blocks, block size, last partial block size or 0, each
/// block's compressed size), base64-encoded on its own, then the compressed blocks, base64-encoded together.
fn zlib_base64(raw: &[u8]) -> io::Result<Vec<u8>> {
    let mut sizes = Vec::new();
    let mut data = Vec::new();
    for chunk in raw.chunks(ZLIB_BLOCK) {
        let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
        z.write_all(chunk)?;
        let c = z.finish()?;
        sizes.push(c.len() as u64);
        data.extend_from_slice(&c);
    }
    let words = [sizes.len() as u64, ZLIB_BLOCK as u64, (raw.len() % ZLIB_BLOCK) as u64];
    let header: Vec<u8> = words.iter().chain(&sizes).flat_map(|w| w.to_le_bytes()).collect();
    let mut out = Vec::with_capacity(base64::encoded_len(header.len()) + base64::encoded_len(data.len()));
    base64::encode(&header, &mut out);
    base64::encode(&data, &mut out);
    Ok(out)
}

fn invalid_input(path: &Path, msg: &str) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, format!("{}: {msg}", path.display()))
}

/// Validates the frame and builds the XML header (up to and including the `_` that starts the appended data)
/// and the list of blocks in the order of their offsets; `stored(k, bytes)` is the length in the appended data
/// of block `k`, whose data has `bytes` bytes.
fn layout<'a>(
    frame: &Frame<'a>,
    encoding: Encoding,
    stored: &mut dyn FnMut(usize, usize) -> usize,
) -> Result<(String, Vec<Block<'a>>, usize), String> {
    use std::fmt::Write as _;

    if !matches!(frame.points, Values::F32(_) | Values::F64(_)) {
        return Err(format!("points must be Float32 or Float64, not {}", frame.points.vtk_type()));
    }
    if !frame.points.len().is_multiple_of(3) {
        return Err(format!("points: {} values is not a multiple of 3 components", frame.points.len()));
    }
    let n = frame.points.len() / 3;
    check_names("field data", frame.field_data.iter().map(|(name, _)| *name))?;
    if let Some((name, _)) = frame.field_data.iter().find(|(name, _)| RESERVED_FIELD_NAMES.contains(name)) {
        return Err(format!("field data \"{name}\" is reserved: it is written from Frame::time"));
    }
    check_names("point array", frame.point_data.iter().map(|a| a.name))?;
    for a in &frame.point_data {
        if a.components == 0 {
            return Err(format!("point array \"{}\": 0 components", a.name));
        }
        if n.checked_mul(a.components) != Some(a.values.len()) {
            return Err(format!(
                "point array \"{}\": {} values, expected {n} particles × {} components",
                a.name,
                a.values.len(),
                a.components
            ));
        }
    }

    let mut blocks = Vec::new();
    let mut offset = 0usize;
    // Declares the next block and returns its offset.
    let mut push = |block: Block<'a>, bytes: usize| {
        let at = offset;
        offset += stored(blocks.len(), bytes);
        blocks.push(block);
        at
    };
    let (compressor, appended) = match encoding {
        Encoding::Raw => ("", "raw"),
        Encoding::Base64Zlib => (r#" compressor="vtkZLibDataCompressor""#, "base64"),
    };

    let mut h = String::new();
    let w = &mut h;
    // Writing into a String cannot fail, so the fmt::Results below are ignored.
    let _ = writeln!(w, r#"<?xml version="1.0"?>"#);
    let _ = writeln!(
        w,
        r#"<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64"{compressor}>"#
    );
    let _ = writeln!(w, "  <UnstructuredGrid>");
    let _ = writeln!(w, "    <FieldData>");
    let scalars = RESERVED_FIELD_NAMES.iter().map(|name| (*name, frame.time)).chain(frame.field_data.iter().copied());
    for (name, x) in scalars {
        let at = push(Block::Scalar(x), 8);
        let name = escape_attr(name);
        let _ = writeln!(
            w,
            r#"      <DataArray type="Float64" Name="{name}" NumberOfTuples="1" format="appended" offset="{at}"/>"#
        );
    }
    let _ = writeln!(w, "    </FieldData>");
    let _ = writeln!(w, r#"    <Piece NumberOfPoints="{n}" NumberOfCells="{n}">"#);
    let _ = writeln!(w, "      <PointData>");
    for a in &frame.point_data {
        let at = push(Block::Values(a.values), a.values.byte_len());
        let (ty, name, c) = (a.values.vtk_type(), escape_attr(a.name), a.components);
        let _ = writeln!(
            w,
            r#"        <DataArray type="{ty}" Name="{name}" NumberOfComponents="{c}" format="appended" offset="{at}"/>"#
        );
    }
    let _ = writeln!(w, "      </PointData>");
    let _ = writeln!(w, "      <Points>");
    let at = push(Block::Values(frame.points), frame.points.byte_len());
    let ty = frame.points.vtk_type();
    let _ = writeln!(
        w,
        r#"        <DataArray type="{ty}" Name="Points" NumberOfComponents="3" format="appended" offset="{at}"/>"#
    );
    let _ = writeln!(w, "      </Points>");
    let _ = writeln!(w, "      <Cells>");
    let cells = [
        (Block::Connectivity, "Int64", "connectivity", 8 * n),
        (Block::Offsets, "Int64", "offsets", 8 * n),
        (Block::Types, "UInt8", "types", n),
    ];
    for (block, ty, name, bytes) in cells {
        let at = push(block, bytes);
        let _ = writeln!(w, r#"        <DataArray type="{ty}" Name="{name}" format="appended" offset="{at}"/>"#);
    }
    let _ = writeln!(w, "      </Cells>");
    let _ = writeln!(w, "    </Piece>");
    let _ = writeln!(w, "  </UnstructuredGrid>");
    let _ = writeln!(w, r#"  <AppendedData encoding="{appended}">"#);
    let _ = write!(w, "   _");
    Ok((h, blocks, n))
}

fn check_names<'a>(what: &str, names: impl Iterator<Item = &'a str>) -> Result<(), String> {
    let mut seen = std::collections::HashSet::new();
    for name in names {
        if name.is_empty() {
            return Err(format!("{what} with an empty name"));
        }
        if !seen.insert(name) {
            return Err(format!("{what} \"{name}\" appears twice"));
        }
    }
    Ok(())
}

/// Writes a Pod slice as little-endian bytes: a straight copy on little-endian hosts, byte-swapped otherwise.
fn write_le<T: Pod>(w: &mut dyn Write, values: &[T]) -> io::Result<()> {
    if cfg!(target_endian = "little") {
        return w.write_all(bytemuck::cast_slice(values));
    }
    for chunk in values.chunks(CHUNK) {
        let mut bytes = bytemuck::cast_slice::<T, u8>(chunk).to_vec();
        bytes.chunks_exact_mut(size_of::<T>()).for_each(<[u8]>::reverse);
        w.write_all(&bytes)?;
    }
    Ok(())
}

/// Elements per chunk when an array is generated or converted on the fly (bounded memory for any n).
const CHUNK: usize = 1 << 14;

/// `first, first + 1, …` (n values) as Int64: the connectivity (from 0) and offsets (from 1) of vertex cells.
fn write_counting(w: &mut dyn Write, first: i64, n: usize) -> io::Result<()> {
    let mut buf = Vec::with_capacity(CHUNK.min(n));
    let mut next = first;
    for len in (0..n).step_by(CHUNK).map(|start| CHUNK.min(n - start)) {
        buf.clear();
        buf.extend((0..len as i64).map(|i| next + i));
        next += len as i64;
        write_le(w, &buf)?;
    }
    Ok(())
}

/// n cell types, all `VTK_VERTEX` (1).
fn write_types(w: &mut dyn Write, n: usize) -> io::Result<()> {
    const VERTEX: [u8; CHUNK] = [1; CHUNK];
    for start in (0..n).step_by(CHUNK) {
        w.write_all(&VERTEX[..CHUNK.min(n - start)])?;
    }
    Ok(())
}

/// Reads a frame written by [`write`]. Anything else (other layouts, encodings, byte orders) is refused with
/// [`io::ErrorKind::InvalidData`] naming the path and what was wrong.
pub fn read(path: &Path) -> io::Result<ReadFrame> {
    let bytes = fs::read(path).map_err(|e| with_path(path, e))?;
    parse(&bytes).map_err(|msg| io::Error::new(io::ErrorKind::InvalidData, format!("{}: {msg}", path.display())))
}

/// A `<DataArray>` declaration of the header.
struct Decl<'a> {
    section: &'a str,
    ty: &'a str,
    name: String,
    components: usize,
    offset: usize,
}

const SECTIONS: [&str; 5] = ["FieldData", "PointData", "CellData", "Points", "Cells"];

fn parse(bytes: &[u8]) -> Result<ReadFrame, String> {
    const RAW: &[u8] = br#"<AppendedData encoding="raw">"#;
    const BASE64: &[u8] = br#"<AppendedData encoding="base64">"#;
    let find = |mark: &[u8]| bytes.windows(mark.len()).position(|w| w == mark).map(|at| (at, at + mark.len()));
    let (encoding, at, after) = match (find(RAW), || find(BASE64)) {
        (Some((at, after)), _) => (Encoding::Raw, at, after),
        (None, base64) => {
            let (at, after) = base64().ok_or("no raw or base64 <AppendedData> element")?;
            (Encoding::Base64Zlib, at, after)
        }
    };
    let header = std::str::from_utf8(&bytes[..at]).map_err(|_| "the XML header is not UTF-8")?;
    let underscore = bytes[after..]
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .map(|i| after + i)
        .filter(|&i| bytes[i] == b'_')
        .ok_or("no '_' at the start of the appended data")?;
    let data = &bytes[underscore + 1..];

    let (n, decls) = declarations(header, encoding)?;

    let mut end = 0; // end of the last block, to check what follows the data
    let mut block = |offset: usize| -> Result<Cow<'_, [u8]>, String> {
        let (bytes, stop) = match encoding {
            Encoding::Raw => raw_block(data, offset).map(|(b, stop)| (Cow::Borrowed(b), stop))?,
            Encoding::Base64Zlib => zlib_base64_block(data, offset).map(|(b, stop)| (Cow::Owned(b), stop))?,
        };
        end = end.max(stop);
        Ok(bytes)
    };

    let mut time = None;
    let mut field_data = Vec::new();
    let mut points = None;
    let mut point_data = Vec::new();
    let (mut connectivity, mut offsets, mut types) = (None, None, None);
    for d in &decls {
        let bytes = block(d.offset)?;
        let bytes = bytes.as_ref();
        let what = format!("{} array \"{}\"", d.section, d.name);
        match d.section {
            "FieldData" => {
                let x = match (d.ty, decode::<f64>(bytes, &what)?.as_slice()) {
                    ("Float64", &[x]) => x,
                    _ => return Err(format!("{what}: expected one Float64 value")),
                };
                if RESERVED_FIELD_NAMES.contains(&d.name.as_str()) {
                    if time.is_some_and(|t: f64| t.to_bits() != x.to_bits()) {
                        return Err("TimeValue and TIME differ".into());
                    }
                    time = Some(x);
                } else {
                    field_data.push((d.name.clone(), x));
                }
            }
            "PointData" | "Points" => {
                let values = match d.ty {
                    "Float32" => OwnedValues::F32(decode(bytes, &what)?),
                    "Float64" => OwnedValues::F64(decode(bytes, &what)?),
                    "UInt32" => OwnedValues::U32(decode(bytes, &what)?),
                    "Int32" => OwnedValues::I32(decode(bytes, &what)?),
                    ty => return Err(format!("{what}: unsupported type {ty}")),
                };
                if d.components == 0 || n.checked_mul(d.components) != Some(values.len()) {
                    return Err(format!(
                        "{what}: {} values for {n} points × {} components",
                        values.len(),
                        d.components
                    ));
                }
                if d.section == "PointData" {
                    point_data.push((d.name.clone(), d.components, values));
                } else if points.is_some()
                    || d.components != 3
                    || matches!(values, OwnedValues::U32(_) | OwnedValues::I32(_))
                {
                    return Err(format!("{what}: expected one Float32 or Float64 array of 3 components"));
                } else {
                    points = Some(values);
                }
            }
            "Cells" => match (d.name.as_str(), d.ty) {
                ("connectivity", "Int64") => connectivity = Some(decode::<i64>(bytes, &what)?),
                ("offsets", "Int64") => offsets = Some(decode::<i64>(bytes, &what)?),
                ("types", "UInt8") => types = Some(bytes.to_vec()),
                _ => return Err(format!("{what}: unexpected {} array in Cells", d.ty)),
            },
            s => return Err(format!("unexpected <DataArray> in {s}")),
        }
    }
    let is_count = |v: Option<Vec<i64>>, first: i64| {
        v.is_some_and(|v| v.len() == n && v.iter().zip(first..).all(|(&a, b)| a == b))
    };
    if !is_count(connectivity, 0)
        || !is_count(offsets, 1)
        || !types.is_some_and(|t| t.len() == n && t.iter().all(|&t| t == 1))
    {
        return Err("the cells are not one vertex per point (connectivity 0..n, offsets 1..=n, types 1)".into());
    }
    let tail = std::str::from_utf8(&data[end..]).map_err(|_| "trailing bytes after the data are not text")?;
    if tail.trim_end().strip_suffix("</VTKFile>").is_none() {
        return Err("the file does not end with </VTKFile> after the data".into());
    }
    Ok(ReadFrame { n, time, points: points.ok_or("no <Points> array")?, point_data, field_data })
}

/// A raw block at `offset` of the appended data: its bytes and where it ends.
fn raw_block(data: &[u8], offset: usize) -> Result<(&[u8], usize), String> {
    let len_at = offset.checked_add(8).and_then(|stop| data.get(offset..stop));
    let len_at = len_at.ok_or_else(|| format!("offset {offset} beyond the data"))?;
    let len = u64::from_le_bytes(len_at.try_into().map_err(|_| "short length prefix")?);
    let len = usize::try_from(len).map_err(|_| format!("block at {offset}: length {len} too large"))?;
    let start = offset + 8;
    let bytes = start.checked_add(len).and_then(|stop| data.get(start..stop));
    let bytes = bytes.ok_or_else(|| format!("block at {offset}: {len} bytes run past the end of the file"))?;
    Ok((bytes, start + len))
}

/// A base64 + zlib block at character `offset` of the appended data (the module's layout): its uncompressed bytes
/// and where it ends.
fn zlib_base64_block(data: &[u8], offset: usize) -> Result<(Vec<u8>, usize), String> {
    // `len` characters from `from`, decoded to `bytes` bytes (misplaced padding would give fewer).
    let at = |from: usize, len: usize, bytes: usize| {
        let text = from.checked_add(len).and_then(|stop| data.get(from..stop));
        let text = text.ok_or_else(|| format!("block at {offset}: runs past the end of the file"))?;
        base64::decode(text).filter(|b| b.len() == bytes).ok_or_else(|| format!("block at {offset}: not base64"))
    };
    let words = |b: &[u8]| -> Vec<u64> {
        b.chunks_exact(8).map(|w| u64::from_le_bytes([w[0], w[1], w[2], w[3], w[4], w[5], w[6], w[7]])).collect()
    };
    let first = words(&at(offset, base64::encoded_len(24), 24)?);
    let (blocks, size, last) = (first[0], first[1], first[2]);
    // Every block takes at least one character: more blocks than characters left is a corrupt header.
    let blocks = usize::try_from(blocks)
        .ok()
        .filter(|&b| b <= data.len())
        .ok_or(format!("block at {offset}: {blocks} blocks"))?;
    let (size, last) = (usize::try_from(size).unwrap_or(0), usize::try_from(last).unwrap_or(usize::MAX));
    if size == 0 || last >= size {
        return Err(format!("block at {offset}: block size {size}, last block {last}"));
    }
    let head_len = base64::encoded_len((3 + blocks) * 8);
    let sizes = words(&at(offset, head_len, (3 + blocks) * 8)?)[3..].to_vec();
    let total = sizes.iter().try_fold(0usize, |t, &s| usize::try_from(s).ok().and_then(|s| t.checked_add(s)));
    let total = total.ok_or(format!("block at {offset}: compressed sizes overflow"))?;
    let data_len = base64::encoded_len(total);
    let packed = at(offset + head_len, data_len, total)?;
    let mut out = Vec::new();
    let mut pos = 0;
    for (k, &c) in sizes.iter().enumerate() {
        let want = if k + 1 == blocks && last != 0 { last } else { size };
        let stop = pos + c as usize;
        let z = packed.get(pos..stop).ok_or(format!("block at {offset}: compressed block {k} runs past its data"))?;
        let before = out.len();
        // At most one byte more than declared is read, so a corrupt stream cannot inflate without bound.
        flate2::read::ZlibDecoder::new(z)
            .take((want as u64).saturating_add(1))
            .read_to_end(&mut out)
            .map_err(|e| format!("block at {offset}: zlib block {k}: {e}"))?;
        if out.len() - before != want {
            return Err(format!(
                "block at {offset}: zlib block {k} holds {} bytes, expected {want}",
                out.len() - before
            ));
        }
        pos = stop;
    }
    Ok((out, offset + head_len + data_len))
}

/// The XML header's checks (an UnstructuredGrid, little-endian, 64-bit headers, the zlib compressor exactly for
/// base64 data, one piece of vertex cells) and its points count and `<DataArray>` declarations, in order.
fn declarations(header: &str, encoding: Encoding) -> Result<(usize, Vec<Decl<'_>>), String> {
    let mut section: Option<&str> = None;
    let mut counts: Option<(usize, usize)> = None;
    let mut vtk_file = false;
    let mut decls = Vec::new();
    for tag in tags(header)? {
        match tag.name {
            "VTKFile" if !tag.closing => {
                let expect = [("type", "UnstructuredGrid"), ("byte_order", "LittleEndian"), ("header_type", "UInt64")];
                for (key, value) in expect {
                    if tag.attr(key) != Some(value) {
                        return Err(format!("<VTKFile> {key} is {:?}, expected \"{value}\"", tag.attr(key)));
                    }
                }
                let compressor = (encoding == Encoding::Base64Zlib).then_some("vtkZLibDataCompressor");
                if tag.attr("compressor") != compressor {
                    return Err(format!(
                        "<VTKFile> compressor is {:?}, expected {compressor:?}",
                        tag.attr("compressor")
                    ));
                }
                vtk_file = true;
            }
            "Piece" if !tag.closing => {
                if counts.is_some() {
                    return Err("more than one <Piece>".into());
                }
                let points = number(tag.attr("NumberOfPoints"), "NumberOfPoints")?;
                counts = Some((points, number(tag.attr("NumberOfCells"), "NumberOfCells")?));
            }
            s if SECTIONS.contains(&s) => section = (!tag.closing && !tag.self_closing).then_some(s),
            "DataArray" if !tag.closing => {
                let section = section.ok_or("<DataArray> outside FieldData, PointData, Points or Cells")?;
                if tag.attr("format") != Some("appended") {
                    return Err(format!("<DataArray> format {:?}, expected \"appended\"", tag.attr("format")));
                }
                let name = tag.attr("Name").unwrap_or("");
                decls.push(Decl {
                    section,
                    ty: tag.attr("type").ok_or("<DataArray> without type")?,
                    name: unescape_attr(name).ok_or_else(|| format!("bad character reference in name {name:?}"))?,
                    components: match tag.attr("NumberOfComponents") {
                        Some(c) => number(Some(c), "NumberOfComponents")?,
                        None => 1,
                    },
                    offset: number(tag.attr("offset"), "offset")?,
                });
            }
            _ => {}
        }
    }
    if !vtk_file {
        return Err("no <VTKFile> element".into());
    }
    let (n, cells) = counts.ok_or("no <Piece>")?;
    if cells != n {
        return Err(format!("{cells} cells for {n} points; expected one vertex per point"));
    }
    Ok((n, decls))
}

fn number(value: Option<&str>, what: &str) -> Result<usize, String> {
    let value = value.ok_or_else(|| format!("missing {what}"))?;
    value.trim().parse().map_err(|_| format!("{what} {value:?} is not a count"))
}

/// Little-endian bytes to values; the copy also handles blocks that are not aligned for `T`.
fn decode<T: Pod>(bytes: &[u8], what: &str) -> Result<Vec<T>, String> {
    let size = size_of::<T>();
    if !bytes.len().is_multiple_of(size) {
        return Err(format!("{what}: {} bytes is not a whole number of {size}-byte values", bytes.len()));
    }
    let mut out = vec![T::zeroed(); bytes.len() / size];
    let out_bytes: &mut [u8] = bytemuck::cast_slice_mut(&mut out);
    out_bytes.copy_from_slice(bytes);
    if cfg!(target_endian = "big") {
        out_bytes.chunks_exact_mut(size).for_each(<[u8]>::reverse);
    }
    Ok(out)
}
