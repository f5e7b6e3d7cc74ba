//! `swarf run --state-at` (host/state_table.rs): the per-particle state after given step counts, the swarf side of
//! the comparison with the original code (ci/original/compare.py `states`, issue 22 item 1).

use std::collections::HashMap;

use swarf::backend::{AnyBackend, BackendChoice};
use swarf::run::{RunOptions, Snapshot, run_observed};
use swarf::scene::Scene;

/// The coarse V0060 cut of tests/cutting.rs (Δx = 20 µm, 765 particles) with a fixed Δt of 2.5 ns, for `steps`
/// steps: the tool (front 3 µm clear, 6.355 m/s) touches the workpiece after about 190 steps.
fn coarse_cut(steps: u64) -> Scene {
    let dt = 2.5e-9;
    let over: Vec<String> = [
        "discretisation.dx=2.0e-5".to_string(),
        "body.0.max=[1.0e-3,2.8e-4]".into(),
        "boundary.1.max=[1.0e-9,1.4e-4]".into(),
        "boundary.2.min=[0.9999e-3,-1.0]".into(),
        "tool.position=[-3.6e-5]".into(),
        "tool.depth_of_cut=0.9e-4".into(),
        format!("time.dt={dt:e}"),
        format!("time.end={:e}", steps as f64 * dt),
        format!("output.every={:e}", 100.0 * dt),
    ]
    .into();
    Scene::load("cases/cutting/v0060.toml", &over).expect("scene")
}

fn out_dir(tag: &str) -> std::path::PathBuf {
    std::env::temp_dir().join(format!("swarf-test-state-table-{tag}-{}", std::process::id()))
}

/// A state table as columns by name.
fn read(path: &std::path::Path) -> HashMap<String, Vec<f64>> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let head: Vec<String> = lines.next().expect("header").split(',').map(str::to_string).collect();
    let mut cols: HashMap<String, Vec<f64>> = head.iter().map(|h| (h.clone(), Vec::new())).collect();
    for line in lines {
        for (h, v) in head.iter().zip(line.split(',')) {
            cols.get_mut(h).expect("column").push(v.parse().expect("number"));
        }
    }
    cols
}

/// Facts: a table is written at exactly each requested step (the batches end there; the last one is the run's
/// final step); the table at step 0 holds every particle at its initial position (x = x0 exactly) and at rest; the
/// table at the final step equals the final state an observer sees, bit for bit (positions print in shortest
/// round-trip form); the contact forces are there once the tool cuts; and ending batches at the requested steps
/// changes no result (forces.csv equal, as text, to the same run without tables).
#[test]
fn state_tables_are_written_at_the_requested_steps_and_change_nothing() {
    let last = 600;
    let scene = coarse_cut(last);
    let any = AnyBackend::select(BackendChoice::Cpu).expect("cpu").0;
    let plain = RunOptions::quiet(out_dir("plain"));
    run_observed(&any, &scene, &plain, None).expect("plain run");
    let opts = RunOptions { state_at: vec![0, 1, 10, 333, last], ..RunOptions::quiet(out_dir("tables")) };
    let mut final_pos: Vec<(u32, [f64; 3])> = Vec::new();
    let mut steps_seen = 0;
    let mut obs = |s: &Snapshot| {
        final_pos = s.id.iter().copied().zip(s.pos.iter().copied()).collect();
        steps_seen = s.diagnostics.step;
        true
    };
    let report = run_observed(&any, &scene, &opts, Some(&mut obs)).expect("run with tables");
    assert_eq!(report.steps, last, "the run's steps");
    assert_eq!(steps_seen, last, "the observer's last step");
    for step in &opts.state_at {
        assert!(swarf::state_table::path(&opts.out_dir, *step).is_file(), "no table at step {step}");
    }
    let t0 = read(&swarf::state_table::path(&opts.out_dir, 0));
    assert_eq!(t0["id"].len(), 765);
    for k in ["x", "y"] {
        assert_eq!(t0[k], t0[&format!("{k}0")], "step 0: {k} ≠ {k}0");
    }
    assert!(t0["vx"].iter().chain(&t0["vy"]).all(|v| *v == 0.0), "step 0: the workpiece starts at rest");
    let tn = read(&swarf::state_table::path(&opts.out_dir, last));
    let by_id: HashMap<u32, [f64; 3]> = final_pos.into_iter().collect();
    for (i, id) in tn["id"].iter().enumerate() {
        let p = by_id[&(*id as u32)];
        assert_eq!([tn["x"][i], tn["y"][i]], [p[0], p[1]], "step {last}: particle {id}");
    }
    let touching = tn["fcx"].iter().zip(&tn["fcy"]).filter(|(x, y)| **x != 0.0 || **y != 0.0).count();
    assert!(touching > 0, "step {last}: no particle touches the tool");
    for k in ["rho", "sxx", "sxy", "syy", "szz", "T", "eps_pl", "ftx", "fty", "tool"] {
        assert!(tn.contains_key(k), "no column {k}");
    }
    let forces = |o: &RunOptions| std::fs::read_to_string(o.out_dir.join("forces.csv")).expect("forces.csv");
    assert_eq!(forces(&opts), forces(&plain), "the tables changed the run's forces");
    for o in [plain, opts] {
        let _ = std::fs::remove_dir_all(&o.out_dir);
    }
}

/// `--state-at` refuses what is not a list of step counts, naming the flag and the expected form.
#[test]
fn state_at_refuses_what_is_not_step_counts() {
    assert_eq!(swarf::state_table::parse_steps("100, 0,10,10").expect("steps"), vec![0, 10, 100]);
    for bad in ["", "1,,2", "-1", "1.5", "ten"] {
        let e = swarf::state_table::parse_steps(bad).expect_err(bad);
        assert!(e.contains("--state-at") && e.contains("step count"), "{bad}: {e}");
    }
}
