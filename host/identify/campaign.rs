//! `swarf identify <file.toml>`: the optimiser of the identification file asks a batch of parameter sets, every
//! set runs every experiment (one run folder each, `runs/<evaluation>-<experiment>/`, frames off), the objective
//! of each set comes from its runs' summary values, and the optimiser is told; until the budget is spent or the
//! method converges. After every batch `history.csv`, `report.md`, the plots and the best set's material file are
//! rewritten (atomically). Everything the file names is checked before any run or folder is made.
//!
//! Stop and resume: Ctrl-C stops the batch in flight (its unfinished runs are run again on resume, its finished ones
//! taken from their folders, `scenes::FINISHED`); `--resume` rebuilds the
//! optimiser from the file's settings and seed and tells it the recorded history batch by batch, checking that
//! every asked point equals the recorded one bitwise, then goes on (docs/identification.md "Determinism and
//! resume"). A folder whose identification file differs is refused.

use std::path::{Path, PathBuf};
use std::time::Instant;

use super::file::{self, Method, Spec};
use super::history::{self, Row};
use super::holdout;
use super::material_key;
use super::objective::{self, Simulated};
use super::scenes::{
    combine_replicas, load_with, measured, observables, replica_name, replicas, scene_for, scene_with_material,
};
use super::{Bayes, Bounds, DifferentialEvolution, NelderMead, Optimizer};
use crate::backend::AnyBackend;
use crate::ensemble::Job;
use crate::run::RunOptions;
use crate::{Error, Result};

/// Files and folders of an identification folder.
pub const COPY: &str = "identification.toml";
pub const STATE: &str = "identify.json";
pub use super::scenes::RUNS;

/// What to identify and where.
#[derive(Clone, Debug)]
pub struct IdentifyOptions {
    pub file: PathBuf,
    pub out_dir: PathBuf,
    /// Overrides the file's `optimizer.batch`.
    pub batch: Option<usize>,
    /// `--only`: identify these of the file's `[[parameter]]` keys only; the others keep the scenes' values.
    pub only: Option<Vec<String>>,
    /// Runs at once (the ensemble's width, `--width`; None: [`crate::ensemble::default_width`]). It changes no
    /// result: a run's bits do not depend on the runs beside it (host/ensemble).
    pub width: Option<usize>,
    pub resume: bool,
    /// Run only the holdout (`--holdout-only`): the folder's best set so far (none in a new folder) and the
    /// `compare` materials on the `[[holdout]]` experiments; the optimisation does not go on.
    pub holdout_only: bool,
    pub quiet: bool,
}

/// A finished (or budget-limited) identification.
#[derive(Clone, Debug)]
pub struct Identification {
    pub spec: Spec,
    pub rows: Vec<Row>,
    /// The best set's material file, where the model has a library material.
    pub material: Option<PathBuf>,
    pub warnings: Vec<String>,
}

/// Runs the identification of `opts.file` into `opts.out_dir` on `backend`.
pub fn identify(backend: &AnyBackend, opts: &IdentifyOptions) -> Result<Identification> {
    let mut spec = file::read(&opts.file)?;
    if let Some(b) = opts.batch {
        spec.optimizer.batch = b.max(1);
    }
    if let Some(keys) = &opts.only {
        restrict(&mut spec, keys)?;
    }
    validate(&spec)?;
    let mut rows = open_folder(&mut spec, opts)?;
    let bounds = bounds(&spec)?;
    let mut opt = optimizer(&spec);
    let header = header(&spec);
    replay(opt.as_mut(), &bounds, &spec, &rows)?;
    let (started, mut runs) = (Instant::now(), 0usize);
    let mut out = Identification { spec: spec.clone(), rows: Vec::new(), material: None, warnings: Vec::new() };
    let width = opts.width.unwrap_or_else(|| crate::ensemble::default_width(backend));
    while rows.len() < spec.optimizer.budget && !opts.holdout_only {
        let asked = opt.ask(spec.optimizer.batch.min(spec.optimizer.budget - rows.len()));
        if asked.is_empty() {
            break;
        }
        let params: Vec<Vec<f64>> = asked.iter().map(|u| bounds.to_params(u)).collect();
        let batch = rows.last().map_or(0, |r| r.batch + 1);
        let evaluated =
            evaluate(backend, &spec, (&opts.out_dir, width), &params, rows.len(), batch).inspect_err(|e| {
                if matches!(e, Error::Interrupted { .. }) {
                    eprintln!(
                        "identify: stopped; continue with `swarf identify {} --out {} --resume`",
                        opts.file.display(),
                        opts.out_dir.display()
                    );
                }
            })?;
        runs += params.len() * spec.experiments.len() * spec.objective.replicas;
        opt.tell(&evaluated.iter().map(|r| r.objective).collect::<Vec<_>>());
        rows.extend(evaluated);
        (out.material, out.warnings) = super::report::write_all(&spec, &header, &rows, &opts.out_dir)?;
        if !opts.quiet {
            eprintln!("{}", progress(&spec, &rows, runs, started.elapsed().as_secs_f64()));
        }
    }
    // A holdout alone in a new folder has no evaluation to report (and no plot to draw).
    if !(opts.holdout_only && rows.is_empty()) {
        (out.material, out.warnings) = super::report::write_all(&spec, &header, &rows, &opts.out_dir)?;
    }
    if !spec.holdout.is_empty() {
        let sets = holdout::sets(&spec, super::report::best(&rows));
        if !opts.quiet {
            eprintln!(
                "identify: holdout: {} sets × {} tests not fitted, into {}",
                sets.len(),
                spec.holdout.len(),
                opts.out_dir.join(holdout::MARKDOWN).display()
            );
        }
        holdout::run(backend, &spec, &sets, &opts.out_dir, width)?;
    }
    out.rows = rows;
    Ok(out)
}

/// The history header of `spec`.
pub fn header(spec: &Spec) -> Vec<String> {
    let keys: Vec<String> = spec.parameters.iter().map(|p| p.key.clone()).collect();
    let names: Vec<String> = spec.experiments.iter().map(|e| e.name.clone()).collect();
    history::header(&keys, &names)
}

fn bounds(spec: &Spec) -> Result<Bounds> {
    let lo = spec.parameters.iter().map(|p| p.lower).collect();
    let hi = spec.parameters.iter().map(|p| p.upper).collect();
    Bounds::new(lo, hi).map_err(|e| Error::Scene(format!("{}: parameter: {e}", spec.file.display())))
}

/// The optimiser the file names, built afresh (so that its seed gives the same sequence).
fn optimizer(spec: &Spec) -> Box<dyn Optimizer> {
    let d = spec.parameters.len();
    match &spec.optimizer.method {
        Method::De(s) => Box::new(DifferentialEvolution::new(d, *s)),
        Method::NelderMead(s) => Box::new(NelderMead::new(s.clone())),
        Method::Bayes(s) => Box::new(Bayes::new(d, *s)),
    }
}

/// Every experiment's scene, then with each parameter alone at its lower and upper bound: a bad override, an
/// unknown parameter key or a bound the scene refuses is named here, before any run.
fn validate(spec: &Spec) -> Result<()> {
    let file = spec.file.display();
    for (i, exp) in spec.holdout.iter().enumerate() {
        let (scene, _) = load_with(spec, exp, &[]).map_err(|e| {
            Error::Scene(format!(
                "{file}: holdout.{i} ({}): expected a scene its set and the file's set accept: {e}",
                exp.name
            ))
        })?;
        fixed_step_without_replicas(spec, &scene, &format!("holdout.{i} ({})", exp.name))?;
        for name in &spec.compare {
            scene_with_material(spec, exp, name, None).map_err(|e| {
                Error::Scene(format!(
                    "{file}: compare = \"{name}\": expected a library material scene {} accepts: {e}",
                    exp.scene.display()
                ))
            })?;
        }
    }
    for (i, exp) in spec.experiments.iter().enumerate() {
        let (scene, _) = load_with(spec, exp, &[]).map_err(|e| {
            Error::Scene(format!(
                "{file}: experiment.{i} ({}): expected a scene its set and the file's set accept: {e}",
                exp.name
            ))
        })?;
        fixed_step_without_replicas(spec, &scene, &format!("experiment.{i} ({})", exp.name))?;
        for (k, p) in spec.parameters.iter().enumerate() {
            for bound in [p.lower, p.upper] {
                load_with(spec, exp, &[(&p.key, bound)]).map_err(|e| {
                    Error::Scene(format!(
                        "{file}: parameter.{k}.key = \"{}\": expected a key that scene {} accepts with values in [{}, {}] \
                         (a scene key such as tool.friction, or {}<key>): {e}",
                        p.key,
                        exp.scene.display(),
                        p.lower,
                        p.upper,
                        material_key::PREFIX
                    ))
                })?;
            }
        }
    }
    Ok(())
}

/// Refuses replicas of a scene with a fixed `time.dt` (`what` names it): they differ by their CFL number only.
fn fixed_step_without_replicas(spec: &Spec, scene: &crate::scene::Scene, what: &str) -> Result<()> {
    if spec.objective.replicas > 1 && scene.time.dt.is_some() {
        return Err(Error::Scene(format!(
            "{}: objective.replicas = {}: expected 1 for {what}, whose scene fixes time.dt (replicas differ by their \
             CFL number)",
            spec.file.display(),
            spec.objective.replicas
        )));
    }
    Ok(())
}

/// Keeps the file's `[[parameter]]`s whose keys `keys` names (`--only`), in the file's order; a key the file does
/// not identify is refused, naming the ones it does.
fn restrict(spec: &mut Spec, keys: &[String]) -> Result<()> {
    let known: Vec<&str> = spec.parameters.iter().map(|p| p.key.as_str()).collect();
    if let Some(k) = keys.iter().find(|k| !known.contains(&k.as_str())) {
        return Err(Error::Scene(format!(
            "--only {k}: expected keys of {}'s [[parameter]]s: {}",
            spec.file.display(),
            known.join(", ")
        )));
    }
    spec.parameters.retain(|p| keys.contains(&p.key));
    Ok(())
}

/// Makes the identification folder, or opens it to resume: returns the recorded history. A new identification
/// refuses a folder that holds one; a resumed one refuses a folder whose file differs, and takes its batch.
fn open_folder(spec: &mut Spec, opts: &IdentifyOptions) -> Result<Vec<Row>> {
    let dir = &opts.out_dir;
    let io = |p: &Path, e: std::io::Error| Error::Output(format!("{}: {e}", p.display()));
    let copy = dir.join(COPY);
    let state = dir.join(STATE);
    if !opts.resume {
        if copy.exists() {
            return Err(Error::Scene(format!(
                "{}: holds an identification: resume it with --resume, or write to another folder with --out DIR",
                dir.display()
            )));
        }
        std::fs::create_dir_all(dir).map_err(|e| io(dir, e))?;
        crate::output::write_atomic(&copy, spec.text.as_bytes()).map_err(|e| io(&copy, e))?;
        let only: Option<Vec<&str>> =
            opts.only.as_ref().map(|_| spec.parameters.iter().map(|p| p.key.as_str()).collect());
        let json = serde_json::json!({ "batch": spec.optimizer.batch, "only": only }).to_string();
        crate::output::write_atomic(&state, json.as_bytes()).map_err(|e| io(&state, e))?;
        return Ok(Vec::new());
    }
    let recorded = std::fs::read_to_string(&copy).map_err(|e| io(&copy, e))?;
    if !same_fit(&recorded, &spec.text) {
        return Err(Error::Scene(format!(
            "{}: differs from {} that this folder was started with: expected the same file to resume (only \
             [[holdout]] and compare may change)",
            spec.file.display(),
            copy.display()
        )));
    }
    let text = std::fs::read_to_string(&state).map_err(|e| io(&state, e))?;
    let json = serde_json::from_str::<serde_json::Value>(&text).ok();
    let batch = json.as_ref().and_then(|v| v["batch"].as_u64());
    let batch = batch.ok_or_else(|| Error::Scene(format!("{}: expected {{\"batch\": N}}", state.display())))? as usize;
    let only: Option<Vec<String>> = json
        .as_ref()
        .and_then(|v| v["only"].as_array().map(|a| a.iter().filter_map(|k| k.as_str().map(String::from)).collect()));
    if opts.only.is_some() && opts.only != only {
        return Err(Error::Scene(format!(
            "--only {}: expected the parameters this folder was started with, {}",
            opts.only.as_deref().unwrap_or_default().join(","),
            only.as_deref().map_or("all of the file's".into(), |k| k.join(","))
        )));
    }
    if let (Some(keys), None) = (&only, &opts.only) {
        restrict(spec, keys)?;
    }
    if opts.batch.is_some_and(|b| b.max(1) != batch) {
        return Err(Error::Scene(format!(
            "--batch {}: expected the batch this folder was started with, {batch}",
            opts.batch.unwrap_or(0)
        )));
    }
    spec.optimizer.batch = batch;
    let path = dir.join(history::FILE);
    if !path.exists() {
        return Ok(Vec::new());
    }
    history::read(&path, &header(spec), spec.parameters.len())
}

/// Whether two identification files ask for the same fit: equal as TOML once the `[[holdout]]` tables and `compare`
/// are set aside. Those run only after the optimisation, so held-out tests may be added to a finished or interrupted
/// identification and run with `--resume --holdout-only`.
fn same_fit(recorded: &str, text: &str) -> bool {
    let fit = |t: &str| {
        toml::from_str::<toml::Table>(t).ok().map(|mut t| {
            t.remove("holdout");
            t.remove("compare");
            t
        })
    };
    recorded == text || fit(recorded).is_some_and(|a| Some(a) == fit(text))
}

/// Tells a fresh optimiser the recorded history in its batches, checking each asked point against the record.
fn replay(opt: &mut dyn Optimizer, bounds: &Bounds, spec: &Spec, rows: &[Row]) -> Result<()> {
    let mut i = 0;
    while i < rows.len() {
        let asked = opt.ask(spec.optimizer.batch.min(spec.optimizer.budget.saturating_sub(i)).max(1));
        let same = !asked.is_empty()
            && i + asked.len() <= rows.len()
            && asked.iter().enumerate().all(|(k, u)| {
                let r = &rows[i + k];
                r.evaluation == i + k && r.batch == rows[i].batch && bounds.to_params(u) == r.params
            });
        if !same {
            return Err(Error::Scene(format!(
                "{}: evaluation {i} is not the one the file's optimiser asks: expected the history this file wrote",
                history::FILE
            )));
        }
        opt.tell(&rows[i..i + asked.len()].iter().map(|r| r.objective).collect::<Vec<_>>());
        i += asked.len();
    }
    Ok(())
}

/// Runs one batch: every parameter set of `params` (evaluations `first`, `first + 1`, ...) on every experiment,
/// `objective.replicas` runs each; returns their history rows. An interruption is returned as the error (the batch
/// is not recorded); the runs that had finished keep their folders, marked (`scenes::FINISHED`), and a resume takes
/// their results from there.
fn evaluate(
    backend: &AnyBackend,
    spec: &Spec,
    (out, width): (&Path, usize),
    params: &[Vec<f64>],
    first: usize,
    batch: usize,
) -> Result<Vec<Row>> {
    let (ne, nr) = (spec.experiments.len(), spec.objective.replicas);
    let obs = observables();
    let mut results: Vec<std::result::Result<Simulated, String>> = vec![Err("not run".into()); params.len() * ne * nr];
    let (mut jobs, mut slots) = (Vec::new(), Vec::new());
    for (s, x) in params.iter().enumerate() {
        for (e, exp) in spec.experiments.iter().enumerate() {
            for (r, loaded) in replicas(nr, |cfl| scene_for(spec, exp, x, cfl)).into_iter().enumerate() {
                let slot = (s * ne + e) * nr + r;
                let dir = out.join(RUNS).join(format!("{:05}-{}", first + s, replica_name(&exp.name, r)));
                match loaded {
                    Ok((scene, overrides)) => {
                        let job = Job { scene, options: RunOptions { overrides, ..RunOptions::quiet(dir.clone()) } };
                        if super::scenes::finished(&job) {
                            results[slot] = super::scenes::measured_in_folder(&job, &obs);
                            continue;
                        }
                        if dir.exists() {
                            std::fs::remove_dir_all(&dir)
                                .map_err(|err| Error::Output(format!("{}: {err}", dir.display())))?;
                        }
                        jobs.push(job);
                        slots.push(slot);
                    }
                    Err(why) => results[slot] = Err(why),
                }
            }
        }
    }
    crate::ensemble::run(backend, &jobs, width, &mut |k, r| {
        results[slots[k]] = measured(r, &jobs[k], &obs);
        if results[slots[k]].is_ok() {
            super::scenes::mark_finished(&jobs[k])?;
        }
        Ok(())
    })?;
    Ok(params
        .iter()
        .enumerate()
        .map(|(s, x)| row(spec, &results[s * ne * nr..(s + 1) * ne * nr], x, first + s, batch))
        .collect())
}

/// The history row of evaluation `evaluation` at `x` from its runs' `results` (experiment-major, the replicas of
/// each together): each experiment's forces and chip are its replicas' mean; a failed run fails the evaluation.
fn row(
    spec: &Spec,
    results: &[std::result::Result<Simulated, String>],
    x: &[f64],
    evaluation: usize,
    batch: usize,
) -> Row {
    let per_experiment: Vec<std::result::Result<Simulated, String>> =
        results.chunks(spec.objective.replicas).map(combine_replicas).collect();
    let sims: Vec<Simulated> = per_experiment.iter().map(|r| r.clone().unwrap_or_default()).collect();
    let terms: Vec<f64> = spec
        .experiments
        .iter()
        .zip(&sims)
        .map(|(exp, sim)| objective::experiment_term(&exp.measured, sim, &spec.objective))
        .collect();
    let failed = spec
        .experiments
        .iter()
        .zip(&per_experiment)
        .find_map(|(exp, r)| r.as_ref().err().map(|m| format!("{}: {m}", exp.name)));
    let objective = match failed {
        Some(_) => f64::NAN,
        None => objective::combine(&terms, &spec.objective),
    };
    Row { evaluation, batch, params: x.to_vec(), sims, objective, status: failed.unwrap_or_else(|| "ok".into()) }
}

/// The progress line after a batch: evaluations, best objective, runs per hour, ETA to the budget.
fn progress(spec: &Spec, rows: &[Row], runs: usize, seconds: f64) -> String {
    let best = super::report::best(rows)
        .map_or("none yet".into(), |r| format!("{:.4} (evaluation {})", r.objective, r.evaluation));
    let rate = runs as f64 / seconds.max(1e-9) * 3600.0;
    let left = (spec.optimizer.budget - rows.len().min(spec.optimizer.budget))
        * spec.experiments.len()
        * spec.objective.replicas;
    let eta_h = left as f64 / rate.max(1e-9);
    format!(
        "identify: batch {}: {} of {} evaluations, best objective {best}, {rate:.0} runs/h, ETA {}",
        rows.last().map_or(0, |r| r.batch),
        rows.len(),
        spec.optimizer.budget,
        if eta_h < 1.0 { format!("{:.1} min", eta_h * 60.0) } else { format!("{eta_h:.2} h") }
    )
}
