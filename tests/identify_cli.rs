//! `swarf identify` (issue 23 items 3 and 4): Klippel's objective against its hand value, the feed scaling of the
//! identification model, a tiny identification on a coarse short V0060 cut (history, report, plots, the best
//! material file), resume after a stop giving the same history bitwise, and bad identification files refused
//! before any run with file, key and expected value. CPU only.

use std::path::{Path, PathBuf};

use swarf::backend::{AnyBackend, BackendChoice};
use swarf::identify::data::{Condition, scale_overrides};
use swarf::identify::file::{Measured, Method, Objective};
use swarf::identify::objective::{Simulated, combine, experiment_term};
use swarf::identify::{IdentifyOptions, Noise, identify};
use swarf::scene::Scene;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn v0060() -> PathBuf {
    root().join("cases/cutting/v0060.toml")
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("swarf-identify-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

fn cpu() -> AnyBackend {
    AnyBackend::select(BackendChoice::Cpu).expect("cpu").0
}

/// Eq. 9.14 with w_c = w_f = 1: Klippel's V0060 best set gave F_c 162.8 and F_f 120.8 N/mm against 157.5 and 115.5
/// measured (klippel-constitutive.md §4.9, Tabs. 9.53–9.54): ΔF² = 5.3² + 5.3² = 56.18, his reported 56.2 N²
/// (§6.5). The chip term adds w_h Δh², Eq. 9.17 sums over experiments, "mean" averages. Exact to 1e-12.
#[test]
fn objective_is_klippels_delta_f_squared() {
    let w = Objective { fc_weight: 1.0, ff_weight: 1.0, mean: false, replicas: 1 };
    let m = Measured { fc: Some(157.5), ff: Some(115.5), chip: Some(99.7), chip_weight: 0.0 };
    let sim = Simulated { fc: Some(162.8), ff: Some(120.8), chip: Some(116.3) };
    let t = experiment_term(&m, &sim, &w);
    assert!((t - 56.18).abs() < 1e-9, "ΔF² = {t}, expected 56.18");
    let with_chip = experiment_term(&Measured { chip_weight: 0.5, ..m }, &sim, &w);
    let hand = 56.18 + 0.5 * (116.3f64 - 99.7).powi(2);
    assert!((with_chip - hand).abs() < 1e-9, "with chip {with_chip}, expected {hand}");
    let other = experiment_term(&Measured { fc: Some(100.0), ff: None, chip: None, chip_weight: 0.0 }, &sim, &w);
    assert!((other - 62.8f64.powi(2)).abs() < 1e-9);
    assert!((combine(&[t, other], &w) - (t + other)).abs() < 1e-12);
    assert!((combine(&[t, other], &Objective { mean: true, ..w }) - 0.5 * (t + other)).abs() < 1e-12);
    // A measured force without a simulated one (a failed run) makes the objective NaN.
    assert!(experiment_term(&m, &Simulated { fc: None, ..sim }, &w).is_nan());
}

/// The feed scaling (klippel-constitutive.md §4.9: Δx = f/10, 188 × 30 particles): V0060 scaled to its own
/// condition is the V0060 scene (lengths within 1e-12 relative); scaled to f = 0.2 mm, 150 m/min, r_n = 36 µm it
/// has the same particle count, Δx = 20 µm, twice the model's cut length (10 f) and the edge's front 2 × 3 µm clear.
#[test]
fn the_model_scales_with_the_feed() {
    let model = Scene::load(v0060(), &[]).expect("v0060");
    let same = scale_overrides(&model, &Condition { vc_m_per_min: 381.3, feed_mm: 0.1, edge_radius_um: 33.0 }).unwrap();
    let s1 = Scene::load(v0060(), &same).expect("scaled to itself");
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1e-300);
    let (t0, t1) = (model.tool.as_ref().unwrap(), s1.tool.as_ref().unwrap());
    assert!(close(s1.discretisation.dx, model.discretisation.dx));
    assert!(close(t1.position[0], t0.position[0]) && close(t1.edge_radius, t0.edge_radius));
    assert!(close(s1.time.end, model.time.end) && close(s1.output.every, model.output.every));
    assert_eq!(s1.bodies, model.bodies);
    let cond = Condition { vc_m_per_min: 150.0, feed_mm: 0.2, edge_radius_um: 36.0 };
    let s2 = Scene::load(v0060(), &scale_overrides(&model, &cond).unwrap()).expect("scaled");
    let t2 = s2.tool.as_ref().unwrap();
    assert!(close(s2.discretisation.dx, 2e-5));
    assert_eq!(s2.generate().unwrap().len(), model.generate().unwrap().len());
    assert_eq!(model.generate().unwrap().len(), 5640);
    let cut = |s: &Scene| s.time.end * s.tool.as_ref().unwrap().velocity[0];
    assert!(close(cut(&s2), 2.0 * cut(&model)), "cut length {} against the model's {}", cut(&s2), cut(&model));
    assert!(close(t2.velocity[0], 2.5) && close(t2.depth_of_cut.unwrap(), 2e-4) && close(t2.edge_radius, 36e-6));
    assert!(close(t2.position[0] + t2.edge_radius, -6e-6), "front at {}", t2.position[0] + t2.edge_radius);
}

/// A coarse short V0060 cut (Δx = 55 µm, 210 particles, 20 µs: under a second a run) with two parameters, one of
/// the scene (μ) and one of the material (A).
fn tiny_file(dir: &Path, extra: &str) -> PathBuf {
    let text = format!(
        r#"name = "tiny"
set = ["time.end=2e-5"]

[[experiment]]
name = "coarse-V0060"
scene = "{scene}"
set = ["discretisation.dx=5.5e-5"]
fc_n_per_mm = 157.5
ff_n_per_mm = 115.5

[[parameter]]
key = "tool.friction"
lower = 0.2
upper = 0.6

[[parameter]]
key = "material.flow_stress.A"
lower = 6e8
upper = 1.1e9

[optimizer]
method = "de"
budget = 6
batch = 3
seed = 7
de = {{ popsize = 2 }}
{extra}"#,
        scene = v0060().display()
    );
    let path = dir.join("tiny.toml");
    std::fs::write(&path, text).expect("write file");
    path
}

/// A new, quiet identification of `file` into `out`, two runs at once.
fn options(file: &Path, out: &Path) -> IdentifyOptions {
    IdentifyOptions {
        file: file.to_path_buf(),
        out_dir: out.to_path_buf(),
        batch: None,
        only: None,
        width: Some(2),
        resume: false,
        holdout_only: false,
        quiet: true,
    }
}

/// The identification writes history (6 evaluations, in 3 batches: 3 + the initial population's last 2 + 1),
/// report, plots and the best set's material file; that file loads and holds the best A; a resume from the first
/// batch (history truncated: a stop after it) writes the same history.csv byte for byte, with its runs one at a
/// time where the first call ran 3 at once (an ensemble's width changes no bit).
#[test]
fn a_tiny_identification_writes_everything_and_resumes_bitwise() {
    let dir = tmp("tiny");
    let file = tiny_file(&dir, "");
    let out = dir.join("out");
    let opts = IdentifyOptions { width: Some(3), ..options(&file, &out) };
    let done = identify(&cpu(), &opts).expect("identify");
    assert_eq!(done.rows.len(), 6);
    assert_eq!(done.rows.iter().map(|r| r.batch).collect::<Vec<_>>(), [0, 0, 0, 1, 1, 2]);
    for f in ["history.csv", "report.md", "convergence.png", "forces.png", "identification.toml"] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    assert!(out.join("runs/00005-coarse-V0060/summary.json").is_file());
    let best = swarf::identify::report::best(&done.rows).expect("a finite objective");
    assert!(best.objective.is_finite() && best.sims[0].fc.is_some());
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("coarse-V0060") && report.contains("material.flow_stress.A"), "{report}");
    // The material file: loadable by the library (swarf material --library <out>/materials), with the best A.
    let path = done.material.expect("material file");
    let m = swarf::material::Material::load(&path).expect("the best material loads");
    let a = m.flow_stress.as_ref().and_then(|f| f.johnson_cook()).map(|jc| jc.a).expect("JC");
    assert_eq!(a, best.params[1], "A in the material file");
    let lib = swarf::material::search::Search::folder(&out.join("materials")).library().expect("library");
    assert!(lib.get(&m.name).is_ok());
    // Resume after a stop after the first batch. Batch 1's runs (evaluations 3, 4) are made unfinished and run again,
    // one at a time; batch 2's run (evaluation 5) stands as an interrupted batch's finished run and is taken from its
    // folder without running (its summary.json is not rewritten).
    let full = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let first: Vec<&str> = full.lines().take(4).collect();
    std::fs::write(out.join("history.csv"), first.join("\n") + "\n").unwrap();
    let run = |e: usize| out.join(format!("runs/{e:05}-coarse-V0060"));
    let mtime = |e: usize| std::fs::metadata(run(e).join("summary.json")).and_then(|m| m.modified()).expect("summary");
    assert!(run(5).join(swarf::identify::scenes::FINISHED).is_file(), "a finished run is not marked");
    for e in [3, 4] {
        std::fs::remove_file(run(e).join(swarf::identify::scenes::FINISHED)).expect("the mark");
    }
    let (t3, t5) = (mtime(3), mtime(5));
    let resumed = identify(&cpu(), &IdentifyOptions { resume: true, width: Some(1), ..opts.clone() }).expect("resume");
    assert_eq!(resumed.rows.len(), 6);
    assert_eq!(std::fs::read_to_string(out.join("history.csv")).unwrap(), full, "resumed history differs");
    assert!(mtime(3) != t3, "evaluation 3 was not run again");
    assert_eq!(mtime(5), t5, "evaluation 5 ran again instead of being taken from its folder");
    // A new identification into the same folder, or a resume with a file that asks for another fit, is refused.
    assert!(identify(&cpu(), &opts).unwrap_err().to_string().contains("--resume"));
    let changed = tiny_file(&dir, "[objective]\nfc_weight = 2.0\n");
    let e = identify(&cpu(), &IdentifyOptions { file: changed, resume: true, ..opts }).unwrap_err().to_string();
    assert!(e.contains("differs"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--only`: the tiny file's two parameters restricted to A. The history has A's column and not μ's, and μ keeps
/// the scene's 0.35 in every run; the initial population is DE's for one parameter (popsize 2 → 2 evaluations).
/// An unknown key is refused naming the file's keys, before any folder is written; a resume with other keys is
/// refused naming the ones the folder was started with; a resume without `--only` keeps them.
#[test]
fn only_identifies_the_named_parameters() {
    let dir = tmp("only");
    let file = tiny_file(&dir, "");
    let out = dir.join("out");
    let opts = IdentifyOptions { only: Some(vec!["material.flow_stress.A".into()]), ..options(&file, &out) };
    let bad =
        IdentifyOptions { only: Some(vec!["material.flow_stress.Q".into()]), out_dir: dir.join("bad"), ..opts.clone() };
    let e = identify(&cpu(), &bad).unwrap_err().to_string();
    assert!(e.contains("--only material.flow_stress.Q") && e.contains("tool.friction, material.flow_stress.A"), "{e}");
    assert!(!dir.join("bad").exists(), "a refused --only wrote a folder");
    let done = identify(&cpu(), &IdentifyOptions { ..opts.clone() }).expect("identify");
    assert_eq!(done.spec.parameters.len(), 1);
    assert!(done.rows.iter().all(|r| r.params.len() == 1));
    let history = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let head = history.lines().next().unwrap();
    assert!(head.contains("material.flow_stress.A") && !head.contains("tool.friction"), "{head}");
    for r in &done.rows {
        let run = out.join(format!("runs/{:05}-coarse-V0060/scene.toml", r.evaluation));
        let mu = Scene::load(&run, &[]).expect("the run's scene").tool.expect("tool").friction;
        assert_eq!(mu, 0.35, "{}: μ changed", run.display());
    }
    let other = IdentifyOptions { only: Some(vec!["tool.friction".into()]), resume: true, ..opts.clone() };
    let e = identify(&cpu(), &other).unwrap_err().to_string();
    assert!(e.contains("expected the parameters this folder was started with, material.flow_stress.A"), "{e}");
    let resumed = identify(&cpu(), &IdentifyOptions { only: None, resume: true, ..opts }).expect("resume");
    assert_eq!(resumed.spec.parameters.len(), 1);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Each bad file is refused naming the file, the key and the value expected, and writes no folder.
#[test]
fn bad_identification_files_are_refused_before_any_run() {
    let dir = tmp("bad");
    let good = std::fs::read_to_string(tiny_file(&dir, "")).unwrap();
    let data = root().join("cases/data/cutting-experiments.csv");
    let with_test = |test: &str| {
        good.replace("name = \"tiny\"", &format!("name = \"tiny\"\ndata = \"{}\"", data.display()))
            .replace("fc_n_per_mm = 157.5\nff_n_per_mm = 115.5", &format!("test = \"{test}\""))
    };
    let bayes = |noise: &str| {
        good.replace("method = \"de\"", "method = \"bayes\"")
            .replace("de = { popsize = 2 }", &format!("bayes = {{ noise = {noise} }}"))
    };
    // A file TOML cannot parse is refused naming the line.
    let budget_line = format!("line {}", good[..good.find("budget = 6").unwrap()].matches('\n').count() + 1);
    let cases: Vec<(&str, String, &str)> = vec![
        ("malformed TOML", good.replace("budget = 6", "budget = 6 7"), &budget_line),
        ("unknown scene key", good.replace("tool.friction", "tool.frictoin"), "parameter.0.key"),
        ("unknown material key", good.replace("flow_stress.A", "flow_stress.Q"), "parameter.1.key"),
        ("inverted bounds", good.replace("lower = 0.2", "lower = 0.7"), "parameter.0.upper"),
        ("empty bounds", good.replace("upper = 0.6", "upper = 0.2"), "parameter.0.upper"),
        ("no measurement", good.replace("fc_n_per_mm = 157.5\nff_n_per_mm = 115.5", ""), "experiment.0.fc_n_per_mm"),
        ("budget 0", good.replace("budget = 6", "budget = 0"), "optimizer.budget"),
        ("unknown optimiser", good.replace("\"de\"", "\"pso\""), "optimizer.method"),
        ("no replicas", format!("{good}\n[objective]\nreplicas = 0\n"), "objective.replicas"),
        (
            "replicas of a fixed time step",
            format!("{good}\n[objective]\nreplicas = 2\n").replace(
                "set = [\"discretisation.dx=5.5e-5\"]",
                "set = [\"discretisation.dx=5.5e-5\", \"time.dt=1e-9\"]",
            ),
            "objective.replicas",
        ),
        ("unknown test id", with_test("V9999"), "experiment.0.test"),
        ("unusable status", with_test("V0068"), "experiment.0.test"),
        ("a Ck45 test on the Ti6Al4V model", with_test("V0069"), "experiment.0.scene"),
        ("unknown noise", bayes("\"fast\""), "optimizer.bayes.noise"),
        ("no noise", bayes("0.0"), "optimizer.bayes.noise"),
    ];
    let rows = std::fs::read_to_string(&data).unwrap();
    assert!(
        rows.lines().any(|l| l.starts_with("V0068,") && !l.ends_with(",ok") && !l.ends_with(",short")),
        "V0068 is not ok/short"
    );
    for (what, text, key) in cases {
        let file = dir.join("bad.toml");
        std::fs::write(&file, &text).unwrap();
        let out = dir.join("out-bad");
        let opts = IdentifyOptions { width: Some(3), ..options(&file, &out) };
        let e = identify(&cpu(), &opts).expect_err(what).to_string();
        assert!(e.contains(&file.display().to_string()) && e.contains(key) && e.contains("expected"), "{what}: {e}");
        assert!(!out.exists(), "{what}: a folder was written");
    }
    // The noise keyword that is accepted: "fit" (a variance chosen by the likelihood), beside a fixed variance.
    for (noise, want) in [("\"fit\"", Noise::Fit), ("1e-3", Noise::Fixed(1e-3))] {
        let file = dir.join("bayes.toml");
        std::fs::write(&file, bayes(noise)).unwrap();
        let spec = swarf::identify::file::read(&file).expect("a Bayes file");
        assert!(matches!(spec.optimizer.method, Method::Bayes(s) if s.noise == want), "{noise}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The command line: a bad file exits with status 1, the message on stderr naming file, key and expected value,
/// and no output folder.
#[test]
fn the_command_refuses_a_bad_file_with_status_1() {
    let dir = tmp("cli");
    let good = std::fs::read_to_string(tiny_file(&dir, "")).unwrap();
    let file = dir.join("bad.toml");
    std::fs::write(&file, good.replace("budget = 6", "budget = 0")).unwrap();
    let out = dir.join("out");
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_swarf"))
        .args(["--backend", "cpu", "identify"])
        .arg(&file)
        .arg("--out")
        .arg(&out)
        .output()
        .expect("swarf runs");
    let err = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{err}");
    assert!(err.contains("optimizer.budget") && err.contains("expected") && err.contains("bad.toml"), "{err}");
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Held-out tests (host/identify/holdout.rs): with `[[holdout]]` and `compare`, the end of an identification runs
/// the best set and the compare material on the tests not fitted. Facts: holdout.csv has one row per set and test;
/// the compare material (here the model's own, Ti6Al4V-V0060-DE-mu035) gives exactly the forces of a plain run of
/// the same scene (no parameter edited: the same bits); each error is (simulated − measured)/measured of its own
/// row; `--holdout-only` in a new folder runs the compare material alone (and writes no empty history); mean |e| and the worst e (sign kept) of
/// [0.1, −0.3, 0.2] are 0.2 (to 1e-15) and −0.3; a compare name the library lacks is refused naming `compare`.
#[test]
fn holdout_tests_run_the_best_set_and_the_compare_materials() {
    use swarf::identify::holdout;
    let dir = tmp("holdout");
    let holdout = HOLDOUT.replace("__SCENE__", &v0060().display().to_string());
    let base = std::fs::read_to_string(tiny_file(&dir, &holdout)).unwrap();
    let text = base.replacen("name = \"tiny\"\n", "name = \"tiny\"\ncompare = [\"Ti6Al4V-V0060-DE-mu035\"]\n", 1);
    let file = dir.join("holdout.toml");
    std::fs::write(&file, &text).unwrap();
    let out = dir.join("out");
    let opts = IdentifyOptions { width: Some(3), ..options(&file, &out) };
    identify(&cpu(), &opts).expect("identify with holdout");
    let (head, rows) = read_holdout(&out);
    assert_eq!(head[..4], ["set", "test", "fc_measured", "fc_simulated"]);
    let sets: Vec<&str> = rows.iter().map(|r| r[0].as_str()).collect();
    assert_eq!(sets, ["best", "Ti6Al4V-V0060-DE-mu035"]);
    for r in &rows {
        let (m, s, e): (f64, f64, f64) = (r[2].parse().unwrap(), r[3].parse().unwrap(), r[4].parse().unwrap());
        assert_eq!(e, (s - m) / m, "{r:?}");
        assert_eq!(r[8], "ok");
    }
    // The compare material's run against a plain run of the same scene.
    let scene = swarf::scene::Scene::load(
        v0060(),
        &["discretisation.dx=5.5e-5".into(), "tool.velocity=[4.0,0.0]".into(), "time.end=2e-5".into()],
    )
    .expect("scene");
    let plain = swarf::run::RunOptions::quiet(dir.join("plain"));
    swarf::run::run(&cpu(), &scene, &plain).expect("plain run");
    let forces = |d: &Path| std::fs::read_to_string(d.join("forces.csv")).unwrap();
    let compare_dir = out.join("holdout/runs/Ti6Al4V-V0060-DE-mu035-slow");
    assert!(forces(&compare_dir) == forces(&plain.out_dir), "the compare material's run differs from a plain run");
    assert!(std::fs::read_to_string(out.join(holdout::MARKDOWN)).unwrap().contains("| best | 1 | 0 |"));
    // Only the holdout, in a new folder: the compare material alone.
    let only = IdentifyOptions { out_dir: dir.join("only"), holdout_only: true, ..opts.clone() };
    let done = identify(&cpu(), &only).expect("holdout only");
    assert!(done.rows.is_empty());
    let (_, rows) = read_holdout(&dir.join("only"));
    assert!(!dir.join("only/history.csv").exists(), "a holdout alone wrote an empty history");
    assert_eq!(rows.iter().map(|r| r[0].as_str()).collect::<Vec<_>>(), ["Ti6Al4V-V0060-DE-mu035"]);
    let (mean, worst) = holdout::mean_and_worst(&[0.1, -0.3, 0.2]).expect("three errors");
    assert!((mean - 0.2).abs() < 1e-15 && worst == -0.3, "{mean} {worst}");
    let bad = dir.join("bad.toml");
    std::fs::write(&bad, text.replace("Ti6Al4V-V0060-DE-mu035", "No-Such-Set")).unwrap();
    let e = identify(&cpu(), &IdentifyOptions { file: bad.clone(), out_dir: dir.join("bad"), ..opts })
        .unwrap_err()
        .to_string();
    assert!(e.contains("compare") && e.contains("No-Such-Set") && e.contains("expected"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Held-out tests may be added to an identification after its fit: `--resume --holdout-only` accepts a file that
/// differs from the folder's only in `[[holdout]]` and `compare`, runs the added test at the recorded best set, and a
/// file that changes the fit (a parameter's bound) is still refused.
#[test]
fn held_out_tests_may_be_added_after_the_fit() {
    let dir = tmp("holdout-added");
    let scene = v0060().display().to_string();
    let file = tiny_file(&dir, "");
    let text = std::fs::read_to_string(&file).unwrap();
    let out = dir.join("out");
    let opts = IdentifyOptions { width: Some(3), ..options(&file, &out) };
    let fit = identify(&cpu(), &opts).expect("identify without holdout");
    assert!(!out.join(swarf::identify::holdout::CSV).exists(), "a fit without [[holdout]] wrote holdout.csv");
    let holdout = HOLDOUT.replace("__SCENE__", &scene);
    std::fs::write(&file, format!("{text}{holdout}")).unwrap();
    let added = IdentifyOptions { resume: true, holdout_only: true, ..opts.clone() };
    let done = identify(&cpu(), &added).expect("holdout added after the fit");
    assert_eq!(done.rows.len(), fit.rows.len(), "the holdout changed the history");
    let (_, rows) = read_holdout(&out);
    assert_eq!(rows.iter().map(|r| (r[0].as_str(), r[1].as_str())).collect::<Vec<_>>(), [("best", "slow")]);
    assert_eq!(rows[0][8], "ok");
    std::fs::write(&file, format!("{}{}", text.replace("upper = 0.6", "upper = 0.7"), holdout)).unwrap();
    let e = identify(&cpu(), &added).unwrap_err().to_string();
    assert!(e.contains("only [[holdout]] and compare may change"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A holdout test for [`tiny_file`]: the coarse cut at 4 m/s instead of 6.355 (a made-up measurement).
const HOLDOUT: &str = r#"
[[holdout]]
name = "slow"
scene = "__SCENE__"
set = ["discretisation.dx=5.5e-5", "tool.velocity=[4.0,0.0]"]
fc_n_per_mm = 150.0
ff_n_per_mm = 110.0
"#;

fn read_holdout(out: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(out.join(swarf::identify::holdout::CSV)).expect("holdout.csv");
    let mut lines = text.lines().map(|l| l.split(',').map(str::to_string).collect::<Vec<_>>());
    let head = lines.next().expect("header");
    (head, lines.collect())
}

/// Every identification file in cases/identify reads and checks (its data rows, model scenes and parameter keys at
/// their bounds, as `swarf identify` checks them before any run), and names at least one experiment and one
/// parameter.
#[test]
fn every_identification_case_reads() {
    let dir = root().join("cases/identify");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).expect("cases/identify") {
        let path = entry.expect("entry").path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let spec = swarf::identify::file::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert!(!spec.experiments.is_empty() && !spec.parameters.is_empty(), "{}", path.display());
        n += 1;
    }
    assert!(n >= 3, "expected the identification cases, found {n}");
}

/// `[objective] replicas = 3`: each experiment runs three times, at the scene's CFL number and 1e-3 below and above
/// it (runs/<evaluation>-<experiment>, -r1, -r2), and the history's forces are the replicas' mean, exactly, which
/// the objective (Eq. 9.14) then uses; the held-out test runs three replicas per set as well (the best set and a
/// compare material), and holdout.csv gives their mean.
#[test]
fn replicas_run_each_experiment_at_shifted_cfl_and_fit_their_mean() {
    let dir = tmp("replicas");
    let holdout = HOLDOUT.replace("__SCENE__", &v0060().display().to_string());
    let file = tiny_file(&dir, &format!("{holdout}\n[objective]\nreplicas = 3\n"));
    let text = std::fs::read_to_string(&file).unwrap().replace("budget = 6", "budget = 2").replacen(
        "name = \"tiny\"\n",
        "name = \"tiny\"\ncompare = [\"Ti6Al4V-V0060-DE-mu035\"]\n",
        1,
    );
    std::fs::write(&file, text).unwrap();
    let out = dir.join("out");
    let done = identify(&cpu(), &IdentifyOptions { width: Some(3), ..options(&file, &out) }).expect("identify");
    assert_eq!(done.rows.len(), 2);
    for row in &done.rows {
        let summary = |suffix: &str| {
            let path = out.join(format!("runs/{:05}-coarse-V0060{suffix}/summary.json", row.evaluation));
            let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            serde_json::from_str::<serde_json::Value>(&text).unwrap()
        };
        let runs: Vec<serde_json::Value> = ["", "-r1", "-r2"].iter().map(|s| summary(s)).collect();
        let value = |v: &serde_json::Value, k: &str| v[k].as_f64().unwrap_or_else(|| panic!("{k} in {v}"));
        let cfl = |v: &serde_json::Value| {
            v["overrides"]
                .as_array()
                .unwrap()
                .iter()
                .rev()
                .find_map(|o| o.as_str()?.strip_prefix("time.cfl="))
                .map(|c| c.parse::<f64>().unwrap())
        };
        assert_eq!(cfl(&runs[0]), None, "the first replica runs the scene's CFL number");
        assert!((cfl(&runs[1]).unwrap() / 0.5 - (1.0 - 1e-3)).abs() < 1e-12);
        assert!((cfl(&runs[2]).unwrap() / 0.5 - (1.0 + 1e-3)).abs() < 1e-12);
        let fc: Vec<f64> = runs.iter().map(|v| value(v, "fc_n_per_mm")).collect();
        let ff: Vec<f64> = runs.iter().map(|v| value(v, "ff_n_per_mm")).collect();
        assert!(fc[0] != fc[1] && fc[1] != fc[2], "the replicas ran the same cut: {fc:?}");
        let (mc, mf) = (fc.iter().sum::<f64>() / 3.0, ff.iter().sum::<f64>() / 3.0);
        assert_eq!((row.sims[0].fc, row.sims[0].ff), (Some(mc), Some(mf)));
        let expect = (mc - 157.5).powi(2) + (mf - 115.5).powi(2);
        assert!((row.objective - expect).abs() <= 1e-12 * expect, "{} vs {expect}", row.objective);
    }
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("the mean of 3 runs"), "{report}");
    // The held-out test runs three replicas per set too, and holdout.csv gives their mean.
    let (_, rows) = read_holdout(&out);
    assert_eq!(rows.len(), 2);
    for r in &rows {
        let fc: Vec<f64> = ["", "-r1", "-r2"]
            .iter()
            .map(|suffix| {
                let path = out.join(format!("holdout/runs/{}-slow{suffix}/summary.json", r[0]));
                let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
                serde_json::from_str::<serde_json::Value>(&text).unwrap()["fc_n_per_mm"].as_f64().unwrap()
            })
            .collect();
        assert_eq!(r[3].parse::<f64>().unwrap(), fc.iter().sum::<f64>() / 3.0, "{r:?}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `extends` (host/identify/extends.rs): a variant is its base with its own keys laid over it. The V0060 variants fit
/// the base's experiment, parameters, objective and optimiser and differ in their name and `set`; V0300's replicas
/// change `objective.replicas` alone (a table merges key by key); the multi-experiment variants keep the base's 24
/// held-out tests and replace its `[[parameter]]` or `[[experiment]]` lists whole. A variant's folder copy
/// (`Spec::text`) is the resolved table, whole, without `extends`.
#[test]
fn a_variant_file_is_its_base_with_its_own_keys_laid_over() {
    let read = |name: &str| swarf::identify::file::read(&root().join("cases/identify").join(name)).expect(name);
    let base = read("v0060-de.toml");
    assert!(base.set.is_empty());
    for (variant, set) in [
        ("v0060-de-noas.toml", "stabilisation.artificial_stress.enabled=false"),
        ("v0060-de-mfree.toml", "model=\"mfree_iwf\""),
    ] {
        let v = read(variant);
        assert_eq!(v.experiments, base.experiments, "{variant}");
        assert_eq!((&v.parameters, &v.objective, &v.optimizer), (&base.parameters, &base.objective, &base.optimizer));
        assert_eq!(v.set, vec![set.to_string()], "{variant}");
        assert_ne!(v.name, base.name);
        let copy: toml::Table = toml::from_str(&v.text).expect("the folder copy parses");
        assert!(copy.contains_key("experiment") && copy.contains_key("parameter"), "{variant}: {}", v.text);
        assert!(!copy.contains_key("extends"), "{variant}: {}", v.text);
    }
    let (b300, r300) = (read("v0300-de.toml"), read("v0300-de-replicas.toml"));
    assert_eq!((b300.objective.replicas, r300.objective.replicas), (1, 3));
    assert_eq!(Objective { replicas: 1, ..r300.objective }, b300.objective);
    assert_eq!(
        (&r300.experiments, &r300.parameters, &r300.optimizer),
        (&b300.experiments, &b300.parameters, &b300.optimizer)
    );
    let multi = read("ti6al4v-multi.toml");
    assert_eq!(multi.holdout.len(), 24);
    let (mu, fast6) = (read("ti6al4v-multi-mu.toml"), read("ti6al4v-fast6.toml"));
    for v in [&mu, &fast6] {
        assert_eq!(v.holdout, multi.holdout, "{}", v.name);
        assert!(v.compare.is_empty() && !multi.compare.is_empty(), "{}", v.name);
        assert_eq!(v.optimizer.seed, multi.optimizer.seed, "{}: the seed is the base's", v.name);
    }
    assert_eq!((mu.experiments.len(), mu.parameters.len(), multi.parameters.len()), (8, 1, 6));
    assert_eq!((fast6.experiments.len(), fast6.parameters), (6, multi.parameters.clone()));
}

/// A bad `extends` is refused with the file, the key and what was expected: not a string, a base that does not
/// exist, and a cycle (two files extending each other); a base's own error names the base.
#[test]
fn bad_extends_are_refused() {
    let dir = tmp("extends");
    let good = std::fs::read_to_string(tiny_file(&dir, "")).unwrap();
    std::fs::write(dir.join("base.toml"), &good).unwrap();
    let cases = [
        ("extends = 3\n", "a.toml", "extends = 3: expected the base identification file's path"),
        ("extends = \"nowhere.toml\"\n", "a.toml", "extends = \"nowhere.toml\": expected a readable file"),
        ("extends = \"b.toml\"\n", "b.toml", "extends = \"a.toml\": expected a file that does not extend this one"),
    ];
    std::fs::write(dir.join("b.toml"), "extends = \"a.toml\"\n").unwrap();
    for (text, names, expected) in cases {
        let file = dir.join("a.toml");
        std::fs::write(&file, text).unwrap();
        let e = swarf::identify::file::read(&file).expect_err(text).to_string();
        assert!(e.contains(&dir.join(names).display().to_string()) && e.contains(expected), "{text}: {e}");
    }
    // A variant of a good base reads; its own bad key is refused as the base's would be.
    let file = dir.join("a.toml");
    std::fs::write(&file, "extends = \"base.toml\"\nname = \"variant\"\n").unwrap();
    let spec = swarf::identify::file::read(&file).expect("a variant of the tiny file");
    assert_eq!(spec.name, "variant");
    std::fs::write(&file, "extends = \"base.toml\"\n[optimizer]\nbudget = 0\n").unwrap();
    let e = swarf::identify::file::read(&file).expect_err("budget 0").to_string();
    assert!(e.contains("a.toml") && e.contains("optimizer.budget") && e.contains("expected"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}
