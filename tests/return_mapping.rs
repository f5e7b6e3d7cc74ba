//! The radial return (roethlin-solver.md §2.4, §10.2 AT-27..AT-29; klippel-constitutive.md §2.2, §8 H5, §9.1
//! U4–U7): consistency, direction, trace, monotone plastic strain, untouched elastic states, Newton against
//! Secant B, the failure modes of H5 (huge trials, near-melt temperatures, zero or negative hardening, tiny and huge
//! Δt, wild initial guesses, zero-strength melt) and adiabatic heating.

use std::path::Path;

use swarf::material::{FlowModel, Library, Material};
use swarf::rng::SplitMix64;
use swarf_kernels::material::return_map::{SQRT_2_3, SQRT_3_2};
use swarf_kernels::material::{
    Bilinear, FlowStress, JohnsonCook, RATE_FORM_UINTAH, ReturnOptions, ReturnResult, ReturnStatus, deviatoric_norm,
    plastic_heating, radial_return, von_mises,
};

fn library() -> Library {
    Library::load_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/materials")).expect("material library")
}

/// A random deviatoric tensor (xx, xy, xz, yy, yz, zz) of von Mises stress `q`; plane strain (xz = yz = 0, zz
/// carried) when `plane`.
fn random_deviator(rng: &mut SplitMix64, q: f64, plane: bool) -> [f64; 6] {
    let mut s: [f64; 6] = std::array::from_fn(|_| rng.normal());
    if plane {
        s[2] = 0.0;
        s[4] = 0.0;
    }
    let mean = (s[0] + s[3] + s[5]) / 3.0;
    s[0] -= mean;
    s[3] -= mean;
    s[5] -= mean;
    let k = q / von_mises(&s);
    s.map(|c| c * k)
}

fn log_uniform(rng: &mut SplitMix64, lo: f64, hi: f64) -> f64 {
    (lo.ln() + rng.uniform() * (hi.ln() - lo.ln())).exp()
}

/// One random material-point state for `model` at temperatures in [t_lo, t_hi].
struct State {
    s: [f64; 6],
    eps: f64,
    rate: f64,
    temp: f64,
    dt: f64,
}

fn random_state(rng: &mut SplitMix64, m: &FlowModel, t_lo: f64, t_hi: f64, overstress: (f64, f64)) -> State {
    let eps = if rng.uniform() < 0.1 { 0.0 } else { 2.0 * rng.uniform() };
    let rate = if rng.uniform() < 0.3 { 0.0 } else { log_uniform(rng, 1e-2, 1e6) };
    let temp = t_lo + (t_hi - t_lo) * rng.uniform();
    let dt = log_uniform(rng, 1e-10, 1e-6);
    let q = (overstress.0 + (overstress.1 - overstress.0) * rng.uniform()) * m.sigma_y(eps, 0.0, temp);
    let plane = rng.uniform() < 0.4;
    State { s: random_deviator(rng, q, plane), eps, rate, temp, dt }
}

/// |√(3/2)‖S_new‖ − σ_y(ε̄_new, ε̄̇_new, T)| / σ_y(new).
fn consistency(m: &FlowModel, st: &State, r: &ReturnResult) -> f64 {
    let sy = m.sigma_y(r.eps, r.rate, st.temp);
    (von_mises(&r.stress) - sy).abs() / sy
}

/// sin of the angle between S_new and S_trial (in the ‖·‖ of the return).
fn misalignment(a: &[f64; 6], b: &[f64; 6]) -> f64 {
    let dot = a[0] * b[0] + a[3] * b[3] + a[5] * b[5] + 2.0 * (a[1] * b[1] + a[2] * b[2] + a[4] * b[4]);
    let k = dot / (deviatoric_norm(b) * deviatoric_norm(b));
    let r: [f64; 6] = std::array::from_fn(|i| a[i] - k * b[i]);
    deviatoric_norm(&r) / deviatoric_norm(a)
}

fn ti_tab_7_5() -> (Material, FlowModel, f64) {
    let m = library().get("Ti6Al4V-Roethlin").unwrap().clone();
    let model = m.flow_stress.unwrap();
    let g = m.shear_modulus().unwrap();
    (m, model, g)
}

/// AT-27 (roethlin §10.2): 10⁴ random trial states, Ti6Al4V Tab 7.5, T ∈ [300, 1500] K, 40 % plane strain, trial
/// von Mises 0.3–4 × σ_y (about a quarter elastic):
/// (a) |√(3/2)‖S_new‖ − σ_y(new)| ≤ 1e-10·σ_y: the relative stopping rule (1e-12 on Δλ, plus 64ε·Δλ_max) gives
///     ≈ 1e-12·(σ_eq,trial − σ_y)/σ_y + 64ε·σ_eq,trial/σ_y ≤ 1e-11 here; AT-27 asks for 1e-6;
/// (b) S_new ∥ S_trial: sin(angle) ≤ 1e-12; (c) |tr S_new| ≤ 1e-14‖S_trial‖ (rounding);
/// (d) Δε̄ ≥ 0 and Δλ ∈ [0, ‖S_trial‖/2G]; (e) elastic states unchanged bit for bit, ε̄̇ = 0.
#[test]
fn at27_random_trial_states() {
    let (_, m, g) = ti_tab_7_5();
    let mut rng = SplitMix64::new(27);
    let (mut elastic, mut worst_a, mut worst_b, mut iters) = (0, 0.0f64, 0.0f64, 0u64);
    for _ in 0..10_000 {
        let st = random_state(&mut rng, &m, 300.0, 1500.0, (0.3, 4.0));
        let r = m.radial_return(&st.s, st.eps, st.rate, st.temp, g, st.dt, &ReturnOptions::DEFAULT);
        if r.status == ReturnStatus::Elastic {
            elastic += 1;
            assert!(r.stress.iter().zip(&st.s).all(|(a, b)| a.to_bits() == b.to_bits()), "(e) stress changed");
            assert_eq!(r.eps.to_bits(), st.eps.to_bits(), "(e) strain changed");
            assert_eq!((r.rate, r.delta_lambda, r.iterations), (0.0, 0.0, 0));
            assert!(von_mises(&st.s) <= m.sigma_y(st.eps, 0.0, st.temp));
            continue;
        }
        assert_eq!(r.status, ReturnStatus::Converged, "capped at {:?}", (st.s, st.eps, st.rate, st.temp, st.dt));
        iters += r.iterations as u64;
        let a = consistency(&m, &st, &r);
        worst_a = worst_a.max(a);
        assert!(a <= 1e-10, "(a) consistency {a:e}");
        let b = misalignment(&r.stress, &st.s);
        worst_b = worst_b.max(b);
        assert!(b <= 1e-12, "(b) misalignment {b:e}");
        let tr = r.stress[0] + r.stress[3] + r.stress[5];
        assert!(tr.abs() <= 1e-14 * deviatoric_norm(&st.s), "(c) trace {tr:e}");
        assert!(r.eps >= st.eps && r.rate >= 0.0, "(d) Δε̄ = {}", r.eps - st.eps);
        assert!(r.delta_lambda >= 0.0 && r.delta_lambda <= deviatoric_norm(&st.s) / (2.0 * g));
        assert!((r.eps - st.eps - SQRT_2_3 * r.delta_lambda).abs() <= 1e-15 * r.eps.max(1.0));
    }
    let plastic = 10_000 - elastic;
    println!(
        "AT-27: {elastic} elastic, {plastic} plastic; worst consistency {worst_a:.2e}·σ_y, worst misalignment \
         {worst_b:.2e}; Newton {:.2} iterations on average",
        iters as f64 / plastic as f64
    );
    assert!(elastic > 1000 && plastic > 5000);
}

/// AT-28 (roethlin §10.2) and klippel §2.2: Newton and Secant B on the same 10⁴ states give the same Δλ within
/// 1e-8 relative (the solvers stop at 1e-12 relative, so they agree to ≈1e-11).
#[test]
fn at28_newton_against_secant_b() {
    let (_, m, g) = ti_tab_7_5();
    let mut rng = SplitMix64::new(28);
    let (mut worst, mut it_n, mut it_s, mut n) = (0.0f64, 0u64, 0u64, 0u64);
    for _ in 0..10_000 {
        let st = random_state(&mut rng, &m, 300.0, 1500.0, (1.0, 4.0));
        let a = m.radial_return(&st.s, st.eps, st.rate, st.temp, g, st.dt, &ReturnOptions::DEFAULT);
        let b = m.radial_return(&st.s, st.eps, st.rate, st.temp, g, st.dt, &ReturnOptions::SECANT_B);
        if a.status == ReturnStatus::Elastic {
            assert_eq!(b.status, ReturnStatus::Elastic);
            continue;
        }
        assert_eq!((a.status, b.status), (ReturnStatus::Converged, ReturnStatus::Converged));
        let d = (a.delta_lambda - b.delta_lambda).abs() / a.delta_lambda;
        worst = worst.max(d);
        assert!(d <= 1e-8, "Newton {} vs Secant B {}", a.delta_lambda, b.delta_lambda);
        assert!(consistency(&m, &st, &b) <= 1e-10);
        it_n += a.iterations as u64;
        it_s += b.iterations as u64;
        n += 1;
    }
    println!(
        "AT-28: {n} plastic states, worst relative Δλ difference {worst:.2e}; iterations Newton {:.2}, Secant B {:.2}",
        it_n as f64 / n as f64,
        it_s as f64 / n as f64
    );
}

/// klippel §9.1 U4/U5 and §8 H5's table: Steel 4340 (Tabs 7.2/7.3), T* = 0.2, G = 77.5 GPa, Δt = 1e-8 s,
/// ‖S_trial‖ ∈ [638, 1274] MPa (30 steps) × Δλ₀ ∈ [1e-15, 1e-3] (30 log steps, Klippel's Δλ = Δε̄): both solvers
/// converge from every initial guess, to residuals < 1e-9 relative, with Δλ identical to 1e-12 relative across
/// guesses and solvers; Newton needs no more iterations than Secant B on average.
#[test]
fn u4_u5_steel_4340_table() {
    let m = library().get("AISI4340-Klippel").unwrap().clone();
    let model = m.flow_stress.unwrap();
    let j = *model.johnson_cook().unwrap();
    let temp = j.ref_temp + 0.2 * (j.melt_temp - j.ref_temp);
    let (g, dt) = (77.5e9, 1e-8);
    let (mut it_n, mut it_s) = (0u64, 0u64);
    let mut max_iter = (0, 0);
    for i in 0..30 {
        let norm = 638e6 + (1274e6 - 638e6) * i as f64 / 29.0;
        let s = [norm / 2f64.sqrt(), 0.0, 0.0, -norm / 2f64.sqrt(), 0.0, 0.0];
        assert!((deviatoric_norm(&s) - norm).abs() < 1e-6);
        let mut first: Option<f64> = None;
        for k in 0..30 {
            let guess_klippel = 10f64.powf(-15.0 + 12.0 * k as f64 / 29.0);
            for opts in [ReturnOptions::DEFAULT, ReturnOptions::SECANT_B] {
                let opts = opts.with_initial_guess(SQRT_3_2 * guess_klippel);
                let r = model.radial_return(&s, 0.0, 0.0, temp, g, dt, &opts);
                assert_eq!(r.status, ReturnStatus::Converged, "‖S‖ = {norm:e}, Δλ₀ = {guess_klippel:e}, {opts:?}");
                let sy = model.sigma_y(r.eps, r.rate, temp);
                let res = (deviatoric_norm(&r.stress) - SQRT_2_3 * sy).abs() / (SQRT_2_3 * sy);
                assert!(res < 1e-9, "residual {res:e}");
                let first = *first.get_or_insert(r.delta_lambda);
                assert!((r.delta_lambda - first).abs() <= 1e-12 * first, "{} vs {first}", r.delta_lambda);
                if opts.solver == swarf_kernels::material::Solver::Newton {
                    it_n += r.iterations as u64;
                    max_iter.0 = max_iter.0.max(r.iterations);
                } else {
                    it_s += r.iterations as u64;
                    max_iter.1 = max_iter.1.max(r.iterations);
                }
            }
        }
    }
    println!(
        "U4/U5: mean iterations Newton {:.2} (max {}), Secant B {:.2} (max {}) over 900 (trial, Δλ₀) pairs",
        it_n as f64 / 900.0,
        max_iter.0,
        it_s as f64 / 900.0,
        max_iter.1
    );
    assert!(it_n <= it_s);
}

/// klippel §9.1 U6, Eq. 3.154: perfect plasticity (B = C = 0, T = T0) gives Δε̄ = (σ_eq,trial − σ_y)/(3G), i.e.
/// Δλ = (‖S_trial‖ − √(2/3)σ_y)/(2G), to 1e-12 relative, with both solvers.
#[test]
fn u6_perfect_plasticity_closed_form() {
    let jc = JohnsonCook {
        a: 500e6,
        b: 0.0,
        c: 0.0,
        n: 0.5,
        m: 1.0,
        ref_rate: 1.0,
        ref_temp: 300.0,
        melt_temp: 1800.0,
        rate_form: 0,
        _pad: 0,
    };
    let g = 40e9;
    let mut rng = SplitMix64::new(6);
    for _ in 0..1000 {
        let q = 500e6 * (1.0 + 10.0 * rng.uniform());
        let plane = rng.uniform() < 0.5;
        let s = random_deviator(&mut rng, q, plane);
        for opts in [ReturnOptions::DEFAULT, ReturnOptions::SECANT_B] {
            let r = radial_return(&jc, &s, 0.3, 0.0, 300.0, g, 1e-8, &opts);
            let expected = (q - 500e6) / (3.0 * g);
            let d_eps = SQRT_2_3 * r.delta_lambda; // r.eps − 0.3 would lose digits to cancellation
            assert!((d_eps - expected).abs() <= 1e-12 * expected, "Δε̄ {d_eps} vs {expected}");
            let dl = (deviatoric_norm(&s) - SQRT_2_3 * 500e6) / (2.0 * g);
            assert!((r.delta_lambda - dl).abs() <= 1e-12 * dl);
        }
    }
}

/// klippel §9.1 U7 and §2.2: an overstress of 1e-7 relative with Δt = 1e-10 s gives a small positive, finite Δλ
/// in f64, consistent with the yield surface.
#[test]
fn u7_tiny_overstress() {
    let (_, m, g) = ti_tab_7_5();
    let mut rng = SplitMix64::new(7);
    for _ in 0..200 {
        let (eps, temp) = (rng.uniform(), 300.0 + 1000.0 * rng.uniform());
        let s = random_deviator(&mut rng, (1.0 + 1e-7) * m.sigma_y(eps, 0.0, temp), false);
        for opts in [ReturnOptions::DEFAULT, ReturnOptions::SECANT_B] {
            let r = m.radial_return(&s, eps, 0.0, temp, g, 1e-10, &opts);
            assert_eq!(r.status, ReturnStatus::Converged);
            assert!(r.delta_lambda > 0.0 && r.delta_lambda.is_finite(), "Δλ = {}", r.delta_lambda);
            let st = State { s, eps, rate: 0.0, temp, dt: 1e-10 };
            assert!(consistency(&m, &st, &r) <= 1e-10);
        }
    }
}

/// klippel §8 H5 (and roethlin §9 F22): every flow-stress set of the library, with its own elastic data, on
/// hostile states: trials up to 1e6 × σ_y, temperatures up to and beyond the melt, Δt from 1e-20 s to 1e3 s, the
/// previous rate up to 1e12 /s (an initial guess far outside [0, Δλ_max]), ε̄ = 0 with n < 1. Both solvers give
/// finite results with Δλ ∈ [0, Δλ_max], never hit the cap, and satisfy the consistency condition to 1e-9·σ_eq,trial,
/// or, where g is too steep for that (Δt = 1e-20 s makes ε̄̇ = Δε̄/Δt astronomically sensitive) or has no root (the
/// Uintah rate form's jump at ε̄̇0), g changes sign within the Δλ tolerance of the result.
#[test]
fn h5_hostile_states_all_models() {
    let lib = library();
    let mut rng = SplitMix64::new(5);
    let (mut models, mut steep, mut uintah, mut total) = (0, 0, 0, 0);
    for mat in lib.iter() {
        let Some(m) = mat.flow_stress else { continue };
        models += 1;
        // The stand-alone flow-curve sets have no elastic data: Ti6Al4V's G (Tab 7.5) stands in.
        let g = mat.shear_modulus().unwrap_or(110e9 / 2.7);
        let tm = m.melt_temperature().min(3000.0);
        for k in 0..400 {
            let eps = [0.0, 1e-9, 0.1, 1.0, 5.0][k % 5];
            let temp = [300.0, 0.5 * tm, tm - 2.0, tm - 0.5, tm, tm + 500.0][k % 6];
            let dt = [1e-20, 1e-12, 1e-8, 1e-6, 1e-3, 1e3][(k / 6) % 6];
            let rate = [0.0, 1e-3, 1e4, 1e12][(k / 36) % 4];
            let sy = m.sigma_y(eps, 0.0, temp).max(1e6);
            let q = sy * log_uniform(&mut rng, 1.0 + 1e-9, 1e6);
            let s = random_deviator(&mut rng, q, k % 2 == 0);
            let lam_max = deviatoric_norm(&s) / (2.0 * g);
            for opts in [ReturnOptions::DEFAULT, ReturnOptions::SECANT_B] {
                total += 1;
                let r = m.radial_return(&s, eps, rate, temp, g, dt, &opts);
                let what = format!("{}: ε̄ {eps}, T {temp}, Δt {dt}, ε̄̇ {rate}, q {q:e}, {:?}", mat.name, opts.solver);
                assert!(r.stress.iter().all(|c| c.is_finite()) && r.eps.is_finite() && r.rate.is_finite(), "{what}");
                assert!(r.delta_lambda >= 0.0 && r.delta_lambda <= lam_max, "{what}: Δλ {}", r.delta_lambda);
                assert_ne!(r.status, ReturnStatus::Capped, "{what}");
                if r.status == ReturnStatus::Elastic {
                    continue;
                }
                let sy_new = m.sigma_y(r.eps, r.rate, temp);
                let res = (von_mises(&r.stress) - sy_new).abs();
                // Where g is too steep (ε̄̇ = Δε̄/Δt with Δt = 1e-20 s) or jumps (the Uintah form at ε̄̇0) the residual
                // says little; then g must change sign within the Δλ tolerance of the result.
                let norm = deviatoric_norm(&s);
                let g_of =
                    |dl: f64| norm - 2.0 * g * dl - SQRT_2_3 * m.sigma_y(eps + SQRT_2_3 * dl, SQRT_2_3 * dl / dt, temp);
                let tol = 1e-12 * r.delta_lambda + 128.0 * f64::EPSILON * lam_max;
                let brackets = g_of((r.delta_lambda - tol).max(0.0)) >= 0.0 && g_of(r.delta_lambda + tol) <= 0.0;
                if res > 1e-9 * q {
                    assert!(brackets, "{what}: residual {res:e} of σ_y {sy_new:e} and no root within {tol:e}");
                    steep += 1;
                    if m.johnson_cook().is_some_and(|j| j.rate_form == RATE_FORM_UINTAH) {
                        uintah += 1;
                    }
                }
            }
        }
    }
    println!(
        "H5: {models} models, {total} returns; {steep} with residual > 1e-9·σ_eq,trial but a root within the Δλ \
         tolerance ({uintah} of them Uintah-form materials)"
    );
    assert!(models >= 35, "{models} models");
}

/// H5, zero hardening and the zero-strength bound: σ_y ≡ 0 (bilinear with σ_y0 = H = 0, and SCGL above its melt)
/// returns Δλ = ‖S_trial‖/(2G) exactly enough that S_new ≈ 0; zero hardening (H = 0) is the closed form.
#[test]
fn h5_zero_strength_and_zero_hardening() {
    let g = 40e9;
    let mut rng = SplitMix64::new(55);
    let s = random_deviator(&mut rng, 1e9, false);
    let none = Bilinear { yield_stress: 0.0, plastic_modulus: 0.0, melt_temp: f64::INFINITY };
    for opts in [ReturnOptions::DEFAULT, ReturnOptions::SECANT_B] {
        let r = radial_return(&none, &s, 0.0, 0.0, 300.0, g, 1e-8, &opts);
        assert_eq!(r.status, ReturnStatus::Converged);
        assert!(deviatoric_norm(&r.stress) <= 1e-12 * deviatoric_norm(&s), "{:?}", r.stress);
    }
    let scgl = library().get("OFHC-Cu-SCGL").unwrap().flow_stress.unwrap();
    let r = scgl.radial_return(&s, 0.1, 0.0, 1400.0, g, 1e-8, &ReturnOptions::DEFAULT);
    assert!(deviatoric_norm(&r.stress) <= 1e-12 * deviatoric_norm(&s));
    let flat = Bilinear { yield_stress: 300e6, plastic_modulus: 0.0, melt_temp: f64::INFINITY };
    let r = radial_return(&flat, &s, 0.2, 0.0, 300.0, g, 1e-8, &ReturnOptions::DEFAULT);
    assert!((von_mises(&r.stress) - 300e6).abs() <= 1e-6, "{}", von_mises(&r.stress));
    assert!(r.iterations <= 3, "{} iterations for a linear g", r.iterations);
}

/// AT-29 (roethlin §10.2): a material point in simple shear driven to ε̄ = 1 with the return map in steps of
/// Δε̄ ≈ 1e-3, heated by ΔT = t_q σ_y(new) Δε̄/(ρ c_p) after each return (roethlin §2.5), JC Tab 7.5 with C = 0
/// and Tm huge (no softening): ΔT = t_q (A + B/(n+1))/(ρ c_p) = 400.9 K within 0.5 %.
#[test]
fn at29_adiabatic_plastic_heating() {
    let (mat, m, g) = ti_tab_7_5();
    let FlowModel::JohnsonCook(mut jc) = m else { panic!() };
    jc.c = 0.0;
    jc.melt_temp = 1e15;
    let (rho, cp, tq) = (4430.0, 562.0, 0.9);
    assert_eq!(mat.density(), Some(rho));
    let expected = tq * (jc.a + jc.b / (jc.n + 1.0)) / (rho * cp);
    assert!((expected - 400.9).abs() < 0.05, "digest arithmetic: {expected}");
    let dt = 1e-6;
    let dgamma = 3f64.sqrt() * 1e-3; // engineering shear strain per step: Δε̄ = Δγ_p/√3
    let (mut s, mut eps, mut rate, mut temp) = ([0.0; 6], 0.0, 0.0, 300.0);
    let (mut prev_eps, mut prev_temp) = (0.0, 300.0);
    let mut steps = 0;
    while eps < 1.0 {
        s[1] += g * dgamma; // 2G·Δe_xy with Δe_xy = Δγ/2
        let r = radial_return(&jc, &s, eps, rate, temp, g, dt, &ReturnOptions::DEFAULT);
        assert_ne!(r.status, ReturnStatus::Capped);
        let d_eps = r.eps - eps;
        prev_eps = eps;
        prev_temp = temp;
        temp += plastic_heating(tq, jc.sigma_y(r.eps, r.rate, temp), d_eps, rho, cp);
        (s, eps, rate) = (r.stress, r.eps, r.rate);
        steps += 1;
    }
    // Temperature at ε̄ = 1, interpolated within the last step.
    let t1 = prev_temp + (temp - prev_temp) * (1.0 - prev_eps) / (eps - prev_eps);
    let dt_heat = t1 - 300.0;
    println!("AT-29: ΔT = {dt_heat:.3} K after {steps} steps (expected {expected:.3} K)");
    assert!((dt_heat - 400.9).abs() <= 0.005 * 400.9, "ΔT = {dt_heat}");
    // The library's own heating function gives the same increment.
    assert_eq!(mat.plastic_heating(1e9, 1e-3), Some(plastic_heating(0.9, 1e9, 1e-3, 4430.0, 562.0)));
}

/// A model whose Newton slope lacks the rate term (∂σ_y/∂ε̄̇ = 0): the negative control of the path derivative.
struct WithoutRateSlope(JohnsonCook);

impl FlowStress for WithoutRateSlope {
    fn sigma_y(&self, eps: f64, rate: f64, temp: f64) -> f64 {
        self.0.sigma_y(eps, rate, temp)
    }
    fn flow(&self, eps: f64, rate: f64, temp: f64) -> swarf_kernels::material::Flow {
        swarf_kernels::material::Flow { d_rate: 0.0, ..self.0.flow(eps, rate, temp) }
    }
    fn melt_temperature(&self) -> f64 {
        self.0.melt_temp
    }
}

/// Newton gets the total derivative along the return path, ∂σ_y/∂ε̄ + (∂σ_y/∂ε̄̇)/Δt: on 2000 Tab 7.5 states
/// it needs ≤ 6 iterations on average and ≤ 20 at most; with the rate term left out of the slope the same states
/// need at least 3 more on average (the bracket still brings them home).
#[test]
fn newton_uses_the_total_path_derivative() {
    let (_, m, g) = ti_tab_7_5();
    let FlowModel::JohnsonCook(jc) = m else { panic!() };
    let mut rng = SplitMix64::new(8);
    let (mut worst, mut sum, mut sum_wrong, mut n) = (0, 0u64, 0u64, 0u64);
    for _ in 0..2000 {
        let st = random_state(&mut rng, &m, 300.0, 1500.0, (1.05, 3.0));
        let r = radial_return(&jc, &st.s, st.eps, st.rate, st.temp, g, st.dt, &ReturnOptions::DEFAULT);
        let w =
            radial_return(&WithoutRateSlope(jc), &st.s, st.eps, st.rate, st.temp, g, st.dt, &ReturnOptions::DEFAULT);
        worst = worst.max(r.iterations);
        sum += r.iterations as u64;
        sum_wrong += w.iterations as u64;
        n += 1;
    }
    let (mean, mean_wrong) = (sum as f64 / n as f64, sum_wrong as f64 / n as f64);
    println!("Newton: {mean:.2} iterations on average, at most {worst}; without the rate slope {mean_wrong:.2}");
    assert!(mean <= 6.0 && worst <= 20, "Newton: mean {mean}, worst {worst}");
    assert!(mean_wrong >= mean + 3.0, "negative control: {mean_wrong} vs {mean}");
    let f = jc.flow(0.3, 1e3, 500.0);
    assert_eq!(jc.path_slope(0.3, 1e3, 500.0, 1e-8), f.d_eps + f.d_rate / 1e-8);
}

/// The flow stress a return hands on, and the plastic update's σ_y after its heating, are bit for bit
/// `FlowStress::sigma_y` at the states they stand for (they are assembled from the parts the return already holds:
/// Johnson–Cook's thermal factor once per return, its strength part once per result). Every model of the library,
/// 3000 states each (a quarter elastic, ε̄ = 0 and below the strain floor included), through the return and through
/// `plastic_particle` with plastic heating, the work sum and the friction cap's σ_y; the temperature and the work
/// against their formulas (roethlin-solver.md §2.5 (3.122)) written with `sigma_y`.
#[test]
fn flow_stress_from_the_return_equals_sigma_y_bitwise() {
    use swarf_kernels::material::{heated_temperature, plastic_heating};
    use swarf_kernels::sph::heat::ThermalMaterial;
    use swarf_kernels::sph::plastic::{DamageArrays, PlasticArrays, PlasticConsts, plastic_particle};
    use swarf_kernels::vector::{Dim2, S2f64};

    fn check<M: FlowStress + Copy>(name: &str, m: &M, g: f64, rho: f64, seed: u64) -> (u32, u32) {
        let mut rng = SplitMix64::new(seed);
        let melt = m.melt_temperature();
        let (mut elastic, mut heated) = (0, 0);
        for k in 0..3000 {
            let eps = match k % 10 {
                0 => 0.0,
                1 => 1e-13,
                _ => 2.0 * rng.uniform(),
            };
            let rate = if rng.uniform() < 0.3 { 0.0 } else { log_uniform(&mut rng, 1e-2, 1e6) };
            let top = if melt.is_finite() && melt < 1e4 { melt + 50.0 } else { 2000.0 };
            let temp = 250.0 + (top - 250.0) * rng.uniform();
            let dt = log_uniform(&mut rng, 1e-10, 1e-7);
            let q = (0.5 + 2.5 * rng.uniform()) * m.sigma_y(eps, 0.0, temp).max(1e6);
            let s = random_deviator(&mut rng, q, true);
            let r = radial_return(m, &s, eps, rate, temp, g, dt, &ReturnOptions::DEFAULT);
            let sy = m.sigma_y(r.eps, r.rate, temp);
            assert_eq!(r.flow_stress.to_bits(), sy.to_bits(), "{name}: return's σ_y {} vs {sy}", r.flow_stress);
            elastic += (r.status == ReturnStatus::Elastic) as u32;

            // The same state through the plastic update of a sorted particle (2D: xx, xy, yy, zz).
            let (tq, cp) = (0.9, 560.0);
            let mut stress = S2f64([s[0], s[1], s[3], s[5]]);
            let (mut e, mut rt, mut t, mut work, mut ys) = (eps, rate, temp, 7.0, 0.0);
            let fl = 0u32;
            let mat = ThermalMaterial { conductivity: 7.0, specific_heat: cp };
            let a = PlasticArrays::<f64, S2f64> {
                stress: &mut stress,
                rho: &rho,
                eps: &mut e,
                rate: &mut rt,
                temp: &mut t,
                flags: &fl,
                materials: &mat,
                yield_stress: &mut ys,
                work: &mut work,
                damage: DamageArrays::NONE,
            };
            let c = PlasticConsts { shear: g, dt, taylor_quinney: tq, flags: 0, _pad: 0 };
            unsafe { plastic_particle::<f64, Dim2, M, false>(m, &c, &a, 0) };
            let r2 = radial_return(m, &[s[0], s[1], 0.0, s[3], 0.0, s[5]], eps, rate, temp, g, dt, &Default::default());
            assert_eq!((e.to_bits(), rt.to_bits()), (r2.eps.to_bits(), r2.rate.to_bits()), "{name}: state");
            let sy_old_t = m.sigma_y(e, rt, temp);
            let d_eps = e - eps;
            let t_expect = if d_eps > 0.0 {
                heated_temperature(temp, plastic_heating(tq, sy_old_t, d_eps, rho, cp), melt)
            } else {
                temp
            };
            assert_eq!(t.to_bits(), t_expect.to_bits(), "{name}: heated temperature {t} vs {t_expect}");
            let w_expect = if e > eps { 7.0 + sy_old_t * (e - eps) / rho } else { 7.0 };
            assert_eq!(work.to_bits(), w_expect.to_bits(), "{name}: work {work} vs {w_expect}");
            let sy_new_t = m.sigma_y(e, rt, t);
            assert_eq!(ys.to_bits(), sy_new_t.to_bits(), "{name}: σ_y after heating {ys} vs {sy_new_t}");
            heated += (t != temp) as u32;
        }
        (elastic, heated)
    }

    let lib = library();
    let mut models = 0;
    for mat in lib.iter() {
        let Some(model) = mat.flow_stress else { continue };
        let g = mat.shear_modulus().unwrap_or(40e9);
        let rho = mat.density().unwrap_or(7800.0);
        let seed = 900 + models;
        let (elastic, heated) = match &model {
            FlowModel::JohnsonCook(p) => check(&mat.name, p, g, rho, seed),
            FlowModel::Calamaz2008(p) => check(&mat.name, p, g, rho, seed),
            FlowModel::Calamaz2010(p) => check(&mat.name, p, g, rho, seed),
            FlowModel::Calamaz2011(p) => check(&mat.name, p, g, rho, seed),
            FlowModel::SimaOzel1(p) => check(&mat.name, p, g, rho, seed),
            FlowModel::SimaOzel2(p) => check(&mat.name, p, g, rho, seed),
            FlowModel::SimaOzel3(p) => check(&mat.name, p, g, rho, seed),
            FlowModel::Scgl(p) => check(&mat.name, p, g, rho, seed),
            FlowModel::Bilinear(p) => check(&mat.name, p, g, rho, seed),
        };
        println!("{}: {elastic} of 3000 elastic, {heated} heated", mat.name);
        // Both branches are exercised: elastic steps (σ_y reused) and heated ones (σ_y at the new temperature).
        assert!(elastic > 100 && heated > 100, "{}: elastic {elastic}, heated {heated}", mat.name);
        models += 1;
    }
    assert!(models >= 9, "{models} models");
}
