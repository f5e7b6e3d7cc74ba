//! Hard case: thermal runaway (issue 8; klippel-constitutive.md §8 H14). Adiabatic shear heats a Ti6Al4V block
//! towards its melt temperature; the temperature must stay at or below T_m, the flow stress non-negative and the
//! stress finite (a non-finite value stops a run with an error) — cases/hard/adiabatic-shear.toml.

use swarf::backend::{AnyBackend, BackendChoice};
use swarf::run::{RunOptions, Snapshot, run_observed};
use swarf::scene::Scene;

#[test]
fn adiabatic_shear_stays_below_melt_with_non_negative_flow_stress() {
    let scene = Scene::load("cases/hard/adiabatic-shear.toml", &[]).expect("scene");
    let lib = scene.material.library.clone().expect("library material");
    let melt = lib.thermal.and_then(|t| t.melt_temperature).expect("melt temperature");
    let opts = RunOptions::quiet(std::env::temp_dir().join(format!("swarf-test-shear-{}", std::process::id())));
    let (mut t_max, mut eps_max, mut sy_min) = (0.0f64, 0.0f64, f64::INFINITY);
    let mut obs = |s: &Snapshot| {
        let t = s.temperature.expect("temperature");
        let e = s.plastic_strain.expect("plastic strain");
        for (i, (&ti, &ei)) in t.iter().zip(e).enumerate() {
            assert!(ti <= melt, "particle {} at {ti} K above T_m = {melt} K (H14)", s.id[i]);
            // The rate term at its floor (ε̇* clamped to 1): the smallest flow stress the particle can have.
            let sy = lib.sigma_y(ei, 0.0, ti);
            assert!(sy >= 0.0 && sy.is_finite(), "particle {}: σ_y = {sy} Pa at T = {ti} K, ε̄ = {ei}", s.id[i]);
            sy_min = sy_min.min(sy);
        }
        t_max = t_max.max(t.iter().copied().fold(0.0, f64::max));
        eps_max = eps_max.max(e.iter().copied().fold(0.0, f64::max));
        true
    };
    let any = AnyBackend::select(BackendChoice::Cpu).expect("cpu").0;
    run_observed(&any, &scene, &opts, Some(&mut obs)).expect("the shear runs to its end without a non-finite value");
    eprintln!(
        "adiabatic shear: T_max = {t_max:.1} K (T_m = {melt} K), ε̄_max = {eps_max:.2}, min σ_y = {sy_min:.3e} Pa"
    );
    // The case must provoke what it is about: the band gets within 10 % of the melt temperature.
    assert!(t_max >= 0.9 * melt, "the shear band only reached {t_max} K");
}
