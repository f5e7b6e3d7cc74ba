//! The scene's `rotation` key of `[tool]` (docs/scenes.md): a rotating tool's motion reaches the solver's
//! `ToolState` on the CPU, a scene without the key keeps the translating path, and a bad axis or a rotating thermal
//! tool is refused with the file, the key and the expected value.

use crate::common;

use common::scenes::drop_scene;
use swarf::backend::CpuBackend;
use swarf::kernels::Dim2;
use swarf::scene::Scene;
use swarf::solver::Solver;
use swarf::tool::Rotation;
use swarf::tool::motion::rotation_matrix;

const FILE: &str = "cases/cutting/drop.toml";

/// The drop scene (a block falling on a resting tool) with `rotation` added to `[tool]`.
fn rotating(rotation: &str) -> String {
    drop_scene(20.0, 0.1, 0.35, 0.0).replacen(
        "contact_stiffness =",
        &format!("rotation = {rotation}\ncontact_stiffness ="),
        1,
    )
}

fn refused(text: &str) -> String {
    match Scene::from_str(text, FILE, &[]) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("accepted a bad rotation:\n{text}"),
    }
}

fn assert_has(msg: &str, parts: &[&str]) {
    for part in parts {
        assert!(msg.contains(part), "message lacks '{part}':\n{msg}");
    }
}

/// Exact: the scene's rotation becomes the motion's unit axis, centre and ω = 2π rpm/60, and after one step the
/// solver's tool state is that motion's state at the solver's time (the same f64 arithmetic, so bit for bit),
/// rotating, with ω along z and R(θ) from Rodrigues' formula.
#[test]
fn a_rotating_tool_reaches_the_solver_tool_state() {
    let scene = Scene::from_str(
        &rotating("{ axis = [0.0, 0.0, 2.0], centre = [-1.0e-4, 5.0e-5, 0.0], rpm = 1000.0 }"),
        FILE,
        &[],
    )
    .expect("scene");
    let setup = swarf::run::setup::<f64, Dim2>(&scene).expect("setup");
    let contact = setup.contact.as_ref().expect("contact");
    let rate = 1000.0 * std::f64::consts::TAU / 60.0;
    assert_eq!(
        contact.tools[0].motion.rotation,
        Some(Rotation { axis: [0.0, 0.0, 1.0], centre: [-1.0e-4, 5.0e-5, 0.0], rate })
    );
    let b = CpuBackend::new();
    let mut solver = Solver::<CpuBackend, f64, Dim2>::new(&b, &setup).expect("solver");
    solver.step(&b, setup.dt).expect("step");
    let s = solver.tool_state().expect("a tool");
    assert_eq!(s, contact.tools[0].motion.state_at(setup.dt, setup.dt, setup.dt));
    assert_eq!(s.rotating, 1);
    assert_eq!(s.centre, [-1.0e-4, 5.0e-5, 0.0]);
    assert_eq!(s.omega, [0.0, 0.0, rate]);
    assert_eq!(s.rotation, rotation_matrix([0.0, 0.0, 1.0], rate * setup.dt));
}

/// A scene without the key builds a translating motion (no rotation: the kernels' translating path).
#[test]
fn without_the_key_the_tool_only_translates() {
    let scene = Scene::from_str(&drop_scene(20.0, 0.1, 0.35, 0.0), FILE, &[]).expect("scene");
    assert_eq!(scene.tool.as_ref().expect("tool").rotation, None);
    let setup = swarf::run::setup::<f64, Dim2>(&scene).expect("setup");
    assert_eq!(setup.contact.as_ref().expect("contact").tools[0].motion.rotation, None);
    let b = CpuBackend::new();
    let solver = Solver::<CpuBackend, f64, Dim2>::new(&b, &setup).expect("solver");
    assert_eq!(solver.tool_state().expect("a tool").rotating, 0);
}

#[test]
fn zero_non_finite_and_in_plane_axes_are_refused() {
    for (axis, expected) in [
        ("[0.0, 0.0, 0.0]", "a finite, non-zero axis [x, y, z]"),
        ("[nan, 0.0, 1.0]", "a finite, non-zero axis [x, y, z]"),
        ("[0.0, 0.0, inf]", "a finite, non-zero axis [x, y, z]"),
        ("[1.0, 0.0, 0.0]", "an axis along z, [0, 0, 1] or [0, 0, -1]: the parametric tool is 2D"),
        ("[0.0, 1.0, 1.0]", "an axis along z, [0, 0, 1] or [0, 0, -1]: the parametric tool is 2D"),
    ] {
        let msg = refused(&rotating(&format!("{{ axis = {axis}, centre = [0.0, 0.0, 0.0], rpm = 100.0 }}")));
        assert_has(&msg, &[FILE, "tool.rotation.axis", expected]);
    }
    let msg = refused(&rotating("{ axis = [0.0, 0.0, 1.0], centre = [0.0, 0.0, 0.0], rpm = nan }"));
    assert_has(&msg, &[FILE, "tool.rotation.rpm", "a finite rotational speed in revolutions per minute"]);
    let msg = refused(&rotating("{ axis = [0.0, 0.0, 1.0], rpm = 100.0 }"));
    assert_has(&msg, &[FILE, "tool.rotation.centre", "the rotation centre [x, y, z]"]);
}

/// The thermal tool particles only translate (their velocity is one entry of the prescribed-velocity table).
#[test]
fn a_rotating_thermal_tool_is_refused() {
    let file = "cases/cutting/reference-cut.toml";
    let text = std::fs::read_to_string(file).expect("the reference cut");
    assert!(text.contains("\n[tool.thermal]"), "the reference cut has a thermal tool");
    let text = text.replacen(
        "\n[tool.thermal]",
        "\nrotation = { axis = [0, 0, 1], centre = [0, 0, 0], rpm = 100 }\n[tool.thermal]",
        1,
    );
    let msg = match Scene::from_str(&text, file, &[]) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("accepted a rotating thermal tool"),
    };
    assert_has(&msg, &[file, "tool.rotation", "no rotation with [tool.thermal]"]);
}

/// A rotating tool makes no steady orthogonal cut: its run writes forces.csv and no cutting analysis
/// (summary.json's `cutting` is null), where the same tool translating without the rotation gets one.
#[test]
fn a_rotating_tool_gets_no_cutting_analysis() {
    use swarf::backend::{AnyBackend, BackendChoice};
    let moving = drop_scene(20.0, 0.1, 0.35, 0.0)
        .replacen("velocity = [0.0, 0.0]\ncontact", "velocity = [1.0, 0.0]\ncontact", 1)
        .replacen("end = 1.2e-6", "end = 6.0e-7", 1);
    let spinning = moving.replacen(
        "contact_stiffness =",
        "rotation = { axis = [0.0, 0.0, 1.0], centre = [-1.0e-4, 5.0e-5, 0.0], rpm = 1000.0 }\ncontact_stiffness =",
        1,
    );
    assert_ne!(moving, spinning, "the rotation was not added");
    let b = AnyBackend::select(BackendChoice::Cpu).expect("cpu").0;
    for (tag, text, analysed) in [("translating", &moving, true), ("rotating", &spinning, false)] {
        let scene = Scene::from_str(text, FILE, &[]).expect("scene");
        let dir = std::env::temp_dir().join(format!("swarf-test-rotation-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        swarf::run::run(&b, &scene, &swarf::run::RunOptions::quiet(dir.clone())).expect("run");
        let text = std::fs::read_to_string(dir.join("summary.json")).expect("summary.json");
        let summary: serde_json::Value = serde_json::from_str(&text).expect("json");
        assert_eq!(summary["cutting"].is_object(), analysed, "{tag}: cutting = {}", summary["cutting"]);
        assert!(dir.join("forces.csv").is_file(), "{tag}: no forces.csv");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
