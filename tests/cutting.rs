//! Cutting on the CPU: the rigid tool's contact inside a run (klippel-constitutive.md §8 H15: a block dropped on the
//! tool penetrates less than 0.1 Δx, without an energy blow-up), a short coarse orthogonal cut (force signs,
//! magnitude and stability; the CI check of issue 5), the thermal tool particles (roethlin-solver.md AT-91), and
//! the scene's refusals of a tool that overlaps or never meets the workpiece.

use crate::common;

use common::scenes::{STEP_CONTACT, drop_scene, plastic_drop_scene};
use swarf::backend::{AnyBackend, BackendChoice};
use swarf::run::{RunOptions, Snapshot, run, run_observed};
use swarf::scene::Scene;

fn opts(tag: &str) -> RunOptions {
    RunOptions::quiet(std::env::temp_dir().join(format!("swarf-test-cutting-{tag}-{}", std::process::id())))
}

fn cpu() -> AnyBackend {
    AnyBackend::select(BackendChoice::Cpu).expect("cpu").0
}

/// H15 (klippel-constitutive.md §8): a block dropped on the rigid tool penetrates less than 0.1 Δx for κ in the
/// chosen range (0.05–0.5), with μ from 0 to 1 and a sliding component, and the energy never rises above its
/// initial value (the penalty contact stores energy only while penetrated; friction dissipates).
#[test]
fn dropped_block_penetrates_less_than_a_tenth_of_the_spacing() {
    let dx = 1.0e-5;
    for (speed, kappa, mu, slide) in
        [(20.0, 0.1, 0.0, 0.0), (50.0, 0.1, 0.35, 10.0), (50.0, 0.05, 1.0, 20.0), (20.0, 0.5, 0.35, 0.0)]
    {
        let scene =
            Scene::from_str(&drop_scene(speed, kappa, mu, slide), "cases/cutting/drop.toml", &[]).expect("scene");
        let tool = swarf::cutting::setup::build_tool(scene.tool.as_ref().expect("tool")).expect("tool");
        let mut depth = 0.0f64;
        let mut e0 = None;
        let mut e_max = 0.0f64;
        let mut touched = false;
        let mut obs = |s: &Snapshot| {
            for p in &s.pos {
                let d = -tool.closest([p[0], p[1]]).distance;
                depth = depth.max(d);
                touched |= d > 0.0;
            }
            let e = s.diagnostics.total();
            let e0 = *e0.get_or_insert(e);
            e_max = e_max.max(e / e0);
            true
        };
        run_observed(&cpu(), &scene, &opts("drop"), Some(&mut obs)).expect("the drop runs");
        assert!(touched, "the block must reach the tool (v = {speed} m/s)");
        assert!(
            depth < 0.1 * dx,
            "κ = {kappa}, μ = {mu}, v = {speed} m/s: the largest penetration is {:.4} Δx, above 0.1 Δx (H15)",
            depth / dx
        );
        assert!(e_max <= 1.0 + 1e-3, "κ = {kappa}, μ = {mu}: the energy rose to {e_max} of its initial value");
    }
}

/// The CI cut: V0060 coarsened to Δx = 20 µm (5 particles per uncut chip thickness), 0.15 mm of cut.
/// Facts checked: the run stays finite to the end (a non-finite value would stop it with an error), the cutting
/// and feed forces are positive, F_c is of the measured order (157.5 N/mm, klippel-constitutive.md §5.3: within
/// a factor of two at this resolution), F_f < F_c as measured (115.5 < 157.5), and a chip is formed above the
/// uncut surface.
#[test]
fn short_coarse_cut_has_forces_of_the_right_sign_and_order() {
    let scene = common::scenes::coarse_cut(&["time.end=2.4e-5", "output.every=2.4e-6"]);
    let o = opts("coarse");
    let r = run(&cpu(), &scene, &o).expect("the coarse cut runs to its end without a non-finite value");
    assert!(r.steps > 4000, "{} steps", r.steps);
    let text = std::fs::read_to_string(o.out_dir.join("summary.json")).expect("summary.json");
    let v: serde_json::Value = serde_json::from_str(&text).expect("json");
    for key in ["particles", "steps", "wall_time_s", "backend", "device", "precision"] {
        assert!(!v[key].is_null(), "summary.json lacks {key}");
    }
    let fc = v["fc_n_per_mm"].as_f64().expect("fc_n_per_mm");
    let ff = v["ff_n_per_mm"].as_f64().expect("ff_n_per_mm");
    assert!(fc > 0.5 * 157.5 && fc < 2.0 * 157.5, "F_c = {fc} N/mm");
    assert!(ff > 0.0 && ff < fc, "F_f = {ff} N/mm against F_c = {fc} N/mm");
    let (head, rows) = swarf::output::csv::read(&o.out_dir.join("forces.csv")).expect("forces.csv");
    assert_eq!(head, swarf::cutting::record::FORCE_COLUMNS);
    assert!(rows.len() > 50, "{} force samples", rows.len());
    assert!(rows.iter().all(|r| r[2].is_finite() && r[3].is_finite()));
}

/// AT-91 (roethlin-solver.md §10.6): with the thermal tool, the held particles of the tool and the fixed bottom
/// of the workpiece stay at exactly 300 K, no temperature exceeds the melt temperature, and the tool heats up
/// near the contact zone (heat flows from the chip into the tool).
#[test]
fn thermal_tool_heats_near_the_contact_and_holds_its_far_boundary() {
    let over: Vec<String> = [
        "discretisation.dx=2.0e-5",
        "body.0.max=[1.0e-3,2.8e-4]",
        "boundary.0.max=[1.0,1.0e-9]",
        "boundary.1.max=[1.0e-9,1.4e-4]",
        "boundary.2.min=[0.9999e-3,-1.0]",
        "tool.position=[-2.2e-5,2.1e-4]",
        "time.end=6.0e-5",
        "output.every=1.0e-5",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let scene = Scene::load("cases/cutting/reference-cut.toml", &over).expect("scene");
    let set = swarf::run::setup::<f64, swarf::kernels::Dim2>(&scene).expect("setup");
    let tool_body = scene.bodies.len() as u32;
    let held: std::collections::HashSet<u32> = (0..set.particles.len())
        .filter(|&i| {
            let f = set.particles.flags[i];
            f & swarf::kernels::sph::params::flags::FIXED_TEMPERATURE != 0
        })
        .map(|i| set.particles.id[i])
        .collect();
    assert!(!held.is_empty());
    let melt = 1836.0;
    let mut tool_max = 0.0f64;
    let mut obs = |s: &Snapshot| {
        let t = s.temperature.expect("temperature");
        for (i, &ti) in t.iter().enumerate() {
            assert!(ti <= melt, "particle {} at {ti} K above the melt temperature", s.id[i]);
            if held.contains(&s.id[i]) {
                assert_eq!(ti, 300.0, "held particle {} left 300 K", s.id[i]);
            } else if s.body[i] == tool_body {
                tool_max = tool_max.max(ti);
            }
        }
        true
    };
    run_observed(&cpu(), &scene, &opts("thermal"), Some(&mut obs)).expect("the thermal cut runs");
    assert!(tool_max > 301.0, "the tool must heat near the contact (max {tool_max} K)");
}

/// A tool overlapping the workpiece at t = 0 and a tool that never reaches it are refused before the run, with
/// the file and the key.
#[test]
fn misplaced_tools_are_refused() {
    let inside = Scene::load("cases/cutting/v0060.toml", &["tool.position=[2.0e-4]".into()]).expect("scene");
    let e = swarf::run::setup::<f64, swarf::kernels::Dim2>(&inside).err().expect("refused").to_string();
    assert!(e.contains("cases/cutting/v0060.toml") && e.contains("tool.position"), "{e}");
    let away = Scene::load("cases/cutting/v0060.toml", &["tool.velocity=[-6.355,0.0]".into()]).expect("scene");
    let e = swarf::run::setup::<f64, swarf::kernels::Dim2>(&away).err().expect("refused").to_string();
    assert!(e.contains("never meets the workpiece"), "{e}");
}

/// Issue 7: the conduction summed in the interaction's neighbour walk (the fused pass) equals the separate
/// conduction pass bit for bit, on the thermal-tool reference cut with a temperature gradient across the tool and
/// the workpiece (so that every pair term is non-zero), with one lane and with eight. Both passes visit the same
/// candidates in the same order and add the same terms (sph::interact::rates_heat), so equality is exact.
#[test]
fn fused_conduction_equals_the_separate_pass() {
    use swarf::backend::CpuBackend;
    use swarf::kernels::{Dim2, Vector};
    use swarf::run::setup;
    use swarf::solver::Solver;
    let scene = Scene::load("cases/cutting/reference-cut.toml", &[]).expect("scene");
    let mut s = setup::<f64, Dim2>(&scene).expect("setup");
    // 300 K + 2 K per µm along x and y: heat flows across every pair, tool–workpiece pairs included.
    let t: Vec<f64> = s.particles.pos.iter().map(|p| 300.0 + 2.0e6 * (p.get(0) + p.get(1))).collect();
    s.temperature = Some(t.clone());
    let b = CpuBackend::new();
    let steps = 12;
    let run = |fuse: bool, lanes: u32| {
        let mut sv = Solver::<CpuBackend, f64, Dim2>::new(&b, &s).expect("solver");
        sv.fuse_conduction = fuse;
        sv.lanes = lanes;
        sv.advance(&b, s.dt, steps).expect("steps");
        let (temp, _, _) = sv.download_internal(&b).expect("internal");
        (sv.download(&b).expect("state"), temp.expect("temperature"))
    };
    for lanes in [1, 8] {
        let (a, ta) = run(true, lanes);
        let (c, tc) = run(false, lanes);
        assert!(a.bitwise_eq(&c), "{lanes} lanes: fused state differs from the separate passes");
        assert!(ta.iter().zip(&tc).all(|(x, y)| x.to_bits() == y.to_bits()), "{lanes} lanes: temperatures differ");
        // Not vacuous: conduction smooths the field, so the temperatures' spread (order-independent) shrank.
        let var = |v: &[f64]| {
            let m = v.iter().sum::<f64>() / v.len() as f64;
            v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / v.len() as f64
        };
        let (v0, v1) = (var(&t), var(&ta));
        assert!(v1 < v0 * (1.0 - 1e-9), "{lanes} lanes: conduction did not act (variance {v0} -> {v1} K²)");
    }
}

/// The pre-pass fused into the predictor and the contact pass fused into the plastic corrector's launch
/// (`Solver::fuse_prepare`, `Solver::fuse_contact`, the defaults) end bit for bit where the separate passes end: a
/// Ti6Al4V block dropped at 50 m/s with a sliding component onto the tool (rebuilding its cell list as it moves),
/// plastic with heating, the CURRENT friction cap (the yield stresses of the same step's return), friction heating
/// and the Usui wear output, until it has touched the tool and yielded.
#[test]
fn fused_prepass_and_contact_equal_the_separate_passes() {
    // The step law (the block yields), then the default damped bulk law (it touches, its contact fused or not).
    for (text, must_yield) in [(plastic_drop_scene(), true), (plastic_drop_scene().replace(STEP_CONTACT, ""), false)] {
        fused_drop_equals_separate(&text, must_yield);
    }
}

/// [`fused_prepass_and_contact_equal_the_separate_passes`] on one scene text.
fn fused_drop_equals_separate(text: &str, must_yield: bool) {
    use swarf::backend::CpuBackend;
    use swarf::kernels::Dim2;
    use swarf::run::setup;
    use swarf::solver::Solver;
    let scene = Scene::from_str(text, "cases/cutting/drop.toml", &[]).expect("scene");
    let s = setup::<f64, Dim2>(&scene).expect("setup");
    let b = CpuBackend::new();
    let run = |fuse: bool| {
        let mut sv = Solver::<CpuBackend, f64, Dim2>::new(&b, &s).expect("solver");
        (sv.fuse_contact, sv.fuse_prepare) = (fuse, fuse);
        let mut touched = 0;
        for _ in 0..40 {
            sv.advance(&b, s.dt, 10).expect("steps");
            touched = touched.max(sv.contact_sample(&b).expect("sample").expect("a tool").contacts);
        }
        let (temp, eps, _) = sv.download_internal(&b).expect("internal");
        let sample = sv.contact_sample(&b).expect("sample").expect("a tool");
        (sv.download(&b).expect("state"), temp.expect("temperature"), eps.expect("plastic strain"), touched, sample)
    };
    let (a, ta, ea, touched, fa) = run(true);
    let (c, tc, ec, _, fc) = run(false);
    assert!(touched > 0, "the block never touched the tool: the contact is not exercised");
    assert!(
        !must_yield || ea.iter().any(|e| *e > 0.0),
        "nothing yielded: the plastic corrector's contact is not exercised"
    );
    assert!(a.bitwise_eq(&c), "fused passes: the state differs from the separate passes");
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<u64>>();
    assert_eq!(bits(&ta), bits(&tc), "fused passes: temperatures differ");
    assert_eq!(bits(&ea), bits(&ec), "fused passes: plastic strains differ");
    assert_eq!(
        (fa.force[0].to_bits(), fa.force[1].to_bits(), fa.contacts, fa.wear_rate.to_bits()),
        (fc.force[0].to_bits(), fc.force[1].to_bits(), fc.contacts, fc.wear_rate.to_bits()),
        "fused passes: the tool's force or wear differs"
    );
    let yielded = ea.iter().filter(|e| **e > 0.0).count();
    eprintln!("fused pre-pass and contact: up to {touched} particles in contact, {yielded} yielded; bitwise equal");
}

/// The Verlet list (docs/neighbour-search.md, "Verlet list") holds each particle's candidates in the order the
/// stencil walk visits them, so with one lane per particle the sums, and the whole run, are bitwise those of the
/// stencil walk when both rebuild at the same steps (skin 0: whenever anything moved); with eight lanes the
/// candidates are dealt to the lanes differently (the list leaves out the far ones), and the runs agree to
/// round-off. On the thermal reference cut (fused conduction, a temperature gradient across every pair) and the
/// 1000 m/s impact (plastic, rebuilding every step).
#[test]
fn verlet_list_sums_equal_the_stencil_walk() {
    use swarf::backend::CpuBackend;
    use swarf::kernels::{Dim2, Vector};
    use swarf::run::setup;
    use swarf::solver::Solver;
    let b = CpuBackend::new();
    let cases: [(&str, &[&str]); 2] =
        [("cases/cutting/reference-cut.toml", &[]), ("cases/impact.toml", &["discretisation.dx=2e-3"])];
    for (file, extra) in cases {
        let run = |verlet: bool, lanes: u32| {
            let mut o: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
            o.push("discretisation.skin_over_h=0".into());
            o.push(format!("discretisation.verlet_list={verlet}"));
            let scene = Scene::load(file, &o).expect("scene");
            let mut s = setup::<f64, Dim2>(&scene).expect("setup");
            assert_eq!(s.grid.list_capacity > 0, verlet, "{file}: the scene key did not reach the grid");
            if let Some(t) = s.temperature.as_mut() {
                for (ti, p) in t.iter_mut().zip(&s.particles.pos) {
                    *ti = 300.0 + 2.0e6 * (p.get(0) + p.get(1));
                }
            }
            let mut sv = Solver::<CpuBackend, f64, Dim2>::new(&b, &s).expect("solver");
            sv.lanes = lanes;
            sv.advance(&b, s.dt, 30).expect("steps");
            let (temp, _, _) = sv.download_internal(&b).expect("internal");
            (sv.download(&b).expect("state"), temp, sv.cell_rebuilds(&b).expect("rebuilds"), scene.discretisation.dx)
        };
        let (a, ta, ra, dx) = run(true, 1);
        let (c, tc, rc, _) = run(false, 1);
        assert_eq!(ra, rc, "{file}: the two runs rebuilt at different steps");
        assert!(a.bitwise_eq(&c), "{file}: one lane: the Verlet list's run differs from the stencil walk's");
        let bits = |t: &Option<Vec<f64>>| t.as_ref().map(|t| t.iter().map(|x| x.to_bits()).collect::<Vec<_>>());
        assert!(bits(&ta) == bits(&tc), "{file}: one lane: temperatures differ");
        let (a8, ta8, _, _) = run(true, 8);
        let (c8, tc8, _, _) = run(false, 8);
        let dpos = a8
            .pos
            .iter()
            .zip(&c8.pos)
            .map(|(p, q)| (0..2).map(|k| (p.get(k) - q.get(k)).abs()).fold(0.0, f64::max))
            .fold(0.0, f64::max);
        eprintln!("{file}: {ra} rebuilds in 30 steps; eight lanes: max |Δx| = {:.2e} dx", dpos / dx);
        assert!(dpos < 1e-9 * dx, "{file}: eight lanes: positions differ by {:.2e} dx", dpos / dx);
        // Not vacuous: with eight lanes the list deals other candidates to the lanes than the stencil walk, so
        // bitwise equal eight-lane runs would mean that the list was never read (the reference cut's workpiece is
        // at rest before the tool arrives: its temperatures tell).
        assert!(
            !(a8.bitwise_eq(&c8) && bits(&ta8) == bits(&tc8)),
            "{file}: eight lanes: the list's run is bitwise the stencil's: list unused?"
        );
    }
}

/// The cell list's skin (docs/neighbour-search.md, "Skin") decides when the list is rebuilt, not what a step
/// computes: runs with the default skin (0.1 h) and with none (a rebuild whenever anything moved) end within
/// round-off of each other (the neighbour sums are only added in another order), particle by particle, and the
/// skin saves rebuilds: on the reference cut, where the particles move about 10⁻³ h per step, only the forced
/// first one; on the 1000 m/s impact the skin test itself triggers rebuilds, every few steps.
#[test]
fn skin_saves_rebuilds_and_changes_results_by_round_off_only() {
    use swarf::backend::CpuBackend;
    use swarf::kernels::{Dim2, Vector};
    use swarf::run::setup;
    use swarf::solver::Solver;
    let b = CpuBackend::new();
    let cases: [(&str, &[&str], usize); 2] =
        [("cases/cutting/reference-cut.toml", &[], 60), ("cases/impact.toml", &["discretisation.dx=2e-3"], 60)];
    for (file, extra, steps) in cases {
        let run = |skin: f64| {
            let mut o: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
            o.push(format!("discretisation.skin_over_h={skin}"));
            let scene = Scene::load(file, &o).expect("scene");
            let s = setup::<f64, Dim2>(&scene).expect("setup");
            let mut sv = Solver::<CpuBackend, f64, Dim2>::new(&b, &s).expect("solver");
            sv.advance(&b, s.dt, steps).expect("steps");
            let mut st = sv.download(&b).expect("state");
            // In scene order (the two runs reorder at different steps).
            let mut order: Vec<usize> = (0..st.id.len()).collect();
            order.sort_by_key(|&i| st.id[i]);
            st.pos = order.iter().map(|&i| st.pos[i]).collect();
            st.stress = order.iter().map(|&i| st.stress[i]).collect();
            (st, sv.cell_rebuilds(&b).expect("rebuilds"), scene.discretisation.dx)
        };
        let (a, ra, dx) = run(0.1);
        let (c, rc, _) = run(0.0);
        assert_eq!(rc as usize, steps, "{file}: without a skin every step rebuilds");
        let dpos =
            a.pos.iter().zip(&c.pos).map(|(p, q)| (0..2).map(|k| (p.get(k) - q.get(k)).abs()).fold(0.0, f64::max));
        let dpos = dpos.fold(0.0, f64::max);
        let smax = c.stress.iter().map(|s| s.0.iter().map(|v| v.abs()).fold(0.0, f64::max)).fold(0.0, f64::max);
        let dstress = a
            .stress
            .iter()
            .zip(&c.stress)
            .map(|(p, q)| p.0.iter().zip(&q.0).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max))
            .fold(0.0, f64::max);
        eprintln!(
            "{file}: rebuilds {ra} (skin) / {rc}; max |Δx| = {:.2e} dx, max |ΔS| = {:.2e} of max |S|",
            dpos / dx,
            dstress / smax
        );
        assert!(dpos < 1e-9 * dx, "{file}: positions differ by {:.2e} dx", dpos / dx);
        if file.contains("impact") {
            assert!(smax > 0.0, "{file}: no stress: the comparison would be vacuous");
            assert!(dstress < 1e-6 * smax, "{file}: stresses differ by {:.2e} of the largest", dstress / smax);
            assert!(
                ra > 1 && (ra as usize) < steps,
                "{file}: the skin test should trigger some rebuilds, not all ({ra})"
            );
        } else {
            // The tool approaches the workpiece (no contact yet) at a small fraction of h per step.
            assert_eq!(ra, 1, "{file}: only the first step should rebuild");
        }
    }
}

/// A non-finite position is flagged by the predictor of the step that produces it (the run loop reads the flag
/// after each batch and stops with its report, instead of stepping on to its next output with non-finite particles
/// that rebuild the cell list every step): clean steps leave the flag clear; one NaN coordinate sets it, and the
/// skin test sends that particle to the void bucket at once.
#[test]
fn predictor_flags_a_non_finite_position() {
    use swarf::backend::{Backend, CpuBackend};
    use swarf::kernels::{Dim2, Vector};
    use swarf::run::setup;
    use swarf::solver::Solver;
    let scene = Scene::load("cases/cutting/reference-cut.toml", &[]).expect("scene");
    let s = setup::<f64, Dim2>(&scene).expect("setup");
    let b = CpuBackend::new();
    let mut sv = Solver::<CpuBackend, f64, Dim2>::new(&b, &s).expect("solver");
    sv.advance(&b, s.dt, 40).expect("steps");
    assert!(!sv.non_finite_seen(&b).expect("flags"), "clean steps flagged a non-finite position");
    let rebuilds = sv.cell_rebuilds(&b).expect("rebuilds");
    let mut pos = b.read(&sv.particles.pos.cur).expect("positions");
    pos[17] = <Dim2 as swarf::kernels::Dim>::Vec::<f64>::new([f64::NAN, pos[17].get(1), 0.0]);
    b.write(&mut sv.particles.pos.cur, &pos).expect("write");
    sv.step(&b, s.dt).expect("step");
    assert!(sv.non_finite_seen(&b).expect("flags"), "the NaN position was not flagged");
    assert_eq!(sv.cell_rebuilds(&b).expect("rebuilds"), rebuilds + 1, "the NaN particle did not trigger a rebuild");
}

/// A run that blows up reports the batch in which a position first went non-finite: the coarse V0060 cut with
/// its tool at 3 km/s (about half the sound speed, far beyond what the penalty contact holds; the ensemble's
/// failing member). The error names the steps (first, last) of that batch, the last being the step it stops
/// at, and how many particles went non-finite and where; the run folder keeps its earlier frames.
#[test]
fn a_blow_up_reports_the_batch_that_went_non_finite() {
    let scene = common::scenes::coarse_cut(&["tool.velocity=[3000.0,0.0]"]);
    let dir = std::env::temp_dir().join(format!("swarf-test-blowup-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let b = AnyBackend::select(BackendChoice::Cpu).expect("cpu").0;
    let err = run(&b, &scene, &RunOptions { frames: true, ..RunOptions::quiet(dir.clone()) }).expect_err("it blows up");
    let msg = err.to_string();
    match err {
        swarf::Error::NonFinite { step, flagged: Some((first, last)), ref region, .. } => {
            assert!(first <= last && last == step, "flagged steps {first}..{last}, stopped at {step}");
            assert!(msg.contains("first went non-finite"), "{msg}");
            // Where: how many particles went non-finite (at least the one named), and the box of those still at
            // a finite position.
            assert!(region.contains("particle(s) non-finite"), "no count of the non-finite particles: {msg}");
        }
        other => panic!("expected a non-finite stop flagged by the predictor, got: {other}"),
    }
    assert!(dir.join("particles.pvd").is_file(), "no frames kept: {msg}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The blow-up report's region (`solver::diagnostics::NonFiniteRegion`): it counts every non-finite particle and
/// boxes those whose position is still finite, exactly; an empty region adds nothing to the message.
#[test]
fn the_non_finite_region_counts_and_boxes_the_blown_up_particles() {
    use swarf::solver::diagnostics::NonFiniteRegion;
    let mut r = NonFiniteRegion::new(2);
    assert_eq!(r.describe(), "", "nothing non-finite, nothing said");
    r.note(Some([1.0e-4, -2.0e-5, 0.0]));
    r.note(None);
    r.note(Some([-3.0e-5, 4.0e-5, 0.0]));
    assert_eq!((r.count, r.located), (3, 2));
    assert_eq!((r.lo[0], r.hi[0], r.lo[1], r.hi[1]), (-3.0e-5, 1.0e-4, -2.0e-5, 4.0e-5));
    let d = r.describe();
    assert_eq!(
        d,
        "; 3 particle(s) non-finite, 2 of them with a finite position at x in [-3.0000e-5, 1.0000e-4], y in \
         [-2.0000e-5, 4.0000e-5] m"
    );
}
