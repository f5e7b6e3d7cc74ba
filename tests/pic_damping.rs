//! The PIC-damping analogue in SPH (issue 26, nairn-mpm.md §7.2; docs/mpm.md "Smoothed-velocity damping"): with
//! `stabilisation.xsph.pic`, each step the velocity gives up the fraction pic of its difference from the
//! kernel-smoothed velocity (Eq. 8 with v̄ for v_g→p, XSPH's sum).

use crate::common;

use swarf::run::{RunOptions, run, run_observed};
use swarf::scene::Scene;

fn scene(file: &str, overrides: &[&str]) -> Scene {
    Scene::load(file, &overrides.iter().map(|s| s.to_string()).collect::<Vec<_>>()).expect("scene")
}

/// A uniform velocity is its own smoothed velocity: the block of AT-60 translating at 100 m/s with every stabiliser
/// and the damping at its largest fraction keeps every velocity at exactly 100 m/s (bit for bit) and stays
/// stress-free (AT-60's |S| < 1e-9 E).
#[test]
fn smoothed_velocity_damping_leaves_a_translation_alone() {
    let s = scene("cases/block-translation.toml", &["stabilisation.xsph={epsilon=0.5, pic=0.5}"]);
    let dir = std::env::temp_dir().join(format!("swarf-pic-translation-{}", std::process::id()));
    let mut last: Option<Vec<[f64; 3]>> = None;
    let mut keep = |snap: &swarf::run::Snapshot| {
        last = Some(snap.vel.clone());
        true
    };
    let report = run_observed(&common::test_backend(), &s, &RunOptions::quiet(dir), Some(&mut keep)).expect("run");
    let vel = last.expect("a snapshot");
    assert!(vel.iter().all(|v| *v == [100.0, 0.0, 0.0]), "a velocity changed");
    let end = report.history.last().expect("outputs");
    assert!(end.elastic < 1e-12 * end.kinetic, "elastic energy {} against kinetic {}", end.elastic, end.kinetic);
}

/// The bonded blocks of V15 in mode I (cases/mpm/sph-bond-mode1.toml) with XSPH, without and with the damping at
/// pic = 0.5: the vibration the tearing leaves is damped (the elastic energy at the end falls more than fourfold;
/// measured 6.6e-3 → 8.4e-4 J/m), the plane releases the same energy (the bonds' work within 0.1 %; the law's
/// G_c either way) and the flying block's momentum stays (within 0.5 %: the held rows take the rest).
#[test]
fn smoothed_velocity_damping_damps_vibration_not_the_fracture() {
    let file = "cases/mpm/sph-bond-mode1.toml";
    let mut ends = Vec::new();
    for (k, ov) in ["stabilisation.xsph={epsilon=0.5}", "stabilisation.xsph={epsilon=0.5, pic=0.5}"].iter().enumerate()
    {
        let dir = std::env::temp_dir().join(format!("swarf-pic-bond-{k}-{}", std::process::id()));
        let h = run(&common::test_backend(), &scene(file, &[ov]), &RunOptions::quiet(dir)).expect("run").history;
        ends.push(h.last().expect("outputs").clone());
    }
    let (off, on) = (&ends[0], &ends[1]);
    eprintln!(
        "pic 0 / 0.5: elastic {:.3e} / {:.3e} J/m, bonds' work {:.5} / {:.5} J/m, momentum y {:.5} / {:.5}",
        off.elastic, on.elastic, off.cohesive_work, on.cohesive_work, off.momentum[1], on.momentum[1]
    );
    assert!(on.elastic < 0.25 * off.elastic, "vibration not damped: {} against {}", on.elastic, off.elastic);
    assert_eq!((off.bonds_failed, on.bonds_failed), (40.0, 40.0));
    assert!((on.cohesive_work / off.cohesive_work - 1.0).abs() < 1e-3, "released energy changed");
    assert!((on.momentum[1] / off.momentum[1] - 1.0).abs() < 5e-3, "momentum changed");
}

/// A fraction beyond the explicit relaxation's stable range is refused before any work, naming the key.
#[test]
fn an_unstable_pic_fraction_is_refused() {
    let ov = ["stabilisation.xsph={epsilon=0.5, pic=0.8}".to_string()];
    let e = Scene::load("cases/block-translation.toml", &ov).expect_err("pic 0.8 accepted").to_string();
    assert!(e.contains("stabilisation.xsph.pic") && e.contains("[0, 0.5]"), "{e}");
}
