//! The original model, `model = "mfree_iwf"` (issue 22; docs/validation.md, "The original model"): each formula
//! of Röthlin's 2D code [C2D] that swarf reproduces, bugs included, against its closed form; the scene key and its
//! refusals; the default model unchanged bit for bit (the short coarse cut's force record against the one the
//! commit before the option, c50d6ee, wrote); and a short coarse cut under the original model, finite and with
//! other forces.

use crate::common;

use std::path::PathBuf;
use swarf::backend::{AnyBackend, BackendChoice};
use swarf::kernels::contact::penalty::{ContactParams, contact_force, slip};
use swarf::kernels::contact::tool2d::{Tool2d, ToolShape};
use swarf::kernels::contact::{ToolGeometry, ToolState};
use swarf::kernels::material::c2d_return::{c2d_return, sqrt_f32};
use swarf::kernels::material::{
    FlowStress, JohnsonCook, RATE_FORM_CLAMP, RATE_FORM_UINTAH, ReturnOptions, ReturnStatus, radial_return,
};
use swarf::kernels::sph::CubicSpline;
use swarf::kernels::sph::params::flags;
use swarf::kernels::{Dim2, Vector};
use swarf::run::{RunOptions, run};
use swarf::scene::{Model, Scene, Switch};

const SQRT_2_3: f64 = 0.816496580927726;

fn cpu() -> AnyBackend {
    AnyBackend::select(BackendChoice::Cpu).expect("cpu").0
}

fn out(tag: &str) -> PathBuf {
    std::env::temp_dir().join(format!("swarf-test-mfree-{tag}-{}", std::process::id()))
}

/// Relative difference.
fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Ti6Al4V-like Johnson–Cook without hardening or rate or thermal softening at T0: σ_y = A (a perfectly plastic
/// material, so the return's closed forms are exact), or with C > 0 for the rate tests.
fn jc(c: f64, rate_form: u32) -> JohnsonCook {
    JohnsonCook {
        a: 862e6,
        b: 0.0,
        c,
        n: 0.34,
        m: 0.8,
        ref_rate: 1.0,
        ref_temp: 300.0,
        melt_temp: 1836.0,
        rate_form,
        _pad: 0,
    }
}

const G: f64 = 40.74e9;
const DT: f64 = 1.4e-9;

/// Erratum 25a on a pure shear state S = τ (e_x ⊗ e_y + e_y ⊗ e_x): the original norm is τ where ‖S‖ = √2 τ, so
/// the return scales S to τ_new = √(2/3) σ_y/n · τ = √(2/3) σ_y (von Mises √2 σ_y) instead of σ_y/√3. Checked in
/// swarf's Newton with the bug alone (to 1e-10, Newton's tolerance) and in the original procedure (to 1e-6: its
/// f32 roundings, its absolute tolerance), with the plastic strain √(2/3) Δλ, Δλ = (n − √(2/3) σ_y)/(2G), and the
/// correct norm's return to σ_y/√3 for contrast.
#[test]
fn the_norm_without_the_factor_two_returns_pure_shear_to_root_two_yield() {
    let m = jc(0.0, RATE_FORM_CLAMP);
    let a = m.a;
    let tau = 0.9 * a; // σ_vm = √3 τ = 1.56 A: plastic; and τ > √(2/3) A, so the bugged g(0) > 0
    let s = [0.0, tau, 0.0, 0.0, 0.0, 0.0];
    let right = radial_return(&m, &s, 0.0, 0.0, 300.0, G, DT, &ReturnOptions::DEFAULT);
    assert!(rel(right.stress[1], a / 3f64.sqrt()) < 1e-10, "τ = {} with the true norm", right.stress[1]);

    let bug = ReturnOptions { c2d_norm: true, ..ReturnOptions::DEFAULT };
    let r = radial_return(&m, &s, 0.0, 0.0, 300.0, G, DT, &bug);
    assert_eq!(r.status, ReturnStatus::Converged);
    assert!(rel(r.stress[1], SQRT_2_3 * a) < 1e-10, "τ_new = {} against √(2/3) A = {}", r.stress[1], SQRT_2_3 * a);
    let dl = (tau - SQRT_2_3 * a) / (2.0 * G);
    assert!(rel(r.delta_lambda, dl) < 1e-10, "Δλ = {} against {dl}", r.delta_lambda);
    assert!(rel(r.eps, SQRT_2_3 * dl) < 1e-10);
    assert!(rel(3f64.sqrt() * r.stress[1], 2f64.sqrt() * a) < 1e-10, "von Mises after the return is √2 σ_y");

    let c = c2d_return(&m, &s, 0.0, 0.0, 300.0, G, DT, true);
    assert!(rel(c.stress[1], SQRT_2_3 * a) < 1e-6, "original procedure: τ_new = {}", c.stress[1]);
    assert!(rel(c.delta_lambda, dl) < 1e-6, "original procedure: Δλ = {} against {dl}", c.delta_lambda);
    assert!(rel(c.eps, SQRT_2_3 * dl) < 1e-6);
    assert!(rel(c.rate, SQRT_2_3 * dl / DT) < 1e-6);
    // ε̄ = f32(√(2/3)) · f32(Δλ), as the code's `sqrtf(2.0/3.0) * fmaxf(delta_lambda, 0.)`.
    let f = |x: f64| x as f32 as f64;
    assert_eq!(c.eps, sqrt_f32(2.0 / 3.0) * f(c.delta_lambda));
    // With the true norm the original procedure returns to σ_y/√3 like swarf's.
    let t = c2d_return(&m, &s, 0.0, 0.0, 300.0, G, DT, false);
    assert!(rel(t.stress[1], a / 3f64.sqrt()) < 1e-6, "original procedure, true norm: τ = {}", t.stress[1]);
}

/// With the norm bug a shear state between σ_y/√3 and √(2/3) σ_y passes the (correct) von Mises check while
/// g(0) = τ − √(2/3) σ_y < 0. swarf's solver returns nothing (Δλ = 0); the original's secant finds the negative root
/// Δλ* = (τ − √(2/3) σ_y)/(2G), flips it to −0.1 Δλ* > 0 and stops there, so the state is scaled although it is
/// inside the bugged surface: Δλ = 0.1 |Δλ*| (to 1e-6).
#[test]
fn the_original_secant_flips_a_negative_root() {
    let m = jc(0.0, RATE_FORM_CLAMP);
    let a = m.a;
    let tau = 0.7 * a;
    let s = [0.0, tau, 0.0, 0.0, 0.0, 0.0];
    let swarf = radial_return(&m, &s, 0.0, 0.0, 300.0, G, DT, &ReturnOptions { c2d_norm: true, ..Default::default() });
    assert_eq!((swarf.delta_lambda, swarf.stress[1]), (0.0, tau));
    let c = c2d_return(&m, &s, 0.0, 0.0, 300.0, G, DT, true);
    let root = (tau - SQRT_2_3 * a) / (2.0 * G);
    assert!(root < 0.0);
    assert!(rel(c.delta_lambda, -0.1 * root) < 1e-6, "Δλ = {} against 0.1 |Δλ*| = {}", c.delta_lambda, -0.1 * root);
    assert!(rel(c.stress[1], tau - 2.0 * G * c.delta_lambda) < 1e-12);
}

/// The original's elastic check is at the previous step's rate: with C > 0 a state between σ_y(ε̄, 0, T) and
/// σ_y(ε̄, ε̄̇_old, T) stays elastic there (and its rate is reset to 0), while swarf's check at rate 0 returns it.
#[test]
fn the_original_checks_yield_at_the_previous_rate() {
    let m = jc(0.02, RATE_FORM_UINTAH);
    let rate_old = 1e5;
    let (sy0, sy_old) = (m.sigma_y(0.1, 0.0, 300.0), m.sigma_y(0.1, rate_old, 300.0));
    assert!(sy_old > 1.2 * sy0);
    // σ_vm = 1.1 σ_y(ε̄, 0): uniaxial deviator (2, −1, −1)·s/3 has σ_vm = s.
    let svm = 1.1 * sy0;
    let s = [2.0 * svm / 3.0, 0.0, 0.0, -svm / 3.0, 0.0, -svm / 3.0];
    let c = c2d_return(&m, &s, 0.1, rate_old, 300.0, G, DT, true);
    assert_eq!(c.status, ReturnStatus::Elastic);
    assert_eq!((c.eps, c.rate, c.stress), (0.1, 0.0, s));
    let r = radial_return(&m, &s, 0.1, rate_old, 300.0, G, DT, &ReturnOptions::DEFAULT);
    assert_ne!(r.status, ReturnStatus::Elastic);
}

/// Erratum 24: W(q = 1.5) = 0.25 · 0.5⁶ · n_c in the old code against 0.25 · 0.5³ · n_c (to 1e-13: q = r/h carries an
/// ulp, which (2 − q)⁶ multiplies by 12); both branches
/// agree with the spline for q ≤ 1 and vanish at q ≥ 2.
#[test]
fn the_kernel_value_bug_is_the_sixth_power() {
    let h = 1.5e-5;
    let k = CubicSpline::<f64>::new(h, 2);
    let norm = 10.0 / (7.0 * std::f64::consts::PI * h * h);
    let w = k.w_c2d(1.5 * h);
    assert!(rel(w, 0.25 * 0.5f64.powi(6) * norm) < 1e-13, "W_c2d(1.5h) = {w}");
    assert!(rel(k.w(1.5 * h), 0.25 * 0.5f64.powi(3) * norm) < 1e-13);
    for q in [0.0, 0.3, 0.5, 0.9, 1.0] {
        assert_eq!(k.w_c2d(q * h), k.w(q * h), "q = {q}");
    }
    assert_eq!(k.w_c2d(2.0 * h), 0.0);
}

/// Erratum 25 on a 45° normal of the edge arc, n = (1, −1)/√2: the original's sliding velocity is
/// v_r − v_r∘n = (v_x (1 − n_x), v_y (1 − n_y)), its friction history is not projected on the tangent, and its
/// friction heat takes |v_r − (v_r·n)(1, 1)|; swarf's v_t = v_r − (v_r·n) n with the projected history. Each against
/// its closed form, to 1e-12 (the normal comes from the tool's geometry).
#[test]
fn the_glm_slip_on_a_45_degree_normal() {
    let t = Tool2d::new(&ToolShape {
        rake_angle: 0.0,
        clearance_angle: 7f64.to_radians(),
        edge_radius: 20e-6,
        length: 4e-4,
        height: 4e-4,
    })
    .expect("tool");
    let s45 = std::f64::consts::FRAC_1_SQRT_2;
    let depth = 0.1e-6;
    let x = [t.centre[0] + (t.radius - depth) * s45, t.centre[1] - (t.radius - depth) * s45];
    let q = t.query([x[0], x[1], 0.0]);
    assert!(q.distance < 0.0);
    let n = [q.normal[0], q.normal[1]];
    assert!((n[0] - s45).abs() < 1e-12 && (n[1] + s45).abs() < 1e-12, "normal {n:?}");
    let (m, rho, cp, dt, mu, kappa, eta) = (1.77e-6, 4430.0, 560.0, 1.4e-9, 10.0, 0.1, 0.9);
    let st = ToolState { velocity: [6.0, 0.0, 0.0], dt, step: dt, ..Default::default() };
    let v = [2.0, 3.0];
    let f_old = [40.0, -25.0];
    let vr = [v[0] - 6.0, v[1]];
    let k = kappa * m / dt;
    let base = ContactParams {
        kappa,
        friction_kappa: kappa,
        friction: mu,
        heat_fraction: eta,
        melt: f64::INFINITY,
        ..Default::default()
    };
    let fc = kappa * m * depth / (dt * dt);
    // The original's.
    let c2d =
        contact_force(&ContactParams { slip_mode: slip::C2D, ..base }, &t, &st, x, v, f_old, m, rho, 300.0, cp, 0.0);
    let vt = [vr[0] * (1.0 - n[0]), vr[1] * (1.0 - n[1])];
    let fs = [f_old[0] - k * vt[0], f_old[1] - k * vt[1]];
    assert!(fs[0].hypot(fs[1]) < mu * fc, "the trial force must stick for the closed form");
    for j in 0..2 {
        assert!(rel(c2d.friction[j], fs[j]) < 1e-12, "friction {:?} against {fs:?}", c2d.friction);
    }
    let vn = vr[0] * n[0] + vr[1] * n[1];
    let heat = eta * dt * fs[0].hypot(fs[1]) * (vr[0] - vn).hypot(vr[1] - vn) / (m * cp);
    assert!(rel(c2d.heating, heat) < 1e-12, "heating {} against {heat}", c2d.heating);
    // swarf's.
    let own = contact_force(&base, &t, &st, x, v, f_old, m, rho, 300.0, cp, 0.0);
    let vt = [vr[0] - vn * n[0], vr[1] - vn * n[1]];
    let on = f_old[0] * n[0] + f_old[1] * n[1];
    let fs = [f_old[0] - on * n[0] - k * vt[0], f_old[1] - on * n[1] - k * vt[1]];
    for j in 0..2 {
        assert!(rel(own.friction[j], fs[j]) < 1e-12, "friction {:?} against {fs:?}", own.friction);
    }
    assert_eq!(own.normal, c2d.normal, "the normal force is the same law");
    // On the 0° rake face, n = (1, 0), the two slips agree (the bug is invisible there) but the history projection
    // still differs.
    let xr = [t.centre[0] + t.radius - 1e-7, t.centre[1] + 30e-6];
    let qr = t.query([xr[0], xr[1], 0.0]);
    assert!(qr.distance < 0.0 && qr.normal[0] == 1.0 && qr.normal[1] == 0.0, "{qr:?}");
    let f0 = [0.0, 0.0];
    let a = contact_force(&base, &t, &st, xr, v, f0, m, rho, 300.0, cp, 0.0);
    let b = contact_force(&ContactParams { slip_mode: slip::C2D, ..base }, &t, &st, xr, v, f0, m, rho, 300.0, cp, 0.0);
    assert_eq!(a.friction, b.friction);
    let (a, b) = (
        contact_force(&base, &t, &st, xr, v, f_old, m, rho, 300.0, cp, 0.0),
        contact_force(&ContactParams { slip_mode: slip::C2D, ..base }, &t, &st, xr, v, f_old, m, rho, 300.0, cp, 0.0),
    );
    assert_ne!(a.friction, b.friction, "the history's normal part is kept by the original only");
}

/// V0060 coarsened to Δx = 20 µm, 0.15 mm of cut (tests/cutting.rs's CI cut), with `extra` overrides: the shared
/// coarse cut (`common::scenes::coarse_cut`, 4 µs) run to 24 µs.
fn coarse_cut(extra: &[&str]) -> Scene {
    let mut over = vec!["time.end=2.4e-5", "output.every=2.4e-6"];
    over.extend_from_slice(extra);
    common::scenes::coarse_cut(&over)
}

/// The original code's datum: the feed below the top row's centres, Δx/2 deeper than swarf's (the row + Δx/2); on
/// the coarse cut, top row y = 2.8e-4 m, depth 0.9e-4 m: y = 1.9e-4 m (to 1e-18 m).
#[test]
fn the_depth_of_cut_is_measured_from_the_top_row() {
    let own = coarse_cut(&[]).tool.expect("tool").position;
    let orig = coarse_cut(&["model=\"mfree_iwf\""]).tool.expect("tool").position;
    assert!((orig[1] - (2.8e-4 - 0.9e-4)).abs() < 1e-18, "y = {}", orig[1]);
    assert!((own[1] - orig[1] - 1.0e-5).abs() < 1e-18, "swarf {} against the original {}", own[1], orig[1]);
    assert_eq!(own[0], orig[0]);
}

/// What the original model sets in the run's set-up, against the closed forms: Δt = CFL h/(c0 + √v) with √v in the
/// cut's cm/µs, 100 √(v [m/s]) m/s (erratum 13; to 1e-14); the cutoff r < 1 µm (erratum 31); the Uintah rate form;
/// the fixed particles held at their temperature; the kernel and plastic flags; the default's swarf values.
#[test]
fn the_original_model_sets_up_its_time_step_cutoff_and_flags() {
    let own = swarf::run::setup::<f64, Dim2>(&coarse_cut(&[])).expect("setup");
    let orig = swarf::run::setup::<f64, Dim2>(&coarse_cut(&["model=\"mfree_iwf\""])).expect("setup");
    let (h, c0) = (1.5 * 2.0e-5, own.c0);
    assert!(rel(own.dt, 0.5 * h / c0) < 1e-14, "swarf Δt = {}", own.dt);
    let dt = 0.5 * h / (c0 + 100.0 * 6.355f64.sqrt());
    assert!(rel(orig.dt, dt) < 1e-14, "original Δt = {} against {dt}", orig.dt);
    assert!(orig.dt < 0.96 * own.dt && orig.dt > 0.94 * own.dt, "√v in cm/µs is about 5 % of c0 at 381 m/min");
    assert_eq!(own.params.min_r2, (1e-6 * h) * (1e-6 * h));
    assert_eq!(orig.params.min_r2, 1e-12);
    assert_eq!(orig.thermal.as_ref().expect("heat").heat.min_r2, 1e-12);
    assert_eq!(own.params.model_flags, 0);
    assert_eq!(orig.params.model_flags, swarf::kernels::sph::params::model::C2D_KERNEL_W);
    let (pl_own, pl_orig) = (own.plastic.as_ref().expect("plastic"), orig.plastic.as_ref().expect("plastic"));
    use swarf::kernels::sph::plastic::return_flags::{C2D_NORM, C2D_RETURN};
    assert_eq!((pl_own.return_flags, pl_orig.return_flags), (0, C2D_RETURN | C2D_NORM));
    let rate_form = |p: &swarf::solver::PlasticSetup| p.model.johnson_cook().expect("JC").rate_form;
    assert_eq!((rate_form(pl_own), rate_form(pl_orig)), (RATE_FORM_CLAMP, RATE_FORM_UINTAH));
    use swarf::kernels::contact::penalty::slip;
    assert_eq!(own.contact.as_ref().expect("tool").tools[0].params.slip_mode, slip::PROJECTED);
    assert_eq!(orig.contact.as_ref().expect("tool").tools[0].params.slip_mode, slip::C2D);
    // Without a thermal tool the original code holds no fixed particle's temperature (its thermal boundary runs only
    // with the tool's thermal constants): V0060 holds only its bottom row, as the scene says, under both models.
    assert!(own.particles.flags == orig.particles.flags);
    let heat = |s: &swarf::run::Setup<f64, Dim2>| s.thermal.as_ref().expect("heat").heat;
    assert_eq!((heat(&own).flags, heat(&orig).flags), (0, swarf::kernels::sph::heat::heat_flags::C2D));
    assert_eq!(heat(&orig).rho0, 4430.0);
}

/// The original's conduction takes the tool particles' volume as the workpiece's particle mass over the tool's
/// density (roethlin-solver.md §5.6): on the thermal reference cut the tool particles get the workpiece's mass. With
/// that thermal tool, the original also holds every mechanically fixed particle at its initial temperature.
#[test]
fn the_original_conduction_gives_the_tool_particles_the_workpiece_mass_and_holds_the_fixed() {
    let load = |model: &str| {
        let sets = vec![format!("model={model}")];
        let scene = Scene::load("cases/cutting/reference-cut.toml", &sets).expect("scene");
        swarf::run::setup::<f64, Dim2>(&scene).expect("setup")
    };
    for (model, same) in [("\"swarf\"", false), ("\"mfree_iwf\"", true)] {
        let s = load(model);
        let p = &s.particles;
        let wp = (0..p.len()).find(|&i| p.flags[i] & flags::THERMAL_ONLY == 0).expect("workpiece");
        let tool = (0..p.len()).find(|&i| p.flags[i] & flags::THERMAL_ONLY != 0).expect("a thermal tool");
        assert_eq!(p.mass[tool] == p.mass[wp], same, "{model}: tool {} against workpiece {}", p.mass[tool], p.mass[wp]);
        let fixed = p.flags.iter().filter(|f| **f & flags::KIND_MASK == flags::FIXED);
        assert!(fixed.clone().count() > 0);
        assert_eq!(fixed.clone().all(|f| f & flags::FIXED_TEMPERATURE != 0), same, "{model}: fixed particles held");
    }
}

/// The scene key: the two names and a list of switches are read; anything else is refused with the file, the line,
/// the key and the values it takes; the original model is 2D only.
#[test]
fn the_model_key_is_read_and_refused() {
    assert_eq!(coarse_cut(&[]).model, Model::Swarf);
    assert_eq!(coarse_cut(&["model=\"swarf\""]).model, Model::Swarf);
    assert_eq!(coarse_cut(&["model=\"mfree_iwf\""]).model, Model::MfreeIwf);
    assert!(Model::MfreeIwf.switches().list() == Switch::ALL.to_vec());
    let list = coarse_cut(&["model=[\"kernel_w6\",\"glm_slip\"]"]).model;
    assert_eq!(list.switches().list(), vec![Switch::KernelW6, Switch::GlmSlip]);
    let text = std::fs::read_to_string("cases/cutting/v0060.toml")
        .expect("v0060")
        .replace("name = \"v0060\"", "name = \"v0060\"\nmodel = \"mfree\"");
    let line = 1 + text.lines().position(|l| l.starts_with("model =")).expect("the line");
    let e = Scene::from_str(&text, "cases/cutting/v0060.toml", &[]).expect_err("refused").to_string();
    let head =
        format!("cases/cutting/v0060.toml:{line}: model = \"mfree\": expected \"swarf\" or \"mfree_iwf\", or a list");
    assert!(e.starts_with(&head) && e.contains("\"kernel_w6\"") && e.contains("\"c2d_conduction\""), "{e}");
    for bad in ["model=[\"kernel_w6\",\"nope\"]", "model=3", "model=[1]"] {
        let e = Scene::load("cases/cutting/v0060.toml", &[bad.to_string()]).expect_err("refused").to_string();
        assert!(e.starts_with(&format!("--set {bad}: model: expected \"swarf\" or \"mfree_iwf\"")), "{e}");
    }
    let e = Scene::load("cases/cylinders-3d.toml", &["model=\"mfree_iwf\"".into()]).expect_err("3D").to_string();
    assert!(e.contains("model: expected \"swarf\" in 3D"), "{e}");
}

fn forces(scene: &Scene, tag: &str) -> (String, f64, f64) {
    let (text, fc, ff, _) = forces_and_model(scene, tag);
    (text, fc, ff)
}

/// The run's forces.csv text, F_c and F_f [N/mm], and summary.json's `model` (null for swarf's).
fn forces_and_model(scene: &Scene, tag: &str) -> (String, f64, f64, serde_json::Value) {
    let o = RunOptions::quiet(out(tag));
    run(&cpu(), scene, &o).expect("the coarse cut runs to its end");
    let text = std::fs::read_to_string(o.out_dir.join("forces.csv")).expect("forces.csv");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(o.out_dir.join("summary.json")).expect("summary")).expect("json");
    let _ = std::fs::remove_dir_all(&o.out_dir);
    (text, v["fc_n_per_mm"].as_f64().expect("F_c"), v["ff_n_per_mm"].as_f64().expect("F_f"), v["model"].clone())
}

/// The default model is unchanged bit for bit: the short coarse cut's force record (every sample, as text: Rust's
/// shortest round-trip numbers) equals the one commit c50d6ee wrote before the option existed
/// (tests/data/coarse-cut-forces-c50d6ee.csv, from `swarf --backend cpu run` with these overrides), with and without
/// `model = "swarf"`. The same cut under `model = "mfree_iwf"` runs to its end (a non-finite value would stop it),
/// with positive forces of the same order that differ from the default's; its summary.json says `"model":
/// "mfree_iwf"` (the default's has no `model`).
#[test]
fn the_default_is_unchanged_and_the_original_model_cuts() {
    // c50d6ee's default contact was the theses' undamped step law; since then the default is the bulk law with
    // ξ = 1, and the step law, set explicitly or by the `step_contact` switch, is that record bit for bit.
    // The record's columns as c50d6ee wrote them (later columns, e.g. friction_ratio, are compared by the GPU and
    // contact tests).
    let reference = std::fs::read_to_string("tests/data/coarse-cut-forces-c50d6ee.csv").expect("reference");
    let ncols = reference.lines().next().map_or(0, |h| h.split(',').count());
    let cols = |text: &str| -> String {
        text.lines().map(|l| l.split(',').take(ncols).collect::<Vec<_>>().join(",") + "\n").collect()
    };
    let step = ["tool.contact_law=\"step\"", "tool.contact_damping=0.0"];
    let (own, fc, ff, model) = forces_and_model(&coarse_cut(&step), "default");
    assert!(cols(&own) == reference, "swarf's model with the step law: the force record differs from c50d6ee's");
    assert!(model.is_null(), "summary.json names no model for swarf's (it is what it was)");
    let (named, _, _) = forces(&coarse_cut(&["model=\"swarf\"", step[0], step[1]]), "named");
    assert!(cols(&named) == reference, "model = \"swarf\" differs from the default");
    let (switched, _, _) = forces(&coarse_cut(&["model=[\"step_contact\"]"]), "step-contact");
    assert!(cols(&switched) == reference, "model = [\"step_contact\"] is not the step law undamped");
    let (bulk, fc_b, ff_b) = forces(&coarse_cut(&[]), "bulk");
    assert!(cols(&bulk) != reference, "the default contact is no longer the step law");
    assert!(fc_b > 0.8 * fc && fc_b < 1.25 * fc && ff_b > 0.0, "bulk law: F_c = {fc_b}, F_f = {ff_b} N/mm");
    let (orig, fc_o, ff_o, model) = forces_and_model(&coarse_cut(&["model=\"mfree_iwf\""]), "mfree");
    assert_eq!(model, serde_json::json!("mfree_iwf"), "summary.json names the original model");
    eprintln!("coarse cut: swarf F_c = {fc:.2}, F_f = {ff:.2} N/mm; mfree_iwf F_c = {fc_o:.2}, F_f = {ff_o:.2} N/mm");
    assert!(cols(&orig) != reference);
    assert!(fc_o > 0.5 * fc && fc_o < 2.0 * fc && ff_o > 0.0, "F_c = {fc_o}, F_f = {ff_o} N/mm");
    assert!((fc_o - fc).abs() > 1e-3 * fc || (ff_o - ff).abs() > 1e-3 * ff, "the forces did not change");
}

/// The kernel bug reaches the run only through W (XSPH and the artificial stress): without those stabilisers
/// `model = ["kernel_w6"]` is the default bit for bit, with them it is not (4 µs of the coarse cut).
#[test]
fn the_kernel_switch_acts_only_through_xsph_and_the_artificial_stress() {
    let short = ["time.end=4.0e-6", "output.every=1.0e-6"];
    let plain = ["stabilisation.xsph.enabled=false", "stabilisation.artificial_stress.enabled=false"];
    let with = |extra: &[&str]| {
        let mut s: Vec<&str> = short.to_vec();
        s.extend_from_slice(extra);
        forces(&coarse_cut(&s), &format!("w6-{}", extra.len())).0
    };
    let w6 = "model=[\"kernel_w6\"]";
    assert_eq!(with(&plain), with(&[plain[0], plain[1], w6]), "no XSPH, no AS: the switch must change nothing");
    assert_ne!(with(&[]), with(&[w6]), "with XSPH and AS the switch must act");
}

/// The measurement of docs/validation.md ("The original model"): the coarse cut's F_c and F_f under the default,
/// the original model and each switch alone. About 10 s a run on the CPU; `cargo test --release --test mfree_iwf
/// -- --ignored --nocapture` prints the table.
#[test]
#[ignore]
fn measure_each_switch_on_the_coarse_cut() {
    let mut rows = vec![("swarf (default)".to_string(), "model=\"swarf\"".to_string())];
    rows.push(("mfree_iwf (all)".into(), "model=\"mfree_iwf\"".into()));
    for s in Switch::ALL {
        rows.push((s.name().to_string(), format!("model=[\"{}\"]", s.name())));
    }
    rows.push(("c2d_return + c2d_norm".into(), "model=[\"c2d_return\",\"c2d_norm\"]".into()));
    let but_datum: Vec<String> =
        Switch::ALL.iter().filter(|s| **s != Switch::RowDatum).map(|s| format!("\"{}\"", s.name())).collect();
    rows.push(("all but row_datum".into(), format!("model=[{}]", but_datum.join(","))));
    let (_, fc0, ff0) = forces(&coarse_cut(&[]), "m-ref");
    println!("| model | F_c [N/mm] | F_f [N/mm] | ΔF_c | ΔF_f |\n|---|---|---|---|---|");
    for (name, set) in rows {
        let (_, fc, ff) = forces(&coarse_cut(&[set.as_str()]), &format!("m-{name}"));
        println!(
            "| {name} | {fc:.1} | {ff:.1} | {:+.1} % | {:+.1} % |",
            100.0 * (fc / fc0 - 1.0),
            100.0 * (ff / ff0 - 1.0)
        );
    }
}

/// The original's tool (`setup_ref_cut`: top-left corner, 0.413176 mm along the top, 0.431 mm down the back, rake
/// 10°, clearance 8°, r = 20 µm) measured from its edge's lowest point: 0.4771 mm to the back, 0.4979 mm to the
/// top (docs/original-code.md, "The thermal tool").
const C2D_TOOL: [&str; 2] = ["tool.length=4.771269497498491e-4", "tool.height=4.978592683264774e-4"];

/// `[tool.thermal] lattice = "nodes"` samples the tool as the original's `tool::sample_tool` does: on the reference
/// cut with the original's tool it gives the original's 1 970 tool particles (its run's 7 610 particles less the
/// 5 640 of the workpiece: docs/measurements/h100-issue22-speed.txt), and with `fixed_width` = Δx holds the
/// original's set, the samples within Δx/2 of the extreme column at the back and row at the top. The default cells
/// keep the 1 429 of the scene's own tool.
#[test]
fn the_original_tool_sampling_gives_its_1970_particles_and_held_layer() {
    let tool = |sets: &[&str]| {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let scene = Scene::load("cases/cutting/reference-cut.toml", &sets).expect("scene");
        let s = swarf::run::setup::<f64, Dim2>(&scene).expect("setup");
        let p = &s.particles;
        (0..p.len())
            .filter(|&i| p.flags[i] & flags::THERMAL_ONLY != 0)
            .map(|i| ([p.pos[i].get(0), p.pos[i].get(1)], p.flags[i] & flags::FIXED_TEMPERATURE != 0))
            .collect::<Vec<_>>()
    };
    assert_eq!(tool(&[]).len(), 1429);
    let dx = 1.03448275862069e-5;
    let width = format!("tool.thermal.fixed_width={dx:e}");
    let nodes = tool(&[C2D_TOOL[0], C2D_TOOL[1], "tool.thermal.lattice=\"nodes\"", &width]);
    assert_eq!(nodes.len(), 1970);
    let min_x = nodes.iter().map(|(p, _)| p[0]).fold(f64::INFINITY, f64::min);
    let max_y = nodes.iter().map(|(p, _)| p[1]).fold(f64::NEG_INFINITY, f64::max);
    for (p, held) in &nodes {
        assert_eq!(*held, p[0] < min_x + dx / 2.0 || p[1] > max_y - dx / 2.0, "{p:?}");
    }
    let held = nodes.iter().filter(|(_, h)| *h).count();
    assert!(held > 40 && held < 120, "{held} held");
    let bad = ["tool.thermal.lattice=\"grid\"".to_string()];
    let e = Scene::load("cases/cutting/reference-cut.toml", &bad).expect_err("refused").to_string();
    assert!(e.contains("tool.thermal.lattice") && e.contains("expected \"nodes\" or \"cells\""), "{e}");
}
