//! `swarf render` (issue 27, expectation 5) and `swarf sweep` (expectation 6) on the CPU.
//!
//! render: a short coarse cut of V0060 (about 1 400 particles to t = 4 µs) is drawn from its run folder: a PNG of
//! the documented size with the particles in colour, a colour bar and the tool; the refusals (a missing field, a
//! 3D run, a frame that does not exist) name what is wrong and write nothing. sweep: a 2 × 2 sweep of the rubber
//! rings (Young's modulus × CFL number, 10 to 20 steps a run) writes four run folders, a table whose values are
//! each run's summary.json, and the plots; a bad key or value is refused before any run starts.

use std::path::{Path, PathBuf};

use swarf::backend::{AnyBackend, BackendChoice};
use swarf::output::{pvd, vtu};
use swarf::render::{Frames, RenderOptions, render};
use swarf::run::{RunOptions, run};
use swarf::scene::Scene;
use swarf::sweep::{Grid, Outcome, SweepOptions, sweep};

fn cpu() -> AnyBackend {
    AnyBackend::select(BackendChoice::Cpu).expect("cpu").0
}

/// A fresh, absent directory for one test.
fn test_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("render_sweep").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// The coarse V0060 cut of tests/cutting.rs (dx = 20 µm), to t = 4 µs with a frame every µs, in `dir`.
fn short_cut(dir: &Path) {
    let over: Vec<String> = [
        "discretisation.dx=2.0e-5",
        "body.0.max=[1.0e-3,2.8e-4]",
        "boundary.1.max=[1.0e-9,1.4e-4]",
        "boundary.2.min=[0.9999e-3,-1.0]",
        "tool.position=[-3.6e-5]",
        "tool.depth_of_cut=0.9e-4",
        "time.end=4e-6",
        "output.every=1e-6",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let scene = Scene::load("cases/cutting/v0060.toml", &over).expect("scene");
    let opts = RunOptions { frames: true, overrides: over, ..RunOptions::quiet(dir.to_path_buf()) };
    run(&cpu(), &scene, &opts).expect("the short cut runs");
}

/// The last frame's temperature, every particle, into `<run>/render` (a 3D run seen along −z).
fn last_temperature(run: &Path) -> RenderOptions {
    RenderOptions {
        run: run.to_path_buf(),
        field: "T".into(),
        frames: Frames::Last,
        out: None,
        slab: None,
        along: 2,
        window: None,
    }
}

/// A decoded PNG: (width, height, RGB pixels).
fn decode(path: &Path) -> (u32, u32, Vec<[u8; 3]>) {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut reader = png::Decoder::new(std::io::BufReader::new(file)).read_info().expect("a PNG");
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).expect("PNG data");
    assert_eq!(info.color_type, png::ColorType::Rgb, "{}", path.display());
    let pixels = buf[..info.buffer_size()].chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
    (info.width, info.height, pixels)
}

/// Pixels of column range `cols` (all rows).
fn region(img: &(u32, u32, Vec<[u8; 3]>), cols: std::ops::Range<u32>) -> Vec<[u8; 3]> {
    let (w, _, px) = img;
    px.iter().enumerate().filter(|(i, _)| cols.contains(&((*i as u32) % w))).map(|(_, p)| *p).collect()
}

/// Pixels of the tool's fill: grey 150 at 70 % over white is 181.5 (182 or 181 after rounding).
fn tool_grey(p: &[u8; 3]) -> bool {
    p[0] == p[1] && p[1] == p[2] && (180..=183).contains(&p[0])
}

/// Coloured (not grey) pixels: particles and the colour bar; text and axes are black or grey.
fn coloured(p: &[u8; 3]) -> bool {
    p.iter().max().unwrap() - p.iter().min().unwrap() > 30
}

/// The picture of a cut: the documented size (swarf::render::SIZE, 1200 × 800); in the plot area more than
/// 10 000 coloured pixels (the particles: about 1 400 discs of 4 to 5 px radius) and more than 2 000 pixels of the
/// tool's grey fill; in the colour bar's strip more than 100 distinct colours (256 slices of the map). The
/// same frame with the run folder's scene.toml removed is drawn with a warning and without the tool (under 200
/// tool-grey pixels, anti-aliased text only): the tool in the first picture comes from the scene.
#[test]
fn render_draws_a_cut_with_its_colour_bar_and_tool() {
    let dir = test_dir("cut");
    short_cut(&dir);
    let opts = last_temperature(&dir);
    let done = render(&opts).expect("render");
    assert!(done.warnings.is_empty(), "{:?}", done.warnings);
    assert_eq!(done.files, vec![dir.join("render").join("temperature_00004.png")]);
    let img = decode(&done.files[0]);
    assert_eq!((img.0, img.1), swarf::render::SIZE);
    let (bar, _) = swarf::render::draw::layout(swarf::render::SIZE);
    let plot = region(&img, 0..img.0 - bar);
    let particles = plot.iter().filter(|p| coloured(p)).count();
    let tool = plot.iter().filter(|p| tool_grey(p)).count();
    assert!(particles > 10_000, "{particles} coloured pixels in the plot area");
    assert!(tool > 2_000, "{tool} tool-grey pixels");
    let mut colours: Vec<[u8; 3]> = region(&img, img.0 - bar..img.0).into_iter().filter(coloured).collect();
    colours.sort();
    colours.dedup();
    assert!(colours.len() > 100, "{} colours in the colour bar", colours.len());

    std::fs::remove_file(dir.join("scene.toml")).expect("remove scene.toml");
    let out = dir.join("no-scene");
    let done = render(&RenderOptions { out: Some(out.clone()), ..opts }).expect("render without the scene");
    assert!(done.warnings.iter().any(|w| w.contains("tool is not drawn")), "{:?}", done.warnings);
    let img = decode(&out.join("temperature_00004.png"));
    let tool = region(&img, 0..img.0 - bar).iter().filter(|p| tool_grey(p)).count();
    assert!(tool < 200, "{tool} tool-grey pixels without a scene");
}

/// `--frame all` draws every frame of particles.pvd (5: t = 0, 1, 2, 3, 4 µs), each named by its entry; the
/// short names resolve to the frame's arrays in display units (von Mises stress in MPa: the frame's Pa × 1e-6);
/// refused: a field the frame lacks (the message names it and lists the fields with their short names), a frame
/// beyond the last (naming the range), a slab for a 2D run, a slab holding no particle of a 3D run. A refusal
/// writes no picture. A 3D run (by its scene's dim, and by z ≠ 0 without a scene) is drawn seen along −z: all its
/// particles, or those of the slab.
#[test]
fn render_all_frames_fields_and_refusals() {
    let dir = test_dir("frames");
    short_cut(&dir);
    let opts = RenderOptions { field: "vmises".into(), frames: Frames::All, ..last_temperature(&dir) };
    let done = render(&opts).expect("render all");
    let names: Vec<String> = done.files.iter().map(|f| f.file_name().unwrap().to_string_lossy().into_owned()).collect();
    assert_eq!(names, (0..5).map(|k| format!("von_mises_{k:05}.png")).collect::<Vec<_>>());

    let frame = vtu::read(&dir.join("frame_00004.vtu")).expect("frame");
    let field = swarf::render::Field::resolve("vmises", &frame, &dir).expect("vmises");
    let pa = frame.point_data.iter().find(|(n, _, _)| n == "von_mises").expect("von_mises array");
    let vtu::OwnedValues::F64(pa) = &pa.2 else { panic!("von_mises is f64") };
    let mpa = field.values(&frame).expect("values");
    assert!(pa.iter().zip(&mpa).all(|(a, b)| (a * 1e-6 - b).abs() <= 1e-12 * a.abs()), "MPa = Pa × 1e-6");
    assert_eq!(field.unit, "MPa");

    let missing = RenderOptions { field: "stress_xx".into(), frames: Frames::Last, out: Some(dir.join("x")), ..opts };
    let e = render(&missing).expect_err("a missing field").to_string();
    assert!(e.contains("'stress_xx'") && e.contains("temperature (T)") && e.contains("von_mises (vmises)"), "{e}");
    let beyond = RenderOptions { field: "T".into(), frames: Frames::Index(5), ..missing.clone() };
    let e = render(&beyond).expect_err("frame 5 of 0..=4").to_string();
    assert!(e.contains("--frame 5") && e.contains("frames 0 to 4"), "{e}");
    assert!(!dir.join("x").exists(), "a refused render wrote {}", dir.join("x").display());

    // A 3D run folder: one frame with z ≠ 0, first without a scene, then with a 3D scene.toml.
    let d3 = test_dir("3d");
    std::fs::create_dir_all(&d3).unwrap();
    let pts = [0.0, 0.0, 0.0, 1e-3, 0.0, 1e-3];
    let t = [300.0, 310.0];
    let f = vtu::Frame {
        time: 0.0,
        points: vtu::Values::F64(&pts),
        point_data: vec![vtu::Array { name: "temperature", components: 1, values: vtu::Values::F64(&t) }],
        field_data: vec![],
    };
    vtu::write(&d3.join("frame_00000.vtu"), &f).unwrap();
    let mut c = pvd::Collection::new(d3.join("particles.pvd"));
    c.push(0.0, "frame_00000.vtu").unwrap();
    c.write().unwrap();
    // Without a scene, z ≠ 0 makes it 3D: every particle, seen along −z; a slab keeps the particles in it; a slab
    // with none is refused before anything is written, as is a slab for a 2D run.
    let all = last_temperature(&d3);
    let empty = RenderOptions { slab: Some((2e-3, 3e-3)), out: Some(d3.join("empty")), ..all.clone() };
    let e = render(&empty).expect_err("an empty slab").to_string();
    assert!(e.contains("--slab") && e.contains("no particle"), "{e}");
    assert!(!d3.join("empty").exists());
    assert_eq!(render(&all).expect("3D, all").drawn, vec![2]);
    // A window (page axes x, y seen along −z) shows the particles in it; one holding none is refused the same way.
    let near = RenderOptions { window: Some(((-1e-4, 5e-4), (-1e-4, 1e-4))), out: Some(d3.join("w")), ..all.clone() };
    assert_eq!(render(&near).expect("a window").drawn, vec![1], "the window holds the particle at the origin only");
    let far = RenderOptions { window: Some(((2e-3, 3e-3), (0.0, 1e-3))), out: Some(d3.join("far")), ..all.clone() };
    let e = render(&far).expect_err("an empty window").to_string();
    assert!(e.contains("--window") && e.contains("no particle"), "{e}");
    assert!(!d3.join("far").exists());
    std::fs::copy("cases/cylinders-3d.toml", d3.join("scene.toml")).unwrap();
    let upper = RenderOptions { slab: Some((0.5e-3, 2e-3)), ..all.clone() };
    let done = render(&upper).expect("3D, a slab");
    assert_eq!(done.drawn, vec![1], "the slab holds the particle at z = 1 mm only");
    let along_x = RenderOptions { along: 0, slab: Some((-0.5e-3, 0.5e-3)), out: Some(d3.join("x")), ..all.clone() };
    assert_eq!(render(&along_x).expect("along x").drawn, vec![1], "the slab along x holds the particle at x = 0");
    assert!(done.files[0].is_file());
    let flat = RenderOptions { run: dir.clone(), slab: Some((0.0, 1.0)), ..all };
    let e = render(&flat).expect_err("a slab for a 2D run").to_string();
    assert!(e.contains("--slab") && e.contains("2D run"), "{e}");
}

/// `--window`'s geometry: the view is the window widened on one axis to the plot area's proportions (a 200 × 100
/// pixel area shows the unit square as x −0.5..1.5, y 0..1); the tool's outline is clipped to the view exactly
/// (a 2 × 2 square cut by x 0.5..1.5, y −1..1 keeps area 1 to rounding, every corner inside the view), where
/// plotters' clamping of corners to the plot area would change it.
#[test]
fn a_window_sets_the_view_and_clips_the_tool() {
    use swarf::render::draw::{clip, view};
    let ((x0, x1), (y0, y1)) = view(&[[5.0, 5.0]], None, (200, 100), Some(((0.0, 1.0), (0.0, 1.0))));
    for (got, want) in [(x0, -0.5), (x1, 1.5), (y0, 0.0), (y1, 1.0)] {
        assert!((got - want).abs() < 1e-15, "view ({x0}, {x1}), ({y0}, {y1})");
    }
    let square = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];
    let cut = clip(&square, ((0.5, 1.5), (-1.0, 1.0)));
    let area = 0.5 * cut.iter().zip(cut.iter().cycle().skip(1)).map(|(p, q)| p[0] * q[1] - q[0] * p[1]).sum::<f64>();
    assert!((area - 1.0).abs() < 1e-12, "clipped area {area}: {cut:?}");
    assert!(cut.iter().all(|p| (0.5..=1.5).contains(&p[0]) && (-1.0..=1.0).contains(&p[1])), "{cut:?}");
    assert!(clip(&square, ((3.0, 4.0), (0.0, 1.0))).is_empty(), "a polygon outside the view leaves nothing");
}

/// The grid syntax: values split at top-level commas (a bracketed value keeps its commas); refused: no '=',
/// an empty value, a value given twice.
#[test]
fn grid_parses_values_and_refuses_malformed_ones() {
    let g = Grid::parse("body.0.velocity=[1.0,0.0],[2.0,0.0]").expect("brackets");
    assert_eq!(g.key, "body.0.velocity");
    assert_eq!(g.values, vec!["[1.0,0.0]", "[2.0,0.0]"]);
    for bad in ["time.cfl", "time.cfl=0.3,,0.5", "time.cfl=0.3,0.3", "=1,2"] {
        let e = Grid::parse(bad).expect_err(bad);
        assert!(e.contains(&format!("--grid {bad}")), "{e}");
    }
}

fn rings_sweep(dir: &Path, grids: &[&str]) -> SweepOptions {
    SweepOptions {
        scene: "cases/rings.toml".into(),
        // Frames (and so steps, which end on them) every µs: the default time.end/50 would cut every step short.
        overrides: vec!["time.end=2e-6".into(), "output.every=1e-6".into()],
        grids: grids.iter().map(|g| Grid::parse(g).expect("grid")).collect(),
        out_dir: dir.to_path_buf(),
        precision: None,
        frames: false,
        quiet: true,
        width: None,
    }
}

/// A 2 × 2 sweep of the rings over Young's modulus and the CFL number: four run folders named by their values;
/// sweep.csv has a header and 4 rows, in the grid's order (the last key fastest), whose particles, steps,
/// wall_time_s and dt_s are exactly those of each run's summary.json (CSV numbers are Rust's shortest round-trip
/// form); the CFL number changes the step count (dt ∝ CFL) and the modulus dt (c0 = √(K/ρ)); sweep.md has the 4
/// rows; a plot per key is drawn.
#[test]
fn sweep_of_the_rings_writes_runs_table_and_plots() {
    let dir = test_dir("sweep");
    let s = sweep(&cpu(), &rings_sweep(&dir, &["material.youngs_modulus=1e7,2e7", "time.cfl=0.3,0.5"])).expect("sweep");
    let names = [
        "000-material.youngs_modulus-1e7_time.cfl-0.3",
        "001-material.youngs_modulus-1e7_time.cfl-0.5",
        "002-material.youngs_modulus-2e7_time.cfl-0.3",
        "003-material.youngs_modulus-2e7_time.cfl-0.5",
    ];
    let (head, rows) = read_csv(&dir.join("sweep.csv"));
    assert_eq!(rows.len(), 4);
    let col = |name: &str| head.iter().position(|h| h == name).unwrap_or_else(|| panic!("no column {name}: {head:?}"));
    let mut dts = Vec::new();
    let mut steps = Vec::new();
    for (k, name) in names.iter().enumerate() {
        let run = dir.join(name);
        assert!(matches!(s.points[k].outcome, Outcome::Done(_)), "{name}: {:?}", s.points[k].outcome);
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(run.join("summary.json")).expect("summary.json")).unwrap();
        assert_eq!(rows[k][col("run")], *name);
        assert_eq!(rows[k][col("status")], "ok");
        assert_eq!(rows[k][col("material.youngs_modulus")], ["1e7", "1e7", "2e7", "2e7"][k]);
        assert_eq!(rows[k][col("time.cfl")], ["0.3", "0.5", "0.3", "0.5"][k]);
        for key in ["particles", "steps", "wall_time_s", "dt_s"] {
            let cell: f64 = rows[k][col(key)].parse().unwrap_or_else(|_| panic!("{name} {key}: {:?}", rows[k]));
            assert_eq!(cell, summary[key].as_f64().expect(key), "{name}: {key}");
        }
        dts.push(summary["dt_s"].as_f64().unwrap());
        steps.push(summary["steps"].as_u64().unwrap());
    }
    assert!(steps[0] > steps[1] && steps[2] > steps[3], "CFL 0.3 takes more steps than 0.5: {steps:?}");
    assert!(dts[2] < dts[0], "a stiffer material takes a smaller dt: {dts:?}");
    let md = std::fs::read_to_string(dir.join("sweep.md")).expect("sweep.md");
    assert_eq!(md.lines().filter(|l| l.starts_with("| 1e7") || l.starts_with("| 2e7")).count(), 4, "{md}");
    for f in ["sweep-material.youngs_modulus.png", "sweep-time.cfl.png"] {
        let (w, h, _) = decode(&dir.join(f));
        assert!(w == 1000 && h >= 320, "{f}: {w}x{h}");
    }
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
}

/// Refused before any run, naming the key: a key the scene does not have, a value out of its range (only the
/// second value of the grid is bad: the first must not have run), a key swept twice or also given by --set.
/// The sweep folder is never created.
#[test]
fn sweep_refuses_bad_keys_and_values_before_any_run() {
    let dir = test_dir("refused");
    let cases: [(&[&str], &[&str], &str); 4] = [
        (&["material.youngs_modulos=1e7,2e7"], &[], "youngs_modulos"),
        (&["time.cfl=0.5,2.0"], &[], "time.cfl=2.0"),
        (&["time.cfl=0.3,0.5", "time.cfl=0.4"], &[], "swept twice"),
        (&["time.cfl=0.3,0.5"], &["time.cfl=0.4"], "also given by --set"),
    ];
    for (grids, sets, expect) in cases {
        let mut opts = rings_sweep(&dir, grids);
        opts.overrides.extend(sets.iter().map(|s| s.to_string()));
        let e = sweep(&cpu(), &opts).expect_err(expect).to_string();
        assert!(e.contains(expect), "{grids:?}: {e}");
        assert!(!dir.exists(), "{grids:?}: {} was created", dir.display());
    }
}

/// The CLI refuses a bad key the same way (exit 1, the key named) without starting a run.
#[test]
fn sweep_command_refuses_a_bad_key() {
    let dir = test_dir("cli-refused");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_swarf"))
        .args(["--backend", "cpu", "sweep", "cases/rings.toml", "--grid", "time.cfll=0.3,0.5", "--out"])
        .arg(&dir)
        .output()
        .expect("swarf runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("cfll"), "{err}");
    assert!(!dir.exists());
}

/// sweep.csv as (header, rows of text cells); the cells here hold no quoted commas.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines().map(|l| l.split(',').map(String::from).collect::<Vec<_>>());
    let head = lines.next().expect("a header");
    (head, lines.collect())
}
