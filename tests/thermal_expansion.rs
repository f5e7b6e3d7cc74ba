//! Thermal expansion in the EOS (klippel-constitutive.md §1.1 [NOTE]: ρ0(T) = ρ0/(1 + 3α (T − T0))).

use swarf::backend::{AnyBackend, BackendChoice};
use swarf::run::{RunOptions, Snapshot, run_observed};
use swarf::scene::Scene;

const SCENE: &str = r#"
name = "expansion"
dim = 3
[discretisation]
dx = 1.0e-3
[material]
density = 7830.0
youngs_modulus = 200e9
poisson_ratio = 0.29
[physics]
initial_temperature = 800.0
thermal_expansion = 1.0e-5
[[body]]
shape = "box"
min = [0.0, 0.0, 0.0]
max = [0.012, 0.012, 0.012]
[stabilisation]
artificial_viscosity = { alpha = 1.0, beta = 1.0, eta = 0.1 }
[time]
end = 1.0e-4
[output]
every = 1.0e-5
"#;

/// Returns the final kinetic energy and the x extent of the interior particles (at least 3Δx from every face at
/// t = 0): the free surface itself over-expands because the uncorrected SPH divergence is too small there
/// (roethlin-solver.md AT-05), so the interior is what the EOS governs.
fn run(overrides: &[String]) -> (f64, f64) {
    let scene = Scene::from_str(SCENE, "expansion (test)", overrides).expect("scene");
    let opts = RunOptions::quiet(std::env::temp_dir().join(format!("swarf-test-expansion-{}", std::process::id())));
    let mut last = (0.0, 0.0);
    let mut interior: Option<Vec<u32>> = None;
    let mut obs = |s: &Snapshot| {
        let ids = interior.get_or_insert_with(|| {
            let inside = |x: f64| (0.0025..=0.0095).contains(&x);
            (0..s.pos.len()).filter(|&i| s.pos[i].iter().all(|&x| inside(x))).map(|i| s.id[i]).collect()
        });
        let (lo, hi) = (0..s.pos.len())
            .filter(|&i| ids.contains(&s.id[i]))
            .fold((f64::MAX, f64::MIN), |(a, b), i| (a.min(s.pos[i][0]), b.max(s.pos[i][0])));
        last = (s.diagnostics.kinetic, hi - lo);
        true
    };
    let any = AnyBackend::select(BackendChoice::Cpu).expect("cpu").0;
    let _ = run_observed(&any, &scene, &opts, Some(&mut obs)).expect("run");
    last
}

/// Material point: the heated material is stress-free at ρ0(T) and, confined at ρ0, carries the thermal
/// pressure 3KαΔT (compression positive) to first order in 3αΔT; at T = T0 the EOS is unchanged.
#[test]
fn eos_with_expansion_at_a_material_point() {
    use swarf::kernels::sph::interact::{pressure, pressure_at};
    let m = swarf::solver::params::Elastic { density: 7830.0, youngs_modulus: 200e9, poisson_ratio: 0.29 };
    let mut p = swarf::solver::params::sph_params::<f64>(&m, 1e-3, 1.7e-3, 3, &Default::default());
    let (alpha, t0, dt) = (1e-5, 300.0, 500.0);
    p.expansion = 3.0 * alpha;
    p.expansion_t0 = t0;
    let rho_t = 7830.0 / (1.0 + 3.0 * alpha * dt);
    assert!(pressure_at(&p, rho_t, t0 + dt).abs() < 1e-6, "ρ0(T) must be stress-free");
    let confined = pressure_at(&p, 7830.0, t0 + dt);
    let linear = 3.0 * m.bulk_modulus() * alpha * dt;
    assert!(
        (confined / linear - 1.0).abs() < 2.0 * 3.0 * alpha * dt,
        "confined: {confined:e} Pa vs 3KαΔT = {linear:e}"
    );
    assert_eq!(pressure_at(&p, 7900.0, t0), pressure(&p, 7900.0), "no change at the reference temperature");
}

/// A free steel cube (3D, 12³ particles) 500 K above the reference temperature, α = 1e-5 /K, settles under
/// artificial viscosity (kinetic energy down by 10⁵) with its interior grown. The stress-free growth is
/// (1.015)^(1/3) − 1 = 0.50 %; the measured interior growth is larger (0.90 % at this size) because the
/// uncorrected SPH divergence is too small at the free surface (AT-05), which leaves the surface layer
/// compressed and the interior stretched. The test bounds it within [1×, 2×] of the stress-free value so that a
/// sign or factor error in the EOS fails; docs/validation.md records the measured value.
#[test]
fn heated_free_cube_expands_and_settles() {
    let (k_cold, cold) = run(&["physics.thermal_expansion=0.0".into()]);
    let (k_hot, hot) = run(&[]);
    assert_eq!(k_cold, 0.0, "without expansion the cube must not move");
    let growth = hot / cold - 1.0;
    let expect = 1.015f64.cbrt() - 1.0;
    eprintln!("interior growth {growth:e}, stress-free {expect:e}, final kinetic energy {k_hot:e} J");
    assert!(growth > expect && growth < 2.0 * expect, "interior grew by {growth:e}, stress-free {expect:e}");
    assert!(k_hot < 1e-4, "the cube must settle (kinetic energy {k_hot:e} J)");
}
