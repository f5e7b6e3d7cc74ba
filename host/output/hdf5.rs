//! Particle frames of a whole run in HDF5, indexed by an XDMF 3 file that ParaView opens as a time series
//! (cargo feature `hdf5`; needs the system HDF5 library, ≥ 1.10, e.g. Debian's `libhdf5-dev`: `ci/install-hdf5.sh`).
//!
//! # Files
//!
//! [`H5Writer::create`]`("out/particles.h5")` writes, and keeps valid after every frame:
//!
//! - `out/particles.h5`: the run file. Root attributes `format = "swarf-particles"`, `version = 1` and `frames`
//!   (the number of frames); group `/frames` holds one member per frame, `/frames/00000`, `/frames/00001`, …,
//!   each an HDF5 *external link* to the frame's group in its frame file. HDF5 follows the links transparently
//!   (h5py: `f["frames/00000/points"]`), resolving the relative file name against the run file's directory
//!   first, so the output folder can be moved as a whole.
//! - `out/particles.frames/00000.h5`, …: one file per frame with the same root attributes (`frames = 1`) and the
//!   group `/frames/00000` (the frame's own number), so that the path of a dataset is the same through the run
//!   file and in the frame file. The group holds
//!   - `points`: n × 3, Float32 or Float64 as given;
//!   - `connectivity`: n UInt32, `0, 1, …, n − 1`, the vertex cells (XDMF readers build no cells without it, and
//!     without cells ParaView draws nothing);
//!   - one dataset per point-data array, named as the array: shape n for one component, n × c otherwise, in the
//!     array's type (Float32, Float64, UInt32, Int32) and component order, bit for bit as given (symmetric
//!     tensors in the VTU order xx, yy, zz, xy, yz, xz);
//!   - attributes `time` (f64), `step` (u64, from a field-data entry named `STEP` or `step` holding a whole
//!     number; f64 otherwise) and every other field-data entry as an f64 attribute of the same name.
//! - `out/particles.xmf`: XDMF 3, a temporal collection of uniform grids, one per frame: `<Time Value>`, topology
//!   `Polyvertex`, geometry `XYZ`, one attribute per array (`Scalar`, `Vector` for 3 components, `Tensor6` for 6,
//!   `Matrix` otherwise) and the field data as grid-centred scalars. Its data items point straight at the frame
//!   files (`particles.frames/00000.h5:/frames/00000/points`), not through the external links, so that a reader
//!   resolves nothing but paths relative to the .xmf. Numbers are printed so that they parse back to the same
//!   bits.
//!
//! In ParaView open the .xmf with one of the *Xdmf3* readers: they take an n × c array as c components as
//! stored, so every array, tensors included, reads as in the VTU frames. The legacy *XDMF Reader* (Xdmf2; checked
//! with VTK 9.7's `vtkXdmfReader`) reads points, cells, scalars and vectors bit for bit too, but expands `Tensor6`
//! to 9 components assuming XDMF's order xx, xy, xz, yy, yz, zz (so VTU-ordered tensors come out permuted),
//! reads a `Matrix` array as one tuple, and reports an error for a frame of 0 particles (giving an empty grid).
//!
//! # Nothing is ever half-written
//!
//! HDF5 cannot append to a file atomically: adding a frame to an open file rewrites metadata that earlier frames
//! depend on (the group's B-tree and name heap, the superblock, free-space that may be reused) in place, in many
//! separate writes during `H5Fflush`/`H5Fclose`, and HDF5 1.10 has no journal. A process killed during those
//! writes can leave a file in which the earlier frames can no longer be found, and SWMR mode, the one crash-safe
//! mode, cannot create groups. So no HDF5 file is ever modified after it is complete; every write goes through a
//! temporary file and a rename, as everywhere in [`crate::output`]:
//!
//! 1. the frame file is written to `particles.frames/.00000.h5.tmp-<pid>`, closed, fsync'ed, renamed to
//!    `00000.h5` and the directory fsync'ed;
//! 2. the run file is rewritten whole the same way, with links to every frame written so far;
//! 3. the .xmf is rewritten whole with [`crate::output::write_atomic`].
//!
//! A reader, or a run killed at any instant, therefore sees complete files only: the run file and the .xmf name
//! the frames written before the last one or all of them, and every frame they name is complete. A kill between
//! steps leaves at most one complete frame file that is not indexed yet. The price of the policy is a file per
//! frame and six fsyncs per frame: 15–40 ms per frame whatever its size on the development machine (a frame of
//! 10⁶ particles, 156 MB, took 0.3–0.6 s in all). Rewriting the run file costs one external link per earlier
//! frame, which did not show in that time up to 2000 frames (the run file was then 149 kB).
//!
//! Errors are [`io::Error`]s naming the file concerned (HDF5's message included); an invalid frame (array
//! lengths, component counts, names, a non-finite time) is refused with [`io::ErrorKind::InvalidInput`] naming
//! the array before any file is touched.
//!
//! HDF5 locks the files it opens (`flock`). On file systems without `flock` support (some NFS and Lustre mounts)
//! set `HDF5_USE_FILE_LOCKING=FALSE`. HDF5 also opens files without `O_CLOEXEC`: a process spawned while a frame is
//! being written inherits the descriptor and its lock, and readers of that frame then fail ("unable to lock
//! file") until the child exits; do not spawn processes while frames are written, or disable the locking.

use std::ffi::OsString;
use std::fmt::Write as _;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use super::atomic::{TempFile, sync_dir};

use ::hdf5::types::VarLenUnicode;
use ::hdf5::{Group, H5Type};

use super::atomic::{with_path, write_atomic};
use super::text::{escape_attr, fmt_f64};
use super::vtu::{Frame, Values};

/// The root attribute `format` of every file this module writes.
pub const FORMAT: &str = "swarf-particles";
/// The root attribute `version`: changes when the layout changes incompatibly.
pub const VERSION: u32 = 1;
/// Dataset names in a frame group that are not point-data arrays; an array may not use them.
pub const RESERVED_DATASETS: [&str; 2] = ["points", "connectivity"];
/// Frame-group attribute names written from [`Frame::time`]; field data may not use them (nor the VTU writer's
/// `TimeValue` and `TIME`, so that one frame suits both writers).
pub const RESERVED_ATTRIBUTES: [&str; 3] = ["time", "TimeValue", "TIME"];

/// Writes the frames of one run (see the module docs for the files and the write order).
#[derive(Debug)]
pub struct H5Writer {
    /// The run file, `…/particles.h5`.
    path: PathBuf,
    /// `…/particles.frames`.
    frames_dir: PathBuf,
    /// The .xmf's `<Grid>` element of every frame written, in order.
    grids: Vec<String>,
}

impl H5Writer {
    /// Starts a run at `path` (e.g. `out/particles.h5`): creates the frame folder (`out/particles.frames/`, and
    /// `out/` if needed) and writes the run file and the .xmf with no frames, so both are valid from the start.
    /// Frame files and temporaries left by an earlier run into the same path are removed once the new, empty index
    /// no longer names them. The file name may not contain `:` (XDMF's separator of file and dataset).
    pub fn create(path: &Path) -> io::Result<Self> {
        let stem = path.file_stem().filter(|s| !s.is_empty()).ok_or_else(|| invalid_input(path, "not a file name"))?;
        match stem.to_str() {
            None => return Err(invalid_input(path, "the file name is not UTF-8 (the .xmf refers to it as text)")),
            // XDMF splits `file:dataset` at the first colon.
            Some(s) if s.contains(':') => return Err(invalid_input(path, "the file name contains ':'")),
            Some(_) => {}
        }
        if path.extension().is_some_and(|e| e == "xmf") {
            return Err(invalid_input(path, "the run file cannot be the .xmf beside it"));
        }
        let mut dir_name = stem.to_os_string();
        dir_name.push(".frames");
        let frames_dir = path.with_file_name(dir_name);
        fs::create_dir_all(&frames_dir).map_err(|e| with_path(&frames_dir, e))?;
        let writer = Self { path: path.to_path_buf(), frames_dir, grids: Vec::new() };
        writer.write_index()?;
        writer.remove_leftovers()?;
        Ok(writer)
    }

    /// Appends `frame`: writes its frame file, then the run file and the .xmf naming it (see the module docs).
    /// An invalid frame is refused with [`io::ErrorKind::InvalidInput`] before any file is touched.
    pub fn write_frame(&mut self, frame: &Frame) -> io::Result<()> {
        let k = self.grids.len();
        let name = frame_name(k);
        let file = self.frame_file(k);
        let checked = check(frame).map_err(|msg| invalid_input(&self.path, &format!("frame {name}: {msg}")))?;
        write_h5_atomic(&file, |f| {
            root_attributes(f, 1)?;
            write_group(&f.create_group("frames")?.create_group(&name)?, frame, &checked)
        })?;
        self.grids.push(self.xdmf_grid(frame, &checked, &name));
        self.write_index()
    }

    /// The run file given to [`H5Writer::create`].
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The XDMF index beside the run file: `particles.h5` → `particles.xmf`.
    pub fn xdmf_path(&self) -> PathBuf {
        self.path.with_extension("xmf")
    }

    /// The folder of the frame files: `particles.h5` → `particles.frames`.
    pub fn frames_dir(&self) -> &Path {
        &self.frames_dir
    }

    /// The file of frame `k` (counting from 0): `particles.frames/00000.h5`, …
    pub fn frame_file(&self, k: usize) -> PathBuf {
        self.frames_dir.join(format!("{}.h5", frame_name(k)))
    }

    /// Frames written so far.
    pub fn frames(&self) -> usize {
        self.grids.len()
    }

    /// The frame file's path relative to the run file's directory, as the links and the .xmf name it.
    fn relative_frame_file(&self, k: usize) -> String {
        let dir = self.frames_dir.file_name().map(|d| d.to_string_lossy()).unwrap_or_default();
        format!("{dir}/{}.h5", frame_name(k))
    }

    /// Rewrites the run file and then the .xmf, both whole and atomically, with every frame written so far.
    fn write_index(&self) -> io::Result<()> {
        write_h5_atomic(&self.path, |f| {
            root_attributes(f, self.grids.len())?;
            let frames = f.create_group("frames")?;
            for k in 0..self.grids.len() {
                let name = frame_name(k);
                frames.link_external(&self.relative_frame_file(k), &format!("/frames/{name}"), &name)?;
            }
            Ok(())
        })?;
        let mut x = String::from("<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n");
        x.push_str("<Xdmf Version=\"3.0\" xmlns:xi=\"http://www.w3.org/2001/XInclude\">\n  <Domain>\n");
        x.push_str("    <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n");
        for grid in &self.grids {
            x.push_str(grid);
        }
        x.push_str("    </Grid>\n  </Domain>\n</Xdmf>\n");
        write_atomic(&self.xdmf_path(), x.as_bytes())
    }

    /// Removes what an earlier run into the same path left and the new, empty index no longer names: frame files
    /// (`NNNNN.h5`) and the temporary files of writers that were killed (`.NNNNN.h5.tmp-<pid>` in the frame folder,
    /// `.particles.h5.tmp-<pid>` and `.particles.xmf.tmp-<pid>` beside the run file). Nothing else is touched.
    fn remove_leftovers(&self) -> io::Result<()> {
        let is_number = |n: &str| n.len() >= 5 && n.bytes().all(|b| b.is_ascii_digit());
        let frame_file = |name: &str| {
            let tmp = name.strip_prefix('.').and_then(|n| n.split_once(".h5.tmp-")).map(|(n, _)| n);
            tmp.or_else(|| name.strip_suffix(".h5")).is_some_and(is_number)
        };
        remove_matching(&self.frames_dir, frame_file)?;
        let temporaries: Vec<String> = [self.path.clone(), self.xdmf_path()]
            .iter()
            .filter_map(|p| p.file_name().map(|n| format!(".{}.tmp-", n.to_string_lossy())))
            .collect();
        let dir = match self.path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        remove_matching(dir, |name| temporaries.iter().any(|t| name.starts_with(t.as_str())))
    }

    /// The .xmf `<Grid>` of one frame.
    fn xdmf_grid(&self, frame: &Frame, checked: &Checked, name: &str) -> String {
        let n = checked.n;
        let file = self.relative_frame_file(self.grids.len());
        let at = |dataset: &str| escape_attr(&format!("{file}:/frames/{name}/{dataset}")).into_owned();
        let mut g = String::new();
        // Writing into a String cannot fail, so the fmt::Results below are ignored.
        let _ = writeln!(g, r#"      <Grid Name="particles" GridType="Uniform">"#);
        let _ = writeln!(g, r#"        <Time Value="{}"/>"#, fmt_f64(frame.time));
        let _ =
            writeln!(g, r#"        <Topology TopologyType="Polyvertex" NumberOfElements="{n}" NodesPerElement="1">"#);
        data_item(&mut g, &n.to_string(), ("UInt", 4), "HDF", &at("connectivity"));
        let _ = writeln!(g, "        </Topology>");
        let _ = writeln!(g, r#"        <Geometry GeometryType="XYZ">"#);
        data_item(&mut g, &format!("{n} 3"), number_type(&frame.points), "HDF", &at("points"));
        let _ = writeln!(g, "        </Geometry>");
        for a in &frame.point_data {
            let kind = match a.components {
                1 => "Scalar",
                3 => "Vector",
                6 => "Tensor6",
                _ => "Matrix",
            };
            let dims = if a.components == 1 { n.to_string() } else { format!("{n} {}", a.components) };
            let name = escape_attr(a.name);
            let _ = writeln!(g, r#"        <Attribute Name="{name}" AttributeType="{kind}" Center="Node">"#);
            data_item(&mut g, &dims, number_type(&a.values), "HDF", &at(a.name));
            let _ = writeln!(g, "        </Attribute>");
        }
        for (field, x) in &frame.field_data {
            let name = escape_attr(field);
            let _ = writeln!(g, r#"        <Attribute Name="{name}" AttributeType="Scalar" Center="Grid">"#);
            data_item(&mut g, "1", ("Float", 8), "XML", &fmt_f64(*x));
            let _ = writeln!(g, "        </Attribute>");
        }
        let _ = writeln!(g, "      </Grid>");
        g
    }
}

/// One `<DataItem>` line of the .xmf; `content` is already escaped.
fn data_item(g: &mut String, dims: &str, (ty, precision): (&str, usize), format: &str, content: &str) {
    let _ = write!(g, r#"          <DataItem Dimensions="{dims}" NumberType="{ty}" Precision="{precision}""#);
    let _ = writeln!(g, r#" Format="{format}">{content}</DataItem>"#);
}

/// Removes the files of `dir` whose (UTF-8) names satisfy `pred`.
fn remove_matching(dir: &Path, pred: impl Fn(&str) -> bool) -> io::Result<()> {
    for entry in fs::read_dir(dir).map_err(|e| with_path(dir, e))? {
        let entry = entry.map_err(|e| with_path(dir, e))?;
        if entry.file_name().to_str().is_some_and(&pred) {
            let path = entry.path();
            match fs::remove_file(&path) {
                Err(e) if e.kind() != io::ErrorKind::NotFound => return Err(with_path(&path, e)),
                _ => {}
            }
        }
    }
    Ok(())
}

/// `00000`, `00001`, …; more digits past 99999.
fn frame_name(k: usize) -> String {
    format!("{k:05}")
}

/// What [`check`] learnt about a valid frame.
struct Checked {
    n: usize,
    /// The field-data entry written as the attribute `step`, if any.
    step: Option<f64>,
}

/// Validates a frame for both the HDF5 layout and the .xmf; the message names the offending array.
fn check(frame: &Frame) -> Result<Checked, String> {
    if !frame.time.is_finite() {
        return Err(format!("time {} is not finite", frame.time));
    }
    if !matches!(frame.points, Values::F32(_) | Values::F64(_)) {
        return Err(format!("points must be Float32 or Float64, not {}", number_type(&frame.points).0));
    }
    if !frame.points.len().is_multiple_of(3) {
        return Err(format!("points: {} values is not a multiple of 3 components", frame.points.len()));
    }
    let n = frame.points.len() / 3;
    if u32::try_from(n).is_err() {
        return Err(format!("{n} particles: the connectivity is UInt32"));
    }
    let mut seen = std::collections::HashSet::new();
    for a in &frame.point_data {
        check_name("point array", a.name)?;
        if RESERVED_DATASETS.contains(&a.name) {
            return Err(format!("point array \"{}\": the name is reserved for the frame's own dataset", a.name));
        }
        if !seen.insert(a.name) {
            return Err(format!("point array \"{}\" appears twice", a.name));
        }
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
    let mut seen = std::collections::HashSet::new();
    let mut step = None;
    for &(name, x) in &frame.field_data {
        check_name("field data", name)?;
        if RESERVED_ATTRIBUTES.contains(&name) {
            return Err(format!("field data \"{name}\" is reserved: it is written from Frame::time"));
        }
        if !seen.insert(name) {
            return Err(format!("field data \"{name}\" appears twice"));
        }
        if name == "STEP" || name == "step" {
            if step.is_some() {
                return Err("field data \"STEP\" and \"step\" both given; both would be the attribute step".into());
            }
            step = Some(x);
        }
    }
    Ok(Checked { n, step })
}

/// HDF5 link and attribute names: non-empty, no `/` (a path separator), not `.`, no NUL.
fn check_name(what: &str, name: &str) -> Result<(), String> {
    if name.is_empty() {
        return Err(format!("{what} with an empty name"));
    }
    if name == "." || name.contains(['/', '\0']) {
        return Err(format!("{what} \"{}\": HDF5 names cannot be \".\" or contain '/' or NUL", name.escape_debug()));
    }
    Ok(())
}

/// The XDMF `NumberType` and `Precision` of the values.
fn number_type(v: &Values) -> (&'static str, usize) {
    match v {
        Values::F32(_) => ("Float", 4),
        Values::F64(_) => ("Float", 8),
        Values::U32(_) => ("UInt", 4),
        Values::I32(_) => ("Int", 4),
    }
}

fn root_attributes(f: &::hdf5::File, frames: usize) -> ::hdf5::Result<()> {
    let format: VarLenUnicode = FORMAT.parse().map_err(|e| format!("{e}"))?;
    f.new_attr::<VarLenUnicode>().create("format")?.write_scalar(&format)?;
    f.new_attr::<u32>().create("version")?.write_scalar(&VERSION)?;
    f.new_attr::<u64>().create("frames")?.write_scalar(&(frames as u64))?;
    Ok(())
}

/// The datasets and attributes of one frame group (the frame is valid).
fn write_group(g: &Group, frame: &Frame, checked: &Checked) -> ::hdf5::Result<()> {
    let n = checked.n;
    write_values(g, "points", &frame.points, n, 3)?;
    let connectivity: Vec<u32> = (0..n as u32).collect();
    write_dataset(g, "connectivity", &connectivity, n, 1)?;
    for a in &frame.point_data {
        write_values(g, a.name, &a.values, n, a.components)?;
    }
    g.new_attr::<f64>().create("time")?.write_scalar(&frame.time)?;
    for &(name, x) in &frame.field_data {
        if name == "STEP" || name == "step" {
            continue;
        }
        g.new_attr::<f64>().create(name)?.write_scalar(&x)?;
    }
    if let Some(step) = checked.step {
        // A whole number goes in as an integer; anything else is kept as it is rather than rounded.
        if step >= 0.0 && step <= (1u64 << 53) as f64 && step.fract() == 0.0 {
            g.new_attr::<u64>().create("step")?.write_scalar(&(step as u64))?;
        } else {
            g.new_attr::<f64>().create("step")?.write_scalar(&step)?;
        }
    }
    Ok(())
}

fn write_values(g: &Group, name: &str, v: &Values, n: usize, components: usize) -> ::hdf5::Result<()> {
    match v {
        Values::F32(v) => write_dataset(g, name, v, n, components),
        Values::F64(v) => write_dataset(g, name, v, n, components),
        Values::U32(v) => write_dataset(g, name, v, n, components),
        Values::I32(v) => write_dataset(g, name, v, n, components),
    }
}

/// A contiguous dataset of shape n (one component) or n × components.
fn write_dataset<T: H5Type>(g: &Group, name: &str, v: &[T], n: usize, components: usize) -> ::hdf5::Result<()> {
    let builder = g.new_dataset::<T>();
    let ds =
        if components == 1 { builder.shape(n).create(name)? } else { builder.shape((n, components)).create(name)? };
    if !v.is_empty() {
        ds.write_raw(v)?;
    }
    Ok(())
}

/// Creates an HDF5 file at `path` atomically: `f` fills a temporary file beside it, which is closed, fsync'ed and
/// renamed over `path`; the directory is fsync'ed. On any failure the temporary file is removed and `path` is
/// left as it was.
fn write_h5_atomic(path: &Path, f: impl FnOnce(&::hdf5::File) -> ::hdf5::Result<()>) -> io::Result<()> {
    let tmp = temp_path(path)?;
    let mut guard = TempFile { path: tmp, armed: true };
    let result = (|| {
        let file = ::hdf5::File::create(&guard.path).map_err(|e| h5_error(path, e))?;
        f(&file).map_err(|e| h5_error(path, e))?;
        // Every handle `f` opened is dropped, so the close is real and writes all metadata out.
        file.close().map_err(|e| h5_error(path, e))?;
        // The data must be on disk before the rename makes it visible.
        fs::File::open(&guard.path).and_then(|f| f.sync_all()).map_err(|e| with_path(path, e))?;
        fs::rename(&guard.path, path).map_err(|e| with_path(path, e))
    })();
    if let Err(e) = result {
        return Err(match guard.remove() {
            Ok(()) => e,
            Err(r) => {
                io::Error::new(e.kind(), format!("{e} (temporary file {} not removed: {r})", guard.path.display()))
            }
        });
    }
    guard.armed = false;
    sync_dir(path).map_err(|e| with_path(path, e))
}

/// An HDF5 error as an [`io::Error`] naming the file.
fn h5_error(path: &Path, e: ::hdf5::Error) -> io::Error {
    io::Error::other(format!("{}: HDF5: {e}", path.display()))
}

fn invalid_input(path: &Path, msg: &str) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, format!("{}: {msg}", path.display()))
}

/// `.<name>.tmp-<pid>` beside `path`, like the temporaries of [`crate::output::write_atomic`].
fn temp_path(path: &Path) -> io::Result<PathBuf> {
    let name = path.file_name().ok_or_else(|| invalid_input(path, "not a file name"))?;
    let mut tmp = OsString::from(".");
    tmp.push(name);
    tmp.push(format!(".tmp-{}", std::process::id()));
    Ok(path.with_file_name(tmp))
}
