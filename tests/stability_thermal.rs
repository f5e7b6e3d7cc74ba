//! Hard cases of issue 8 with plasticity and heat: thermal runaway (below) and the 1000 m/s impact (at the end).
//! Thermal runaway (klippel-constitutive.md §8 H14). Adiabatic shear heats a Ti6Al4V block
//! towards its melt temperature; the temperature must stay at or below T_m, the flow stress non-negative and the
//! stress finite (a non-finite value stops a run with an error) — cases/hard/adiabatic-shear.toml.

use crate::common;
use crate::on_test_backend;

use swarf::run::{RunOptions, Snapshot, run_observed};
use swarf::scene::Scene;

#[test]
fn adiabatic_shear_stays_below_melt_with_non_negative_flow_stress() {
    let (_, t_max, melt) = adiabatic_shear(&[]);
    // The case must provoke what it is about: the band gets within 10 % of the melt temperature.
    assert!(t_max >= 0.9 * melt, "the shear band only reached {t_max} K");
}

/// The same shear with ductile damage (issue 25: damage and its mask add no non-finite value to the hard cases):
/// Klippel's Ti6Al4V JC fracture set and G_f (cases/materials/Ti6Al4V-Klippel-JC.toml, Tab. 8.10) and the mask.
/// The same criteria but the band's temperature: damage must initiate in the band (a volume with ω ≥ 1 at the end),
/// or the case provokes nothing. (Full damage does not follow: with G_f = 44.5 kJ/m² the softening needs far more
/// strain than the band gets.) The band heats less than without damage, since a damaged particle heats with the
/// stress it acts with, η e^{−D} σ_y Δε̄ (docs/damage.md): measured T_max 1 526 K (CPU and H200), against 1 780 K
/// when the heating used the undamaged σ_y, and above 0.9 T_m without damage.
#[test]
fn adiabatic_shear_with_damage_stays_below_melt_and_finite() {
    let damage = "damage={ model = \"jc\", D1 = -0.09, D2 = 0.27, D3 = 0.48, D4 = 0.014, D5 = 3.87, \
                  reference_temperature = 273.0, melt_temperature = 1878.0, fracture_energy = 44501.7, mask = true }";
    let (initiated, _, _) = adiabatic_shear(&[damage.into()]);
    assert!(initiated > 0.0, "damage did not initiate in the band");
}

/// Runs cases/hard/adiabatic-shear.toml with `sets`, checks H14's criteria at every output, and returns the volume
/// where damage initiated (ω ≥ 1) at the end (NaN without damage), the largest temperature and T_m.
fn adiabatic_shear(sets: &[String]) -> (f64, f64, f64) {
    let scene = Scene::load("cases/hard/adiabatic-shear.toml", sets).expect("scene");
    let lib = scene.material.library.clone().expect("library material");
    let melt = lib.thermal.and_then(|t| t.melt_temperature).expect("melt temperature");
    let tag = if sets.is_empty() { "plain" } else { "damage" };
    let opts = RunOptions::quiet(std::env::temp_dir().join(format!("swarf-test-shear-{tag}-{}", std::process::id())));
    let (mut t_max, mut eps_max, mut sy_min, mut initiated) = (0.0f64, 0.0f64, f64::INFINITY, f64::NAN);
    let mut obs = |s: &Snapshot| {
        initiated = s.diagnostics.initiated_volume;
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
    let any = common::test_backend();
    run_observed(&any, &scene, &opts, Some(&mut obs)).expect("the shear runs to its end without a non-finite value");
    eprintln!(
        "adiabatic shear {sets:?}: T_max = {t_max:.1} K (T_m = {melt} K), ε̄_max = {eps_max:.2}, min σ_y = \
         {sy_min:.3e} Pa, initiated volume {initiated:.3e}"
    );
    (initiated, t_max, melt)
}

/// Hard case: high-velocity impact (issue 8), cases/hard/impact-1000.toml at Δx = 2 mm (2197 particles) for CI:
/// the AISI 4340 disk into the wall at 1000 m/s. No non-finite value (the run would stop with an error), every
/// density positive and above half the reference density (no collapse: SPH particles overrunning each other),
/// ε̄ ≥ 0, T ≤ T_m, and kinetic + elastic energy never above its initial value × (1 + 1e-3).
#[test]
fn impact_at_1000_m_per_s_stays_physical() {
    impact(&[]);
}

/// The same impact with ductile damage (issue 25: damage adds no non-finite value to the hard cases): Johnson–Cook
/// fracture of AISI 4340 (Johnson and Cook 1985: D1 0.05, D2 3.44, D3 −2.12, D4 0.002, D5 0.61; no G_f, so damage
/// is full at initiation), without the interaction mask. Criteria: no non-finite value (the run would stop), T ≤ T_m,
/// ε̄ ≥ 0, kinetic + elastic energy never above its start × (1 + 1e-3), the elastic energy that of the degraded stress
/// the particles act with, in the damaged moduli (energy.csv's; the stored stress of a damaged particle pulled apart
/// grows without acting, and counted it gave 3.9 E0); the energy balance (kinetic + elastic + plastic work + viscous
/// dissipation + the elastic energy the degradation released) never above its start × (1 + 1e-2): a damaged
/// particle's plastic work is booked with the stress it acts with, e^{−D} σ_y Δε̄ (docs/damage.md; with the
/// undamaged σ_y it ended 10 % above); the case damages (a fully damaged volume > 0) and its degradation releases
/// energy (> 0, finite). No density bound: a fully damaged particle in tension may expand. Measured (f64, CPU):
/// printed by the test; the balance ends near the undamaged impact's 0.930 (docs/damage.md, "Energy").
#[test]
fn impact_at_1000_m_per_s_with_damage_stays_physical() {
    damaged_impact("");
}

/// [`impact_at_1000_m_per_s_with_damage_stays_physical`] with the interaction mask in its Galilean-invariant form
/// (`mask_form = "invariant"`, docs/damage.md): the same criteria. Klippel's printed form (the default) sees a
/// masked neighbour at rest in the lab frame, a 1000 m/s jump across a spacing here, and gained energy (kinetic
/// 3.3 E0, v_max 4 557 m/s; docs/stability.md).
#[test]
fn impact_at_1000_m_per_s_with_the_invariant_mask_stays_physical() {
    damaged_impact(", mask = true, mask_form = \"invariant\"");
}

fn damaged_impact(extra: &str) {
    let damage = format!("damage={{ model = \"jc\", D1 = 0.05, D2 = 3.44, D3 = -2.12, D4 = 0.002, D5 = 0.61{extra} }}");
    let sets: Vec<String> = vec!["discretisation.dx=2e-3".into(), damage];
    let scene = Scene::load("cases/hard/impact-1000.toml", &sets).expect("scene");
    let lib = scene.material.library.clone().expect("library material");
    let melt = lib.thermal.and_then(|t| t.melt_temperature).expect("melt temperature");
    let tag = if extra.is_empty() { "" } else { "-mask" };
    let dir = std::env::temp_dir().join(format!("swarf-test-impact-dmg{tag}-{}", std::process::id()));
    let opts = RunOptions::quiet(dir.clone());
    let (mut e0, mut b0, mut e_max, mut b_max, mut b_end, mut damaged) = (None, None, 0.0f64, 0.0f64, 0.0, 0.0);
    let mut released = f64::NAN;
    let mut obs = |s: &Snapshot| {
        let d = s.diagnostics;
        let e0 = *e0.get_or_insert(d.kinetic + d.elastic);
        let b0 = *b0.get_or_insert(d.balance());
        e_max = e_max.max((d.kinetic + d.elastic) / e0);
        b_end = d.balance() / b0;
        b_max = b_max.max(b_end);
        damaged = d.damaged_volume;
        released = d.damage_dissipation;
        let (t, e) = (s.temperature.expect("temperature"), s.plastic_strain.expect("plastic strain"));
        assert!(t.iter().all(|&x| x.is_finite() && x <= melt), "temperature above T_m at t = {}", d.time);
        assert!(e.iter().all(|&x| x >= 0.0), "negative plastic strain at t = {}", d.time);
        true
    };
    run_observed(&common::test_backend(), &scene, &opts, Some(&mut obs)).expect("the damaged impact runs to its end");
    eprintln!(
        "impact 1000 m/s with damage{extra}: max (kinetic + elastic)/E0 = {e_max:.6}, balance max {b_max:.6}, \
         end {b_end:.6}, damaged volume {damaged:.3e} m², released by the degradation {released:.4e} J/m ({:.4} E0)",
        released / e0.unwrap_or(f64::NAN)
    );
    assert!(e_max <= 1.0 + 1e-3, "kinetic + elastic energy rose to {e_max} of its initial value");
    assert!(b_max <= 1.0 + 1e-2, "the energy balance rose to {b_max} of its initial value");
    assert!(damaged > 0.0, "the impact damaged nothing");
    assert!(released.is_finite() && released > 0.0, "the degradation released {released} J/m");
    let _ = std::fs::remove_dir_all(&dir);
}

fn impact(sets: &[String]) {
    let sets: Vec<String> = std::iter::once("discretisation.dx=2e-3".to_string()).chain(sets.iter().cloned()).collect();
    let scene = Scene::load("cases/hard/impact-1000.toml", &sets).expect("scene");
    let lib = scene.material.library.clone().expect("library material");
    let melt = lib.thermal.and_then(|t| t.melt_temperature).expect("melt temperature");
    let rho0 = scene.material.density;
    let set = swarf::run::setup::<f64, swarf::kernels::Dim2>(&scene).expect("setup");
    // Densities are not in the snapshot: the run is observed through its state by a solver of our own.
    on_test_backend!(impact_on(&scene, &set, melt, rho0))
}

fn impact_on<B: swarf::backend::Backend>(
    b: &B,
    scene: &Scene,
    set: &swarf::solver::Setup<f64, swarf::kernels::Dim2>,
    melt: f64,
    rho0: f64,
) {
    let mut solver = swarf::solver::Solver::<_, f64, swarf::kernels::Dim2>::new(b, set).expect("solver");
    let mut e0 = None;
    let (mut rho_min, mut t_max, mut e_max) = (f64::INFINITY, 0.0f64, 0.0f64);
    let steps = (scene.time.end / set.dt).ceil() as u64;
    for k in 0..=steps {
        if k % 50 == 0 || k == steps {
            let h = solver.download(b).expect("download");
            let (temp, eps, _) = solver.download_internal(b).expect("internal");
            let d = swarf::solver::diagnostics::compute(&h, &solver.host_params, solver.time, solver.steps, None, None);
            assert!(d.non_finite.is_none(), "non-finite {:?} at step {k}", d.non_finite);
            let e0 = *e0.get_or_insert(d.total());
            e_max = e_max.max(d.total() / e0);
            rho_min = rho_min.min(h.rho.iter().copied().fold(f64::INFINITY, f64::min));
            let (t, e) = (temp.expect("temperature"), eps.expect("plastic strain"));
            assert!(e.iter().all(|&x| x >= 0.0), "negative plastic strain at step {k}");
            assert!(t.iter().all(|&x| x.is_finite() && x <= melt), "temperature above T_m at step {k}");
            t_max = t_max.max(t.iter().copied().fold(0.0, f64::max));
        }
        if k < steps {
            solver.step(b, set.dt).expect("step");
        }
    }
    eprintln!(
        "impact 1000 m/s: {steps} steps, min ρ/ρ0 = {:.3}, T_max = {t_max:.0} K, max E/E0 = {e_max:.6}",
        rho_min / rho0
    );
    assert!(rho_min > 0.5 * rho0, "density collapsed to {rho_min} kg/m³");
    assert!(e_max <= 1.0 + 1e-3, "kinetic + elastic energy rose to {e_max} of its initial value");
}
