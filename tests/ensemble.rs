//! Batched ensembles (host/ensemble, issue 23): members that differ in material, friction, tool geometry, speed,
//! feed and resolution give the same bits alone and in a batch, and a member that blows up stops alone with its
//! report while the others finish. On the CPU here; tests/gpu.rs repeats the bitwise check on a GPU.

use std::path::PathBuf;
use swarf::backend::{AnyBackend, BackendChoice};
use swarf::ensemble::run as run_ensemble;

use crate::common;
use common::scenes::{coarse_cut, ensemble_jobs as jobs, ensemble_members as members, run_record as record};

fn cpu() -> AnyBackend {
    AnyBackend::select(BackendChoice::Cpu).expect("cpu").0
}

fn dir(tag: &str) -> PathBuf {
    std::env::temp_dir().join(format!("swarf-test-ensemble-{tag}-{}", std::process::id()))
}

/// Each member of a batch of 7 run 4 at a time equals its run alone bit for bit (forces and energies at every
/// sample), and the members differ from each other (so that equality is not that of one repeated run).
#[test]
fn members_equal_their_solo_runs_bitwise() {
    let (solo_dir, batch_dir) = (dir("solo"), dir("batch"));
    let b = cpu();
    let solo = jobs(members(), &solo_dir);
    let batch = jobs(members(), &batch_dir);
    let mut ok = vec![false; solo.len()];
    run_ensemble(&b, &solo, 1, &mut |k, r| {
        ok[k] = r.is_ok();
        Ok(())
    })
    .expect("solo runs");
    assert!(ok.iter().all(|&o| o), "a solo run failed: {ok:?}");
    let mut order = Vec::new();
    run_ensemble(&b, &batch, 4, &mut |k, r| {
        assert!(r.is_ok(), "member {k}: {:?}", r.as_ref().err());
        order.push(k);
        Ok(())
    })
    .expect("batch");
    order.sort();
    assert_eq!(order, (0..solo.len()).collect::<Vec<_>>(), "every member reported once");
    let records: Vec<_> = solo.iter().map(|j| record(&j.options.out_dir)).collect();
    for (k, j) in batch.iter().enumerate() {
        assert!(record(&j.options.out_dir) == records[k], "member {k} differs from its solo run");
    }
    for k in 1..records.len() {
        assert!(records[k].0 != records[0].0, "member {k} has the model's forces: the change did nothing");
    }
    let _ = std::fs::remove_dir_all(solo_dir);
    let _ = std::fs::remove_dir_all(batch_dir);
}

/// A member whose tool moves at 3 km/s (about half the workpiece's sound speed: far beyond what the penalty
/// contact holds) stops with its error and report, alone: the two members beside it finish and equal their solo
/// runs.
#[test]
fn a_member_that_blows_up_stops_alone() {
    let root = dir("blowup");
    let b = cpu();
    let scenes = vec![coarse_cut(&[]), coarse_cut(&["tool.velocity=[3000.0,0.0]"]), coarse_cut(&["tool.friction=0.2"])];
    let batch = jobs(scenes, &root);
    let mut results: Vec<Option<String>> = vec![None; 3];
    run_ensemble(&b, &batch, 3, &mut |k, r| {
        results[k] = Some(match r {
            Ok(_) => "ok".to_string(),
            Err(e) => e.to_string(),
        });
        Ok(())
    })
    .expect("the ensemble itself does not fail");
    assert_eq!(results[0].as_deref(), Some("ok"));
    assert_eq!(results[2].as_deref(), Some("ok"));
    let why = results[1].clone().expect("member 1 reported");
    assert!(why != "ok", "the 3 km/s tool ran to its end");
    assert!(
        why.contains("non-finite") || why.contains("unstable") || why.contains("Δt"),
        "member 1's error does not say what happened: {why}"
    );
    let solo = jobs(vec![coarse_cut(&[])], &root.join("solo"));
    run_ensemble(&b, &solo, 1, &mut |_, r| {
        assert!(r.is_ok());
        Ok(())
    })
    .expect("solo");
    assert!(
        record(&batch[0].options.out_dir) == record(&solo[0].options.out_dir),
        "member 0 changed beside the failure"
    );
    let _ = std::fs::remove_dir_all(root);
}
