//! The field registry (`solver::fields`, issue 21 item 2): the memory estimate is its sum and equals the bytes the
//! CPU backend allocates for every scene of cases/, cases/cutting/ and cases/hard/ in every precision; the
//! checkpoint saves exactly the registered fields that exist, under the names checkpoints have always used; the
//! in-place reorder's fixed capacity holds the largest case.

use std::collections::BTreeSet;
use swarf::backend::CpuBackend;
use swarf::kernels::sph::TensorOps;
use swarf::kernels::{Dim2, Dim3, Real};
use swarf::scene::{Precision, Scene};
use swarf::solver::Solver;
use swarf::solver::fields::{Checkpoint, FIELDS, When, max_reorder_entries};
use swarf::state::{HostParticles, MAX_REORDER};

/// Builds the solver of `scene` in `R` on a fresh CPU backend and checks, exactly: the bytes `Solver::new`
/// allocates equal `check::memory_estimate`; `save_state` names the registered checkpointed fields whose condition
/// holds, in registry order; the frame fields likewise. Returns the conditions that held.
fn check_scene<R: Real, D: TensorOps<R>>(scene: &Scene, what: &str) -> Vec<When> {
    let s = swarf::run::setup::<R, D>(scene).unwrap_or_else(|e| panic!("{what}: {e}"));
    let b = CpuBackend::new();
    let before = b.allocated_bytes();
    let solver = Solver::<CpuBackend, R, D>::new(&b, &s).unwrap_or_else(|e| panic!("{what}: {e}"));
    let allocated = b.allocated_bytes() - before;
    assert_eq!(swarf::check::memory_estimate(&s), allocated, "{what}: estimate against the bytes allocated");
    let held: Vec<When> = When::ALL.into_iter().filter(|w| w.holds(&s)).collect();
    let saved: Vec<String> = solver.save_state(&b).expect("save").into_iter().map(|(n, _)| n).collect();
    let expected: Vec<&str> = FIELDS
        .iter()
        .filter(|f| f.checkpoint != Checkpoint::Scratch && held.contains(&f.when))
        .map(|f| f.name)
        .collect();
    assert_eq!(saved, expected, "{what}: checkpointed fields");
    let downloaded = solver.download_frame_fields(&b).expect("frames");
    for f in &downloaded {
        assert_eq!(
            f.values.len(),
            f.components * solver.n,
            "{what}: frame field {} holds n × components values",
            f.name
        );
    }
    let frames: Vec<&str> = downloaded.iter().map(|f| f.name).collect();
    let expected: Vec<&str> = FIELDS.iter().filter(|f| held.contains(&f.when)).filter_map(|f| f.frame).collect();
    assert_eq!(frames, expected, "{what}: frame fields");
    held
}

/// Every scene in f64, f32 and mixed precision (the scenes accept each), and a cut with the current-yield friction
/// cap and the wear rate, a damaged cut, the disk with CSPM and with the Balsara switch (no scene file turns them
/// on). Every condition of the registry holds in at least one of
/// them, so every entry's size and condition is compared with an allocation.
#[test]
fn memory_estimate_equals_the_bytes_allocated_for_every_scene() {
    let mut scenes = Vec::new();
    for dir in ["cases", "cases/cutting", "cases/hard"] {
        for entry in std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{dir}: {e}")) {
            let path = entry.expect("entry").path();
            if path.extension().is_some_and(|e| e == "toml") {
                scenes.push((path, vec![]));
            }
        }
    }
    let cap_wear = vec!["tool.friction_cap=\"current\"".to_string(), "tool.usui={}".to_string()];
    scenes.push(("cases/cutting/v0060.toml".into(), cap_wear));
    // Damage (issue 25): ω, D and the mask.
    let damage: Vec<String> =
        ["damage.model=\"jc\"", "damage.D1=0.1", "damage.D2=0.2", "damage.D3=0.5", "damage.D4=0.0"]
            .iter()
            .map(|s| s.to_string())
            .chain(["damage.D5=0.0".to_string(), "damage.mask=true".to_string()])
            .collect();
    scenes.push(("cases/cutting/v0060.toml".into(), damage));
    // CSPM (issue 24): the correction buffer.
    scenes.push(("cases/disk-rotation.toml".into(), vec!["stabilisation.cspm={}".to_string()]));
    // The SPH cohesive path (issue 26; cases/mpm/ holds it beside the MPM scenes): the bonds.
    scenes.push(("cases/mpm/nairn-cut-sph.toml".into(), vec![]));
    // Blanking (issue 24): the velocities of the last rebuild.
    let blank = ["blanking.min=[-0.2e-3,-1.0e-3]", "blanking.max=[0.6e-3,1.0e-3]"].map(String::from).to_vec();
    scenes.push(("cases/cutting/v0060.toml".into(), blank));
    // The viscosity's Balsara switch: its factors.
    let switch = vec!["stabilisation.artificial_viscosity.switch=\"balsara\"".to_string()];
    scenes.push(("cases/disk-rotation.toml".into(), switch));
    let mut covered = BTreeSet::new();
    let mut runs = 0;
    for (path, overrides) in &scenes {
        let scene = Scene::load(path, overrides).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        for p in [Precision::F64, Precision::F32, Precision::Mixed] {
            let scene = scene.with_precision(Some(p));
            let what = format!("{} {overrides:?} ({})", path.display(), p.as_str());
            let held = match (scene.dim, p) {
                (2, Precision::F64) => check_scene::<f64, Dim2>(&scene, &what),
                (2, _) => check_scene::<f32, Dim2>(&scene, &what),
                (_, Precision::F64) => check_scene::<f64, Dim3>(&scene, &what),
                (_, _) => check_scene::<f32, Dim3>(&scene, &what),
            };
            covered.extend(held.into_iter().map(|w| format!("{w:?}")));
            runs += 1;
        }
    }
    assert!(runs >= 3 * 19, "expected the scenes of cases/, cases/cutting/ and cases/hard/, ran {runs}");
    let all: BTreeSet<String> = When::ALL.iter().map(|w| format!("{w:?}")).collect();
    assert_eq!(covered, all, "conditions no scene exercises");
}

/// The in-place reorder stages every reordered field that can exist and the reference positions' snapshot; its
/// fixed capacity must hold them all (else `ReorderBatch::run` refuses the batch at the first rebuild).
#[test]
fn reorder_batch_holds_every_reordered_field() {
    let most = max_reorder_entries();
    assert!(most <= MAX_REORDER, "{most} reordered buffers, MAX_REORDER = {MAX_REORDER}");
}

/// The checkpointed fields keep the names (and order) of the checkpoints written before the registry, so that
/// those checkpoints resume (checkpoint.bin looks fields up by name).
#[test]
fn checkpoint_names_are_unchanged() {
    let names: Vec<&str> = FIELDS.iter().filter(|f| f.checkpoint != Checkpoint::Scratch).map(|f| f.name).collect();
    let before = [
        "id",
        "flags",
        "pos",
        "vel",
        "mass",
        "rho",
        "stress",
        "pos0",
        "pos_ref",
        "vel0",
        "rho0",
        "stress0",
        "pos_t",
        "vel_t",
        "rho_t",
        "stress_t",
        "temp",
        "pos_lo",
        "temp0",
        "temp_t",
        "eps",
        "eps_rate",
        "plastic_work",
        "contact_normal",
        "contact_friction",
        "mech_mass",
        "viscous_dissipation",
        // Issue 25: the damage's ω and D (present only with [damage]).
        "damage_omega",
        "damage",
        // Issue 24: the tool each particle's friction history belongs to (several tools).
        "contact_owner",
        // Issue 26: the SPH cohesive path's bonds (present only with [cohesive]).
        "bond_partner",
        "bond_reference",
        "bond_state",
        "bond_work",
        "bond_damping",
        // Issue 24: the velocities of the last rebuild with blanking (its rest speed).
        "vel_ref",
        // The viscosity's Balsara switch (present only with `switch = "balsara"`).
        "av_switch",
        // Issue 25: the elastic energy the damage's degradation released (optional: older checkpoints lack it).
        "damage_work",
        // Issue 26: the SPH cohesive path's onsets and columns under `coupling = "continuum"` (optional: older
        // checkpoints lack them).
        "bond_onset",
        "bond_column",
    ];
    assert_eq!(names, before);
    let frames: Vec<&str> = FIELDS.iter().filter_map(|f| f.frame).collect();
    // The contact forces joined the frames in issue 27 (item 4), as vectors.
    assert_eq!(
        frames,
        [
            "temperature",
            "plastic_strain",
            "plastic_strain_rate",
            "contact_normal_force",
            "contact_friction_force",
            "damage_initiation",
            "damage",
            "contact_tool",
            "damage_mask",
            // Issue 26: the work each SPH bond has absorbed (on its owner).
            "cohesive_work",
            // The viscosity's Balsara factor.
            "av_switch"
        ]
    );
}

/// The particle state's fields (`state::particle_fields!`) are registry entries too, reordered, always present and
/// checkpointed under their own names: a particle field added there and not to the registry fails here (and the
/// estimate's test).
#[test]
fn every_particle_field_is_registered() {
    for name in HostParticles::<f64, Dim2>::FIELD_NAMES {
        let f = FIELDS.iter().find(|f| f.name == *name).unwrap_or_else(|| panic!("particle field {name} unregistered"));
        assert!(f.reordered && f.when == When::Always && f.checkpoint == Checkpoint::Save, "{name}: {f:?}");
    }
}
