//! Output files: VTU frames read back bit for bit and laid out as ParaView expects, the PVD index, CSV time
//! series, and the atomic-write guarantees (no partial file, no stray temporary, old file kept on failure).

use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use crate::common::files::entries;

use swarf::output::vtu::{self, Array, Frame, OwnedValues, Values};
use swarf::output::{Collection, TimeSeries, csv, pvd, write_atomic, write_atomic_with};

/// A fresh, empty directory for one test.
fn test_dir(name: &str) -> PathBuf {
    crate::common::files::fresh_dir("output", name)
}

fn temporaries(dir: &Path) -> Vec<String> {
    entries(dir).into_iter().filter(|n| n.contains(".tmp-")).collect()
}

/// Deterministic f64 values spanning signs and magnitudes, with the awkward ones (−0, subnormal, ±∞, NaN) first.
fn values_f64(len: usize, seed: u64) -> Vec<f64> {
    let special = [-0.0, 5e-324, f64::INFINITY, f64::NEG_INFINITY, f64::NAN, 1.0 / 3.0, -1e300];
    let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    (0..len)
        .map(|i| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            special.get(i).copied().unwrap_or_else(|| f64::from_bits(s >> 2 | 0x3000_0000_0000_0000) - 1.0)
        })
        .collect()
}

fn bits64(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

fn bits32(v: &[f32]) -> Vec<u32> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// Bitwise comparison of written and read values (NaN-safe, −0 ≠ +0).
fn assert_bitwise(written: Values, read: &OwnedValues, what: &str) {
    match (written, read) {
        (Values::F64(a), OwnedValues::F64(b)) => assert_eq!(bits64(a), bits64(b), "{what}"),
        (Values::F32(a), OwnedValues::F32(b)) => assert_eq!(bits32(a), bits32(b), "{what}"),
        (Values::U32(a), OwnedValues::U32(b)) => assert_eq!(a, b.as_slice(), "{what}"),
        (Values::I32(a), OwnedValues::I32(b)) => assert_eq!(a, b.as_slice(), "{what}"),
        (a, b) => panic!("{what}: wrote {a:?}, read a different type {b:?}"),
    }
}

const N: usize = 1000;

/// The test frame's arrays: one of each type and component layout a run writes.
struct Data {
    rho: Vec<f64>,
    vel: Vec<f32>,
    id: Vec<u32>,
    material: Vec<i32>,
    stress: Vec<f64>,
}

impl Data {
    fn new(n: usize) -> Self {
        Data {
            rho: values_f64(n, 1),
            vel: values_f64(3 * n, 2).iter().map(|&x| x as f32).collect(),
            id: (0..n as u32).map(|i| i.wrapping_mul(2_654_435_761)).collect(),
            material: (0..n as i32).map(|i| i % 7 - 3).collect(),
            stress: values_f64(6 * n, 3),
        }
    }

    fn frame<'a>(&'a self, points: Values<'a>) -> Frame<'a> {
        Frame {
            time: 1.25e-4 / 3.0,
            points,
            point_data: vec![
                Array { name: "density", components: 1, values: Values::F64(&self.rho) },
                Array { name: "velocity", components: 3, values: Values::F32(&self.vel) },
                Array { name: "id", components: 1, values: Values::U32(&self.id) },
                Array { name: "material", components: 1, values: Values::I32(&self.material) },
                Array { name: "stress", components: 6, values: Values::F64(&self.stress) },
            ],
            field_data: vec![("STEP", 4711.0), ("cut depth", 2e-5)],
        }
    }
}

fn check_vtu_round_trip(points: Values, dir: &str) {
    let dir = test_dir(dir);
    let path = dir.join("frame_000001.vtu");
    let data = Data::new(N);
    let frame = data.frame(points);
    vtu::write(&path, &frame).expect("write");
    let back = vtu::read(&path).expect("read");

    assert_eq!(back.n, N);
    assert_eq!(back.time.map(f64::to_bits), Some(frame.time.to_bits()), "time");
    assert_bitwise(frame.points, &back.points, "points");
    assert_eq!(back.point_data.len(), frame.point_data.len());
    for (a, (name, components, values)) in frame.point_data.iter().zip(&back.point_data) {
        assert_eq!((a.name, a.components), (name.as_str(), *components));
        assert_bitwise(a.values, values, a.name);
    }
    let field: Vec<(&str, u64)> = back.field_data.iter().map(|(k, v)| (k.as_str(), v.to_bits())).collect();
    let expected: Vec<(&str, u64)> = frame.field_data.iter().map(|(k, v)| (*k, v.to_bits())).collect();
    assert_eq!(field, expected, "field data");
    assert_eq!(entries(&dir), ["frame_000001.vtu"], "only the frame remains in the directory");
}

#[test]
fn vtu_round_trip_is_bitwise_with_f64_points() {
    let points = values_f64(3 * N, 4);
    check_vtu_round_trip(Values::F64(&points), "vtu_round_trip_f64");
}

#[test]
fn vtu_round_trip_is_bitwise_with_f32_points() {
    let points: Vec<f32> = values_f64(3 * N, 5).iter().map(|&x| x as f32).collect();
    check_vtu_round_trip(Values::F32(&points), "vtu_round_trip_f32");
}

/// `name="value"` of one tag, parsed independently of the crate's reader.
fn attr<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let start = tag.find(&key)? + key.len();
    Some(&tag[start..start + tag[start..].find('"')?])
}

fn le_u64(bytes: &[u8], at: usize) -> u64 {
    u64::from_le_bytes(bytes[at..at + 8].try_into().expect("8 bytes"))
}

/// The header a ParaView reader relies on: counts, the appended offsets (recomputed from the declared arrays, each
/// block being an 8-byte length and the data), the block lengths, vertex cells, and the closing tags.
#[test]
fn vtu_header_is_consistent_for_paraview() {
    let dir = test_dir("vtu_header");
    let path = dir.join("f.vtu");
    let data = Data::new(N);
    let points = values_f64(3 * N, 6);
    vtu::write(&path, &data.frame(Values::F64(&points))).expect("write");
    let bytes = fs::read(&path).expect("read bytes");

    let mark = b"<AppendedData encoding=\"raw\">";
    let at = bytes.windows(mark.len()).position(|w| w == mark).expect("raw AppendedData");
    let header = std::str::from_utf8(&bytes[..at]).expect("UTF-8 header");
    assert!(header.starts_with("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\""), "{header}");
    let root = &header[header.find("<VTKFile").expect("VTKFile")..];
    assert_eq!(attr(root, "byte_order"), Some("LittleEndian"));
    assert_eq!(attr(root, "header_type"), Some("UInt64"));
    let piece = &header[header.find("<Piece").expect("Piece")..];
    assert_eq!(attr(piece, "NumberOfPoints"), Some("1000"));
    assert_eq!(attr(piece, "NumberOfCells"), Some("1000"));
    let data_start = at + mark.len() + bytes[at + mark.len()..].iter().position(|&b| b == b'_').expect("_") + 1;
    assert!(bytes[at + mark.len()..data_start - 1].iter().all(u8::is_ascii_whitespace), "only blanks before _");

    let mut expected_offset = 0;
    let mut names = Vec::new();
    let mut blocks = std::collections::HashMap::new();
    for decl in header.split("<DataArray").skip(1) {
        let decl = &decl[..decl.find("/>").expect("self-closing DataArray")];
        let name = attr(decl, "Name").expect("Name");
        let ty = attr(decl, "type").expect("type");
        assert_eq!(attr(decl, "format"), Some("appended"), "{name}");
        let size = match ty {
            "Float64" | "Int64" => 8,
            "Float32" | "UInt32" | "Int32" => 4,
            "UInt8" => 1,
            _ => panic!("{name}: unexpected type {ty}"),
        };
        let count = match attr(decl, "NumberOfTuples") {
            Some(tuples) => tuples.parse::<usize>().expect("tuples"), // field data
            None => N * attr(decl, "NumberOfComponents").map_or(1, |c| c.parse::<usize>().expect("components")),
        };
        let offset: usize = attr(decl, "offset").expect("offset").parse().expect("offset number");
        assert_eq!(offset, expected_offset, "offset of {name}");
        assert_eq!(le_u64(&bytes, data_start + offset), (count * size) as u64, "length prefix of {name}");
        blocks.insert(name, &bytes[data_start + offset + 8..data_start + offset + 8 + count * size]);
        expected_offset += 8 + count * size;
        names.push(name);
    }
    assert_eq!(
        names,
        [
            "TimeValue",
            "TIME",
            "STEP",
            "cut depth",
            "density",
            "velocity",
            "id",
            "material",
            "stress",
            "Points",
            "connectivity",
            "offsets",
            "types"
        ]
    );
    assert!(blocks["types"].iter().all(|&t| t == 1), "all cells are VTK_VERTEX");
    let int64 = |b: &[u8]| -> Vec<i64> {
        b.chunks_exact(8).map(|c| i64::from_le_bytes(c.try_into().expect("8 bytes"))).collect()
    };
    assert_eq!(int64(blocks["connectivity"]), (0..N as i64).collect::<Vec<_>>());
    assert_eq!(int64(blocks["offsets"]), (1..=N as i64).collect::<Vec<_>>());
    assert_eq!(blocks["TimeValue"], blocks["TIME"], "both time conventions carry the frame time");
    assert_eq!(&bytes[data_start + expected_offset..], b"\n  </AppendedData>\n</VTKFile>\n", "tail after the data");
}

#[test]
fn vtu_with_zero_particles_round_trips() {
    let dir = test_dir("vtu_empty");
    let path = dir.join("empty.vtu");
    let frame = Frame {
        time: 0.0,
        points: Values::F32(&[]),
        point_data: vec![Array { name: "stress", components: 6, values: Values::F64(&[]) }],
        field_data: vec![],
    };
    vtu::write(&path, &frame).expect("write");
    let back = vtu::read(&path).expect("read");
    assert_eq!(back.n, 0);
    assert_eq!(back.time, Some(0.0));
    assert_eq!(back.points, OwnedValues::F32(vec![]));
    assert_eq!(back.point_data, vec![("stress".to_string(), 6, OwnedValues::F64(vec![]))]);
    assert!(back.field_data.is_empty());
}

#[test]
fn vtu_invalid_frames_are_refused_naming_the_array_and_write_nothing() {
    let dir = test_dir("vtu_invalid");
    let path = dir.join("bad.vtu");
    let points = vec![0.0f64; 3 * 10];
    let short = vec![0.0f32; 3 * 9];
    let ok = vec![0u32; 10];
    let refused = |frame: Frame, needle: &str| {
        let e = vtu::write(&path, &frame).expect_err("an invalid frame must be refused");
        assert_eq!(e.kind(), io::ErrorKind::InvalidInput, "{e}");
        assert!(e.to_string().contains(needle), "{e:?} should name {needle}");
        assert!(entries(&dir).is_empty(), "nothing written for {needle}");
    };
    let frame = |point_data, field_data| Frame { time: 1.0, points: Values::F64(&points), point_data, field_data };
    let array = |name, components, values| Array { name, components, values };

    refused(
        frame(vec![array("id", 1, Values::U32(&ok)), array("velocity", 3, Values::F32(&short))], vec![]),
        "velocity",
    );
    refused(frame(vec![array("velocity", 0, Values::F32(&[]))], vec![]), "velocity");
    refused(frame(vec![array("id", 1, Values::U32(&ok)), array("id", 1, Values::U32(&ok))], vec![]), "id");
    refused(frame(vec![], vec![("TIME", 1.0)]), "TIME");
    refused(Frame { time: 0.0, points: Values::F64(&points[..29]), point_data: vec![], field_data: vec![] }, "points");
    refused(Frame { time: 0.0, points: Values::U32(&[0; 3]), point_data: vec![], field_data: vec![] }, "points");
}

#[test]
fn pvd_round_trips_times_and_files_after_every_frame() {
    let dir = test_dir("pvd");
    let path = dir.join("run.pvd");
    let pushed = [(0.0, "frames/f_0.vtu"), (1e-7 / 3.0, "frames/f_1.vtu"), (2.5e-3, "frames/a&b <\"c\">.vtu")];
    let mut pvd = Collection::new(&path);
    for (i, (t, f)) in pushed.iter().enumerate() {
        pvd.push(*t, *f).expect("push");
        pvd.write().expect("write");
        let back = pvd::read(&path).expect("read");
        let expected: Vec<(u64, String)> = pushed[..=i].iter().map(|(t, f)| (t.to_bits(), f.to_string())).collect();
        assert_eq!(back.into_iter().map(|(t, f)| (t.to_bits(), f)).collect::<Vec<_>>(), expected);
    }
    let text = fs::read_to_string(&path).expect("text");
    assert!(text.contains("<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">"), "{text}");
    assert!(text.contains("<DataSet timestep=\"0\" group=\"\" part=\"0\" file=\"frames/f_0.vtu\"/>"), "{text}");
    assert_eq!(pvd.push(f64::NAN, "x.vtu").expect_err("NaN time").kind(), io::ErrorKind::InvalidInput);
    assert_eq!(entries(&dir), ["run.pvd"]);
}

#[test]
fn csv_round_trip_is_bitwise() {
    let dir = test_dir("csv");
    let path = dir.join("history.csv");
    let header = ["time", "F_c, N", "say \"hi\"", ""];
    let rows = [
        [1e-300, -0.0, 123456.789, 1.0 / 3.0],
        [5e-324, 1e300, f64::MAX, -f64::MIN_POSITIVE],
        [f64::INFINITY, f64::NEG_INFINITY, f64::NAN, 0.1 + 0.2],
    ];
    let mut series = TimeSeries::new(&path, &header);
    for row in &rows {
        series.push(row).expect("push");
    }
    series.write().expect("write");
    let (h, back) = csv::read(&path).expect("read");
    assert_eq!(h, header);
    let bits = |rows: &[Vec<f64>]| -> Vec<Vec<u64>> { rows.iter().map(|r| bits64(r)).collect() };
    assert_eq!(bits(&back), bits(&rows.map(|r| r.to_vec())));
    assert_eq!(bits(&back), bits(series.rows()));
    let text = fs::read_to_string(&path).expect("text");
    assert!(text.starts_with("time,\"F_c, N\",\"say \"\"hi\"\"\",\"\"\n1e-300,-0,123456.789,"), "{text}");
}

#[test]
fn csv_rows_of_the_wrong_length_are_refused() {
    let dir = test_dir("csv_length");
    let mut series = TimeSeries::new(dir.join("h.csv"), &["a", "b"]);
    let e = series.push(&[1.0]).expect_err("short row");
    assert_eq!(e.kind(), io::ErrorKind::InvalidInput);
    assert!(series.push(&[1.0, 2.0, 3.0]).is_err(), "long row");
    assert!(series.rows().is_empty(), "refused rows are not kept");
}

#[test]
fn writing_into_a_missing_directory_fails_naming_the_path_and_leaves_nothing() {
    let dir = test_dir("missing_dir");
    let path = dir.join("no").join("such").join("f.csv");
    let e = write_atomic(&path, b"x").expect_err("missing directory");
    assert_eq!(e.kind(), io::ErrorKind::NotFound);
    assert!(e.to_string().contains(&path.display().to_string()), "{e}");
    let e = vtu::write(&path, &Frame { time: 0.0, points: Values::F64(&[]), point_data: vec![], field_data: vec![] })
        .expect_err("missing directory");
    assert!(e.to_string().contains(&path.display().to_string()), "{e}");
    assert!(entries(&dir).is_empty(), "nothing created");
}

#[test]
fn successful_writes_leave_no_temporary_file() {
    let dir = test_dir("no_temporaries");
    write_atomic(&dir.join("a.bin"), &[1, 2, 3]).expect("write_atomic");
    write_atomic_with(&dir.join("b.txt"), |w| writeln!(w, "hello")).expect("write_atomic_with");
    vtu::write(
        &dir.join("c.vtu"),
        &Frame { time: 0.0, points: Values::F64(&[1.0; 6]), point_data: vec![], field_data: vec![] },
    )
    .expect("vtu");
    let mut pvd = Collection::new(dir.join("d.pvd"));
    pvd.push(0.0, "c.vtu").expect("push");
    pvd.write().expect("pvd");
    let mut series = TimeSeries::new(dir.join("e.csv"), &["t"]);
    series.push(&[0.0]).expect("push");
    series.write().expect("csv");
    assert_eq!(entries(&dir), ["a.bin", "b.txt", "c.vtu", "d.pvd", "e.csv"]);
    assert_eq!(fs::read(dir.join("b.txt")).expect("b"), b"hello\n");
}

#[test]
fn a_failing_writer_keeps_the_old_file_and_removes_the_temporary() {
    let dir = test_dir("failing_writer");
    let path = dir.join("f.dat");
    write_atomic(&path, b"old contents").expect("first write");
    let e = write_atomic_with(&path, |w| {
        w.write_all(&vec![0u8; 3 << 20])?; // more than the buffer: the temporary file has data
        Err(io::Error::other("simulated failure"))
    })
    .expect_err("the closure's error is returned");
    assert!(e.to_string().contains("simulated failure") && e.to_string().contains(&path.display().to_string()), "{e}");
    assert_eq!(fs::read(&path).expect("old file"), b"old contents");
    assert!(temporaries(&dir).is_empty(), "{:?}", entries(&dir));
}

#[test]
fn a_panicking_writer_removes_the_temporary() {
    let dir = test_dir("panicking_writer");
    let path = dir.join("f.dat");
    write_atomic(&path, b"old").expect("first write");
    let r = std::panic::catch_unwind(|| {
        write_atomic_with(&path, |w| {
            w.write_all(b"partial")?;
            panic!("simulated panic while writing")
        })
    });
    assert!(r.is_err(), "the panic propagates");
    assert_eq!(fs::read(&path).expect("old file"), b"old");
    assert!(temporaries(&dir).is_empty(), "{:?}", entries(&dir));
}

#[test]
fn an_existing_file_is_replaced_whole() {
    let dir = test_dir("overwrite");
    let path = dir.join("f.txt");
    write_atomic(&path, &[b'A'; 10_000]).expect("write A");
    write_atomic(&path, b"B").expect("write B");
    assert_eq!(fs::read(&path).expect("read"), b"B", "no tail of A survives");

    let vtu_path = dir.join("f.vtu");
    let big = vec![1.0f64; 3 * N];
    vtu::write(&vtu_path, &Frame { time: 1.0, points: Values::F64(&big), point_data: vec![], field_data: vec![] })
        .expect("write big frame");
    vtu::write(&vtu_path, &Frame { time: 2.0, points: Values::F64(&[7.0; 3]), point_data: vec![], field_data: vec![] })
        .expect("write small frame");
    let back = vtu::read(&vtu_path).expect("read");
    assert_eq!((back.n, back.time, back.points), (1, Some(2.0), OwnedValues::F64(vec![7.0; 3])));
    assert_eq!(entries(&dir), ["f.txt", "f.vtu"]);
}

// base64 (host/output/base64.rs), the VTU frames' encoding.
/// RFC 4648 §10's test vectors, both ways.
#[test]
fn rfc_4648_vectors() {
    let cases = [("", ""), ("f", "Zg=="), ("fo", "Zm8="), ("foo", "Zm9v"), ("foob", "Zm9vYg=="), ("fooba", "Zm9vYmE=")];
    for (plain, coded) in cases {
        let mut out = Vec::new();
        swarf::output::base64::encode(plain.as_bytes(), &mut out);
        assert_eq!(out, coded.as_bytes());
        assert_eq!(swarf::output::base64::decode(coded.as_bytes()).as_deref(), Some(plain.as_bytes()));
    }
    assert_eq!(swarf::output::base64::decode(b"Zg==Zg=="), None, "padding only at the end");
    assert_eq!(swarf::output::base64::decode(b"Zm9"), None);
}

// FNV-1a (host/hash.rs), the checksums of checkpoints and provenance.
/// The published test vectors of FNV-1a 64.
#[test]
fn known_values() {
    assert_eq!(swarf::hash::fnv1a64(b""), 0xcbf2_9ce4_8422_2325);
    assert_eq!(swarf::hash::fnv1a64(b"a"), 0xaf63_dc4c_8601_ec8c);
    assert_eq!(swarf::hash::fnv1a64(b"foobar"), 0x8594_4171_f739_67e8);
}
