//! `swarf study` on the CPU: the files it writes, its errors against the reference run and the experiment, the
//! `[experiment]` table and `tool.depth_of_cut` of the scene format, and the refusals of bad input.
//!
//! The studied scene is the rubber disk of cases/disk-rotation.toml (276 particles, roethlin-solver.md §7.1) cut to
//! t = 1 ms: about 50 steps at Δx and 100 at Δx/2, a second or two per study.

use std::path::{Path, PathBuf};

use swarf::backend::{AnyBackend, BackendChoice};
use swarf::scene::{Precision, Scene};
use swarf::study::{Level, Outcome, StudyOptions, study, table};

const DISK: &str = "cases/disk-rotation.toml";

fn cpu() -> AnyBackend {
    AnyBackend::select(BackendChoice::Cpu).expect("cpu").0
}

fn out(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("swarf-test-study-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn options(scene: &Path, sets: &[&str], levels: &[&str], precisions: &[Precision], dir: &Path) -> StudyOptions {
    StudyOptions {
        scene: scene.to_path_buf(),
        overrides: sets.iter().map(|s| s.to_string()).collect(),
        levels: levels.iter().map(|l| Level::parse(l).expect("level")).collect(),
        precisions: precisions.to_vec(),
        out_dir: dir.to_path_buf(),
        quiet: true,
    }
}

fn stats(o: &Outcome) -> &swarf::study::RunStats {
    match o {
        Outcome::Done(s) => s,
        other => panic!("the run did not finish: {other:?}"),
    }
}

/// Two levels × two precisions of the disk: every file is written; the reference is the finest f64 run and its
/// errors are exactly 0; the f32 run at the same level differs from it by more than 0 and at most 1e-3 in every
/// observable. Why 1e-3: f32 rounds each operation to 6e-8 relative; over 100 steps the positions (extents)
/// drift by a few 1e-7 and the kinetic energy by less, while the elastic energy, built from stresses that are
/// differences of nearly equal displacements at t = 1 ms (the disk has barely begun to stretch), loses about
/// three more digits (2.5e-5 measured); 1e-3 leaves a factor 40. The coarse level's error is the resolution's:
/// f32 and f64 agree there to the same 1e-3.
#[test]
fn study_of_the_disk_writes_its_files_and_measures_f32_against_the_finest_f64_run() {
    let dir = out("disk");
    let opts = options(Path::new(DISK), &["time.end=1e-3"], &["1", "1/2"], &[Precision::F64, Precision::F32], &dir);
    let s = study(&[cpu()], &opts).expect("the study runs");
    for f in ["study.csv", "study.md", "study.png"] {
        assert!(dir.join(f).is_file(), "{f} missing in {}", dir.display());
    }
    assert_eq!(s.runs.len(), 4);
    for r in &s.runs {
        assert!(r.dir.join("summary.json").is_file() && r.dir.join("energy.csv").is_file(), "{}", r.dir.display());
        assert!(!r.dir.join("particles.pvd").exists(), "a study run writes no frames");
    }
    // Runs nest levels × precisions: [1 f64, 1 f32, 1/2 f64, 1/2 f32]; the reference is 1/2 f64.
    assert_eq!(s.reference, 2);
    assert_eq!((s.runs[2].precision, s.runs[2].level.factor()), (Precision::F64, 0.5));
    assert_eq!(stats(&s.runs[0].outcome).particles, 276, "the thesis' disk at Δx = 2/19 m (§7.1)");
    assert_eq!(s.runs[2].dx, 0.10526315789473684 * 0.5);
    let names: Vec<&str> = s.observables.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(
        names,
        ["kinetic_energy_j", "elastic_energy_j", "disk_extent_x_m", "disk_extent_y_m", "disk_radius_xy_max_m"]
    );
    let e = table::errors(&s, 2);
    assert!(e.reference.iter().all(|x| *x == Some(0.0)), "the reference against itself: {:?}", e.reference);
    let f32_fine = table::errors(&s, 3);
    for (o, err) in s.observables.iter().zip(&f32_fine.reference) {
        let err = err.expect("measured");
        assert!(err > 0.0 && err <= 1e-3, "f32 at Δx/2, {}: relative error {err:e} not in (0, 1e-3]", o.name);
    }
    let (c64, c32) = (table::errors(&s, 0), table::errors(&s, 1));
    for ((o, a), b) in s.observables.iter().zip(&c64.reference).zip(&c32.reference) {
        let (a, b) = (a.expect("measured"), b.expect("measured"));
        assert!((a - b).abs() <= 1e-3 * a.max(1e-300) + 1e-12, "{} at Δx: f64 {a:e}, f32 {b:e}", o.name);
    }
    // study.csv holds the same numbers, a row per run, and the run folders' summaries agree with it.
    let text = std::fs::read_to_string(dir.join("study.csv")).expect("study.csv");
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().expect("header").split(',').collect();
    for col in ["level", "dx_m", "precision", "backend", "particles", "steps", "wall_s", "ms_per_step", "max_err_ref"] {
        assert!(head.contains(&col), "study.csv lacks {col}: {head:?}");
    }
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 4);
    let col = |name: &str| head.iter().position(|h| *h == name).expect("column");
    for (row, run) in rows.iter().zip(&s.runs) {
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(run.dir.join("summary.json")).expect("summary"))
                .expect("json");
        assert_eq!(row[col("particles")], summary["particles"].to_string());
        assert_eq!(row[col("steps")], summary["steps"].to_string());
        assert_eq!(row[col("precision")], summary["precision"].as_str().expect("precision"));
        let dx_set = format!("discretisation.dx={:e}", run.dx);
        assert!(summary["overrides"].as_array().expect("overrides").iter().any(|v| v == &dx_set), "{summary}");
    }
    assert_eq!(rows[2][col("kinetic_energy_j_err_ref")], "0");
    let md = std::fs::read_to_string(dir.join("study.md")).expect("study.md");
    assert_eq!(md.lines().filter(|l| l.starts_with("| ")).count(), 5, "header and 4 rows:\n{md}");
    assert!(md.contains("(ref)") && md.contains("ref ") && md.contains("%"), "{md}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The error against the experiment is |a − m|/|m| with m the `[experiment]` value, bit for bit, for every
/// measured observable and no other; the Markdown table shows the measurement with its uncertainty.
#[test]
fn experiment_error_is_relative_to_the_measured_value() {
    let dir = out("experiment");
    std::fs::create_dir_all(&dir).expect("dir");
    let text = std::fs::read_to_string(DISK).expect("scene")
        + "\n[experiment]\nkinetic_energy_j = { value = 1800.0, uncertainty = 5.0 }\ndisk_extent_x_m = 2.0\n";
    let scene = dir.join("disk-experiment.toml");
    std::fs::write(&scene, text).expect("scene written");
    let opts = options(&scene, &["time.end=1e-3"], &["1"], &[Precision::F64], &dir.join("study"));
    let s = study(&[cpu()], &opts).expect("the study runs");
    let values = &stats(&s.runs[0].outcome).values;
    let e = table::errors(&s, 0);
    for (i, o) in s.observables.iter().enumerate() {
        let want = match o.name.as_str() {
            "kinetic_energy_j" => Some((values[i].expect("kinetic") - 1800.0).abs() / 1800.0),
            "disk_extent_x_m" => Some((values[i].expect("extent") - 2.0).abs() / 2.0),
            _ => None,
        };
        assert_eq!(e.experiment[i].map(f64::to_bits), want.map(f64::to_bits), "{}", o.name);
    }
    assert!(e.max_experiment.expect("max") > 0.0);
    assert_eq!(table::relative(Some(3.0), Some(2.0)), Some(0.5));
    assert_eq!(table::relative(Some(-1.0), Some(-4.0)), Some(0.75));
    assert_eq!(table::relative(Some(0.0), Some(0.0)), Some(0.0));
    assert_eq!(table::relative(None, Some(1.0)), None);
    let csv = std::fs::read_to_string(dir.join("study").join("study.csv")).expect("study.csv");
    let head: Vec<&str> = csv.lines().next().expect("header").split(',').collect();
    assert!(head.contains(&"kinetic_energy_j_err_exp") && head.contains(&"disk_extent_x_m_err_exp"), "{head:?}");
    assert!(!head.contains(&"elastic_energy_j_err_exp"), "no experiment column without a measurement: {head:?}");
    let md = std::fs::read_to_string(dir.join("study").join("study.md")).expect("study.md");
    assert!(md.contains("| experiment |") && md.contains("1800 ± 5.0"), "{md}");
    // Only the experiment panel has a non-zero error to draw (the single run is its own reference).
    assert!(dir.join("study").join("study.png").is_file());
    let _ = std::fs::remove_dir_all(&dir);
}

/// A run that fails is recorded with its message and the study goes on: a fixed Δt of 1.5e-5 s is stable at
/// Δx (limit 2.17e-5 s) but not at Δx/2 (limit 1.08e-5 s), so the finest runs, the reference among them, fail;
/// the errors against the reference are then missing, not zero.
#[test]
fn a_failing_run_is_recorded_and_the_study_goes_on() {
    let dir = out("failing");
    let sets = ["time.end=1e-3", "time.dt=1.5e-5"];
    let opts = options(Path::new(DISK), &sets, &["1", "1/2"], &[Precision::F64], &dir);
    let s = study(&[cpu()], &opts).expect("the study itself succeeds");
    assert!(matches!(s.runs[0].outcome, Outcome::Done(_)));
    match &s.runs[1].outcome {
        Outcome::Failed(m) => assert!(m.contains("time.dt") && m.contains("stability limit"), "{m}"),
        other => panic!("expected a failed run, got {other:?}"),
    }
    assert_eq!(table::errors(&s, 0).max_reference, None);
    let csv = std::fs::read_to_string(dir.join("study.csv")).expect("study.csv");
    assert!(csv.lines().nth(2).expect("second row").contains(",failed,"), "{csv}");
    let md = std::fs::read_to_string(dir.join("study.md")).expect("study.md");
    assert!(md.contains("- failed: ") && md.contains("stability limit"), "{md}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `tool.depth_of_cut` places V0060's and V0300's tool where their absolute positions did (y = 1.95e-4 m: the top
/// row 2.9e-4 m + Δx/2 − 0.1 mm), both in the scene and in the solver's set-up, to 1e-15 m (in fact bit for bit,
/// so the default run is unchanged); at Δx/2 the edge stays 0.1 mm below the new surface (2.9e-4 + 2.5e-6 m).
#[test]
fn depth_of_cut_places_the_tool_as_the_absolute_position_did() {
    for (file, x) in [("cases/cutting/v0060.toml", -3.6e-5), ("cases/cutting/v0300.toml", -4.5e-5)] {
        let scene = Scene::load(file, &[]).expect("scene");
        let t = scene.tool.as_ref().expect("tool");
        assert_eq!(t.depth_of_cut, Some(1.0e-4));
        let old = [x, 1.95e-4];
        for k in 0..2 {
            assert!((t.position[k] - old[k]).abs() <= 1e-15, "{file}: position {:?} against {old:?}", t.position);
        }
        let set = swarf::run::setup::<f64, swarf::kernels::Dim2>(&scene).expect("setup");
        let start3 = set.contact.expect("contact").tools[0].motion.start;
        let start = [start3[0], start3[1]];
        for k in 0..2 {
            assert!((start[k] - old[k]).abs() <= 1e-15, "{file}: the solver's tool starts at {start:?}");
        }
        assert_eq!(start.map(f64::to_bits), old.map(f64::to_bits), "{file}: bit for bit");
    }
    let half = Scene::load("cases/cutting/v0060.toml", &["discretisation.dx=5e-6".into()]).expect("scene");
    let y = half.tool.as_ref().expect("tool").position[1];
    assert!((y - (2.9e-4 + 2.5e-6 - 1.0e-4)).abs() <= 1e-15, "y = {y:e} at Δx/2");
}

/// A lattice that does not fit V0060's 1.87 mm × 0.29 mm workpiece is warned about (Δx · 0.333: 87.09 Δx high);
/// the fractions the study offers fit (Δx/3: 87 Δx).
#[test]
fn lattice_warnings_name_a_box_that_the_level_does_not_fit() {
    let at = |dx: f64| {
        let scene = Scene::load("cases/cutting/v0060.toml", &[format!("discretisation.dx={dx:e}")]).expect("scene");
        swarf::study::lattice_warnings(&scene)
    };
    let third = Level::parse("1/3").expect("1/3");
    assert_eq!(third.apply(1.0e-5), 1.0e-5 / 3.0);
    assert!(at(third.apply(1.0e-5)).is_empty(), "{:?}", at(third.apply(1.0e-5)));
    assert!(at(Level::parse("1/4").expect("1/4").apply(1.0e-5)).is_empty());
    let w = at(Level::parse("0.333").expect("0.333").apply(1.0e-5));
    assert!(!w.is_empty() && w[0].contains("'workpiece'") && w[0].contains("not a whole number"), "{w:?}");
    for bad in ["0", "-1", "a", "1/0", "", "inf"] {
        assert!(Level::parse(bad).is_err(), "'{bad}' accepted as a level");
    }
}

/// Every observable of a cutting scene is a key the cutting recorder writes to summary.json.
#[test]
fn cutting_observables_are_the_summary_keys() {
    let json = swarf::cutting::record::CutAnalysis::default().json();
    let scene = Scene::load("cases/cutting/v0060.toml", &[]).expect("scene");
    let catalogue = swarf::study::observe::catalogue(2, true, &scene.bodies);
    assert_eq!(catalogue.len(), swarf::cutting::record::SUMMARY_OBSERVABLES.len());
    for o in &catalogue {
        assert!(json.get(&o.name).is_some(), "summary.json has no key {}", o.name);
    }
    let names: Vec<&str> = scene.experiment.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["fc_n_per_mm", "ff_n_per_mm", "chip_thickness_um"]);
    assert_eq!((scene.experiment[0].value, scene.experiment[0].uncertainty), (157.5, Some(3.3)));
}

/// Bad `[experiment]` and `tool.depth_of_cut` input is refused when the scene is read, with the file, the line and
/// the key; a study with such input refuses before it creates its folder.
#[test]
fn bad_experiment_and_depth_of_cut_are_refused_with_file_and_key() {
    let v0060 = std::fs::read_to_string("cases/cutting/v0060.toml").expect("v0060");
    let refused = |text: &str| -> String {
        Scene::from_str(text, "cases/cutting/v0060.toml", &[]).expect_err("refused").to_string()
    };
    let line_of = |text: &str, needle: &str| text.lines().position(|l| l.contains(needle)).expect("line") + 1;
    let has = |msg: &str, parts: &[&str]| {
        for p in parts {
            assert!(msg.contains(p), "message lacks '{p}':\n{msg}");
        }
    };
    let with_exp = |entry: &str| v0060.replace("chip_thickness_um = { value = 99.7 }", entry);
    let t = with_exp("fc = 157.5");
    has(
        &refused(&t),
        &[&format!("cases/cutting/v0060.toml:{}", line_of(&t, "fc = 157.5")), "experiment.fc", "fc_n_per_mm"],
    );
    has(
        &refused(&with_exp("chip_thickness_um = { value = 0.0 }")),
        &["experiment.chip_thickness_um.value", "non-zero"],
    );
    has(
        &refused(&with_exp("chip_thickness_um = { value = 99.7, uncertainty = -1.0 }")),
        &["experiment.chip_thickness_um.uncertainty", "non-negative"],
    );
    has(
        &refused(&with_exp("chip_thickness_um = { value = 99.7, sd = 1.0 }")),
        &["chip_thickness_um.sd", "uncertainty"],
    );
    has(&refused(&with_exp("chip_thickness_um = \"thick\"")), &["experiment.chip_thickness_um", "a measured value"]);
    // A scene without a tool has other observables.
    let disk = std::fs::read_to_string(DISK).expect("disk") + "\n[experiment]\nfc_n_per_mm = 1.0\n";
    has(
        &Scene::from_str(&disk, DISK, &[]).expect_err("refused").to_string(),
        &["experiment.fc_n_per_mm", "kinetic_energy_j", "disk_extent_x_m"],
    );
    // depth_of_cut with a y in position, a non-positive depth, an unknown body, a body without a depth, an x alone.
    let both = v0060.replace("position = [-3.6e-5]", "position = [-3.6e-5, 1.95e-4]");
    has(
        &refused(&both),
        &[&format!("cases/cutting/v0060.toml:{}", line_of(&both, "position = [")), "tool.position", "depth_of_cut"],
    );
    has(&refused(&v0060.replace("depth_of_cut = 1.0e-4", "depth_of_cut = 0.0")), &["tool.depth_of_cut", "positive"]);
    let body = v0060.replace("depth_of_cut = 1.0e-4", "depth_of_cut = 1.0e-4\nbody = \"chip\"");
    has(&refused(&body), &["tool.body", "'workpiece'"]);
    let absolute =
        v0060.replace("depth_of_cut = 1.0e-4", "body = \"workpiece\"").replace("[-3.6e-5]", "[-3.6e-5, 1.95e-4]");
    has(&refused(&absolute), &["tool.body", "without depth_of_cut"]);
    has(&refused(&v0060.replace("depth_of_cut = 1.0e-4", "")), &["tool.position", "[x, y]"]);
    // The study refuses before any run or file.
    let dir = out("refused");
    let opts =
        options(Path::new("cases/cutting/v0060.toml"), &["experiment.fc=1.0"], &["1", "1/2"], &[Precision::F64], &dir);
    let e = study(&[cpu()], &opts).expect_err("refused").to_string();
    has(&e, &["--set experiment.fc=1.0", "experiment.fc"]);
    assert!(!dir.exists(), "the refused study created {}", dir.display());
}

/// An MPM scene is studied on its own resolution key (issue 26: `study` for MPM). The mode-I bond
/// (cases/mpm/bond-mode1.toml, 1 mm wide, cell 125 µm) at levels 1 and 1/2: the cell halves (spacing 62.5 and
/// 31.25 µm, 4 times the particles), and at both levels the energy released per unit crack area is V15's
/// 2000 J/m² within 5 % (nairn-mpm.md §6.2); the finest level is the reference. A cut's levels scale
/// `cut.particles_across` to the nearest odd count: 15 through h gives 31 at level 1/2 and 7 at level 2.
#[test]
fn an_mpm_study_scales_its_particle_spacing() {
    let dir = out("mpm");
    let sets = ["bond.width=1e-3", "bond.cell=1.25e-4"];
    let s = study(
        &[cpu()],
        &options(Path::new("cases/mpm/bond-mode1.toml"), &sets, &["1", "1/2"], &[Precision::F64], &dir),
    )
    .expect("study");
    assert_eq!(s.runs.len(), 2);
    assert_eq!(s.reference, 1, "the finest level is the reference");
    assert!((s.runs[0].dx / 6.25e-5 - 1.0).abs() < 1e-12 && (s.runs[1].dx / 3.125e-5 - 1.0).abs() < 1e-12);
    let released = s.observables.iter().position(|o| o.name == "released_j_per_m2").expect("released column");
    let (coarse, fine) = (stats(&s.runs[0].outcome), stats(&s.runs[1].outcome));
    assert_eq!(fine.particles, 4 * coarse.particles);
    for r in [coarse, fine] {
        let g = r.values[released].expect("released energy");
        assert!((g / 2000.0 - 1.0).abs() < 0.05, "{g} J/m²");
    }
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    assert!(dir.join(swarf::study::CSV).is_file() && dir.join(swarf::study::MARKDOWN).is_file());
    let cut = swarf::scene::mpm::MpmScene::load("cases/mpm/nairn-cut.toml", &[]).expect("cut");
    let counts: Vec<String> = [1.0, 0.5, 2.0].iter().map(|f| cut.level_override(*f)).collect();
    assert_eq!(counts, ["cut.particles_across=15", "cut.particles_across=31", "cut.particles_across=7"]);
    let _ = std::fs::remove_dir_all(&dir);
}
