//! The runs of an identification: the scene of an experiment at a parameter set (scene keys as overrides,
//! `material.flow_stress.*` as edits of a copy of the library material), or with another library material, and
//! what a finished run gave (F_c, F_f, chip thickness from its summary values).

use super::file::{Experiment, Spec};
use super::material_key;
use super::objective::Simulated;
use crate::Result;
use crate::ensemble::Job;
use crate::run::RunReport;
use crate::scene::Scene;
use crate::scene::observe::{self, Observable, Source};

/// The folder of an identification's run folders.
pub const RUNS: &str = "runs";

/// A loaded scene and the overrides it was loaded with, or why it cannot be loaded.
pub type Loaded = std::result::Result<(Scene, Vec<String>), String>;

/// The scene of experiment `exp` at parameter values `x`, and the overrides it was loaded with: the experiment's
/// overrides, the file's global ones, then the scene parameters, then `cfl` as `time.cfl` where given (a replica,
/// [`replicas`]); material parameters edit its library material.
pub fn scene_for(spec: &Spec, exp: &Experiment, x: &[f64], cfl: Option<f64>) -> Loaded {
    let mut pairs: Vec<(&str, f64)> = spec.parameters.iter().map(|p| p.key.as_str()).zip(x.iter().copied()).collect();
    pairs.extend(cfl.map(|c| ("time.cfl", c)));
    load_with(spec, exp, &pairs)
}

/// The relative CFL offset of replica `r` (`[objective] replicas`): 0 for the first, then −1e-3, +1e-3, −2e-3,
/// +2e-3, ... A step this much shorter or longer changes nothing a cut's mean should depend on, yet it decorrelates
/// the chaotic runs (the scatter of docs/identification.md "Ck45 V0300 by DE" was measured so).
pub fn replica_cfl(r: usize) -> f64 {
    let k = r.div_ceil(2) as f64 * 1e-3;
    if r % 2 == 1 { -k } else { k }
}

/// The scenes of the `n` replicas of one run: `load(None)` loads the scene as the file gives it (replica 0), once;
/// `load(Some(c))` each other replica at its CFL number times 1 + [`replica_cfl`]`(r)`. A scene that cannot be
/// loaded fails every replica with its reason.
pub fn replicas(n: usize, load: impl Fn(Option<f64>) -> Loaded) -> Vec<Loaded> {
    let first = load(None);
    let cfl = match &first {
        Ok((scene, _)) => scene.time.cfl,
        Err(why) => return vec![Err(why.clone()); n],
    };
    let mut out = vec![first];
    out.extend((1..n).map(|r| load(Some(cfl * (1.0 + replica_cfl(r))))));
    out
}

/// The run folder's name of replica `r` of experiment `name`: the name, then `<name>-r<r>`.
pub fn replica_name(name: &str, r: usize) -> String {
    if r == 0 { name.to_string() } else { format!("{name}-r{r}") }
}

/// One experiment's result from its replicas' runs: the first failure, else [`mean_of`] their results.
pub fn combine_replicas(runs: &[std::result::Result<Simulated, String>]) -> std::result::Result<Simulated, String> {
    match runs.iter().find_map(|r| r.as_ref().err()) {
        Some(why) => Err(why.clone()),
        None => Ok(mean_of(&runs.iter().filter_map(|r| r.as_ref().ok().copied()).collect::<Vec<_>>())),
    }
}

/// The mean of replicas' results: each value the mean over the replicas, None where any replica lacks it.
fn mean_of(replicas: &[Simulated]) -> Simulated {
    let mean = |get: fn(&Simulated) -> Option<f64>| {
        let v: Option<Vec<f64>> = replicas.iter().map(get).collect();
        v.filter(|v| !v.is_empty()).map(|v| v.iter().sum::<f64>() / v.len() as f64)
    };
    Simulated { fc: mean(|s| s.fc), ff: mean(|s| s.ff), chip: mean(|s| s.chip) }
}

/// [`scene_for`] with the parameters `pairs` (key, value) only.
pub(super) fn load_with(spec: &Spec, exp: &Experiment, pairs: &[(&str, f64)]) -> Loaded {
    let mut sets = exp.set.clone();
    sets.extend(spec.set.iter().cloned());
    let mut edits = Vec::new();
    for &(key, v) in pairs {
        match material_key::flow_key(key) {
            Some(k) => edits.push((k, v)),
            None => sets.push(format!("{key}={v:?}")),
        }
    }
    let mut scene = Scene::load(&exp.scene, &sets).map_err(|e| e.to_string())?;
    material_key::apply(&mut scene, &edits)?;
    Ok((scene, sets))
}

/// The scene of experiment `exp` with the library material `name` in place of the model's (`material.name`),
/// after the experiment's and the file's overrides, then `cfl` as `time.cfl` where given (a replica).
pub fn scene_with_material(spec: &Spec, exp: &Experiment, name: &str, cfl: Option<f64>) -> Loaded {
    let mut sets = exp.set.clone();
    sets.extend(spec.set.iter().cloned());
    sets.push(format!("material.name=\"{name}\""));
    sets.extend(cfl.map(|c| format!("time.cfl={c:?}")));
    let scene = Scene::load(&exp.scene, &sets).map_err(|e| e.to_string())?;
    Ok((scene, sets))
}

/// The summary values a cut writes.
pub fn observables() -> Vec<Observable> {
    observe::SUMMARY_OBSERVABLES[..3]
        .iter()
        .map(|&(key, unit)| Observable { name: key.to_string(), unit, source: Source::Summary(key) })
        .collect()
}

/// A run's F_c, F_f and chip thickness, or why there are none.
pub fn measured(r: &Result<RunReport>, job: &Job, obs: &[Observable]) -> std::result::Result<Simulated, String> {
    r.as_ref().map_err(|e| e.to_string())?;
    measured_in_folder(job, obs)
}

/// [`measured`] from the summary of `job`'s finished run folder.
pub fn measured_in_folder(job: &Job, obs: &[Observable]) -> std::result::Result<Simulated, String> {
    let v = observe::measure(&job.options.out_dir, obs, job.scene.discretisation.dx).map_err(|e| e.to_string())?;
    Ok(Simulated { fc: v[0], ff: v[1], chip: v[2] })
}

/// The file a finished run's folder gets once its result is taken: the job's [`fingerprint`]. A batch interrupted
/// after some of its runs finished takes theirs from their folders on resume instead of running them again.
pub const FINISHED: &str = "identify-finished.txt";

/// The identity of `job`: FNV-1a of its scene as JSON (every value, an edited material's included) and overrides.
pub fn fingerprint(job: &Job) -> String {
    let text = serde_json::json!({ "scene": job.scene, "overrides": job.options.overrides }).to_string();
    format!("{:016x}", crate::hash::fnv1a64(text.as_bytes()))
}

/// Whether `job`'s folder holds its finished run: the [`FINISHED`] file with the job's fingerprint.
pub fn finished(job: &Job) -> bool {
    std::fs::read_to_string(job.options.out_dir.join(FINISHED)).is_ok_and(|f| f.trim() == fingerprint(job))
}

/// Marks `job`'s folder as its finished run (after its result was taken).
pub fn mark_finished(job: &Job) -> Result<()> {
    let path = job.options.out_dir.join(FINISHED);
    crate::output::write_atomic(&path, fingerprint(job).as_bytes())
        .map_err(|e| crate::Error::Output(format!("{}: {e}", path.display())))
}
