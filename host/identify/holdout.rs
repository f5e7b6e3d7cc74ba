//! Held-out prediction errors (issue 23): the identification's best set, and each `compare` material (e.g.
//! Klippel's single-experiment sets), run on the `[[holdout]]` experiments, which were not fitted. Written as
//! `holdout.csv` (one row per set and test) and `holdout.md` (per set the mean and worst relative error of F_c and
//! F_f, then every test), after the optimisation ends and with `swarf identify --holdout-only`.
//!
//! The relative error of a force is e = (F^sim − F^exp)/F^exp; the table gives mean |e| and the e of largest |e|
//! (its sign kept) over the tests a set ran; a failed run is counted and named, not averaged.

use std::path::Path;

use super::file::{Experiment, Spec};
use super::history::Row;
use super::objective::Simulated;
use super::scenes::{self, RUNS};
use crate::backend::AnyBackend;
use crate::ensemble::Job;
use crate::run::RunOptions;
use crate::{Error, Result};

pub const CSV: &str = "holdout.csv";
pub const MARKDOWN: &str = "holdout.md";
/// The folder of the holdout runs, inside the identification folder.
pub const FOLDER: &str = "holdout";

/// A parameter set run on the holdout: the best set's parameters, or a library material by name.
#[derive(Clone, Debug, PartialEq)]
pub enum Set {
    Best(Vec<f64>),
    Material(String),
}

impl Set {
    pub fn label(&self) -> String {
        match self {
            Set::Best(_) => "best".into(),
            Set::Material(name) => name.clone(),
        }
    }
}

/// One set's result on one holdout experiment.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    pub set: String,
    pub test: String,
    pub sim: std::result::Result<Simulated, String>,
}

/// The sets to run: the best row's parameters (where there is one), then each `compare` material.
pub fn sets(spec: &Spec, best: Option<&Row>) -> Vec<Set> {
    let mut v: Vec<Set> = best.map(|r| Set::Best(r.params.clone())).into_iter().collect();
    v.extend(spec.compare.iter().cloned().map(Set::Material));
    v
}

/// The scene of holdout experiment `exp` for `set` (at `cfl` for a replica): the best set's parameters as in the fit,
/// or the model with its library material replaced by `material.name`.
fn scene(spec: &Spec, exp: &Experiment, set: &Set, cfl: Option<f64>) -> scenes::Loaded {
    match set {
        Set::Best(x) => scenes::scene_for(spec, exp, x, cfl),
        Set::Material(name) => scenes::scene_with_material(spec, exp, name, cfl),
    }
}

/// Runs every set on every holdout experiment, `objective.replicas` runs each as in the fit (`width` at once), into
/// `<out>/holdout/`, writes `holdout.csv` and `holdout.md`, and returns the outcomes (set-major), each the mean of
/// its replicas.
pub fn run(backend: &AnyBackend, spec: &Spec, sets: &[Set], out: &Path, width: usize) -> Result<Vec<Outcome>> {
    let nr = spec.objective.replicas;
    let mut outcomes = Vec::new();
    let mut replicas: Vec<std::result::Result<Simulated, String>> = Vec::new();
    let (mut jobs, mut slots) = (Vec::new(), Vec::new());
    for set in sets {
        for exp in &spec.holdout {
            for (r, loaded) in scenes::replicas(nr, |cfl| scene(spec, exp, set, cfl)).into_iter().enumerate() {
                let dir =
                    out.join(FOLDER).join(RUNS).join(format!("{}-{}", set.label(), scenes::replica_name(&exp.name, r)));
                if dir.exists() {
                    std::fs::remove_dir_all(&dir).map_err(|e| Error::Output(format!("{}: {e}", dir.display())))?;
                }
                replicas.push(match loaded {
                    Ok((scene, overrides)) => {
                        jobs.push(Job { scene, options: RunOptions { overrides, ..RunOptions::quiet(dir) } });
                        slots.push(replicas.len());
                        Err("not run".to_string())
                    }
                    Err(why) => Err(why),
                });
            }
            outcomes.push(Outcome { set: set.label(), test: exp.name.clone(), sim: Err("not run".into()) });
        }
    }
    let obs = scenes::observables();
    crate::ensemble::run(backend, &jobs, width, &mut |k, r| {
        replicas[slots[k]] = scenes::measured(r, &jobs[k], &obs);
        Ok(())
    })?;
    for (o, reps) in outcomes.iter_mut().zip(replicas.chunks(nr)) {
        o.sim = scenes::combine_replicas(reps);
    }
    write(spec, &outcomes, out)?;
    Ok(outcomes)
}

/// The relative error of `sim` against `exp` (None where either is missing).
pub fn relative(sim: Option<f64>, exp: Option<f64>) -> Option<f64> {
    match (sim, exp) {
        (Some(s), Some(e)) if s.is_finite() && e != 0.0 => Some((s - e) / e),
        _ => None,
    }
}

/// Mean |e| and the e of largest |e| of `errors` (None where empty).
pub fn mean_and_worst(errors: &[f64]) -> Option<(f64, f64)> {
    let worst = errors.iter().copied().fold(None, |w: Option<f64>, e| match w {
        Some(w) if w.abs() >= e.abs() => Some(w),
        _ => Some(e),
    })?;
    Some((errors.iter().map(|e| e.abs()).sum::<f64>() / errors.len() as f64, worst))
}

fn write(spec: &Spec, outcomes: &[Outcome], out: &Path) -> Result<()> {
    let measured = |test: &str| spec.holdout.iter().find(|e| e.name == test).map(|e| e.measured);
    let num = |x: Option<f64>| x.map_or("NaN".to_string(), |v| format!("{v:?}"));
    let mut csv = String::from("set,test,fc_measured,fc_simulated,fc_error,ff_measured,ff_simulated,ff_error,status\n");
    for o in outcomes {
        let m = measured(&o.test);
        let sim = o.sim.as_ref().ok();
        let (fc, ff) = (sim.and_then(|s| s.fc), sim.and_then(|s| s.ff));
        let (mfc, mff) = (m.and_then(|m| m.fc), m.and_then(|m| m.ff));
        let status = o.sim.as_ref().err().map_or("ok".to_string(), |e| e.replace([',', '\n'], ";"));
        csv += &format!(
            "{},{},{},{},{},{},{},{},{status}\n",
            o.set,
            o.test,
            num(mfc),
            num(fc),
            num(relative(fc, mfc)),
            num(mff),
            num(ff),
            num(relative(ff, mff))
        );
    }
    let io = |p: &Path, e: std::io::Error| Error::Output(format!("{}: {e}", p.display()));
    let path = out.join(CSV);
    crate::output::write_atomic(&path, csv.as_bytes()).map_err(|e| io(&path, e))?;
    let path = out.join(MARKDOWN);
    crate::output::write_atomic(&path, markdown(spec, outcomes).as_bytes()).map_err(|e| io(&path, e))
}

/// `holdout.md`: a summary row per set, then every test.
pub fn markdown(spec: &Spec, outcomes: &[Outcome]) -> String {
    let pct = |x: Option<f64>| x.map_or("–".to_string(), |v| format!("{:+.1} %", 100.0 * v));
    let abs = |x: Option<f64>| x.map_or("–".to_string(), |v| format!("{:.1} %", 100.0 * v));
    let mut md = format!(
        "# Held-out prediction errors: {}\n\n{} tests not fitted; error = (simulated − measured)/measured.\n\n\
         | set | tests run | failed | F_c mean \\|e\\| | F_c worst | F_f mean \\|e\\| | F_f worst |\n|---|---|---|---|---|---|---|\n",
        spec.name,
        spec.holdout.len()
    );
    let mut labels: Vec<&str> = Vec::new();
    for o in outcomes {
        if !labels.contains(&o.set.as_str()) {
            labels.push(&o.set);
        }
    }
    let errors = |label: &str, f: fn(&Simulated) -> Option<f64>, m: fn(&super::file::Measured) -> Option<f64>| {
        outcomes
            .iter()
            .filter(|o| o.set == label)
            .filter_map(|o| {
                let exp = spec.holdout.iter().find(|e| e.name == o.test)?;
                relative(f(o.sim.as_ref().ok()?), m(&exp.measured))
            })
            .collect::<Vec<f64>>()
    };
    for label in &labels {
        let ran = outcomes.iter().filter(|o| o.set == *label && o.sim.is_ok()).count();
        let failed = outcomes.iter().filter(|o| o.set == *label && o.sim.is_err()).count();
        let fc = mean_and_worst(&errors(label, |s| s.fc, |m| m.fc));
        let ff = mean_and_worst(&errors(label, |s| s.ff, |m| m.ff));
        md += &format!(
            "| {label} | {ran} | {failed} | {} | {} | {} | {} |\n",
            abs(fc.map(|v| v.0)),
            pct(fc.map(|v| v.1)),
            abs(ff.map(|v| v.0)),
            pct(ff.map(|v| v.1))
        );
    }
    md += "\n| set | test | F_c measured | F_c simulated | error | F_f measured | F_f simulated | error |\n\
           |---|---|---|---|---|---|---|---|\n";
    for o in outcomes {
        let Some(exp) = spec.holdout.iter().find(|e| e.name == o.test) else { continue };
        let f = |x: Option<f64>| x.map_or("–".to_string(), |v| format!("{v:.1}"));
        match &o.sim {
            Ok(s) => {
                md += &format!(
                    "| {} | {} | {} | {} | {} | {} | {} | {} |\n",
                    o.set,
                    o.test,
                    f(exp.measured.fc),
                    f(s.fc),
                    pct(relative(s.fc, exp.measured.fc)),
                    f(exp.measured.ff),
                    f(s.ff),
                    pct(relative(s.ff, exp.measured.ff))
                )
            }
            Err(why) => md += &format!("| {} | {} | failed: {} |||||| \n", o.set, o.test, why.replace('|', "/")),
        }
    }
    md
}
