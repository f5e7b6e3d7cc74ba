//! swarf outside the repository (issue 27, "What users of peer tools expect"): every command runs with a working
//! directory outside the source tree, as an installed `swarf` does. Before the material library was embedded, a
//! scene naming a library material, `swarf material` and `--resume` failed there with "cases/materials: No such
//! file or directory"; `swarf run` without a scene read cases/cutting/v0060.toml from the source tree.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const REPO: &str = env!("CARGO_MANIFEST_DIR");

/// A fresh folder under the system's temporary folder (outside the repository).
fn scratch(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("swarf-test-port-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("create scratch folder");
    d
}

/// `swarf` on the CPU in the folder `cwd`, with SWARF_MATERIALS unset unless `materials` is given.
fn swarf(cwd: &Path, materials: Option<&Path>, args: &[&str]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_swarf"));
    c.current_dir(cwd).env_remove("SWARF_MATERIALS").args(["--backend", "cpu"]).args(args);
    if let Some(m) = materials {
        c.env("SWARF_MATERIALS", m);
    }
    c.output().expect("swarf starts")
}

fn ok(out: &Output, what: &str) -> String {
    let text = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "{what} failed: {text}");
    text
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// A 2D block of 10 × 10 particles of the library material AISI4340-Roethlin, moving at 10 m/s: a few steps.
const SCENE: &str = r#"
name = "block"
dim = 2
[discretisation]
dx = 1.0e-3
h_over_dx = 1.5
[material]
name = "AISI4340-Roethlin"
[[body]]
name = "block"
shape = "rectangle"
min = [0.0, 0.0]
max = [0.01, 0.01]
velocity = [10.0, 0.0]
[time]
end = 2.0e-6
"#;

fn library_file(name: &str) -> String {
    read(&Path::new(REPO).join("cases/materials").join(format!("{name}.toml")))
}

/// A user's copy of AISI4340-Roethlin with another density, in its own folder.
fn user_library(dir: &Path) -> (PathBuf, String) {
    let lib = dir.join("mylib");
    std::fs::create_dir_all(&lib).expect("mkdir");
    let text = library_file("AISI4340-Roethlin");
    let edited = text.replacen("density = 7830.0", "density = 7000.0", 1);
    assert_ne!(edited, text, "cases/materials/AISI4340-Roethlin.toml gives density = 7830.0");
    std::fs::write(lib.join("AISI4340-Roethlin.toml"), &edited).expect("write");
    (lib, edited)
}

/// A scene outside the repository that names a library material runs (from the built-in library), and its run
/// folder records the material's file (`materials/AISI4340-Roethlin.toml`, the library's text) beside the scene.
/// Before: "material.name: expected a material of the library cases/materials (No such file or directory)".
#[test]
fn library_material_scene_runs_outside_the_repository() {
    let d = scratch("lib");
    std::fs::write(d.join("block.toml"), SCENE).expect("write scene");
    let out = swarf(&d, None, &["run", "block.toml", "--quiet", "--out", "run"]);
    ok(&out, "swarf run block.toml");
    assert_eq!(read(&d.join("run/materials/AISI4340-Roethlin.toml")), library_file("AISI4340-Roethlin"));
    assert_eq!(read(&d.join("run/scene.toml")), SCENE);
}

/// SWARF_MATERIALS shadows the built-in material of the same name: `swarf material` names the user's file and
/// prints its density, and a run records the user's values. A folder in SWARF_MATERIALS that does not exist is an
/// error naming it.
#[test]
fn swarf_materials_overrides_the_built_in_library() {
    let d = scratch("env");
    let (lib, edited) = user_library(&d);
    let text = ok(&swarf(&d, Some(&lib), &["material", "AISI4340-Roethlin"]), "swarf material");
    assert!(text.contains("density 7000 kg/m^3"), "{text}");
    assert!(text.contains(&lib.join("AISI4340-Roethlin.toml").display().to_string()), "{text}");
    std::fs::write(d.join("block.toml"), SCENE).expect("write scene");
    ok(&swarf(&d, Some(&lib), &["run", "block.toml", "--quiet", "--out", "run"]), "swarf run");
    assert_eq!(read(&d.join("run/materials/AISI4340-Roethlin.toml")), edited);
    let missing = d.join("no-such-folder");
    let out = swarf(&d, Some(&missing), &["check", "block.toml"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("no-such-folder") && err.contains("material.name"), "{err}");
}

/// A `materials/` folder beside the scene shadows the built-in library; one without the name falls through to
/// the built-in library (an empty folder does not hide it).
#[test]
fn materials_folder_beside_the_scene() {
    let d = scratch("beside");
    std::fs::write(d.join("block.toml"), SCENE).expect("write scene");
    std::fs::create_dir_all(d.join("materials")).expect("mkdir");
    ok(&swarf(&d, None, &["check", "block.toml"]), "check with an empty materials/");
    let (lib, edited) = user_library(&d);
    std::fs::rename(lib.join("AISI4340-Roethlin.toml"), d.join("materials/AISI4340-Roethlin.toml")).expect("mv");
    ok(&swarf(&d, None, &["run", "block.toml", "--quiet", "--out", "run"]), "swarf run");
    assert_eq!(read(&d.join("run/materials/AISI4340-Roethlin.toml")), edited);
}

/// `swarf material` lists the built-in library from any folder (before: "cases/materials: No such file").
#[test]
fn material_command_runs_outside_the_repository() {
    let d = scratch("list");
    let text = ok(&swarf(&d, None, &["material"]), "swarf material");
    let files = std::fs::read_dir(Path::new(REPO).join("cases/materials")).expect("cases/materials").count();
    assert_eq!(text.lines().count(), files, "one line per file of cases/materials:\n{text}");
    assert!(text.contains("Ti6Al4V-Roethlin"), "{text}");
}

/// `--resume` of a run folder works from another folder and uses the materials the run recorded, not a
/// SWARF_MATERIALS set since: the resumed run's folder still holds the library's values.
#[test]
fn resume_uses_the_recorded_materials_from_any_folder() {
    let d = scratch("resume");
    std::fs::write(d.join("block.toml"), SCENE).expect("write scene");
    let run = d.join("run");
    let args = ["run", "block.toml", "--quiet", "--checkpoint-every", "1e-6", "--out", "run"];
    ok(&swarf(&d, None, &args), "swarf run");
    assert!(run.join("checkpoint.bin").is_file(), "a checkpoint half way");
    let elsewhere = scratch("resume-cwd");
    let (lib, _) = user_library(&elsewhere);
    let run_arg = run.display().to_string();
    ok(&swarf(&elsewhere, Some(&lib), &["run", "--quiet", "--resume", &run_arg]), "swarf run --resume");
    assert_eq!(read(&run.join("materials/AISI4340-Roethlin.toml")), library_file("AISI4340-Roethlin"));
}

/// The default scene is built in: `swarf check` and a short `swarf run` without a scene work outside the
/// repository, and the run folder holds the scene's text and its material.
#[test]
fn default_scene_is_built_in() {
    let d = scratch("default");
    let text = ok(&swarf(&d, None, &["check"]), "swarf check");
    assert!(text.contains("v0060"), "{text}");
    // 5e-7 s: the tool (3 µm clear at 6.355 m/s) must reach the workpiece before the end.
    let out = swarf(&d, None, &["run", "--quiet", "--set", "time.end=5e-7", "--set", "output.every=2.5e-7"]);
    ok(&out, "swarf run");
    let run = d.join("runs/v0060");
    assert_eq!(read(&run.join("scene.toml")), read(&Path::new(REPO).join("cases/cutting/v0060.toml")));
    assert!(run.join("materials/Ti6Al4V-V0060-DE-mu035.toml").is_file());
}

/// The version and the git commit are in `swarf info`, `swarf --version`, run.log and summary.json (before: the
/// version only, in `swarf info`).
#[test]
fn version_and_commit_are_recorded() {
    let d = scratch("version");
    let commit = Command::new("git")
        .current_dir(REPO)
        .args(["rev-parse", "--short", "HEAD"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map_or("unknown".to_string(), |o| String::from_utf8_lossy(&o.stdout).trim().to_string());
    let line = format!("{} (commit {commit})", env!("CARGO_PKG_VERSION"));
    assert_eq!(swarf::run::VERSION, line);
    assert!(ok(&swarf(&d, None, &["info"]), "swarf info").starts_with(&format!("swarf {line}\n")));
    assert!(ok(&swarf(&d, None, &["--version"]), "swarf --version").contains(&line));
    std::fs::write(d.join("block.toml"), SCENE).expect("write scene");
    ok(&swarf(&d, None, &["run", "block.toml", "--quiet", "--out", "run"]), "swarf run");
    assert!(read(&d.join("run/run.log")).starts_with(&format!("swarf {line}\n")));
    let summary: serde_json::Value = serde_json::from_str(&read(&d.join("run/summary.json"))).expect("json");
    assert_eq!(summary["swarf_version"], env!("CARGO_PKG_VERSION"));
    assert_eq!(summary["git_commit"], commit.as_str());
}

/// A frame of n particles with an array of each type a run writes (f64 and f32, u32, i32, several components),
/// values that compress (ids, a smooth field) and values that do not (hashes).
struct FrameData {
    points: Vec<f64>,
    rho: Vec<f64>,
    vel: Vec<f32>,
    id: Vec<u32>,
    kind: Vec<i32>,
}

impl FrameData {
    fn new(n: usize) -> Self {
        let hash = |i: usize| (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 11;
        FrameData {
            points: (0..3 * n).map(|i| (hash(i) as f64) * 1e-18).collect(),
            rho: (0..n).map(|i| 7830.0 + (i as f64 * 1e-3).sin()).collect(),
            vel: (0..3 * n).map(|i| hash(i + 7) as f32 * 1e-12).collect(),
            id: (0..n as u32).collect(),
            kind: (0..n as i32).map(|i| i % 5 - 2).collect(),
        }
    }

    fn frame(&self) -> swarf::output::Frame<'_> {
        use swarf::output::{Array, Frame, Values};
        Frame {
            time: 1.0 / 3.0,
            points: Values::F64(&self.points),
            point_data: vec![
                Array { name: "density", components: 1, values: Values::F64(&self.rho) },
                Array { name: "velocity", components: 3, values: Values::F32(&self.vel) },
                Array { name: "id", components: 1, values: Values::U32(&self.id) },
                Array { name: "kind", components: 1, values: Values::I32(&self.kind) },
            ],
            field_data: vec![("STEP", 42.0)],
        }
    }
}

/// Frames written with `base64-zlib` (VTK's zlib layout, `compressor="vtkZLibDataCompressor"`, base64 appended
/// data) read back, through swarf's own reader, equal to the raw frame bit for bit, for sizes below, at and above
/// one 32 KiB zlib block (n = 0, 1, 4096 = 32 KiB of f64, 50 000). Before: one encoding (raw), which meshio
/// cannot read.
#[test]
fn base64_zlib_frames_read_back_as_the_raw_ones() {
    use swarf::output::vtu::{self, Encoding};
    let d = scratch("vtu");
    for n in [0, 1, 4096, 50_000] {
        let data = FrameData::new(n);
        let (raw, zlib) = (d.join(format!("raw{n}.vtu")), d.join(format!("zlib{n}.vtu")));
        vtu::write_encoded(&raw, &data.frame(), Encoding::Raw).expect("write raw");
        vtu::write_encoded(&zlib, &data.frame(), Encoding::Base64Zlib).expect("write zlib");
        let text = std::fs::read(&zlib).expect("read");
        let head = String::from_utf8_lossy(&text[..text.len().min(4096)]).to_string();
        assert!(head.contains(r#"compressor="vtkZLibDataCompressor""#) && head.contains(r#"encoding="base64""#));
        assert!(text.iter().all(|b| b.is_ascii()), "a base64 frame is text");
        let (a, b) = (vtu::read(&raw).expect("raw"), vtu::read(&zlib).expect("zlib"));
        assert_eq!((a.n, b.n), (n, n));
        assert_eq!(a.points, b.points, "n = {n}: points");
        assert_eq!(a.point_data, b.point_data, "n = {n}: point data");
        assert_eq!(a.time.map(f64::to_bits), b.time.map(f64::to_bits));
        assert_eq!(a.field_data, b.field_data);
    }
}

/// A damaged base64-zlib frame is refused with an error naming the file, not a panic or a silent wrong value:
/// a flipped character in the compressed data, a file cut short, and padding inside the first array's header
/// (which decodes to fewer bytes than the header's three words).
#[test]
fn damaged_base64_zlib_frames_are_refused() {
    use swarf::output::vtu::{self, Encoding};
    let d = scratch("vtu-bad");
    let data = FrameData::new(2000);
    let good = d.join("good.vtu");
    vtu::write_encoded(&good, &data.frame(), Encoding::Base64Zlib).expect("write");
    let text = std::fs::read(&good).expect("read");
    let start = text.windows(2).rposition(|w| w == b"_A").expect("the appended data starts with _") + 1;
    let mut flipped = text.clone();
    let k = start + (text.len() - start) / 2;
    flipped[k] = if flipped[k] == b'A' { b'B' } else { b'A' };
    let cut = text[..start + (text.len() - start) / 3].to_vec();
    let mut padded = text.clone();
    padded[start + 30..start + 32].copy_from_slice(b"==");
    for (name, bytes) in [("flipped.vtu", flipped), ("cut.vtu", cut), ("padded.vtu", padded)] {
        let path = d.join(name);
        std::fs::write(&path, bytes).expect("write");
        let e = vtu::read(&path).expect_err("a damaged frame must be refused");
        assert!(e.to_string().contains(name), "{e}");
    }
}

/// `output.vtu_encoding` picks the frames' encoding for a run: the base64-zlib run's frames read back equal to
/// the raw run's; an unknown value is refused naming the key and the allowed values.
#[test]
fn vtu_encoding_scene_key() {
    let d = scratch("vtu-key");
    std::fs::write(d.join("block.toml"), SCENE).expect("write scene");
    ok(&swarf(&d, None, &["run", "block.toml", "--quiet", "--out", "raw"]), "raw run");
    let set = r#"output.vtu_encoding="base64-zlib""#;
    ok(&swarf(&d, None, &["run", "block.toml", "--quiet", "--out", "zlib", "--set", set]), "zlib run");
    let frame = "frame_00050.vtu";
    let zlib = std::fs::read(d.join("zlib").join(frame)).expect("zlib frame");
    assert!(String::from_utf8_lossy(&zlib).contains(r#"<AppendedData encoding="base64">"#));
    let a = swarf::output::vtu::read(&d.join("raw").join(frame)).expect("raw");
    let b = swarf::output::vtu::read(&d.join("zlib").join(frame)).expect("zlib");
    assert_eq!((a.points, a.point_data), (b.points, b.point_data));
    let out = swarf(&d, None, &["check", "block.toml", "--set", r#"output.vtu_encoding="gzip""#]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("output.vtu_encoding") && err.contains("base64-zlib"), "{err}");
}

fn v0060() -> String {
    read(&Path::new(REPO).join("cases/cutting/v0060.toml"))
}

/// Replaces the line starting with `key =` (its first occurrence) by `key = value`.
fn set_line(text: &str, key: &str, value: &str) -> String {
    let prefix = format!("{key} =");
    let line = text.lines().find(|l| l.starts_with(&prefix)).unwrap_or_else(|| panic!("no line {prefix}"));
    text.replacen(line, &format!("{key} = {value}"), 1)
}

/// Length, speed, angle and temperature keys take a unit suffix: the V0060 cut written in the units of the
/// experiment's report (381.3 m/min, 33 µm, 7°, 24.85 °C, 10 µm) is the same scene as the SI file, to the
/// conversions' rounding; from the file and from `--set`. Before: "expected a positive radius in m".
#[test]
fn unit_suffixes_give_the_si_scene() {
    use swarf::scene::Scene;
    let si = Scene::from_str(&v0060(), "v0060.toml", &[]).expect("v0060");
    let mut text = v0060();
    for (key, value) in [
        ("velocity", r#"["381.3 m/min", 0.0]"#),
        ("edge_radius", r#""33 um""#),
        ("clearance_angle", r#""7 deg""#),
        ("initial_temperature", r#""24.85 C""#),
        ("dx", r#""10 µm""#),
        ("depth_of_cut", r#""0.1 mm""#),
    ] {
        text = set_line(&text, key, value);
    }
    let with_units = Scene::from_str(&text, "v0060.toml", &[]).expect("the scene with units");
    let (a, b) = (si.tool.as_ref().expect("tool"), with_units.tool.as_ref().expect("tool"));
    let close = |x: f64, y: f64, what: &str| assert!((x - y).abs() <= 1e-12 * y.abs().max(1.0), "{what}: {x} {y}");
    close(b.velocity[0], a.velocity[0], "tool.velocity: 381.3 m/min = 6.355 m/s");
    close(b.edge_radius, a.edge_radius, "tool.edge_radius");
    close(b.clearance_angle, a.clearance_angle, "tool.clearance_angle");
    close(with_units.physics.initial_temperature, si.physics.initial_temperature, "physics.initial_temperature");
    close(with_units.discretisation.dx, si.discretisation.dx, "discretisation.dx");
    // The summary echoes SI.
    assert!(with_units.summary().contains("dx = 1e-5 m"), "{}", with_units.summary());
    let set = [r#"tool.velocity=["381.3 m/min", "0 m/s"]"#.to_string(), r#"tool.rake_angle="0.1 rad""#.to_string()];
    let s = Scene::from_str(&v0060(), "v0060.toml", &set).expect("--set with units");
    let t = s.tool.as_ref().expect("tool");
    close(t.velocity[0], a.velocity[0], "--set tool.velocity");
    close(t.rake_angle, 0.1f64.to_degrees(), "--set tool.rake_angle in rad, stored in degrees");
}

/// An unknown unit, a unit of another quantity, or a unit on a key without units is refused, naming the file, the
/// line, the key and (for keys with units) the units allowed.
#[test]
fn unknown_units_are_refused_with_the_allowed_ones() {
    use swarf::scene::Scene;
    let cases = [
        ("edge_radius", r#""33 uM""#, "tool.edge_radius", Some("m, cm, mm, um, µm, μm, nm")),
        ("edge_radius", r#""33 m/s""#, "tool.edge_radius", Some("length unit")),
        ("clearance_angle", r#""7 grad""#, "tool.clearance_angle", Some("deg, °, rad")),
        ("initial_temperature", r#""25 F""#, "physics.initial_temperature", Some("K, C, °C, degC")),
        ("velocity", r#"["381.3 m/h", 0.0]"#, "tool.velocity", Some("m/s, m/min, mm/s, mm/min, km/h")),
        ("end", r#""1 ms""#, "time.end", None),
    ];
    for (key, value, dotted, units) in cases {
        let text = set_line(&v0060(), key, value);
        let line = text.lines().position(|l| l.starts_with(&format!("{key} = {value}"))).expect("line") + 1;
        let e = Scene::from_str(&text, "v0060.toml", &[]).expect_err(value).to_string();
        assert!(e.contains(&format!("v0060.toml:{line}")) && e.contains(dotted), "{value}: {e}");
        match units {
            Some(u) => assert!(e.contains(u), "{value}: {e}"),
            None => assert!(!e.contains("unit:"), "{value}: {e}"),
        }
    }
    // Converted values are range-checked like plain ones.
    let e = Scene::from_str(&set_line(&v0060(), "edge_radius", r#""-3 um""#), "v0060.toml", &[]).expect_err("< 0");
    assert!(e.to_string().contains("tool.edge_radius"), "{e}");
}
