//! Plastic impact (roethlin-solver.md §7.5, AT-80/AT-81): the AISI 4340 disk into the AISI 4340 wall at 500 m/s,
//! Johnson–Cook plasticity with adiabatic heating, coarse (Δx = 2 mm, 2197 particles) for CI.

use swarf::backend::{AnyBackend, BackendChoice};
use swarf::run::{RunOptions, Snapshot, run_observed};
use swarf::scene::Scene;

#[test]
fn plastic_impact_is_finite_and_heats_only_plastic_particles() {
    let scene = Scene::load("cases/impact.toml", &["discretisation.dx=2e-3".into()]).expect("scene");
    let t0 = scene.physics.initial_temperature;
    let opts = RunOptions::quiet(std::env::temp_dir().join(format!("swarf-test-impact-{}", std::process::id())));
    let mut first_total = None;
    let mut eps_max = 0.0f64;
    let mut t_max = 0.0f64;
    let mut v_end = 0.0;
    let mut obs = |s: &Snapshot| {
        let d = s.diagnostics;
        let e0 = *first_total.get_or_insert(d.total());
        let eps = s.plastic_strain.expect("plastic strain is modelled");
        let temp = s.temperature.expect("temperature is modelled");
        for (i, (&e, &t)) in eps.iter().zip(temp).enumerate() {
            assert!(e >= 0.0, "negative plastic strain {e} at particle {} (AT-81)", s.id[i]);
            // Heating only where the particle deformed plastically (AT-81).
            assert!(t <= t0 || e > 0.0, "particle {} heated to {t} K without plastic strain", s.id[i]);
            assert!(t >= t0, "particle {} cooled to {t} K with no conduction", s.id[i]);
        }
        eps_max = eps_max.max(eps.iter().copied().fold(0.0, f64::max));
        t_max = t_max.max(temp.iter().copied().fold(0.0, f64::max));
        assert!(d.total() <= 1.001 * e0, "kinetic + elastic energy rose to {} of its initial value", d.total() / e0);
        let proj: Vec<usize> = (0..s.body.len()).filter(|&i| s.body[i] == 0).collect();
        v_end = proj.iter().map(|&i| s.vel[i][0]).sum::<f64>() / proj.len() as f64;
        true
    };
    // A non-finite value anywhere would stop the run with an error (AT-81: no blanked particle).
    let any = AnyBackend::select(BackendChoice::Cpu).expect("cpu").0;
    let r = run_observed(&any, &scene, &opts, Some(&mut obs)).expect("the impact runs to its end");
    assert_eq!(r.particles, 2197);
    assert!(eps_max > 0.3, "the impact must deform plastically (max ε̄ = {eps_max})");
    assert!(t_max > t0 + 50.0, "plastic work must heat the contact zone (max T = {t_max} K)");
    assert!(v_end < 250.0, "the projectile must be slowed by the wall (mean v_x = {v_end} m/s)");
}

/// A fixed time step above the stability limit is refused before the run, naming the file, the key and the limit.
#[test]
fn fixed_dt_above_the_stability_limit_is_refused() {
    let scene = Scene::load("cases/impact.toml", &["time.dt=1e-6".into()]).expect("scene");
    let err = match swarf::run::setup::<f64, swarf::kernels::Dim2>(&scene) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("a dt of 1e-6 s must be refused (the limit is about 1e-7 s)"),
    };
    assert!(err.contains("cases/impact.toml") && err.contains("time.dt") && err.contains("stability limit"), "{err}");
}
