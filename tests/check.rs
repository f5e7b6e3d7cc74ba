//! `swarf check` on every scene in cases/, cases/cutting/ and cases/hard/ (issues 5, 6, 8): each validates, and the report's derived quantities are
//! consistent with the scene (steps = ⌈end/Δt⌉, Δt within the CFL limit, memory at least the particle state).

use swarf::backend::{AnyBackend, BackendChoice};
use swarf::scene::Scene;

#[test]
fn every_case_checks() {
    let any = AnyBackend::select(BackendChoice::Cpu).expect("cpu").0;
    let mut n = 0;
    let dirs = ["cases", "cases/cutting", "cases/hard", "cases/damage"];
    let paths = dirs.iter().flat_map(|d| std::fs::read_dir(d).unwrap_or_else(|e| panic!("{d}: {e}")));
    for entry in paths {
        let path = entry.expect("entry").path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let scene = Scene::load(&path, &[]).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let r = swarf::check::check(&any, &scene, None, 1).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let cfl = scene.time.cfl * r.h / r.c0;
        assert!(r.dt <= cfl * (1.0 + 1e-12), "{}: dt {} above the CFL limit {cfl}", path.display(), r.dt);
        assert_eq!(r.steps, (scene.time.end / r.dt).ceil() as u64, "{}", path.display());
        assert!(r.memory_bytes > r.particles * 100, "{}: memory estimate {} too small", path.display(), r.memory_bytes);
        assert!(r.seconds_per_step > 0.0 && r.expected_run_time().is_finite());
        n += 1;
    }
    assert!(n >= 18, "expected the scenes of cases/, cases/cutting/ and cases/hard/, found {n}");
}

/// The 3D cases (cases/3d: up to 372 400 particles and five mesh tools, whose one-step probe and engagement
/// checks take about 30 s each on CI's CPU) load: every key valid, every mesh read, checked and hashed, each
/// tool's table complete.
#[test]
fn every_3d_case_loads() {
    let mut n = 0;
    for entry in std::fs::read_dir("cases/3d").expect("cases/3d") {
        let path = entry.expect("entry").path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let scene = Scene::load(&path, &[]).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert_eq!(scene.dim, 3, "{}", path.display());
        assert!(scene.tools().count() >= 1, "{}: a 3D case has a tool", path.display());
        n += 1;
    }
    assert!(n >= 7, "expected the 3D cases, found {n}");
}

/// A scene larger than the GPU's memory is refused before anything is allocated, with the bytes it needs.
#[test]
fn a_scene_too_large_for_the_gpu_is_refused() {
    let scene = Scene::load("cases/rings.toml", &[]).expect("scene");
    let s = swarf::run::setup::<f64, swarf::kernels::Dim2>(&scene).expect("setup");
    let need = swarf::check::memory_estimate(&s);
    let small = swarf::backend::DeviceInfo { backend: "gpu", memory_bytes: need / 2, ..Default::default() };
    let msg = swarf::check::fits(need, &small).expect_err("must not fit").to_string();
    assert!(msg.contains(&need.to_string()) && msg.contains("out of memory"), "{msg}");
    let big = swarf::backend::DeviceInfo { backend: "gpu", memory_bytes: 2 * need, ..Default::default() };
    assert!(swarf::check::fits(need, &big).is_ok());
}
