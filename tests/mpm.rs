//! The MPM solver (issue 26; docs/mpm.md) on the CPU: its shape functions, constitutive update and cohesive law
//! against their equations (nairn-mpm.md §1.1, §1.4, §1.5), the cohesive energy test V15 (§6.2) in mode I and
//! mode II, a short cut, and the scene's checks.

use swarf::backend::{AnyBackend, Backend, CpuBackend};
use swarf::kernels::cohesive::{CUBIC, Cohesive, FAILED, MODE_I, TRIANGULAR, TRIANGULAR_PEAK, TractionLaw, traction};
use swarf::kernels::mpm::hyperelastic::{NeoHookeanJ2, relative_gradient, update};
use swarf::kernels::mpm::shape::ugimp;
use swarf::mpm::run::{MpmRunOptions, run};
use swarf::mpm::setup::setup;
use swarf::mpm::solver::MpmSolver;
use swarf::rng::SplitMix64;
use swarf::scene::mpm::MpmScene;

use crate::common;

/// The uGIMP weight is the grid's hat averaged over the particle's domain [x − l_p, x + l_p] (Bardenhagen &
/// Kober 2004; nairn-mpm.md §1.1): against a midpoint quadrature of that average (1e-9), and the weights and
/// gradients of the nodes a particle reaches sum to 1 and 0 (partition of unity, 1e-14).
#[test]
fn ugimp_is_the_averaged_hat_and_a_partition_of_unity() {
    let (dx, lp) = (1.0f64, 0.25f64);
    let mut rng = SplitMix64::new(7);
    for _ in 0..2000 {
        let x = 3.0 * rng.uniform() - 1.5;
        let (s, _) = ugimp(x, dx, lp);
        let q = 20_000;
        let avg = (0..q)
            .map(|k| {
                let y = x - lp + (k as f64 + 0.5) * 2.0 * lp / q as f64;
                (1.0 - y.abs() / dx).max(0.0)
            })
            .sum::<f64>()
            / q as f64;
        assert!((s - avg).abs() < 1e-9, "S({x}) = {s}, averaged hat {avg}");
        let p = 10.0 * rng.uniform();
        let (mut sum, mut grad) = (0.0, 0.0);
        for i in -2..14 {
            let (w, g) = ugimp(p - i as f64 * dx, dx, lp);
            sum += w;
            grad += g;
        }
        assert!((sum - 1.0).abs() < 1e-14 && grad.abs() < 1e-13, "at {p}: ΣS = {sum}, ΣdS = {grad}");
    }
}

/// The cubic law (Eq. 3): its peak σ_c at δ_c/3, its energy J(δ_c) = 9σ_cδ_c/16 and J(δ) = ∫σ (Simpson, 1e-9
/// relative); a point loaded in mode I fails where J_I = J_c (δ = δ_c), unloads along the secant, and once failed
/// resists only closing with the law's initial stiffness 27σ_c/(4δ_c).
#[test]
fn cubic_law_and_its_failure_follow_eqs_3_and_4() {
    let law = TractionLaw::of_toughness(CUBIC, 2000.0, 40e6);
    assert!((law.delta_c - 16.0 * 2000.0 / (9.0 * 40e6)).abs() < 1e-18);
    assert!((law.traction(law.delta_c / 3.0) - 40e6).abs() < 1e-6);
    assert!((law.energy(law.delta_c) - 2000.0).abs() < 1e-9);
    energy_is_the_tractions_integral(&law);
    let c = Cohesive { mode1: law, mode2: law };
    let mut st = [0.0f64; 4];
    let (_, t) = traction(&c, &mut st, 0.0, 0.5 * law.delta_c);
    assert_eq!(t, law.traction(0.5 * law.delta_c));
    let (_, t_back) = traction(&c, &mut st, 0.0, 0.25 * law.delta_c);
    assert!((t_back - 0.5 * t).abs() < 1e-6 * t, "secant unloading: {t_back} vs {}", 0.5 * t);
    assert_eq!(st[FAILED], 0.0);
    let _ = traction(&c, &mut st, 0.0, law.delta_c);
    assert_eq!(st[FAILED], 1.0, "mode I fails at δ_c");
    assert!((st[MODE_I] - 1.0).abs() < 1e-12);
    assert_eq!(traction(&c, &mut st, 1e-6, 0.5 * law.delta_c), (0.0, 0.0), "a failed point carries no tension");
    let (_, closing) = traction(&c, &mut st, 0.0, -1e-7);
    assert!((closing - (-1e-7 * 6.75 * 40e6 / law.delta_c)).abs() < 1e-3, "closing: {closing}");
    // Mixed mode (Eq. 4): J_I/J_c + J_II/J_c reaches 1 at failure, not before.
    let mut st = [0.0f64; 4];
    let d = 0.5 * law.delta_c;
    let _ = traction(&c, &mut st, d, d);
    let share = law.energy(d) / law.toughness();
    assert_eq!(st[FAILED], if 2.0 * share >= 1.0 { 1.0 } else { 0.0 });
}

/// J(δ) = ∫₀^δ σ (Simpson over 2000 intervals, 1e-9 relative; for the triangular law the kink at δ_p falls
/// between nodes, so its tolerance is Simpson's O(h²) error across it, 1e-6).
fn energy_is_the_tractions_integral(law: &TractionLaw) {
    let tol = if law.shape == TRIANGULAR { 1e-6 } else { 1e-9 };
    for f in [0.1, 0.3, 0.7, 1.0] {
        let d = f * law.delta_c;
        let n = 2000;
        let h = d / n as f64;
        let simpson: f64 = (0..=n)
            .map(|k| {
                let w = if k == 0 || k == n {
                    1.0
                } else if k % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                w * law.traction(k as f64 * h)
            })
            .sum::<f64>()
            * h
            / 3.0;
        assert!((simpson - law.energy(d)).abs() < tol * law.energy(d), "J({f} δc): {simpson} vs {}", law.energy(d));
    }
}

/// The triangular law (nairn-mpm.md §1.5, "also tried"; docs/mpm.md "Traction laws"): J_c = ½σ_cδ_c = G_c, its
/// peak σ_c at δ_p = (32/243) δ_c, J(δ) = ∫σ, and its initial (closing) stiffness the cubic law's of the same
/// σ_c and G_c (1e-12 relative); a point loaded past δ_c in mode I fails with mode-I share 1.
#[test]
fn triangular_law_keeps_the_toughness_and_the_cubic_laws_stiffness() {
    let (g, sc) = (2000.0, 40e6);
    let law = TractionLaw::of_toughness(TRIANGULAR, g, sc);
    let cubic = TractionLaw::of_toughness(CUBIC, g, sc);
    assert!((law.delta_c - 2.0 * g / sc).abs() < 1e-18);
    assert!((law.toughness() - g).abs() < 1e-9 && (law.energy(law.delta_c) - g).abs() < 1e-9);
    assert!((law.traction(TRIANGULAR_PEAK * law.delta_c) - sc).abs() < 1e-6 * sc);
    let tail = 1e-3 / (1.0 - TRIANGULAR_PEAK) * sc;
    assert!((law.traction(0.999 * law.delta_c) - tail).abs() < 1e-6 * sc && law.traction(law.delta_c) == 0.0);
    let (k, kc) = (law.stiffness::<f64>(), cubic.stiffness::<f64>());
    assert!((k - kc).abs() < 1e-12 * kc, "initial stiffness {k:e} vs the cubic's {kc:e}");
    energy_is_the_tractions_integral(&law);
    let c = Cohesive { mode1: law, mode2: law };
    let mut st = [0.0f64; 4];
    let _ = traction(&c, &mut st, 0.0, 0.9 * law.delta_c);
    assert_eq!(st[FAILED], 0.0);
    let _ = traction(&c, &mut st, 0.0, law.delta_c);
    assert_eq!((st[FAILED], st[MODE_I]), (1.0, 1.0), "mode I fails at δ_c");
}

/// Small strains: the neo-Hookean update reduces to linear elasticity, σ_xx = (K + 4G/3)ε, σ_yy = σ_zz =
/// (K − 2G/3)ε for a plane-strain uniaxial strain ε (relative error O(ε), here 1e-3 at ε = 1e-5).
#[test]
fn small_strain_is_linear_elastic() {
    let m = NeoHookeanJ2 { bulk: 980e6, shear: 376e6, yield_stress: 1e12, plastic_modulus: 0.0 };
    let (mut be, mut jac, mut eps) = ([1.0f64, 0.0, 1.0, 1.0], 1.0f64, 0.0f64);
    let (rate, dt, steps) = (1.0, 1e-7, 100);
    let mut s = [0.0; 4];
    for _ in 0..steps {
        s = update(&m, relative_gradient([[rate, 0.0], [0.0, 0.0]], dt), &mut be, &mut jac, &mut eps);
    }
    let e = rate * dt * steps as f64;
    let (k, g) = (m.bulk, m.shear);
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    assert!(rel(s[0], (k + 4.0 * g / 3.0) * e) < 1e-3, "σ_xx {}", s[0]);
    assert!(rel(s[2], (k - 2.0 * g / 3.0) * e) < 1e-3, "σ_yy {}", s[2]);
    assert!(rel(s[3], (k - 2.0 * g / 3.0) * e) < 1e-3, "σ_zz {}", s[3]);
    assert!(s[1].abs() < 1e-6);
}

/// Large simple shear: the radial return keeps the Kirchhoff deviator on the yield surface ‖s‖ = √(2/3)(σ_y0 +
/// E_p ε) (Eq. 2) to 1e-9, hardens by E_p, and leaves J = det F = 1 to 1e-12 (an isochoric motion).
#[test]
fn return_mapping_holds_the_yield_surface_in_large_shear() {
    for ep in [0.0, 111.1e6] {
        let m = NeoHookeanJ2 { bulk: 980e6, shear: 376e6, yield_stress: 25e6, plastic_modulus: ep };
        let (mut be, mut jac, mut eps) = ([1.0f64, 0.0, 1.0, 1.0], 1.0f64, 0.0f64);
        let (rate, dt) = (1000.0f64, 1e-6f64);
        let mut s = [0.0; 4];
        for _ in 0..800 {
            s = update(&m, relative_gradient([[0.0, rate], [0.0, 0.0]], dt), &mut be, &mut jac, &mut eps);
        }
        // τ = J σ; its deviator's norm.
        let tau = s.map(|x| x * jac);
        let p = (tau[0] + tau[2] + tau[3]) / 3.0;
        let d = [tau[0] - p, tau[2] - p, tau[3] - p];
        let norm = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + 2.0 * tau[1] * tau[1]).sqrt();
        let target = (2.0f64 / 3.0).sqrt() * (25e6 + ep * eps);
        assert!((norm - target).abs() < 1e-9 * target, "E_p {ep}: ‖s‖ {norm} vs {target}");
        assert!(eps > 0.3, "E_p {ep}: plastic strain {eps} after a shear of 0.8");
        assert!((jac - 1.0).abs() < 1e-12, "J = {jac}");
    }
}

fn bond_released(file: &str, dir: &str, sets: &[&str]) -> (f64, f64) {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let scene = MpmScene::load(file, &sets).expect("scene");
    let out = std::env::temp_dir().join(dir);
    let _ = std::fs::remove_dir_all(&out);
    let opts = MpmRunOptions { frames: false, ..MpmRunOptions::new(out) };
    let r = run(&AnyBackend::Cpu(CpuBackend::new()), &scene, &opts).expect("run");
    let released = r.released.expect("the plane separated");
    (released.per_area, r.mode_i_share.expect("failed points"))
}

/// V15 (nairn-mpm.md §6.2): a block bonded by the cubic law (G_c = 2000 J/m²) and pulled apart in pure mode I
/// releases, per unit of new crack area, the grip's work less the energies the specimen holds when the last
/// point fails: 2000 J/m² within 5 %, every point failing in mode I.
#[test]
fn bond_releases_its_toughness_in_mode_1() {
    let (g, share) = bond_released("cases/mpm/bond-mode1.toml", "swarf-mpm-bond1", &[]);
    assert!((g / 2000.0 - 1.0).abs() < 0.05, "mode I: {g} J/m²");
    assert!(share > 0.99, "mode-I share {share}");
}

/// V15 in pure mode II: the grip slides the upper block along the plane; 2000 J/m² within 5 %, in mode II.
#[test]
fn bond_releases_its_toughness_in_mode_2() {
    let (g, share) = bond_released("cases/mpm/bond-mode2.toml", "swarf-mpm-bond2", &[]);
    assert!((g / 2000.0 - 1.0).abs() < 0.05, "mode II: {g} J/m²");
    assert!(share < 0.01, "mode-I share {share}");
}

/// V15 with the triangular law (docs/mpm.md "Traction laws"): the same blocks release G_c = 2000 J/m² within 5 %
/// in pure mode I and pure mode II, each point failing in its mode.
#[test]
fn bond_releases_its_toughness_with_the_triangular_law() {
    let tri = ["cohesive.law=\"triangular\""];
    let (g1, share1) = bond_released("cases/mpm/bond-mode1.toml", "swarf-mpm-bond1-tri", &tri);
    let (g2, share2) = bond_released("cases/mpm/bond-mode2.toml", "swarf-mpm-bond2-tri", &tri);
    eprintln!("triangular law: mode I {g1:.1} J/m² (share {share1:.4}), mode II {g2:.1} J/m² (share {share2:.4})");
    assert!((g1 / 2000.0 - 1.0).abs() < 0.05 && share1 > 0.99, "mode I: {g1} J/m², share {share1}");
    assert!((g2 / 2000.0 - 1.0).abs() < 0.05 && share2 < 0.01, "mode II: {g2} J/m², share {share2}");
}

/// A short coarse cut: the tool reaches the specimen and pushes it (F_c > 0), the crack opens from the end of
/// its starter as a contiguous run of failed points (the tool drives it), and the tool's particles ride with it.
/// Each particle's det F equals its J (1e-12), and the deformed domains tile the specimen (the glyph test, V14:
/// area mismatch and gaps each below 1 %).
#[test]
fn a_short_cut_opens_the_crack_ahead_of_the_tool() {
    let sets: Vec<String> =
        ["cut.particles_across=7", "cut.cut_length=2.0", "time.end=1.3e-3"].iter().map(|s| s.to_string()).collect();
    let scene = MpmScene::load("cases/mpm/nairn-cut.toml", &sets).expect("scene");
    let s = setup(&scene).expect("setup");
    let b = CpuBackend::new();
    let mut m = MpmSolver::<CpuBackend, f64>::new(&b, &s, 1.0).expect("solver");
    while m.steps < s.steps {
        m.step(&b).expect("step");
    }
    assert_eq!(m.take_flags(&b).expect("flags"), (false, false));
    let t = m.tallies(&b).expect("tallies");
    assert!(t.tool[0] > 0.0, "the tool pushed the specimen along +x: {:?}", t.tool);
    let crack = m.crack_state(&b).expect("crack");
    let failed: Vec<bool> = crack.iter().map(|c| c[FAILED] != 0.0).collect();
    let starter =
        (0..crack.len()).filter(|&k| s.params.points_lo + (k as f64 + 0.5) * s.params.crack_ds < s.starter_end).count();
    let last = failed.iter().rposition(|&f| f).expect("failed points");
    assert!(last >= starter, "the crack grew beyond its starter ({starter} points): last failed {last}");
    assert!(failed[..=last].iter().all(|&f| f), "the failed points are not contiguous: {failed:?}");
    let snap = m.snapshot(&b).expect("snapshot");
    // F and J advance by the same f = I + LΔt (docs/mpm.md "Position updates"): det F = J to rounding.
    let worst = (0..snap.pos.len())
        .map(|i| {
            let f = snap.def[i];
            ((f[0] * f[3] - f[1] * f[2]) / snap.jac[i] - 1.0).abs()
        })
        .fold(0.0, f64::max);
    assert!(worst < 1e-12, "det F against J: {worst:e}");
    let c = swarf::mpm::coverage::coverage(&snap, |_| true).expect("coverage");
    eprintln!("short cut: det F/J − 1 ≤ {worst:.2e}; coverage {c:?}");
    assert!(c.mismatch < 0.01 && c.gap_share < 0.01, "the domains tile the specimen: {c:?}");
    let d = s.tool.expect("tool").0.displacement(m.time);
    for (i, k) in snap.kind.iter().enumerate() {
        if *k == swarf::kernels::mpm::grid::TOOL {
            let x0 = s.points.pos[i];
            assert!((snap.pos[i][0] - x0[0] - d[0]).abs() < 1e-15 && (snap.pos[i][1] - x0[1]).abs() < 1e-15);
        }
    }
}

/// Bad MPM scenes are refused before any work, naming the file, the key and what was expected.
#[test]
fn bad_mpm_scenes_are_refused_with_the_key() {
    let text = std::fs::read_to_string("cases/mpm/nairn-cut.toml").expect("scene");
    let cases = [
        ("cut.particles_across=14", "cut.particles_across", "odd"),
        ("cut.crack=40.0", "cut.crack", "shorter than the width"),
        ("material.tangent_modulus=2e9", "material.tangent_modulus", "below Young's modulus"),
        ("damping.pic=1.5", "damping.pic", "[0, 1]"),
        ("cut.depht=1e-3", "cut.depht", "depth"),
        ("cohesive.law=\"linear\"", "cohesive.law", "\"triangular\""),
    ];
    for (set, key, expected) in cases {
        let e = MpmScene::from_str(&text, "nairn-cut.toml", &[set.to_string()]).expect_err(set).to_string();
        assert!(e.contains(key) && e.contains(expected), "{set}: {e}");
    }
    // A cut whose tool would run past the crack's end (18 h by default) is refused before any work.
    for set in ["cut.cut_length=20", "time.end=2e-2"] {
        let scene = MpmScene::from_str(&text, "nairn-cut.toml", &[set.to_string()]).expect(set);
        let e = setup(&scene).err().unwrap_or_else(|| panic!("{set}: accepted")).to_string();
        assert!(e.contains("cut.cut_length") && e.contains("crack"), "{set}: {e}");
    }
    let both = format!("{text}\n[bond]\nwidth = 1e-3\nheight = 1e-3\ncell = 1e-4\npull = [0.0, 1.0]\n");
    let e = MpmScene::from_str(&both, "both.toml", &[]).expect_err("both").to_string();
    assert!(e.contains("bond") && e.contains("one set-up"), "{e}");
    let sph = text.replace("method = \"mpm\"", "method = \"mpm\"\ndim = 2");
    let e = MpmScene::from_str(&sph, "sph-key.toml", &[]).expect_err("dim").to_string();
    assert!(e.contains("dim") && e.contains("MPM scene"), "{e}");
}

/// An SPH reader given an MPM scene says which commands read it, naming the file, line and key; `swarf check`
/// of an MPM scene reports the set-up's sizes and the step count of its Δt.
#[test]
fn mpm_scenes_are_checked_and_refused_by_sph_commands() {
    let text = std::fs::read_to_string("cases/mpm/bond-mode1.toml").expect("scene");
    let e = swarf::scene::Scene::from_str(&text, "bond.toml", &[]).expect_err("an MPM scene").to_string();
    assert!(e.contains("bond.toml:") && e.contains("method") && e.contains("swarf run"), "{e}");
    let scene = MpmScene::from_str(&text, "bond.toml", &[]).expect("scene");
    let s = setup(&scene).expect("setup");
    let report = swarf::mpm::run::check(&AnyBackend::Cpu(CpuBackend::new()), &scene).expect("check");
    let expected = format!("{} particles (800 specimen, 0 tool)", s.points.pos.len());
    assert!(report.contains(&expected) && report.contains(&format!("{} steps", s.steps)), "{report}");
}

/// `swarf sweep` of an MPM scene (the h × α × μ generator, issue 26): every point is an ensemble member, and a
/// batch of 2 at once gives each point's forces.csv byte for byte as its run alone; the table holds each bond's
/// released energy per crack area, V15's 2000 J/m² within 5 % at both peak tractions, and the points differ
/// (so that the equality is not one run repeated).
#[test]
fn an_mpm_sweep_runs_its_points_as_a_batch_equal_to_solo_runs() {
    let b = AnyBackend::Cpu(CpuBackend::new());
    let root = std::env::temp_dir().join(format!("swarf-mpm-sweep-{}", std::process::id()));
    let sets = ["bond.width=1e-3", "bond.cell=1.25e-4"];
    let grids = ["cohesive.peak=40e6,30e6"];
    let file = "cases/mpm/bond-mode1.toml";
    let (batch, forces) = common::scenes::mpm_sweep(&b, file, &sets, &grids, 2, &root.join("batch"));
    let (_, solo) = common::scenes::mpm_sweep(&b, file, &sets, &grids, 1, &root.join("solo"));
    assert_eq!(forces, solo, "a batch member differs from its solo run");
    assert_ne!(forces[0], forces[1], "the two points ran the same");
    let column = batch.columns.iter().position(|c| c.name == "released_j_per_m2").expect("released column");
    for p in &batch.points {
        let swarf::sweep::Outcome::Done(v) = &p.outcome else { panic!("{:?}: {:?}", p.values, p.outcome) };
        let g = v[column].expect("released energy");
        assert!((g / 2000.0 - 1.0).abs() < 0.05, "{:?}: {g} J/m²", p.values);
    }
    let _ = std::fs::remove_dir_all(root);
}

/// The start-up damping (nairn-mpm.md §1.3): during the ramp, each step's α_g is the last one plus
/// 2 K Δt/(Q M), K the grid's kinetic energy summed over the nodes (1e-12 relative, against the sum on the
/// host); it is positive by the ramp's end and reset to 0 after it; and it takes kinetic energy out: the
/// specimen holds less at the ramp's end than without it.
#[test]
fn start_up_damping_follows_the_feedback_law() {
    let run = |gain: &str| {
        let sets: Vec<String> = ["cut.particles_across=7", "cut.cut_length=2.0", "time.end=1.3e-3", gain]
            .iter()
            .map(|s| s.to_string())
            .collect();
        let scene = MpmScene::load("cases/mpm/nairn-cut.toml", &sets).expect("scene");
        let s = setup(&scene).expect("setup");
        let b = CpuBackend::new();
        let mut m = MpmSolver::<CpuBackend, f64>::new(&b, &s, 1.0).expect("solver");
        let ramp = s.tool.expect("tool").0.ramp;
        let mut checked = 0;
        let mut alpha = 0.0;
        while m.time + m.dt <= ramp {
            m.step(&b).expect("step");
            let next = b.read(&m.nodes.damping).expect("damping")[0];
            if s.feedback > 0.0 {
                let k: f64 = b.read(&m.nodes.ke).expect("ke").iter().sum();
                let expected = alpha + s.feedback * 2.0 * k * m.dt;
                assert!((next - expected).abs() <= 1e-12 * expected.abs(), "step {}: {next} vs {expected}", m.steps);
                checked += 1;
            }
            alpha = next;
        }
        let kinetic = m.snapshot(&b).expect("snapshot").energies(&s.params.material).0;
        m.advance(&b, 2).expect("past the ramp");
        let after = b.read(&m.nodes.damping).expect("damping")[0];
        (alpha, after, kinetic, checked)
    };
    let (alpha, after, damped, checked) = run("damping.feedback=1000");
    assert!(checked > 1000 && alpha > 0.0, "{checked} steps checked, α_g = {alpha} at the ramp's end");
    assert_eq!(after, 0.0, "the damping is off after the ramp");
    let (off, _, free, _) = run("damping.feedback=0");
    assert_eq!(off, 0.0, "no feedback, no damping");
    assert!(damped < free, "kinetic energy at the ramp's end: {damped} J/m damped against {free} J/m");
    eprintln!("α_g = {alpha:.4e} 1/s at the ramp's end; kinetic energy {damped:.4e} J/m against {free:.4e} J/m");
}

/// The contact normals (docs/mpm.md "Which face's normal"): along the crack, the chip's material (above the cut
/// plane: a node's own field above it, the other field below it) takes the rake face's normal and the workpiece's
/// the flank's, wherever the node lies about the cutting edge; beyond the crack's ends, the node's side of the
/// wedge's bisector decides (ahead of the edge: the rake's; below and behind it: the flank's).
#[test]
fn contact_normals_follow_the_fields_side_of_the_crack() {
    let scene = MpmScene::load("cases/mpm/nairn-cut.toml", &[]).expect("scene");
    let p = setup(&scene).expect("setup").params;
    let (rake, flank) = (p.rake_normal, p.flank_normal);
    let alpha = scene_rake(&scene).to_radians();
    assert!((rake[0] + alpha.cos()).abs() < 1e-15 && (rake[1] + alpha.sin()).abs() < 1e-15, "{rake:?}");
    let tip = [p.crack_lo + 10.0 * p.dx, p.crack_y];
    let h = 0.5 * p.dx;
    for x in [tip[0] - 3.0 * p.dx, tip[0], tip[0] + 3.0 * p.dx] {
        let (up, down) = ([x, p.crack_y + h], [x, p.crack_y - h]);
        assert_eq!(p.tool_normal(up, tip, 0), rake, "chip field above the plane at x = {x}");
        assert_eq!(p.tool_normal(up, tip, 1), flank, "workpiece field above the plane at x = {x}");
        assert_eq!(p.tool_normal(down, tip, 0), flank, "workpiece field below the plane at x = {x}");
        assert_eq!(p.tool_normal(down, tip, 1), rake, "chip field below the plane at x = {x}");
    }
    // Beyond the crack's far end, by the bisector: ahead of the edge the rake's, below and behind it the flank's.
    let far = [p.crack_hi + 5.0 * p.dx, p.crack_y];
    for field in [0, 1] {
        assert_eq!(p.tool_normal([far[0] + p.dx, far[1] + h], far, field), rake);
        assert_eq!(p.tool_normal([far[0] - 2.0 * p.dx, far[1] - h], far, field), flank);
    }
}

/// The field a specimen particle joins at a node (`MpmParams::field_of`): across the crack, the other side's; a
/// workpiece particle a cell above the plane still joins its own side (the other field at a node above), but one
/// more than `STRAY_CELLS` cells above has left the faces and joins the chip's field there, and the workpiece's
/// other field below the plane (docs/mpm.md "Stray particles"); beyond the crack's end the sides are one body.
#[test]
fn a_particle_far_across_the_plane_joins_the_side_it_is_in() {
    use swarf::kernels::mpm::grid::{ABOVE, BELOW, STRAY_CELLS};
    let scene = MpmScene::load("cases/mpm/nairn-cut.toml", &[]).expect("scene");
    let p = setup(&scene).expect("setup").params;
    let x = p.crack_lo + 20.0 * p.dx;
    let (node_up, node_down) = ([x + 0.3 * p.dx, p.crack_y + 0.5 * p.dx], [x + 0.3 * p.dx, p.crack_y - 0.5 * p.dx]);
    // Each on its side: its own field at its side's nodes, the other field across.
    assert_eq!(p.field_of(ABOVE, x, p.crack_y + 0.25 * p.dx, node_up), 0);
    assert_eq!(p.field_of(ABOVE, x, p.crack_y + 0.25 * p.dx, node_down), 1);
    assert_eq!(p.field_of(BELOW, x, p.crack_y - 0.25 * p.dx, node_up), 1);
    // A workpiece particle a cell above the plane keeps its side.
    assert_eq!(p.field_of(BELOW, x, p.crack_y + p.dx, node_up), 1);
    assert_eq!(p.field_of(BELOW, x, p.crack_y + p.dx, node_down), 0);
    // Past the band it is in the chip: the chip's field above, the other field below.
    let far = p.crack_y + (STRAY_CELLS + 0.5) * p.dx;
    let node_far = [x, far + 0.5 * p.dx];
    assert_eq!(p.field_of(BELOW, x, far, node_far), 0);
    assert_eq!(p.field_of(BELOW, x, far, node_up), 0);
    assert_eq!(p.field_of(BELOW, x, far, node_down), 1);
    // And a chip particle pushed far below the plane joins the workpiece's.
    let deep = p.crack_y - (STRAY_CELLS + 0.5) * p.dx;
    assert_eq!(p.field_of(ABOVE, x, deep, node_down), 0);
    assert_eq!(p.field_of(ABOVE, x, deep, node_up), 1);
    // Beyond the crack's end no field parts them.
    let beyond = p.crack_hi + 3.0 * p.dx;
    assert_eq!(p.field_of(BELOW, beyond, p.crack_y - 0.25 * p.dx, [beyond, p.crack_y + 0.5 * p.dx]), 0);
}

/// A particle alone on its nodes is a fragment and unloads in one step: σ = 0 and B̄_e = I exactly, and its own
/// stress moves it by nothing (the forces on its nodes sum to zero: |v| < 1e-9 m/s). The same B̄_e inside the
/// block and at its corner keeps its stress: σ_xy = G dev B̄_e,xy / J within 1 % after one step (Eq. 1's Kirchhoff
/// stress; the neighbours' reaction moves it by much less). docs/mpm.md "Fragments".
#[test]
fn a_particle_alone_on_its_nodes_unloads_and_the_material_keeps_its_stress() {
    use common::mpm_fragment::{BE, fragment_setup, fragment_solver};
    let b = CpuBackend::new();
    let (s, f) = fragment_setup();
    let mut m = fragment_solver::<CpuBackend, f64>(&b, &s, &f);
    m.advance(&b, 1).expect("a step");
    let snap = m.snapshot(&b).expect("snapshot");
    assert_eq!(snap.stress[f.lone], [0.0; 4], "the fragment keeps a stress");
    assert_eq!(snap.be[f.lone], [1.0, 0.0, 1.0, 1.0], "the fragment keeps its elastic strain");
    let g = s.params.material.shear;
    for (what, i) in [("interior", f.interior), ("corner", f.corner)] {
        let want = g * BE[1] / snap.jac[i];
        let got = snap.stress[i][1];
        assert!((got - want).abs() < 0.01 * want, "{what}: σ_xy {got} Pa against {want} Pa");
    }
    m.advance(&b, 10).expect("steps");
    let v = m.snapshot(&b).expect("snapshot").vel[f.lone];
    assert!(v[0].hypot(v[1]) < 1e-9, "the fragment moves at {v:?} m/s");
}

fn scene_rake(scene: &MpmScene) -> f64 {
    match scene.setup {
        swarf::scene::mpm::Setup::Cut(c) => c.rake,
        swarf::scene::mpm::Setup::Bond(_) => panic!("a cut"),
    }
}

/// An MPM checkpoint (host/mpm/checkpoint.rs) restores the state bit for bit: a short cut with the start-up
/// damping stepped 1 000 steps, saved, restored into a new solver and stepped 1 000 more equals the same cut
/// stepped 2 000 steps at once (every stateful buffer and the clock), and the last sample's tallies come back.
#[test]
fn an_mpm_checkpoint_restores_the_state_bitwise() {
    use swarf::mpm::checkpoint;
    use swarf::mpm::solver::Tallies;
    let sets: Vec<String> =
        ["cut.particles_across=7", "cut.cut_length=2.0", "time.end=1.3e-3"].iter().map(|s| s.to_string()).collect();
    let scene = MpmScene::load("cases/mpm/nairn-cut.toml", &sets).expect("scene");
    let s = setup(&scene).expect("setup");
    let b = CpuBackend::new();
    let new = || MpmSolver::<CpuBackend, f64>::new(&b, &s, 1.0).expect("solver");
    let mut whole = new();
    whole.advance(&b, 2000).expect("advance");
    let mut first = new();
    first.advance(&b, 1000).expect("advance");
    let dir = std::env::temp_dir().join(format!("swarf-mpm-ck-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("folder");
    let last = (first.time, Tallies { tool: [1.0, -2.0], grip: [0.5, 0.25], work: 3.0 });
    checkpoint::save(&b, &first, &dir, &sets, 3, &last).expect("save");
    let mut resumed = new();
    assert_eq!(checkpoint::restore(&b, &mut resumed, &dir).expect("restore"), last);
    assert_eq!((resumed.time.to_bits(), resumed.steps), (first.time.to_bits(), 1000));
    resumed.advance(&b, 1000).expect("advance");
    assert_eq!(resumed.save_state(&b).expect("state"), whole.save_state(&b).expect("state"), "the state differs");
    assert_eq!((resumed.time.to_bits(), resumed.steps), (whole.time.to_bits(), whole.steps));
    let header = checkpoint::header(&dir).expect("header");
    assert_eq!((header.overrides, header.frame, header.precision.as_str()), (sets, 3, "f64"));
    // A checkpoint of another scene (another Δt) is refused, saying so.
    let other = setup(&MpmScene::load("cases/mpm/nairn-cut.toml", &["cut.particles_across=9".into()]).expect("scene"))
        .expect("setup");
    let mut wrong = MpmSolver::<CpuBackend, f64>::new(&b, &other, 1.0).expect("solver");
    let e = checkpoint::restore(&b, &mut wrong, &dir).expect_err("another scene").to_string();
    assert!(e.contains("checkpoint.bin") && e.contains("particles"), "{e}");
    let _ = std::fs::remove_dir_all(dir);
}

/// Ctrl-C stops an MPM run with a checkpoint (exit status 130) and `swarf run --resume` finishes it: the bonded
/// block's forces.csv and released energy equal the uninterrupted run's byte for byte.
#[test]
fn an_interrupted_mpm_run_resumes_to_the_same_bytes() {
    use std::process::Command;
    let bin = env!("CARGO_BIN_EXE_swarf");
    let root = std::env::temp_dir().join(format!("swarf-mpm-resume-{}", std::process::id()));
    let (a, b) = (root.join("a"), root.join("b"));
    let run = |out: &std::path::Path| {
        Command::new(bin)
            .args(["--backend", "cpu", "run", "cases/mpm/bond-mode1.toml", "--quiet", "--force", "--out"])
            .arg(out)
            .spawn()
            .expect("swarf")
    };
    assert!(run(&a).wait().expect("run").success());
    let mut child = run(&b);
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let _ = Command::new("kill").args(["-INT", &child.id().to_string()]).status();
    let code = child.wait().expect("run").code();
    if code == Some(0) {
        return; // finished before the signal (a faster machine than expected): nothing to resume
    }
    assert_eq!(code, Some(130), "Ctrl-C must exit with 130 after writing the checkpoint");
    assert!(b.join("checkpoint.bin").is_file() && !b.join("summary.json").exists());
    let st =
        Command::new(bin).args(["--backend", "cpu", "run", "--quiet", "--resume"]).arg(&b).status().expect("swarf");
    assert!(st.success(), "resume failed");
    let read = |d: &std::path::Path, f: &str| std::fs::read(d.join(f)).expect(f);
    assert_eq!(read(&a, "forces.csv"), read(&b, "forces.csv"), "forces.csv differs");
    let released = |d: &std::path::Path| {
        let v: serde_json::Value = serde_json::from_slice(&read(d, "summary.json")).expect("json");
        v["released"]["per_area"].as_f64().expect("released energy")
    };
    assert_eq!(released(&a).to_bits(), released(&b).to_bits());
    let _ = std::fs::remove_dir_all(root);
}

// V14's glyph coverage (host/mpm/coverage.rs) on lattices moved by hand.
use swarf::mpm::coverage::coverage;
use swarf::mpm::output::Snapshot;

fn lattice(n: usize, side: f64, f: [f64; 4], drop: Option<usize>) -> Snapshot {
    let mut s = Snapshot::default();
    for j in 0..n {
        for i in 0..n {
            if Some(j * n + i) == drop {
                continue;
            }
            let x0 = [(i as f64 + 0.5) * side, (j as f64 + 0.5) * side];
            s.pos.push([f[0] * x0[0] + f[1] * x0[1], f[2] * x0[0] + f[3] * x0[1]]);
            s.def.push(f);
            s.jac.push(f[0] * f[3] - f[1] * f[2]);
            s.vol0.push(side * side);
            s.kind.push(0);
        }
    }
    s
}

/// A lattice moved by a homogeneous F (shear 0.7, stretch 1.3) tiles its image: the union is Σ J V0 within
/// the raster's edge error (the boundary's pixels, 1 % here) and no gap; with one particle removed from the
/// middle, a gap of one domain (within 3 %).
#[test]
fn an_affine_motion_tiles_and_a_missing_particle_is_a_gap() {
    let f = [1.3, 0.7, 0.0, 0.9];
    let c = coverage(&lattice(20, 1e-4, f, None), |_| true).expect("coverage");
    assert!(c.mismatch < 0.01 && c.gap_count == 0, "{c:?}");
    let c = coverage(&lattice(20, 1e-4, f, Some(10 * 20 + 10)), |_| true).expect("coverage");
    let domain = 1e-8 * (f[0] * f[3] - f[1] * f[2]);
    assert!(c.gap_count == 1 && (c.gaps / domain - 1.0).abs() < 0.03, "{c:?}");
}

/// Domains drawn at 1.2 times their spacing overlap: the union falls 1 − 1/1.44 short, less the boundary.
#[test]
fn overlapping_domains_fall_short_of_their_volume() {
    let mut s = lattice(20, 1e-4, [1.0, 0.0, 0.0, 1.0], None);
    s.def.iter_mut().for_each(|f| *f = [1.2, 0.0, 0.0, 1.2]);
    s.jac.iter_mut().for_each(|j| *j = 1.44);
    let c = coverage(&s, |_| true).expect("coverage");
    // The union is the lattice's square grown by 0.1 of a side all round: (20.2/20)² of 400 domains.
    let expected = 1.0 - (20.2f64 / 20.0).powi(2) / 1.44;
    assert!((c.mismatch - expected).abs() < 0.01, "{} vs {expected}", c.mismatch);
}
