//! `[analysis] early_stop` (host/cutting/early_stop.rs, the check in host/run.rs's output step): a coarse, fast cut
//! stops once F_c and F_f are steady to the tolerance, ends normally, and its forces agree with the full-length
//! run's; the check leaves the run itself unchanged; bad values are refused naming the key.

use swarf::backend::{AnyBackend, BackendChoice};
use swarf::run::{RunOptions, run};
use swarf::scene::Scene;

fn cpu() -> AnyBackend {
    AnyBackend::select(BackendChoice::Cpu).expect("cpu").0
}

/// V0060 coarsened to Δx = 25 µm (4 particles per uncut chip thickness t1 = 0.1 mm), a workpiece 1.25 mm long and
/// 0.25 mm high (500 particles), cut at 50 m/s instead of 6.355 (the chip-formation time scale t1/v_c shrinks
/// eightfold while the step, set by the sound speed, does not: the same cut length in an eighth of the steps);
/// 1.0 mm of travel, force samples every 36 ns. Minimum transient 3 t1 = 6 µs, shortest early-stop window
/// 4 t1 = 8 µs.
const END: f64 = 2.0e-5;

fn coarse_fast_cut(extra: &[&str]) -> Scene {
    let mut over: Vec<String> = [
        "discretisation.dx=2.5e-5",
        "body.0.max=[1.25e-3,2.5e-4]",
        "boundary.1.max=[1.0e-9,1.25e-4]",
        "boundary.2.min=[1.2499e-3,-1.0]",
        "tool.velocity=[50.0,0.0]",
        "output.every=3.6e-7",
        "time.end=2.0e-5",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    over.extend(extra.iter().map(|s| s.to_string()));
    Scene::load("cases/cutting/v0060.toml", &over).expect("scene")
}

fn summary(o: &RunOptions) -> serde_json::Value {
    let text = std::fs::read_to_string(o.out_dir.join("summary.json")).expect("summary.json");
    serde_json::from_str(&text).expect("json")
}

fn forces(o: &RunOptions) -> Vec<Vec<f64>> {
    swarf::output::csv::read(&o.out_dir.join("forces.csv")).expect("forces.csv").1
}

#[test]
fn early_stopped_cut_agrees_with_the_full_length_run() {
    let tol = 0.05;
    let dir = |tag: &str| std::env::temp_dir().join(format!("swarf-test-early-stop-{tag}-{}", std::process::id()));
    let (full_o, early_o) = (RunOptions::quiet(dir("full")), RunOptions::quiet(dir("early")));
    let full = run(&cpu(), &coarse_fast_cut(&[]), &full_o).expect("the full-length run");
    let set = format!("analysis.early_stop.tolerance={tol}");
    let early = run(&cpu(), &coarse_fast_cut(&[&set]), &early_o).expect("the early-stopped run");
    let (sf, se) = (summary(&full_o), summary(&early_o));

    // Without the key: the run goes to its end and says the early stop was off.
    assert_eq!(sf["early_stop"]["enabled"], serde_json::json!(false), "{}", sf["early_stop"]);
    // With it: stopped before the end, at an output step, after the minimum transient and the shortest window.
    let es = &se["early_stop"];
    assert_eq!((es["enabled"].as_bool(), es["stopped"].as_bool()), (Some(true), Some(true)), "{es}");
    let at = es["at_time_s"].as_f64().expect("at_time_s");
    assert!((6e-6 + 8e-6..0.95 * END).contains(&at), "stopped at {at} s");
    assert_eq!(es["at_step"].as_u64(), Some(early.steps), "{es}");
    assert!(early.steps < full.steps, "{} steps against {}", early.steps, full.steps);
    assert_eq!(es["tolerance"].as_f64(), Some(tol));

    // The check changes nothing in the run: the stopped run's force samples are the full run's first ones, bit
    // for bit.
    let (rf, re) = (forces(&full_o), forces(&early_o));
    assert!(re.len() < rf.len());
    for (a, b) in re.iter().zip(&rf) {
        assert_eq!(
            a.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            b.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
        );
    }

    // Forces: each early mean has a standard error ≤ tol of itself; the full run's mean its own, comparable one.
    // Their difference is then within 2 tol (about 1.4 tol is one standard deviation of the difference of two
    // independent means with standard error tol; they share the early samples, which makes it smaller).
    eprintln!(
        "early stop at {at:e} s of {END:e} s, {} of {} steps, {:.2} s against {:.2} s of wall time",
        early.steps, full.steps, early.wall_s, full.wall_s
    );
    for key in ["fc_n_per_mm", "ff_n_per_mm"] {
        let (f, e) = (sf[key].as_f64().expect("full"), se[key].as_f64().expect("early"));
        eprintln!("{key}: early {e:.2}, full {f:.2} ({:+.2} %)", 100.0 * (e - f) / f);
        assert!(((e - f) / f).abs() <= 2.0 * tol, "{key}: early {e} against full {f}");
    }
    for o in [&full_o, &early_o] {
        let _ = std::fs::remove_dir_all(&o.out_dir);
    }
}

#[test]
fn bad_early_stop_values_are_refused_naming_the_key() {
    let v0060 = std::fs::read_to_string("cases/cutting/v0060.toml").expect("v0060");
    let refused = |text: &str| -> String {
        Scene::from_str(text, "cases/cutting/v0060.toml", &[]).expect_err("refused").to_string()
    };
    for bad in ["0", "-0.02", "nan", "1.5", "inf", "\"0.02\""] {
        let text = format!("{v0060}\n[analysis]\nearly_stop = {{ tolerance = {bad} }}\n");
        let e = refused(&text);
        assert!(
            e.contains("cases/cutting/v0060.toml")
                && e.contains("analysis.early_stop.tolerance")
                && e.contains("(0, 1]"),
            "tolerance = {bad}: {e}"
        );
    }
    // Not a table, a missing or unknown key.
    let e = refused(&format!("{v0060}\n[analysis]\nearly_stop = 0.02\n"));
    assert!(e.contains("analysis.early_stop") && e.contains("tolerance"), "{e}");
    let e = refused(&format!("{v0060}\n[analysis]\nearly_stop = {{}}\n"));
    assert!(e.contains("analysis.early_stop.tolerance"), "{e}");
    let e = refused(&format!("{v0060}\n[analysis]\nearly_stop = {{ tolerance = 0.02, every = 3 }}\n"));
    assert!(e.contains("every"), "{e}");
    // Through --set, as the scene file.
    let e = Scene::load("cases/cutting/v0060.toml", &["analysis.early_stop.tolerance=0".to_string()])
        .expect_err("refused")
        .to_string();
    assert!(e.contains("analysis.early_stop.tolerance"), "{e}");
    // A scene without a tool has no forces to be steady.
    let rings = std::fs::read_to_string("cases/rings.toml").expect("rings");
    let e = Scene::from_str(
        &format!("{rings}\n[analysis]\nearly_stop = {{ tolerance = 0.02 }}\n"),
        "cases/rings.toml",
        &[],
    )
    .expect_err("refused")
    .to_string();
    assert!(e.contains("analysis.early_stop") && e.contains("[tool]"), "{e}");
    // A good value is kept.
    let ok = Scene::load("cases/cutting/v0060.toml", &["analysis.early_stop.tolerance=0.02".to_string()]).expect("ok");
    assert_eq!(ok.analysis.early_stop.map(|e| e.tolerance), Some(0.02));
}
