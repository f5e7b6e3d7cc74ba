#![cfg(feature = "hdf5")]
//! HDF5 + XDMF particle output (`--features hdf5`): frames read back bit for bit with the `hdf5` crate through the
//! run file's external links and from the frame files, the .xmf naming exactly the frames written, empty frames,
//! refused input, and a writer killed at random instants leaving only complete, readable files.

use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::{RwLock, RwLockReadGuard};
use std::time::Duration;

use hdf5::types::VarLenUnicode;
use swarf::output::hdf5::{FORMAT, H5Writer, VERSION};
use swarf::output::vtu::{Array, Frame, OwnedValues, Values};

/// Taken for reading by every test that writes or reads HDF5 files, and for writing by the one that spawns
/// processes. HDF5 opens files without `O_CLOEXEC`, so a child spawned while another test thread has a file open
/// inherits the descriptor with HDF5's `flock` lock on it: a frame file being written at that instant stays locked
/// after its rename until the child exits, and opening it fails ("unable to lock file"). Disabling HDF5's file
/// locking (`HDF5_USE_FILE_LOCKING=FALSE`) has the same effect.
static SPAWN: RwLock<()> = RwLock::new(());

fn hdf5_files() -> RwLockReadGuard<'static, ()> {
    SPAWN.read().unwrap_or_else(|e| e.into_inner())
}

/// A fresh, empty directory for one test.
fn test_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("hdf5_output").join(name);
    match fs::remove_dir_all(&dir) {
        Err(e) if e.kind() != io::ErrorKind::NotFound => panic!("{}: {e}", dir.display()),
        _ => {}
    }
    fs::create_dir_all(&dir).expect("create test directory");
    dir
}

/// Deterministic f64 values with the awkward ones (−0, subnormal, ±∞, NaN with a payload) first.
fn values_f64(len: usize, seed: u64) -> Vec<f64> {
    let special = [-0.0, 5e-324, f64::INFINITY, f64::NEG_INFINITY, f64::from_bits(0x7ff8_dead_beef_0001), 1.0 / 3.0];
    let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    (0..len)
        .map(|i| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            if i < special.len() { special[i] } else { f64::from_bits(s >> 2) * if s & 1 == 1 { -1.0 } else { 1.0 } }
        })
        .collect()
}

fn values_f32(len: usize, seed: u64) -> Vec<f32> {
    values_f64(len, seed)
        .iter()
        .enumerate()
        .map(|(i, x)| if i < 6 { *x as f32 } else { f32::from_bits(x.to_bits() as u32) })
        .collect()
}

fn values_u32(len: usize, seed: u64) -> Vec<u32> {
    values_f64(len, seed).iter().map(|x| (x.to_bits() >> 17) as u32).collect()
}

fn values_i32(len: usize, seed: u64) -> Vec<i32> {
    values_u32(len, seed).iter().map(|x| *x as i32).collect()
}

/// The owned data of one test frame; [`Data::frame`] borrows it as the writers take it.
struct Data {
    time: f64,
    points: OwnedValues,
    arrays: Vec<(&'static str, usize, OwnedValues)>,
    field: Vec<(&'static str, f64)>,
}

impl Data {
    /// Frame `k` of n particles: F64 points for even k and F32 for odd k; scalar, vector, tensor and matrix arrays
    /// of every value type.
    fn new(k: usize, n: usize, time: f64) -> Self {
        let seed = 1000 * k as u64;
        let points = if k.is_multiple_of(2) {
            OwnedValues::F64(values_f64(3 * n, seed).iter().map(|x| if x.is_finite() { *x } else { 0.5 }).collect())
        } else {
            OwnedValues::F32(values_f32(3 * n, seed).iter().map(|x| if x.is_finite() { *x } else { 0.5 }).collect())
        };
        let arrays = vec![
            ("id", 1, OwnedValues::U32((0..n as u32).map(|i| i * 7 + k as u32).collect())),
            ("velocity", 3, OwnedValues::F64(values_f64(3 * n, seed + 1))),
            ("stress", 6, OwnedValues::F64(values_f64(6 * n, seed + 2))),
            ("temperature", 1, OwnedValues::F32(values_f32(n, seed + 3))),
            ("strain_f32", 6, OwnedValues::F32(values_f32(6 * n, seed + 4))),
            ("flags", 1, OwnedValues::U32(values_u32(n, seed + 5))),
            ("signed", 2, OwnedValues::I32(values_i32(2 * n, seed + 6))),
            ("cells", 3, OwnedValues::U32(values_u32(3 * n, seed + 7))),
        ];
        Self { time, points, arrays, field: vec![("STEP", (10 * k) as f64), ("dt", 1e-9 / 3.0)] }
    }

    fn frame(&self) -> Frame<'_> {
        Frame {
            time: self.time,
            points: self.points.as_values(),
            point_data: self
                .arrays
                .iter()
                .map(|(name, components, v)| Array { name, components: *components, values: v.as_values() })
                .collect(),
            field_data: self.field.clone(),
        }
    }

    fn n(&self) -> usize {
        self.points.len() / 3
    }
}

/// Reads a dataset in the type of `expect` and compares bit for bit, and its shape.
fn check_dataset(ds: &hdf5::Dataset, expect: &OwnedValues, shape: &[usize], what: &str) {
    assert_eq!(ds.shape(), shape, "{what}: shape");
    let bits: Vec<u64> = match expect {
        OwnedValues::F64(_) => ds.read_raw::<f64>().expect(what).iter().map(|x| x.to_bits()).collect(),
        OwnedValues::F32(_) => ds.read_raw::<f32>().expect(what).iter().map(|x| x.to_bits().into()).collect(),
        OwnedValues::U32(_) => ds.read_raw::<u32>().expect(what).iter().map(|x| (*x).into()).collect(),
        OwnedValues::I32(_) => ds.read_raw::<i32>().expect(what).iter().map(|x| (*x as u32).into()).collect(),
    };
    let want: Vec<u64> = match expect {
        OwnedValues::F64(v) => v.iter().map(|x| x.to_bits()).collect(),
        OwnedValues::F32(v) => v.iter().map(|x| x.to_bits().into()).collect(),
        OwnedValues::U32(v) => v.iter().map(|x| (*x).into()).collect(),
        OwnedValues::I32(v) => v.iter().map(|x| (*x as u32).into()).collect(),
    };
    assert_eq!(bits.len(), want.len(), "{what}: length");
    if let Some(i) = bits.iter().zip(&want).position(|(a, b)| a != b) {
        panic!("{what}: value {i} differs: {:#x} != {:#x}", bits[i], want[i]);
    }
    // The stored type is the given one, not a conversion of it.
    let dtype = ds.dtype().expect(what);
    let same = match expect {
        OwnedValues::F64(_) => dtype.is::<f64>(),
        OwnedValues::F32(_) => dtype.is::<f32>(),
        OwnedValues::U32(_) => dtype.is::<u32>(),
        OwnedValues::I32(_) => dtype.is::<i32>(),
    };
    assert!(same, "{what}: stored as {:?}", dtype.to_descriptor());
}

/// Checks frame group `g` (`/frames/<name>` of the run file or of a frame file) against `d`.
fn check_group(g: &hdf5::Group, d: &Data, what: &str) {
    let n = d.n();
    check_dataset(&g.dataset("points").expect(what), &d.points, &[n, 3], &format!("{what}/points"));
    let connectivity = OwnedValues::U32((0..n as u32).collect());
    check_dataset(&g.dataset("connectivity").expect(what), &connectivity, &[n], &format!("{what}/connectivity"));
    for (name, components, v) in &d.arrays {
        let shape = if *components == 1 { vec![n] } else { vec![n, *components] };
        check_dataset(&g.dataset(name).expect(name), v, &shape, &format!("{what}/{name}"));
    }
    let mut members = g.member_names().expect(what);
    members.sort();
    let mut want: Vec<String> = d.arrays.iter().map(|(name, ..)| name.to_string()).collect();
    want.extend(["points".to_string(), "connectivity".to_string()]);
    want.sort();
    assert_eq!(members, want, "{what}: datasets");
    let time: f64 = g.attr("time").expect("time").read_scalar().expect("time");
    assert_eq!(time.to_bits(), d.time.to_bits(), "{what}: time");
    for (name, x) in &d.field {
        if *name == "STEP" {
            let step: u64 = g.attr("step").expect("step").read_scalar().expect("step");
            assert_eq!(step as f64, *x, "{what}: step");
            assert!(!g.attr_names().expect(what).contains(&"STEP".to_string()), "{what}: STEP written twice");
        } else {
            let y: f64 = g.attr(name).expect(name).read_scalar().expect(name);
            assert_eq!(y.to_bits(), x.to_bits(), "{what}: attribute {name}");
        }
    }
}

fn check_root(f: &hdf5::File, frames: u64, what: &str) {
    let format: VarLenUnicode = f.attr("format").expect("format").read_scalar().expect("format");
    assert_eq!(format.as_str(), FORMAT, "{what}: format");
    let version: u32 = f.attr("version").expect("version").read_scalar().expect("version");
    assert_eq!(version, VERSION, "{what}: version");
    let count: u64 = f.attr("frames").expect("frames").read_scalar().expect("frames");
    assert_eq!(count, frames, "{what}: frames attribute");
}

/// Opens the run file and checks it against `frames`, through the external links, and every frame file directly.
fn check_run(w: &H5Writer, frames: &[Data]) {
    let f = hdf5::File::open(w.path()).expect("open run file");
    check_root(&f, frames.len() as u64, "run file");
    let mut names = f.group("frames").expect("/frames").member_names().expect("members");
    names.sort();
    let want: Vec<String> = (0..frames.len()).map(|k| format!("{k:05}")).collect();
    assert_eq!(names, want, "run file: frames");
    for (k, d) in frames.iter().enumerate() {
        let name = format!("frames/{k:05}");
        check_group(&f.group(&name).expect(&name), d, &format!("run file {name}"));
        let file = w.frame_file(k);
        let ff = hdf5::File::open(&file).expect("open frame file");
        check_root(&ff, 1, &file.display().to_string());
        assert_eq!(ff.group("frames").unwrap().member_names().unwrap(), [format!("{k:05}")]);
        check_group(&ff.group(&name).expect(&name), d, &file.display().to_string());
    }
}

/// One `<Grid GridType="Uniform">` of the .xmf, taken apart with plain string matching.
#[derive(Debug)]
struct XGrid {
    time: f64,
    /// Every `<DataItem>` in file order, described as `Element Type "Name" [Dimensions] NumberTypePrecision
    /// Format:content`, e.g. `Geometry XYZ "" [1000 3] Float8 HDF:particles.frames/00000.h5:/frames/00000/points`.
    items: Vec<String>,
}

/// The value of `key="…"` in `tag`.
fn attr<'a>(tag: &'a str, key: &str) -> &'a str {
    let pat = format!(" {key}=\"");
    let start = tag.find(&pat).unwrap_or_else(|| panic!("no {key} in {tag}")) + pat.len();
    let len = tag[start..].find('"').unwrap_or_else(|| panic!("unterminated {key} in {tag}"));
    &tag[start..start + len]
}

fn parse_xmf(path: &Path) -> Vec<XGrid> {
    let text = fs::read_to_string(path).expect("read .xmf");
    assert!(text.starts_with("<?xml"), "{text}");
    assert!(text.contains(r#"<Xdmf Version="3.0""#), "{text}");
    assert!(text.contains(r#"<Grid Name="particles" GridType="Collection" CollectionType="Temporal">"#), "{text}");
    assert!(text.trim_end().ends_with("</Xdmf>"), "{text}");
    let mut grids = Vec::new();
    let mut rest = text.as_str();
    while let Some(at) = rest.find(r#"GridType="Uniform">"#) {
        rest = &rest[at..];
        let end = rest.find("</Grid>").expect("</Grid>");
        let body = &rest[..end];
        rest = &rest[end..];
        let time_tag = &body[body.find("<Time ").expect("<Time>")..];
        let time: f64 = attr(&time_tag[..time_tag.find("/>").unwrap()], "Value").parse().expect("time");
        let mut items = Vec::new();
        let mut b = body;
        let mut parent = String::new();
        while let Some(i) = b.find('<') {
            b = &b[i + 1..];
            let tag = &b[..b.find('>').unwrap()];
            match tag.split_whitespace().next().unwrap_or("") {
                "Topology" => parent = format!("Topology {} \"\"", attr(tag, "TopologyType")),
                "Geometry" => parent = format!("Geometry {} \"\"", attr(tag, "GeometryType")),
                "Attribute" => {
                    let centre = attr(tag, "Center");
                    parent = format!("Attribute {} {:?} {centre}", attr(tag, "AttributeType"), attr(tag, "Name"));
                }
                "DataItem" => {
                    let content = &b[tag.len() + 1..b.find("</DataItem>").unwrap()];
                    items.push(format!(
                        "{parent} [{}] {}{} {}:{content}",
                        attr(tag, "Dimensions"),
                        attr(tag, "NumberType"),
                        attr(tag, "Precision"),
                        attr(tag, "Format"),
                    ));
                }
                _ => {}
            }
        }
        grids.push(XGrid { time, items });
    }
    grids
}

/// The XDMF `NumberType` and `Precision` of the values, as one word.
fn xdmf_type(v: &OwnedValues) -> &'static str {
    match v {
        OwnedValues::F64(_) => "Float8",
        OwnedValues::F32(_) => "Float4",
        OwnedValues::U32(_) => "UInt4",
        OwnedValues::I32(_) => "Int4",
    }
}

/// Checks that the .xmf names exactly `frames`, with their times, dataset paths, dimensions and types.
fn check_xmf(w: &H5Writer, frames: &[Data]) {
    let grids = parse_xmf(&w.xdmf_path());
    assert_eq!(grids.len(), frames.len(), "frames in the .xmf");
    for (k, (g, d)) in grids.iter().zip(frames).enumerate() {
        assert_eq!(g.time.to_bits(), d.time.to_bits(), "frame {k}: time");
        let n = d.n();
        let at = |ds: &str| format!("HDF:particles.frames/{k:05}.h5:/frames/{k:05}/{ds}");
        let mut want = vec![
            format!("Topology Polyvertex \"\" [{n}] UInt4 {}", at("connectivity")),
            format!("Geometry XYZ \"\" [{n} 3] {} {}", xdmf_type(&d.points), at("points")),
        ];
        for (name, c, v) in &d.arrays {
            let kind = match c {
                1 => "Scalar",
                3 => "Vector",
                6 => "Tensor6",
                _ => "Matrix",
            };
            let dims = if *c == 1 { n.to_string() } else { format!("{n} {c}") };
            want.push(format!("Attribute {kind} {name:?} Node [{dims}] {} {}", xdmf_type(v), at(name)));
        }
        for (name, x) in &d.field {
            // Inline values must parse back to the same bits.
            let prefix = format!("Attribute Scalar {name:?} Grid [1] Float8 XML:");
            let item = g.items.iter().find(|i| i.starts_with(&prefix)).unwrap_or_else(|| panic!("{prefix} in {g:?}"));
            let value: f64 = item[prefix.len()..].parse().expect("number");
            assert_eq!(value.to_bits(), x.to_bits(), "frame {k}: field {name}");
            want.push(item.clone());
        }
        assert_eq!(g.items, want, "frame {k}: data items");
    }
}

#[test]
fn three_frames_read_back_bit_for_bit() {
    let _files = hdf5_files();
    let dir = test_dir("three_frames");
    let path = dir.join("particles.h5");
    let mut w = H5Writer::create(&path).expect("create");
    assert_eq!(w.xdmf_path(), dir.join("particles.xmf"));
    assert_eq!(w.frames_dir(), dir.join("particles.frames"));
    // Valid, empty index from the start.
    check_run(&w, &[]);
    check_xmf(&w, &[]);
    let times = [0.0, 1.25e-7, 1.0 / 3.0 * 1e-6];
    let mut written = Vec::new();
    for (k, t) in times.into_iter().enumerate() {
        let d = Data::new(k, 1000, t);
        w.write_frame(&d.frame()).expect("write frame");
        written.push(d);
        assert_eq!(w.frames(), written.len());
        // After every frame, the index names exactly the frames written so far.
        check_run(&w, &written);
        check_xmf(&w, &written);
    }
    let mut files: Vec<String> =
        fs::read_dir(w.frames_dir()).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into()).collect();
    files.sort();
    assert_eq!(files, ["00000.h5", "00001.h5", "00002.h5"]);
    let mut top: Vec<String> =
        fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into()).collect();
    top.sort();
    assert_eq!(top, ["particles.frames", "particles.h5", "particles.xmf"], "no temporaries left");
}

#[test]
fn empty_frame() {
    let _files = hdf5_files();
    let dir = test_dir("empty_frame");
    let mut w = H5Writer::create(&dir.join("particles.h5")).expect("create");
    let frames = [Data::new(0, 0, 0.0), Data::new(1, 5, 2e-6), Data::new(2, 0, 3e-6)];
    for d in &frames {
        w.write_frame(&d.frame()).expect("write frame");
    }
    check_run(&w, &frames);
    check_xmf(&w, &frames);
    let text = fs::read_to_string(w.xdmf_path()).unwrap();
    assert!(text.contains(r#"NumberOfElements="0""#) && text.contains(r#"Dimensions="0 3""#), "{text}");
}

#[test]
fn length_mismatch_is_refused_naming_the_array() {
    let _files = hdf5_files();
    let dir = test_dir("length_mismatch");
    let mut w = H5Writer::create(&dir.join("particles.h5")).expect("create");
    let good = Data::new(0, 10, 0.0);
    w.write_frame(&good.frame()).expect("write frame");
    let before_xmf = fs::read(w.xdmf_path()).unwrap();
    let before_h5 = fs::read(w.path()).unwrap();

    let short = vec![1.0f64; 3 * 10 - 1];
    let mut bad = good.frame();
    bad.point_data.push(Array { name: "displacement", components: 3, values: Values::F64(&short) });
    let e = w.write_frame(&bad).expect_err("a short array must be refused");
    assert_eq!(e.kind(), io::ErrorKind::InvalidInput, "{e}");
    let msg = e.to_string();
    assert!(msg.contains("displacement") && msg.contains("29 values"), "{msg}");
    assert!(msg.contains("particles.h5"), "the error names the file: {msg}");

    // Nothing was touched: no frame file, the same index.
    assert_eq!(w.frames(), 1);
    assert!(!w.frame_file(1).exists());
    assert_eq!(fs::read(w.xdmf_path()).unwrap(), before_xmf);
    assert_eq!(fs::read(w.path()).unwrap(), before_h5);
    let names: Vec<_> = fs::read_dir(w.frames_dir()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names, ["00000.h5"]);

    // The writer goes on after a refusal.
    let next = Data::new(1, 10, 1.0);
    w.write_frame(&next.frame()).expect("write frame");
    check_run(&w, &[good, next]);
}

#[test]
fn invalid_frames_are_refused() {
    let _files = hdf5_files();
    let dir = test_dir("invalid");
    let mut w = H5Writer::create(&dir.join("run.h5")).expect("create");
    let d = Data::new(0, 4, 0.0);
    static ONES: [u32; 12] = [1; 12];
    type Change = Box<dyn Fn(&mut Frame)>;
    let cases: Vec<(&str, Change)> = vec![
        ("\"points\": the name is reserved", Box::new(|f| f.point_data[0].name = "points")),
        ("\"connectivity\": the name is reserved", Box::new(|f| f.point_data[0].name = "connectivity")),
        ("\"a/b\": HDF5 names", Box::new(|f| f.point_data[0].name = "a/b")),
        ("empty name", Box::new(|f| f.point_data[0].name = "")),
        ("\"id\" appears twice", Box::new(|f| f.point_data[1].name = "id")),
        ("\"velocity\": 0 components", Box::new(|f| f.point_data[1].components = 0)),
        ("time NaN is not finite", Box::new(|f| f.time = f64::NAN)),
        ("points must be Float32 or Float64", Box::new(|f| f.points = Values::U32(&ONES))),
        ("\"time\" is reserved", Box::new(|f| f.field_data.push(("time", 1.0)))),
        ("\"TIME\" is reserved", Box::new(|f| f.field_data.push(("TIME", 1.0)))),
        ("both given", Box::new(|f| f.field_data.push(("step", 1.0)))),
        ("\"dt\" appears twice", Box::new(|f| f.field_data.push(("dt", 1.0)))),
    ];
    for (expect, change) in &cases {
        let mut f = d.frame();
        change(&mut f);
        let e = w.write_frame(&f).expect_err(expect);
        assert_eq!(e.kind(), io::ErrorKind::InvalidInput, "{e}");
        assert!(e.to_string().contains(expect), "expected {expect:?} in {e}");
    }
    assert_eq!(w.frames(), 0);
    assert_eq!(fs::read_dir(w.frames_dir()).unwrap().count(), 0);
    assert!(H5Writer::create(Path::new("/")).is_err());
}

#[test]
fn a_new_run_replaces_the_old_frames() {
    let _files = hdf5_files();
    let dir = test_dir("rerun");
    let path = dir.join("particles.h5");
    let mut w = H5Writer::create(&path).expect("create");
    for k in 0..3 {
        w.write_frame(&Data::new(k, 3, k as f64).frame()).expect("write frame");
    }
    // Leftover temporaries of a killed writer, and files that are not the writer's.
    fs::write(w.frames_dir().join(".00003.h5.tmp-1"), b"partial").unwrap();
    fs::write(dir.join(".particles.h5.tmp-1"), b"partial").unwrap();
    fs::write(dir.join(".particles.xmf.tmp-1"), b"partial").unwrap();
    fs::write(w.frames_dir().join("notes.txt"), b"keep me").unwrap();
    fs::write(w.frames_dir().join("123.h5"), b"keep me").unwrap();
    fs::write(dir.join(".other.h5.tmp-1"), b"keep me").unwrap();
    let mut w = H5Writer::create(&path).expect("create again");
    check_run(&w, &[]);
    check_xmf(&w, &[]);
    let sorted = |d: &Path| {
        let mut v: Vec<String> =
            fs::read_dir(d).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        v.sort();
        v
    };
    assert_eq!(sorted(w.frames_dir()), ["123.h5", "notes.txt"], "old frames and temporaries removed, others kept");
    assert_eq!(sorted(&dir), [".other.h5.tmp-1", "particles.frames", "particles.h5", "particles.xmf"]);
    let d = Data::new(7, 2, 0.5);
    w.write_frame(&d.frame()).expect("write frame");
    check_run(&w, &[d]);
}

#[test]
fn io_errors_name_the_file_and_leave_the_index_as_it_was() {
    let _files = hdf5_files();
    let dir = test_dir("io_error");
    let mut w = H5Writer::create(&dir.join("particles.h5")).expect("create");
    let d = Data::new(0, 8, 0.0);
    w.write_frame(&d.frame()).expect("write frame");
    let before_xmf = fs::read(w.xdmf_path()).unwrap();
    // The frame folder is gone: HDF5 cannot create the frame file.
    fs::rename(w.frames_dir(), dir.join("moved")).unwrap();
    let e = w.write_frame(&Data::new(1, 8, 1.0).frame()).expect_err("no frame folder");
    let msg = e.to_string();
    assert!(msg.contains("00001.h5") && msg.contains("HDF5"), "{msg}");
    assert_eq!(w.frames(), 1);
    assert_eq!(fs::read(w.xdmf_path()).unwrap(), before_xmf);
    // Back in place, the writer goes on with the next number.
    fs::rename(dir.join("moved"), w.frames_dir()).unwrap();
    let next = Data::new(1, 8, 1.0);
    w.write_frame(&next.frame()).expect("write frame");
    check_run(&w, &[d, next]);
    assert_eq!(H5Writer::create(&dir.join("a:b.h5")).expect_err(":").kind(), io::ErrorKind::InvalidInput);
    assert_eq!(H5Writer::create(&dir.join("a.xmf")).expect_err(".xmf").kind(), io::ErrorKind::InvalidInput);
}

/// Frame `k` of the killed writer: 20 000 particles, contents a function of k.
fn killed_frame(k: usize) -> Data {
    let n = 20_000;
    let mut d = Data::new(0, 0, k as f64 * 1e-6);
    d.points = OwnedValues::F64((0..3 * n).map(|i| (k * 3 * n + i) as f64 * 0.25).collect());
    d.arrays = vec![
        ("id", 1, OwnedValues::U32((0..n as u32).map(|i| i ^ k as u32).collect())),
        ("stress", 6, OwnedValues::F64((0..6 * n).map(|i| (i as f64).sqrt() + k as f64).collect())),
    ];
    d.field = vec![("STEP", k as f64)];
    d
}

const CHILD_DIR: &str = "SWARF_HDF5_TEST_CHILD_DIR";

/// Not a test on its own: the child process of `killed_writer_leaves_complete_files`, which writes frames until it
/// is killed. Without the environment variable it returns at once.
#[test]
fn killed_writer_child() {
    let Some(dir) = std::env::var_os(CHILD_DIR) else { return };
    let mut w = H5Writer::create(&Path::new(&dir).join("particles.h5")).expect("create");
    for k in 0.. {
        w.write_frame(&killed_frame(k).frame()).expect("write frame");
    }
}

/// Kills a writer with SIGKILL at spread-out instants (during frame files, run files and .xmf rewrites alike)
/// and checks each time that the run file and the .xmf open, agree and name only complete frames with the right
/// contents, and that every frame file present is complete.
#[test]
fn killed_writer_leaves_complete_files() {
    let _spawn = SPAWN.write().unwrap_or_else(|e| e.into_inner());
    let exe = std::env::current_exe().expect("test binary");
    let mut seen = Vec::new();
    for (trial, delay_ms) in [40u64, 95, 150, 210, 275, 340, 420, 505].into_iter().enumerate() {
        let dir = test_dir(&format!("killed_{trial}"));
        let mut child = Command::new(&exe)
            .args(["killed_writer_child", "--exact", "--test-threads=1", "--nocapture"])
            .env(CHILD_DIR, &dir)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("spawn the writer");
        std::thread::sleep(Duration::from_millis(delay_ms));
        child.kill().expect("kill the writer");
        child.wait().expect("wait for the writer");

        let path = dir.join("particles.h5");
        if !path.exists() {
            // Killed before create finished: nothing but temporaries may be there.
            seen.push(0);
            continue;
        }
        let f = hdf5::File::open(&path).expect("run file opens after a kill");
        let linked: u64 = f.attr("frames").unwrap().read_scalar().unwrap();
        let linked = linked as usize;
        // `create` writes the run file first: killed before the .xmf, the run file has no frames yet.
        let xmf_path = dir.join("particles.xmf");
        let xmf = if linked == 0 && !xmf_path.exists() { Vec::new() } else { parse_xmf(&xmf_path) };
        assert!(xmf.len() == linked || xmf.len() + 1 == linked, "xmf {} frames, run file {linked}", xmf.len());
        for k in 0..linked {
            let d = killed_frame(k);
            check_group(
                &f.group(&format!("frames/{k:05}")).expect("linked frame"),
                &d,
                &format!("killed {trial} frame {k}"),
            );
        }
        for (k, g) in xmf.iter().enumerate() {
            assert_eq!(g.time, killed_frame(k).time);
        }
        // Every frame file (not temporaries) is complete, including one written but not yet indexed.
        for entry in fs::read_dir(dir.join("particles.frames")).unwrap() {
            let name = entry.unwrap().file_name().to_string_lossy().into_owned();
            if name.contains(".tmp-") {
                assert!(name.starts_with('.'), "{name}");
                continue;
            }
            let k: usize = name.strip_suffix(".h5").expect("frame file").parse().expect("frame number");
            assert!(k <= linked, "frame file {name} beyond the index ({linked})");
            let ff = hdf5::File::open(dir.join("particles.frames").join(&name)).expect("frame file opens");
            check_group(&ff.group(&format!("frames/{k:05}")).unwrap(), &killed_frame(k), &name);
        }
        seen.push(linked);
    }
    eprintln!("frames indexed when killed: {seen:?}");
    assert!(seen.iter().any(|&k| k > 0), "the writer was always killed before its first frame: {seen:?}");
}
