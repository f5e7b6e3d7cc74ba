//! Checkpoints (issue 6): a run stopped at a checkpoint and resumed reproduces the uninterrupted run bit for bit
//! on the same backend and precision; Ctrl-C writes a checkpoint and exits cleanly.

use crate::common;

use common::scenes::{drop_scene_3d, prism_obj};
use std::path::{Path, PathBuf};
use std::process::Command;
use swarf::backend::{AnyBackend, BackendChoice};
use swarf::run::{RunOptions, Snapshot, resume_scene, run_observed};
use swarf::scene::Scene;

fn opts(out: &Path, overrides: &[String], every: Option<f64>, resume: bool) -> RunOptions {
    RunOptions {
        out_dir: out.to_path_buf(),
        precision: None,
        frames: true,
        hdf5: false,
        quiet: true,
        verbose: false,
        overrides: overrides.to_vec(),
        checkpoint_every: every,
        resume,
        checkpoint_wall: None,
        state_at: Vec::new(),
    }
}

/// Final state as bits: positions, velocities, temperatures, plastic strains.
fn bits(s: &Snapshot) -> Vec<u64> {
    let mut v: Vec<u64> = s.pos.iter().chain(&s.vel).flat_map(|p| p.map(f64::to_bits)).collect();
    v.extend(s.temperature.unwrap_or(&[]).iter().map(|x| x.to_bits()));
    v.extend(s.plastic_strain.unwrap_or(&[]).iter().map(|x| x.to_bits()));
    v
}

fn dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("swarf-test-ckpt-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// The plastic impact with conduction (x, v, ρ, S, T, ε̄, ε̄̇, the start-of-step copies and the rates all carry
/// state), stopped at the checkpoint half way and resumed: the final state and the whole energy.csv equal the
/// uninterrupted run's bit for bit.
#[test]
fn resumed_run_equals_uninterrupted() {
    resume_equals_uninterrupted(&[], "f64");
}

/// The same in the mixed precision, whose positions' low parts are state too: the observer's positions are
/// hi + lo, so a resume that lost them would differ.
#[test]
fn resumed_mixed_run_equals_uninterrupted() {
    resume_equals_uninterrupted(&["precision=\"mixed\"".to_string()], "mixed");
}

/// The same with the viscosity's Balsara switch, whose factors (written by the interaction, read by the next
/// pre-pass) carry state from step to step.
#[test]
fn resumed_balsara_run_equals_uninterrupted() {
    resume_equals_uninterrupted(&["stabilisation.artificial_viscosity.switch=\"balsara\"".to_string()], "balsara");
}

/// The same with ductile damage (Johnson and Cook's 1985 fracture constants of AISI 4340, full damage at
/// initiation; tests/stability_thermal.rs): ω, D and the energy the degradation released are state, and
/// energy.csv's `damaged_volume`, `initiated_volume` and `damage_dissipation` (> 0 at the end) must come back bit for
/// bit.
#[test]
fn resumed_damaged_run_equals_uninterrupted() {
    let damage = "damage={ model = \"jc\", D1 = 0.05, D2 = 3.44, D3 = -2.12, D4 = 0.002, D5 = 0.61 }";
    let rows = resume_equals_uninterrupted(&[damage.to_string()], "damage");
    let released = rows.1.last().map_or(f64::NAN, |r| r[rows.0]);
    assert!(released > 0.0, "the degradation released {released} J/m: the case must damage");
}

fn resume_equals_uninterrupted(extra: &[String], tag: &str) -> (usize, Vec<Vec<f64>>) {
    let mut ov: Vec<String> =
        vec!["discretisation.dx=2e-3".into(), "physics.conduction=\"brookshaw\"".into(), "time.end=1e-4".into()];
    ov.extend_from_slice(extra);
    let scene = Scene::load("cases/impact.toml", &ov).expect("scene");
    let any = AnyBackend::select(BackendChoice::Cpu).expect("cpu").0;
    let end = scene.time.end;

    let a = dir(&format!("a-{tag}"));
    let mut last_a = Vec::new();
    let mut obs = |s: &Snapshot| {
        last_a = bits(s);
        true
    };
    run_observed(&any, &scene, &opts(&a, &ov, None, false), Some(&mut obs)).expect("uninterrupted");

    let b = dir(&format!("b-{tag}"));
    let mut obs = |s: &Snapshot| s.diagnostics.time < 0.5 * end;
    run_observed(&any, &scene, &opts(&b, &ov, Some(0.5 * end), false), Some(&mut obs)).expect("first half");
    assert!(b.join("checkpoint.bin").is_file(), "the checkpoint was written");
    let (resumed, rov) = resume_scene(&b).expect("resume scene");
    assert_eq!(rov, ov, "the checkpoint records the overrides");
    let mut last_b = Vec::new();
    let mut obs = |s: &Snapshot| {
        last_b = bits(s);
        true
    };
    run_observed(&any, &resumed, &opts(&b, &rov, Some(0.5 * end), true), Some(&mut obs)).expect("second half");
    assert!(
        !last_a.is_empty() && last_a == last_b,
        "the resumed run's final state differs from the uninterrupted run's"
    );
    let (head, ra) = swarf::output::csv::read(&a.join("energy.csv")).unwrap();
    let (_, rb) = swarf::output::csv::read(&b.join("energy.csv")).unwrap();
    let eq = ra.len() == rb.len()
        && ra.iter().zip(&rb).all(|(x, y)| x.iter().zip(y).all(|(p, q)| p.to_bits() == q.to_bits()));
    assert!(eq, "energy.csv differs after resuming ({} against {} rows)", rb.len(), ra.len());
    (head.iter().position(|c| c == "damage_dissipation").unwrap_or(0), rb)
}

/// Ctrl-C (SIGINT) writes a checkpoint and exits with 130; `swarf run --resume` finishes the run, and its last
/// frame file equals the uninterrupted run's byte for byte. The signal is sent twice back to back, as `timeout -s
/// INT` delivers it (to the command and to its process group): that must still count as one Ctrl-C.
#[test]
fn ctrl_c_checkpoints_and_resume_finishes_bitwise() {
    let bin = env!("CARGO_BIN_EXE_swarf");
    let set = ["--set", "time.end=1.5e-4"];
    let a = dir("cli-a");
    let st = Command::new(bin)
        .args(["--backend", "cpu", "run", "cases/rings.toml", "--quiet"])
        .args(set)
        .arg("--out")
        .arg(&a)
        .status()
        .unwrap();
    assert!(st.success());
    let b = dir("cli-b");
    let mut child = Command::new(bin)
        .args(["--backend", "cpu", "run", "cases/rings.toml", "--quiet"])
        .args(set)
        .arg("--out")
        .arg(&b)
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(800));
    let _ = Command::new("kill").args(["-INT", &child.id().to_string()]).status();
    let _ = Command::new("kill").args(["-INT", &child.id().to_string()]).status();
    let code = child.wait().unwrap().code();
    if code == Some(0) {
        return; // finished before the signal: nothing to resume (a slower machine than expected)
    }
    assert_eq!(code, Some(130), "Ctrl-C must exit with 130 after writing the checkpoint");
    assert!(b.join("checkpoint.bin").is_file());
    let st = Command::new(bin).args(["--backend", "cpu", "run", "--quiet", "--resume"]).arg(&b).status().unwrap();
    assert!(st.success(), "resume failed");
    let last = "frame_00050.vtu";
    assert_eq!(std::fs::read(a.join(last)).unwrap(), std::fs::read(b.join(last)).unwrap(), "last frames differ");
}

/// A cut interrupted between two output steps (Ctrl-C) and resumed writes the uninterrupted run's forces.csv byte
/// for byte: the samples taken since the last output step (ten per output interval) reach the file before the
/// checkpoint, so that the resume keeps them. Before, they were held only in memory and lost (a 2 M-particle grain
/// on the GPU resumed with 0.7 µs of samples missing). The default scene, 3 µs with one output interval.
#[test]
fn a_cut_interrupted_between_outputs_resumes_with_every_force_sample() {
    let bin = env!("CARGO_BIN_EXE_swarf");
    let cut = |out: &Path| {
        let mut c = Command::new(bin);
        c.args(["--backend", "cpu", "run", "--quiet", "--set", "time.end=3e-6", "--set", "output.every=3e-6"])
            .arg("--out")
            .arg(out);
        c
    };
    let (a, b) = (dir("cut-a"), dir("cut-b"));
    let mut whole = cut(&a).spawn().expect("spawn the uninterrupted cut");
    let mut child = cut(&b).spawn().expect("spawn the interrupted cut");
    std::thread::sleep(std::time::Duration::from_millis(2500));
    let _ = Command::new("kill").args(["-INT", &child.id().to_string()]).status();
    let code = child.wait().expect("the interrupted cut").code();
    assert!(whole.wait().expect("the uninterrupted cut").success());
    if code == Some(0) {
        return; // finished before the signal: nothing to resume (a much faster machine than expected)
    }
    assert_eq!(code, Some(130), "Ctrl-C must exit with 130 after writing the checkpoint");
    let read = |d: &Path| std::fs::read_to_string(d.join("forces.csv")).expect("forces.csv");
    let st = Command::new(bin).args(["--backend", "cpu", "run", "--quiet", "--resume"]).arg(&b).status().unwrap();
    assert!(st.success(), "resume failed");
    assert_eq!(read(&a), read(&b), "forces.csv differs after resuming");
    let _ = (std::fs::remove_dir_all(&a), std::fs::remove_dir_all(&b));
}

/// A mesh tool's run folder resumes from anywhere (issue 24): the scene names its mesh relative to its own folder
/// (`tools/prism.obj`), the run records a copy under `meshes/`, and after the scene's folder is deleted the run
/// folder still resumes; the resumed forces.csv equals the uninterrupted run's bit for bit.
#[test]
fn a_mesh_tool_run_resumes_without_its_scene_folder() {
    let base = dir("mesh");
    let scene_dir = base.join("scene");
    std::fs::create_dir_all(scene_dir.join("tools")).expect("scene folder");
    std::fs::write(scene_dir.join("tools/prism.obj"), prism_obj(-1e-3, 1e-3)).expect("mesh");
    let tool = "mesh = { file = \"tools/prism.obj\" }\nposition = [0.0, 0.0, 0.0]\nvelocity = [0.0, 0.0, 0.0]";
    let path = scene_dir.join("drop.toml");
    std::fs::write(&path, drop_scene_3d(10.0, 2.0, tool)).expect("scene");
    let scene = Scene::load(path.to_str().expect("utf-8 path"), &[]).expect("scene");
    let any = AnyBackend::select(BackendChoice::Cpu).expect("cpu").0;
    let end = scene.time.end;

    let a = base.join("a");
    run_observed(&any, &scene, &opts(&a, &[], None, false), None).expect("uninterrupted");
    let b = base.join("b");
    let mut obs = |s: &Snapshot| s.diagnostics.time < 0.5 * end;
    run_observed(&any, &scene, &opts(&b, &[], Some(0.5 * end), false), Some(&mut obs)).expect("first half");
    assert!(b.join("meshes/tools__prism.obj").is_file(), "the run folder records the mesh");
    std::fs::remove_dir_all(&scene_dir).expect("remove the scene's folder");
    let (resumed, rov) = resume_scene(&b).expect("the run folder resumes without the scene's folder");
    run_observed(&any, &resumed, &opts(&b, &rov, Some(0.5 * end), true), None).expect("second half");
    let (_, ra) = swarf::output::csv::read(&a.join("forces.csv")).expect("forces.csv");
    let (_, rb) = swarf::output::csv::read(&b.join("forces.csv")).expect("forces.csv");
    assert!(ra.iter().any(|r| r[4] > 0.0), "the block must reach the tool");
    let eq = ra.len() == rb.len()
        && ra.iter().zip(&rb).all(|(x, y)| x.iter().zip(y).all(|(p, q)| p.to_bits() == q.to_bits()));
    assert!(eq, "forces.csv differs after resuming ({} against {} rows)", rb.len(), ra.len());
    let _ = std::fs::remove_dir_all(&base);
}

/// A tool whose velocity is ramped and whose thermal particles move with it (the reference cut's tool, 20 m/s
/// reached over `ramp = 0.5 µs`), stopped at a checkpoint after the ramp (1 µs) and resumed to 1.5 µs, equals the uninterrupted run
/// bit for bit. The tool particles' prescribed velocity is the ramp's at each step's midpoint; after the ramp it is
/// the final velocity in both runs. Before, the uninterrupted run kept its last ramp step's midpoint velocity (a
/// little below the final one) and the resumed run the velocity restored with the state.
#[test]
fn a_ramped_tool_resumes_at_its_velocity() {
    let ov: Vec<String> = ["tool.velocity=[20.0,0.0]", "tool.ramp=5.0e-7", "time.end=1.5e-6", "output.every=2.5e-7"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    let scene = Scene::load("cases/cutting/reference-cut.toml", &ov).expect("scene");
    let any = AnyBackend::select(BackendChoice::Cpu).expect("cpu").0;
    let a = dir("ramp-a");
    let mut last_a = Vec::new();
    let mut obs = |s: &Snapshot| {
        last_a = bits(s);
        true
    };
    run_observed(&any, &scene, &opts(&a, &ov, None, false), Some(&mut obs)).expect("uninterrupted");
    let b = dir("ramp-b");
    let mut first = |s: &Snapshot| s.diagnostics.time < 1.0e-6;
    run_observed(&any, &scene, &opts(&b, &ov, Some(1.0e-6), false), Some(&mut first)).expect("first part");
    let (resumed, rov) = resume_scene(&b).expect("resume scene");
    let mut last_b = Vec::new();
    let mut obs = |s: &Snapshot| {
        last_b = bits(s);
        true
    };
    run_observed(&any, &resumed, &opts(&b, &rov, Some(1.0e-6), true), Some(&mut obs)).expect("second part");
    assert!(!last_a.is_empty() && last_a == last_b, "the resumed run's final state differs");
    let read = |d: &Path| std::fs::read_to_string(d.join("forces.csv")).expect("forces.csv");
    assert_eq!(read(&a), read(&b), "forces.csv differs after resuming");
    let _ = std::fs::remove_dir_all(&a);
    let _ = std::fs::remove_dir_all(&b);
}
