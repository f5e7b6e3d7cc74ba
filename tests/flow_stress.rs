//! Flow-stress models against the digests' values (roethlin-solver.md §10.2 AT-22..AT-26; klippel-constitutive.md
//! §6.3 Tab 9.23, §9.1 U2, U8, U12–U14), against the published equations written again here in plain f64, their
//! derivatives against central differences, their behaviour at and above the melt, and the material library.

use std::path::Path;

use swarf::material::{FlowModel, Library, Material, MaterialError};
use swarf_kernels::material::{
    Bilinear, Calamaz2008, Calamaz2010, Calamaz2011, FlowStress, JohnsonCook, RATE_FORM_UINTAH, Scgl, SimaOzel1,
    SimaOzel2, SimaOzel3, plastic_heating,
};

const MPA: f64 = 1e6;

fn library() -> Library {
    Library::load_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/materials")).expect("material library")
}

fn material(lib: &Library, name: &str) -> Material {
    lib.get(name).unwrap().clone()
}

fn assert_mpa(got_pa: f64, expected_mpa: f64, tol_mpa: f64, what: &str) {
    let got = got_pa / MPA;
    assert!((got - expected_mpa).abs() <= tol_mpa, "{what}: {got} MPa, expected {expected_mpa} ± {tol_mpa} MPa");
}

// ---------------------------------------------------------------------------------------------------------------
// Values of the digests

/// AT-22 (roethlin §10.2): standard JC, Ti6Al4V Tab 7.5, ln form: σ_y(0, 1/s, 300 K) = 862.0,
/// σ_y(0.1, 1e4/s, 300 K) = 1106.6, σ_y(0.1, 1e4/s, 800 K) = 655.7 MPa, ± 0.05 MPa.
#[test]
fn at22_johnson_cook_ti6al4v() {
    let ti = material(&library(), "Ti6Al4V-Roethlin");
    assert_mpa(ti.sigma_y(0.0, 1.0, 300.0), 862.0, 0.05, "σ_y(0, 1, 300)");
    assert_mpa(ti.sigma_y(0.1, 1e4, 300.0), 1106.6, 0.05, "σ_y(0.1, 1e4, 300)");
    assert_mpa(ti.sigma_y(0.1, 1e4, 800.0), 655.7, 0.05, "σ_y(0.1, 1e4, 800)");
}

/// AT-23: the [C2D] Uintah low-rate variant gives σ_y(0, 1/s, 300 K) = 862·2^0.01 = 868.0 MPa ± 0.05.
#[test]
fn at23_uintah_low_rate_form() {
    let ti = material(&library(), "Ti6Al4V-Roethlin-C2D");
    assert_mpa(ti.sigma_y(0.0, 1.0, 300.0), 868.0, 0.05, "σ_y(0, 1, 300), Uintah");
    // Below the reference rate it never softens (klippel U8), and it is 1 at ε̇ = 0.
    assert_mpa(ti.sigma_y(0.0, 0.0, 300.0), 862.0, 1e-9, "σ_y(0, 0, 300), Uintah");
}

/// AT-24: JC AISI 4340 (Tab 7.3): σ_y(0.2, 1e3/s, 300 K) = 1236.7 MPa ± 0.05.
#[test]
fn at24_johnson_cook_aisi4340() {
    let steel = material(&library(), "AISI4340-Roethlin");
    assert_mpa(steel.sigma_y(0.2, 1e3, 300.0), 1236.7, 0.05, "σ_y(0.2, 1e3, 300)");
}

/// AT-25/AT-26: modified JC (7.11) with Tab 7.8 (a = 1.6, b = 0.4, c = 6, d = 1) on Tab 7.5, ε̇ = 1e3/s, at
/// ε̄ = 0, 0.1, 0.5, 1, 2: 921.5, 1079.3, 1085.8, 895.9, 789.7 MPa at 300 K and 672.0, 787.1, 665.5, 529.2,
/// 463.7 MPa at 600 K, ± 0.1 MPa.
#[test]
fn at25_at26_calamaz_2008() {
    let m = material(&library(), "Ti6Al4V-Calamaz2008-Roethlin");
    let strains = [0.0, 0.1, 0.5, 1.0, 2.0];
    for (t, expected) in [(300.0, [921.5, 1079.3, 1085.8, 895.9, 789.7]), (600.0, [672.0, 787.1, 665.5, 529.2, 463.7])]
    {
        for (e, x) in strains.iter().zip(expected) {
            assert_mpa(m.sigma_y(*e, 1e3, t), x, 0.1, &format!("Calamaz 2008 σ_y({e}, 1e3, {t})"));
        }
    }
}

/// klippel §9.1 U2: 50SiB8 (Tab 7.9), ε̄ = 0, T = 300 K, ε̇ = ε̇0: σ_y = 423.5 MPa ± 0.05.
#[test]
fn u2_50sib8_initial_yield() {
    let m = material(&library(), "50SiB8-Klippel");
    assert_mpa(m.sigma_y(0.0, 1e-3, 300.0), 423.5, 0.05, "50SiB8 σ_y(0, ε̇0, 300)");
}

/// klippel §6.3 Tab 9.23 (and U3): the adiabatic 50SiB8 curve, η_TQ = 0.9, T_init = 300 K, ε̇ = ε̇0 = 1e-3/s,
/// explicit Euler with Δε = 1e-5 to ε = 3 (σ_{k+1} = σ(ε_{k+1}, T_k), T_{k+1} = T_k + η σ_{k+1} Δε/(ρ c_p),
/// ρ = 7850, c_p = 466). The thesis' table within 0.2 MPa (the digest's statement of its own re-integration);
/// the digest's re-integrated values, printed to 0.1 MPa, within 0.06 MPa.
#[test]
fn tab_9_23_adiabatic_curve_50sib8() {
    let m = material(&library(), "50SiB8-Klippel");
    let table = [423.5, 911.7, 994.6, 1024.5, 1028.5, 1017.3, 996.3, 968.7, 936.6, 901.7, 864.9];
    let digest = [423.5, 911.5, 994.5, 1024.4, 1028.4, 1017.2, 996.1, 968.6, 936.6, 901.6, 864.8];
    let (rho, cp) = (m.density().unwrap(), m.thermal.unwrap().specific_heat.unwrap());
    assert_eq!((rho, cp), (7850.0, 466.0));
    let tq = m.thermal.unwrap().taylor_quinney.unwrap();
    assert_eq!(tq, 0.9);
    let de = 1e-5;
    let mut t = 300.0;
    let mut curve = vec![m.sigma_y(0.0, 1e-3, t)];
    for k in 1..=300_000u32 {
        let s = m.sigma_y(k as f64 * de, 1e-3, t);
        t += plastic_heating(tq, s, de, rho, cp);
        if k % 30_000 == 0 {
            curve.push(s);
        }
    }
    for (j, s) in curve.iter().enumerate() {
        assert_mpa(*s, table[j], 0.2, &format!("Tab 9.23 at ε = {:.1}", 0.3 * j as f64));
        assert_mpa(*s, digest[j], 0.06, &format!("digest re-integration at ε = {:.1}", 0.3 * j as f64));
    }
}

/// klippel §9.1 U8: the rate factor for ε̇* ∈ [1e-6, 1] is never below 1 (floor), or is the Uintah form.
#[test]
fn u8_no_softening_below_the_reference_rate() {
    let lib = library();
    let clamp = material(&lib, "Ti6Al4V-Roethlin");
    let uintah = material(&lib, "Ti6Al4V-Roethlin-C2D");
    let FlowModel::JohnsonCook(jc) = uintah.flow_stress.unwrap() else { panic!() };
    for k in 0..=60 {
        let r = 10f64.powf(-6.0 + 0.1 * k as f64);
        assert_eq!(clamp.sigma_y(0.1, r, 500.0), clamp.sigma_y(0.1, 0.0, 500.0), "clamp at ε̇* = {r}");
        let expected = (1.0 + r).powf(jc.c);
        assert!((jc.rate_factor(r).0 - expected).abs() <= 1e-14, "Uintah factor at ε̇* = {r}");
        assert!(jc.rate_factor(r).0 >= 1.0);
    }
}

/// klippel §9.1 U12: SCG melt T_f(η = 1) = 1356.5 K, T_f(η = 1.05) = 1356.5·e^{3(1−1/1.05)}·1.05^{2(1.99−1.5−1/3)}
/// = 1589 K (± 0.5 K); constant in tension (η < 1).
#[test]
fn u12_scg_melt_temperature() {
    let m = material(&library(), "OFHC-Cu-SCGL");
    let FlowModel::Scgl(p) = m.flow_stress.unwrap() else { panic!() };
    assert!((p.melt_temperature() - 1356.5).abs() < 1e-9);
    let expected = 1356.5 * (3.0f64 * (1.0 - 1.0 / 1.05)).exp() * 1.05f64.powf(2.0 * (1.99 - 1.5 - 1.0 / 3.0));
    assert!((expected - 1589.0).abs() < 0.5, "digest arithmetic: {expected}");
    assert!((p.at_state(0.0, 1.05).melt_temperature() - 1589.0).abs() < 0.5);
    assert_eq!(p.at_state(-1e8, 0.95).melt_temperature(), 1356.5);
}

/// klippel §9.1 U13: σ_th from the bisection satisfies the implicit Eq. 8.30 to 1e-10 relative (in the rate)
/// with 0 < σ_th ≤ σ_p = 20 MPa, and is capped at σ_p where even σ_p is too slow.
#[test]
fn u13_scgl_thermal_stress_root() {
    let m = material(&library(), "OFHC-Cu-SCGL");
    let FlowModel::Scgl(p) = m.flow_stress.unwrap() else { panic!() };
    let kb = 8.617333262e-5;
    for t in [100.0, 300.0, 600.0, 1000.0, 1300.0] {
        for rate in [1e-6, 1e-3, 1.0, 100.0, 1000.0, 1500.0] {
            let (s, _) = p.thermal_stress(rate, t);
            assert!(s > 0.0 && s <= 20e6, "σ_th({rate}, {t}) = {s}");
            // Eq. 8.30 evaluated at the root, in plain f64.
            let k = 2.0 * 0.31 / (kb * t);
            let q = (k * (1.0 - s / 20e6).powi(2)).exp() / 0.71e6 + 0.012e6 / s;
            if s < 20e6 {
                assert!((1.0 / q - rate).abs() <= 1e-10 * rate, "rate at σ_th: {} vs {rate} (T = {t})", 1.0 / q);
            } else {
                assert!(1.0 / q <= rate, "capped only when even σ_p is too slow");
            }
        }
        // Above 1/(1/C1 + C2/σ_p) ≈ 1664 /s the drag caps σ_th at σ_p.
        assert_eq!(p.thermal_stress(1e4, t).0, 20e6);
        assert_eq!(p.thermal_stress(0.0, t).0, 0.0);
    }
}

/// klippel §9.1 U14: SO3 with S = 1 and r = c equals TANH2008 (to 1e-12 relative).
#[test]
fn u14_sima_ozel_3_reduces_to_tanh2008() {
    let m = material(&library(), "Ti6Al4V-Klippel-TANH2008");
    let FlowModel::Calamaz2008(c) = m.flow_stress.unwrap() else { panic!() };
    let so3 = SimaOzel3 { jc: c.jc, a: c.a, b: c.b, d: c.d, r: c.c, s: 1.0 };
    for e in [0.0, 0.01, 0.2, 0.8, 2.0] {
        for t in [293.15, 500.0, 900.0, 1500.0] {
            let (x, y) = (c.sigma_y(e, 1e3, t), so3.sigma_y(e, 1e3, t));
            assert!((x - y).abs() <= 1e-12 * x, "ε = {e}, T = {t}: {x} vs {y}");
        }
    }
}

/// The bilinear model: σ_y = σ_y0 + H ε̄ with H the plastic modulus (Taylor bar: 400 MPa, H = 100 MPa); the
/// tangent modulus of the uniaxial curve is E H/(E + H).
#[test]
fn bilinear_taylor_bar() {
    let m = material(&library(), "Cu-TaylorBar-Bilinear");
    let FlowModel::Bilinear(b) = m.flow_stress.unwrap() else { panic!() };
    assert_eq!(m.sigma_y(0.0, 0.0, 300.0), 400e6);
    assert!((m.sigma_y(0.5, 1e5, 3000.0) - 450e6).abs() < 1e-6);
    let e = m.elastic.unwrap().youngs_modulus;
    assert!((b.tangent_modulus(e) - 117e9 * 100e6 / (117e9 + 100e6)).abs() < 1e-3);
    let soft = Bilinear { yield_stress: 100e6, plastic_modulus: -50e6, melt_temp: f64::INFINITY };
    assert_eq!(soft.sigma_y(3.0, 0.0, 300.0), 0.0, "softening stops at zero strength");
    assert_eq!(soft.flow(3.0, 0.0, 300.0).d_eps, 0.0);
}

// ---------------------------------------------------------------------------------------------------------------
// The published equations, written again in plain f64 with the documented guards (T ≤ Tm − 1 K, θ ≥ 0, ε̇* ≥ 1 in
// the ln form, σ_y ≥ 0).

fn t_clamped(t: f64, tm: f64) -> f64 {
    t.min(tm - 1.0)
}

fn jc_rate(p: &JohnsonCook, rate: f64) -> f64 {
    let r = rate / p.ref_rate;
    if p.rate_form == RATE_FORM_UINTAH && r <= 1.0 { (1.0 + r.max(0.0)).powf(p.c) } else { 1.0 + p.c * r.max(1.0).ln() }
}

fn jc_thermal(p: &JohnsonCook, t: f64) -> f64 {
    let theta = ((t_clamped(t, p.melt_temp) - p.ref_temp) / (p.melt_temp - p.ref_temp)).max(0.0);
    1.0 - theta.powf(p.m)
}

fn ratio(p: &JohnsonCook, t: f64) -> f64 {
    t_clamped(t, p.melt_temp).max(0.0) / p.melt_temp
}

/// Roethlin (3.101), Klippel Eq. 3.95.
fn ref_jc(p: &JohnsonCook, e: f64, rate: f64, t: f64) -> f64 {
    ((p.a + p.b * e.powf(p.n)) * jc_rate(p, rate) * jc_thermal(p, t)).max(0.0)
}

/// Klippel Eqs. 8.1–8.4, Roethlin (7.11).
fn ref_calamaz_2008(p: &Calamaz2008, e: f64, rate: f64, t: f64) -> f64 {
    let j = &p.jc;
    let tau = ratio(j, t);
    let d = 1.0 - tau.powf(p.d);
    let s = tau.powf(p.b);
    let h = j.a + j.b * e.powf(j.n) * (-e.powf(p.a)).exp();
    (h * jc_rate(j, rate) * jc_thermal(j, t) * (d + (1.0 - d) * (1.0 / (e + s).powf(p.c)).tanh())).max(0.0)
}

/// Klippel Eqs. 8.11–8.12 (q on tanh(·), argument ≥ 0).
fn ref_calamaz_2010(p: &Calamaz2010, e: f64, rate: f64, t: f64) -> f64 {
    let j = &p.jc;
    let arg = ((t_clamped(t, j.melt_temp) - j.ref_temp) / (p.t_rec - j.ref_temp)).max(0.0);
    let g = 1.0 - (p.p * e / (1.0 + p.p * e)) * arg.tanh().powf(p.q);
    let f = g + (1.0 - g) * (1.0 / (e + p.eps0)).tanh();
    ((j.a + j.b * e.powf(j.n)) * jc_rate(j, rate) * jc_thermal(j, t) * f).max(0.0)
}

/// Klippel Eq. 8.13 (ε̇* ≥ 1 in the B term, exponent ≥ 0).
fn ref_calamaz_2011(p: &Calamaz2011, e: f64, rate: f64, t: f64) -> f64 {
    let j = &p.jc;
    let r = (rate / j.ref_rate).max(1.0);
    let k = (j.n - 0.12 * (e * r).powf(p.a)).max(0.0);
    ((j.a + j.b * (1.0 / r).powf(p.a) * e.powf(k)) * jc_rate(j, rate) * jc_thermal(j, t)).max(0.0)
}

fn so_factor(g: f64, p: f64, r: f64, s: f64, e: f64) -> f64 {
    g + (1.0 - g) * (1.0 / (e + p).powf(r)).tanh().powf(s)
}

/// Klippel Eq. 8.14.
fn ref_so1(p: &SimaOzel1, e: f64, rate: f64, t: f64) -> f64 {
    let j = &p.jc;
    ((j.a + j.b * e.powf(j.n)) * jc_rate(j, rate) * jc_thermal(j, t) * so_factor(p.big_m, p.p, p.r, p.s, e)).max(0.0)
}

/// Klippel Eqs. 8.15–8.16.
fn ref_so2(p: &SimaOzel2, e: f64, rate: f64, t: f64) -> f64 {
    let j = &p.jc;
    let tau = ratio(j, t);
    let f = so_factor(1.0 - tau.powf(p.d), tau.powf(p.b), p.r, p.s, e);
    ((j.a + j.b * e.powf(j.n)) * jc_rate(j, rate) * jc_thermal(j, t) * f).max(0.0)
}

/// Klippel Eq. 8.17.
fn ref_so3(p: &SimaOzel3, e: f64, rate: f64, t: f64) -> f64 {
    let j = &p.jc;
    let tau = ratio(j, t);
    let f = so_factor(1.0 - tau.powf(p.d), tau.powf(p.b), p.r, p.s, e);
    ((j.a + j.b * e.powf(j.n) * (-e.powf(p.a)).exp()) * jc_rate(j, rate) * jc_thermal(j, t) * f).max(0.0)
}

/// Klippel Eqs. 8.26–8.30, with σ_th solved here by bisection on ln ε̇(σ) (200 halvings).
fn ref_scgl(p: &Scgl, e: f64, rate: f64, t: f64) -> f64 {
    let tf = if p.eta < 1.0 {
        p.melt_temp0
    } else {
        p.melt_temp0
            * (2.0 * p.melt_a * (1.0 - 1.0 / p.eta)).exp()
            * p.eta.powf(2.0 * (p.gamma0 - p.melt_a - 1.0 / 3.0))
    };
    if t >= tf {
        return 0.0;
    }
    let mu = (p.mu0 + p.dmu_dp * p.pressure / p.eta.cbrt() + p.dmu_dt * (t - p.ref_temp)).max(0.0);
    let ath = (p.sigma_a * (1.0 + p.beta * (e + p.eps_i)).powf(p.n)).min(p.sigma_max);
    let k = 2.0 * p.uk_over_kb / t.max(1.0);
    let ln_rate = |s: f64| -((k * (1.0 - s / p.sigma_p).powi(2)).exp() / p.c1 + p.c2 / s).ln();
    let th = if rate <= 0.0 {
        0.0
    } else if ln_rate(p.sigma_p) <= rate.ln() {
        p.sigma_p
    } else {
        let (mut lo, mut hi) = (0.0, p.sigma_p);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if ln_rate(mid) < rate.ln() { lo = mid } else { hi = mid }
        }
        hi
    };
    ((ath + th) * mu / p.mu0).max(0.0)
}

fn reference(m: &FlowModel, e: f64, rate: f64, t: f64) -> f64 {
    match m {
        FlowModel::JohnsonCook(p) => ref_jc(p, e, rate, t),
        FlowModel::Calamaz2008(p) => ref_calamaz_2008(p, e, rate, t),
        FlowModel::Calamaz2010(p) => ref_calamaz_2010(p, e, rate, t),
        FlowModel::Calamaz2011(p) => ref_calamaz_2011(p, e, rate, t),
        FlowModel::SimaOzel1(p) => ref_so1(p, e, rate, t),
        FlowModel::SimaOzel2(p) => ref_so2(p, e, rate, t),
        FlowModel::SimaOzel3(p) => ref_so3(p, e, rate, t),
        FlowModel::Scgl(p) => ref_scgl(p, e, rate, t),
        FlowModel::Bilinear(p) => (p.yield_stress + p.plastic_modulus * e).max(0.0),
    }
}

/// Reference temperature and melt of a model (for the temperature grid).
fn temperatures(m: &FlowModel) -> (f64, f64) {
    match m {
        FlowModel::Scgl(p) => (p.ref_temp, p.melt_temperature()),
        FlowModel::Bilinear(_) => (300.0, 1500.0),
        _ => {
            let j = m.johnson_cook().unwrap();
            (j.ref_temp, j.melt_temp)
        }
    }
}

/// Every model of the library against its equation written again, on a grid of (ε̄, ε̄̇, T) that includes ε̄ = 0,
/// ε̄̇ → 0 and T at, around and above the melt: 1e-11 relative (the kernels compute x^y as exp(y ln x), libm;
/// the references use std's powf).
#[test]
fn every_model_matches_its_published_equation() {
    let lib = library();
    let strains = [0.0, 1e-12, 1e-9, 1e-3, 0.05, 0.3, 1.0, 2.5, 10.0];
    let rates = [0.0, 1e-12, 1e-4, 0.5, 1.0, 3.0, 1e3, 1e6, 1e9];
    let mut count = 0;
    for mat in lib.iter() {
        let Some(model) = mat.flow_stress else { continue };
        let (t0, tm) = temperatures(&model);
        let temps = [1.0, 250.0, t0, 0.5 * (t0 + tm), tm - 1.5, tm - 1.0, tm - 0.5, tm, tm + 10.0, 1e4];
        let variants: Vec<FlowModel> = match model {
            // SCGL also under compression (η > 1 raises the melt) and pressure.
            FlowModel::Scgl(p) => vec![model, FlowModel::Scgl(p.at_state(5e9, 1.05))],
            _ => vec![model],
        };
        for m in &variants {
            for &e in &strains {
                for &r in &rates {
                    for &t in &temps {
                        let (got, want) = (m.sigma_y(e, r, t), reference(m, e, r, t));
                        assert!(
                            (got - want).abs() <= 1e-11 * want.abs() + 1e-6,
                            "{}: σ_y({e}, {r}, {t}) = {got}, equation gives {want}",
                            mat.name
                        );
                        count += 1;
                    }
                }
            }
        }
    }
    assert!(count > 20_000, "{count} points");
}

/// ∂σ_y/∂ε̄ and ∂σ_y/∂ε̄̇ of every library model against central differences (relative step 1e-6) at interior points
/// (away from the clamps' kinks): within 1e-6 relative, or 1e-8 of the natural scale σ_y/ε̄ (σ_y/ε̄̇).
#[test]
fn derivatives_match_central_differences() {
    let lib = library();
    let mut count = 0;
    for mat in lib.iter() {
        let Some(m) = mat.flow_stress else { continue };
        let (t0, tm) = temperatures(&m);
        let ref_rate = m.johnson_cook().map_or(1.0, |j| j.ref_rate);
        for e in [0.01, 0.05, 0.2, 0.7, 1.5] {
            for r in [0.3 * ref_rate, 10.0 * ref_rate, 1e3, 1e5] {
                for t in [t0 + 20.0, 0.5 * (t0 + tm), tm - 100.0] {
                    let f = m.flow(e, r, t);
                    assert!(f.sigma == m.sigma_y(e, r, t), "{}: flow and sigma_y agree", mat.name);
                    let h = 1e-6 * e;
                    let fd = (m.sigma_y(e + h, r, t) - m.sigma_y(e - h, r, t)) / (2.0 * h);
                    assert!(
                        (f.d_eps - fd).abs() <= 1e-6 * fd.abs() + 1e-8 * f.sigma / e,
                        "{}: ∂σ/∂ε at ({e}, {r}, {t}) = {}, central difference {fd}",
                        mat.name,
                        f.d_eps
                    );
                    let h = 1e-6 * r;
                    let fd = (m.sigma_y(e, r + h, t) - m.sigma_y(e, r - h, t)) / (2.0 * h);
                    assert!(
                        (f.d_rate - fd).abs() <= 1e-6 * fd.abs() + 1e-8 * f.sigma / r,
                        "{}: ∂σ/∂ε̇ at ({e}, {r}, {t}) = {}, central difference {fd}",
                        mat.name,
                        f.d_rate
                    );
                    // The path slope Newton uses is ∂σ/∂ε̄ + (∂σ/∂ε̄̇)/Δt.
                    let dt = 1e-7;
                    assert_eq!(f.path_slope(dt), f.d_eps + f.d_rate / dt);
                    count += 1;
                }
            }
        }
    }
    assert!(count > 1000, "{count} points");
}

/// klippel §8 H14: σ_y ≥ 0 and finite (with finite derivatives) at and above the melt, at ε̄ = 0, ε̄̇ = 0 and
/// extreme strains and rates, for every library model; the JC family keeps a small positive strength up to
/// T_m − 1 K (its clamp), SCGL drops to zero at its melt.
#[test]
fn finite_and_non_negative_everywhere() {
    let lib = library();
    for mat in lib.iter() {
        let Some(m) = mat.flow_stress else { continue };
        let (_, tm) = temperatures(&m);
        for t in [0.0, 1.0, tm - 1.0, tm - 1e-9, tm, tm + 1.0, 2.0 * tm, 1e5] {
            for e in [0.0, 1e-300, 1e-12, 0.5, 50.0, 1e6] {
                for r in [0.0, 1e-300, 1e-3, 1.0, 1e8, 1e200] {
                    let f = m.flow(e, r, t);
                    assert!(
                        f.sigma.is_finite() && f.sigma >= 0.0 && f.d_eps.is_finite() && f.d_rate.is_finite(),
                        "{}: flow({e}, {r}, {t}) = {f:?}",
                        mat.name
                    );
                }
            }
        }
        if let Some(j) = m.johnson_cook() {
            // No hardening below T0 (klippel §2.1: θ = 0 for T < T_ref); the tanh models' own factors use T/Tm.
            if matches!(m, FlowModel::JohnsonCook(_) | FlowModel::Calamaz2011(_)) {
                let below = m.sigma_y(0.2, 10.0, j.ref_temp - 100.0);
                assert_eq!(below, m.sigma_y(0.2, 10.0, j.ref_temp), "{}", mat.name);
            }
            // The melt clamp: T ≥ Tm − 1 K all evaluate at Tm − 1 K, with positive strength.
            let at = m.sigma_y(0.2, 10.0, j.melt_temp - 1.0);
            assert!(at > 0.0 && at < 0.05 * m.sigma_y(0.2, 10.0, j.ref_temp), "{}: {at}", mat.name);
            assert_eq!(m.sigma_y(0.2, 10.0, j.melt_temp + 500.0), at, "{}", mat.name);
        }
        if let FlowModel::Scgl(p) = m {
            assert_eq!(m.sigma_y(0.2, 10.0, p.melt_temperature()), 0.0);
        }
    }
}

// ---------------------------------------------------------------------------------------------------------------
// The library

/// Every file of cases/materials loads, its name is its file name, and it says where its numbers come from.
#[test]
fn every_library_file_loads() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/materials");
    let files = std::fs::read_dir(&dir).unwrap().filter(|e| e.as_ref().unwrap().path().extension().unwrap() == "toml");
    let lib = library();
    assert_eq!(lib.len(), files.count());
    for m in lib.iter() {
        assert_eq!(m.file.file_stem().unwrap().to_str().unwrap(), m.name);
        assert!(!m.source.is_empty() && !m.description.is_empty(), "{}", m.name);
        assert!(m.elastic.is_some() || m.thermal.is_some(), "{}: neither elastic nor thermal", m.name);
        assert!(m.density().is_some(), "{}: no density", m.name);
    }
    // Spot checks of the sets the brief names.
    let ti = material(&lib, "Ti6Al4V-V0060-DE-mu035");
    let j = *ti.flow_stress.unwrap().johnson_cook().unwrap();
    assert_eq!((j.a, j.b, j.c, j.m, j.n), (852.1e6, 338.9e6, 0.02754, 0.5961, 0.1483));
    let ck = material(&lib, "Ck45-V0300-DE-mu035");
    let j = *ck.flow_stress.unwrap().johnson_cook().unwrap();
    assert_eq!((j.a, j.b, j.c, j.m, j.n), (569.0e6, 736.6e6, 0.06005, 0.7147, 0.0685));
    for name in ["Rubber", "WC-Roethlin", "Diamond-Roethlin"] {
        assert!(material(&lib, name).flow_stress.is_none());
        assert_eq!(material(&lib, name).sigma_y(1.0, 1.0, 300.0), f64::INFINITY);
    }
    for (name, model) in [
        ("Ti6Al4V-Klippel-TANH2010", "calamaz_2010"),
        ("Ti6Al4V-Klippel-CALAMAZ2011-a011", "calamaz_2011"),
        ("Ti6Al4V-Klippel-TANHSO1", "sima_ozel_1"),
        ("Ti6Al4V-Klippel-TANHSO2", "sima_ozel_2"),
        ("Ti6Al4V-Klippel-TANHSO3", "sima_ozel_3"),
        ("OFHC-Cu-SCGL", "scgl"),
        ("Cu-TaylorBar-Bilinear", "bilinear"),
    ] {
        assert_eq!(material(&lib, name).flow_stress.unwrap().name(), model);
    }
    assert!(matches!(lib.get("Unobtainium"), Err(MaterialError::NotFound { .. })));
}

const GOOD: &str = r#"
name = "X"
description = "test"
source = "here"
[elastic]
density = 4430.0
youngs_modulus = 110e9
poisson_ratio = 0.35
[thermal]
reference_temperature = 300.0
melt_temperature = 1836.0
[flow_stress]
model = "johnson_cook"
A = 862e6
B = 331e6
C = 0.01
n = 0.34
m = 0.8
reference_strain_rate = 1.0
"#;

/// Errors name the file, the line, the dotted key and what was expected; unknown keys are refused.
#[test]
fn errors_name_file_key_and_expectation() {
    assert!(Material::parse(GOOD, "x.toml", Some("X")).is_ok());
    let err = |text: &str| Material::parse(text, "x.toml", Some("X")).unwrap_err();

    let e = err(&GOOD.replace("A = 862e6", "AA = 862e6"));
    let msg = e.to_string();
    assert!(matches!(&e, MaterialError::UnknownKey { key, line: Some(14), .. } if key == "flow_stress.AA"), "{e:?}");
    assert!(
        msg.contains("x.toml:14") && msg.contains("flow_stress.AA") && msg.contains("reference_strain_rate"),
        "{msg}"
    );

    let e = err(&GOOD.replace("poisson_ratio = 0.35", "poisson_ratio = 0.5"));
    assert!(matches!(&e, MaterialError::Invalid { key, .. } if key == "elastic.poisson_ratio"), "{e:?}");
    assert!(e.to_string().contains("(-1, 0.5)"), "{e}");

    let e = err(&GOOD.replace("m = 0.8\n", ""));
    assert!(matches!(&e, MaterialError::Invalid { key, value: None, .. } if key == "flow_stress.m"), "{e:?}");

    let e = err(&GOOD.replace("johnson_cook", "johnson-cook"));
    assert!(e.to_string().contains("calamaz_2008") && e.to_string().contains("flow_stress.model"), "{e}");

    let e = err(&GOOD.replace("melt_temperature = 1836.0\n", ""));
    assert!(matches!(&e, MaterialError::Invalid { key, .. } if key == "thermal.melt_temperature"), "{e:?}");

    let e = err(&GOOD.replace("[thermal]", "[thermal]\nspecific_heat = \"562\""));
    assert!(matches!(&e, MaterialError::Invalid { key, .. } if key == "thermal.specific_heat"), "{e:?}");

    let e = Material::parse(GOOD, "y.toml", Some("Y")).unwrap_err();
    assert!(e.to_string().contains("\"Y\" (the file name)"), "{e}");

    let e = err(&GOOD.replace("[elastic]", "colour = \"red\"\n[elastic]"));
    assert!(matches!(&e, MaterialError::UnknownKey { key, .. } if key == "colour"), "{e:?}");

    let e = err("name = ");
    assert!(matches!(&e, MaterialError::Syntax { line: Some(1), .. }), "{e:?}");

    // A tanh-model key under plain JC is refused, with the model named.
    let e = err(&GOOD.replace("m = 0.8", "m = 0.8\nd = 1.0"));
    assert!(e.to_string().contains("for model 'johnson_cook'"), "{e}");
}

/// The return mapping evaluates Johnson–Cook's thermal factor once per return (`FlowStress::thermal_part`) and
/// hands it to `flow_at`: the result must be `flow`'s bit for bit, over strains, rates (both rate forms, below and
/// above the reference rate) and temperatures from below the reference to past the melt.
#[test]
fn johnson_cook_flow_at_a_frozen_temperature_equals_flow_bitwise() {
    use swarf_kernels::material::johnson_cook::RATE_FORM_CLAMP;
    let lib = library();
    for name in ["Ti6Al4V-Roethlin-C2D", "AISI4340-Roethlin"] {
        let Some(FlowModel::JohnsonCook(jc)) = material(&lib, name).flow_stress else {
            panic!("{name}: not a Johnson–Cook material")
        };
        for form in [RATE_FORM_CLAMP, RATE_FORM_UINTAH] {
            let p = JohnsonCook { rate_form: form, ..jc };
            let mut checked = 0;
            for t in [200.0, 293.0, 300.0, 800.0, 1500.0, p.melt_temp - 0.5, p.melt_temp + 10.0] {
                let th = p.thermal_part(t);
                for e in [0.0, 1e-9, 0.01, 0.3, 2.5] {
                    for r in [0.0, 0.5 * p.ref_rate, p.ref_rate, 1e3, 1e6] {
                        let (a, b) = (p.flow(e, r, t), p.flow_at(e, r, t, th));
                        for (x, y) in [(a.sigma, b.sigma), (a.d_eps, b.d_eps), (a.d_rate, b.d_rate)] {
                            assert_eq!(x.to_bits(), y.to_bits(), "{name}: ε̄ {e}, ε̄̇ {r}, T {t}");
                        }
                        checked += 1;
                    }
                }
            }
            assert_eq!(checked, 175);
        }
    }
}
