//! `swarf sweep <scene> --grid key=v1,v2,... [--grid ...]`: the scene run over the cross product of scene
//! overrides, one run folder each, and one table (`sweep.csv`, `sweep.md`) and plots (`sweep-<key>.png`) of each
//! run's summary values against every swept key.
//!
//! - **Overrides** are those of `swarf run --set key=value`: each run's scene is the scene file with the user's
//!   `--set` arguments, then one `key=value` per grid. Every run's scene is loaded (and so validated) before the
//!   first run starts: a bad key or value is refused up front, naming it.
//! - **Run folders** are `<out>/<NNN>-<key>-<value>_<key>-<value>...`, the values made plain file names (any
//!   character but letters, digits, `.`, `+` and `-` becomes `_`); the index keeps them distinct and in order.
//! - **Values** are read back from each run folder ([`crate::scene::observe::measure`], as `study` does):
//!   summary.json's `particles`, `steps`, `wall_time_s` and `dt_s`, the final total energy of energy.csv, and the
//!   scene's observables (a cut's forces, chip thickness and segmentation; otherwise the final energies and body
//!   extents). So the table is a function of the run folders, whoever ran them.
//! - **Runs** go through the ensemble runner ([`crate::ensemble::run`]): up to `--batch` at once (by default 8
//!   on a GPU, one at a time on the CPU), each result recorded as it comes.
//! - **Methods:** a scene file with `method = "mpm"` sweeps MPM runs ([`crate::mpm::run`]); their values are
//!   summary.json's run facts and a cut's steady forces beside Nairn's touching model (or a bond's released
//!   energy per crack area). So `swarf sweep cases/mpm/nairn-cut.toml --grid cut.depth=... --grid cut.rake=...
//!   --grid cut.friction=...` is the generator of Nairn's h × α × μ figures (docs/mpm.md). A failed run is recorded with its message and the sweep goes on; Ctrl-C stops it after writing the table of
//!   the runs so far. The table and plots are rewritten (atomically) after every run.

pub mod plot;
pub mod table;

use std::path::{Path, PathBuf};

use crate::backend::AnyBackend;
pub use crate::ensemble::{Job, MpmJob};
use crate::mpm::run::MpmRunOptions;
use crate::run::RunOptions;
use crate::scene::mpm::{MpmScene, Setup as MpmSetupKind};
use crate::scene::observe::{self, Observable, Source};
use crate::scene::{Precision, Scene};
use crate::{Error, Result};

/// Files of the sweep folder.
pub const CSV: &str = "sweep.csv";
pub const MARKDOWN: &str = "sweep.md";

/// One swept key and its values, as given (`key=v1,v2`).
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    pub key: String,
    pub values: Vec<String>,
}

impl Grid {
    /// Parses `key=v1,v2,...`. Commas inside brackets belong to the value (`body.0.velocity=[1.0,0.0],[2.0,0.0]`).
    pub fn parse(text: &str) -> std::result::Result<Grid, String> {
        let bad = |why: &str| format!("--grid {text}: {why} (expected KEY=V1,V2,..., e.g. time.cfl=0.3,0.5)");
        let (key, list) = text.split_once('=').ok_or_else(|| bad("no '='"))?;
        let key = key.trim();
        if key.is_empty() {
            return Err(bad("no key"));
        }
        let mut values = Vec::new();
        let (mut depth, mut start) = (0i32, 0);
        for (i, c) in list.char_indices() {
            match c {
                '[' | '{' => depth += 1,
                ']' | '}' => depth -= 1,
                ',' if depth == 0 => {
                    values.push(list[start..i].trim().to_string());
                    start = i + 1;
                }
                _ => {}
            }
        }
        values.push(list[start..].trim().to_string());
        if values.iter().any(String::is_empty) {
            return Err(bad("an empty value"));
        }
        if let Some((k, v)) = values.iter().enumerate().find(|(k, v)| values[..*k].contains(v)) {
            return Err(bad(&format!("value {v} is given twice (value {k})")));
        }
        Ok(Grid { key: key.to_string(), values })
    }
}

/// What to sweep.
#[derive(Clone, Debug)]
pub struct SweepOptions {
    pub scene: PathBuf,
    /// The user's `--set` overrides, applied to every run before the grid's.
    pub overrides: Vec<String>,
    pub grids: Vec<Grid>,
    /// The sweep folder (`runs/sweep-<scene name>` on the command line).
    pub out_dir: PathBuf,
    pub precision: Option<Precision>,
    /// Write each run's particle frames (off by default: a sweep is about its summary values).
    pub frames: bool,
    pub quiet: bool,
    /// Runs at once (`--batch`; None: [`crate::ensemble::default_width`]).
    pub width: Option<usize>,
}

/// What became of one run.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    Pending,
    /// The values of [`Sweep::columns`], in order (`None`: not measured by this run).
    Done(Vec<Option<f64>>),
    Failed(String),
}

/// One point of the grid.
#[derive(Clone, Debug)]
pub struct Point {
    /// One value per grid, in [`Sweep::keys`] order.
    pub values: Vec<String>,
    pub dir: PathBuf,
    pub outcome: Outcome,
}

/// A sweep: its keys, the values read from each run, its points.
#[derive(Clone, Debug)]
pub struct Sweep {
    pub scene: String,
    pub file: String,
    pub keys: Vec<String>,
    pub columns: Vec<Observable>,
    pub points: Vec<Point>,
    /// Plots that could not be drawn.
    pub warnings: Vec<String>,
}

/// The summary values every run has, before the scene's observables.
fn run_columns() -> Vec<Observable> {
    let summary = |key: &'static str, unit| Observable { name: key.to_string(), unit, source: Source::Summary(key) };
    vec![
        summary("particles", "-"),
        summary("steps", "-"),
        summary("wall_time_s", "s"),
        summary("dt_s", "s"),
        Observable { name: "total_energy_j".into(), unit: "J (J/m in 2D)", source: Source::Energy("total") },
    ]
}

/// The runs of a sweep, of the method the scene file names (`method = "mpm"` or SPH).
enum Members {
    Sph(Vec<Job>),
    Mpm(Vec<MpmJob>),
}

/// Runs the sweep on `backend` and writes the table and plots into `opts.out_dir`. Bad keys or values are
/// refused before any run; a failing run is recorded and the sweep goes on; Ctrl-C writes the table so far and
/// returns [`Error::Interrupted`].
pub fn sweep(backend: &AnyBackend, opts: &SweepOptions) -> Result<Sweep> {
    let (mut sweep, members, dx) = plan(opts)?;
    std::fs::create_dir_all(&opts.out_dir).map_err(|e| Error::Output(format!("{}: {e}", opts.out_dir.display())))?;
    let width = opts.width.unwrap_or_else(|| crate::ensemble::default_width(backend));
    let count = sweep.points.len();
    let mut record = |k: usize, result: std::result::Result<(), String>| {
        let outcome = match result {
            Ok(()) => match observe::measure(&sweep.points[k].dir, &sweep.columns, dx[k]) {
                Ok(values) => Outcome::Done(values),
                Err(e) => Outcome::Failed(format!("summary values not read: {e}")),
            },
            Err(e) => Outcome::Failed(e),
        };
        if !opts.quiet {
            eprintln!("sweep: {} of {count}: {}", k + 1, line(&sweep, k, &outcome));
        }
        sweep.points[k].outcome = outcome;
        write(&mut sweep, &opts.out_dir, false)
    };
    let result = match &members {
        Members::Sph(jobs) => crate::ensemble::run(backend, jobs, width, &mut |k, r| record(k, plain(r))),
        Members::Mpm(jobs) => crate::ensemble::run(backend, jobs, width, &mut |k, r| record(k, plain(r))),
    };
    write(&mut sweep, &opts.out_dir, true)?;
    result.map(|()| sweep)
}

/// A run's result as the sweep records it: done, or its error's message.
fn plain<T>(r: &Result<T>) -> std::result::Result<(), String> {
    r.as_ref().map(drop).map_err(ToString::to_string)
}

/// The points of the grid (every scene loaded, so a bad key or value is refused here), their runs, and each
/// run's particle spacing (for the extents read back).
fn plan(opts: &SweepOptions) -> Result<(Sweep, Members, Vec<f64>)> {
    let refuse = |m: String| Err(Error::Scene(format!("sweep: {m}")));
    if opts.grids.is_empty() {
        return refuse("expected at least one --grid KEY=V1,V2,...".into());
    }
    for (k, g) in opts.grids.iter().enumerate() {
        if opts.grids[..k].iter().any(|h| h.key == g.key) {
            return refuse(format!("--grid {}: the key is swept twice", g.key));
        }
        if opts.overrides.iter().any(|s| s.split_once('=').is_some_and(|(key, _)| key.trim() == g.key)) {
            return refuse(format!("--grid {}: the key is also given by --set", g.key));
        }
    }
    let points: Vec<(Vec<String>, Vec<String>, PathBuf)> = product(&opts.grids)
        .into_iter()
        .enumerate()
        .map(|(index, values)| {
            let mut sets = opts.overrides.clone();
            sets.extend(opts.grids.iter().zip(&values).map(|(g, v)| format!("{}={v}", g.key)));
            let dir = opts.out_dir.join(folder(index, &opts.grids, &values));
            (values, sets, dir)
        })
        .collect();
    // Which method: the file's `method` key, read as the scene readers read it.
    let file = opts.scene.display().to_string();
    let mpm = crate::scene::mpm::is_mpm_file(&opts.scene).map_err(|e| Error::Scene(e.to_string()))?;
    let (name, columns, members, dx) = if mpm { plan_mpm(opts, &points)? } else { plan_sph(opts, &points)? };
    let sweep = Sweep {
        scene: name,
        file,
        keys: opts.grids.iter().map(|g| g.key.clone()).collect(),
        columns,
        points: points.into_iter().map(|(values, _, dir)| Point { values, dir, outcome: Outcome::Pending }).collect(),
        warnings: Vec::new(),
    };
    Ok((sweep, members, dx))
}

/// A point's scene could not be loaded: the error, naming the point's grid values.
fn point_error(opts: &SweepOptions, values: &[String], e: impl std::fmt::Display) -> Error {
    let pairs: Vec<String> = opts.grids.iter().zip(values).map(|(g, v)| format!("{}={v}", g.key)).collect();
    Error::Scene(format!("sweep: --grid {}: {e}", pairs.join(" --grid ")))
}

type Planned = (String, Vec<Observable>, Members, Vec<f64>);

/// An SPH sweep: its columns (the runs' and the scene's observables) and runs.
fn plan_sph(opts: &SweepOptions, points: &[(Vec<String>, Vec<String>, PathBuf)]) -> Result<Planned> {
    let base = Scene::load(&opts.scene, &opts.overrides).map_err(|e| Error::Scene(e.to_string()))?;
    let mut columns = run_columns();
    for o in observe::catalogue(base.dim, base.tool.is_some(), &base.bodies) {
        if !columns.iter().any(|c| c.name == o.name) {
            columns.push(o);
        }
    }
    let mut jobs = Vec::new();
    let mut dx = Vec::new();
    for (values, sets, dir) in points {
        let scene = Scene::load(&opts.scene, sets).map_err(|e| point_error(opts, values, e))?;
        let options = RunOptions {
            precision: opts.precision,
            frames: opts.frames,
            quiet: opts.quiet,
            overrides: sets.clone(),
            ..RunOptions::quiet(dir.clone())
        };
        dx.push(scene.discretisation.dx);
        jobs.push(Job { scene, options });
    }
    Ok((base.name, columns, Members::Sph(jobs), dx))
}

/// An MPM sweep's run columns (name, unit, summary.json pointer), before the scene's observables
/// ([`observe::mpm_catalogue`]).
const MPM_RUN_COLUMNS: &[(&str, &str, &str)] = &[
    ("particles", "-", "/particles"),
    ("steps", "-", "/steps"),
    ("wall_time_s", "s", "/wall_s"),
    ("dt_s", "s", "/dt"),
    ("failed_points", "-", "/failed_points"),
];

/// An MPM sweep: its columns (the runs' facts, then a cut's steady forces beside Nairn's touching model, or a
/// bond's released energy) and runs.
fn plan_mpm(opts: &SweepOptions, points: &[(Vec<String>, Vec<String>, PathBuf)]) -> Result<Planned> {
    let base = MpmScene::load(&opts.scene, &opts.overrides).map_err(|e| Error::Scene(e.to_string()))?;
    let columns = MPM_RUN_COLUMNS
        .iter()
        .map(|&(name, unit, at)| Observable { name: name.to_string(), unit, source: Source::Pointer(at) })
        .chain(observe::mpm_catalogue(matches!(base.setup, MpmSetupKind::Cut(_))))
        .collect();
    let mut jobs = Vec::new();
    for (values, sets, dir) in points {
        let mut scene = MpmScene::load(&opts.scene, sets).map_err(|e| point_error(opts, values, e))?;
        // The set-up's checks too (the tool's travel against the crack), before any point runs.
        crate::mpm::setup::setup(&scene).map_err(|e| point_error(opts, values, e))?;
        if let Some(p) = opts.precision {
            scene.precision = p;
        }
        let options = MpmRunOptions { frames: opts.frames, overrides: sets.clone(), ..MpmRunOptions::new(dir.clone()) };
        jobs.push(MpmJob { scene, options });
    }
    Ok((base.name, columns, Members::Mpm(jobs), vec![0.0; points.len()]))
}

/// The cross product of the grids' values, the last grid varying fastest.
fn product(grids: &[Grid]) -> Vec<Vec<String>> {
    let mut out: Vec<Vec<String>> = vec![Vec::new()];
    for g in grids {
        out = out
            .iter()
            .flat_map(|head| g.values.iter().map(move |v| [head.clone(), vec![v.clone()]].concat()))
            .collect();
    }
    out
}

/// A run folder's name: `NNN-key-value_key-value`, a plain file name.
fn folder(index: usize, grids: &[Grid], values: &[String]) -> String {
    let plain = |s: &str| -> String {
        s.chars().map(|c| if c.is_ascii_alphanumeric() || matches!(c, '.' | '+' | '-') { c } else { '_' }).collect()
    };
    let parts: Vec<String> = grids.iter().zip(values).map(|(g, v)| format!("{}-{}", plain(&g.key), plain(v))).collect();
    format!("{index:03}-{}", parts.join("_"))
}

/// The sweep's line about a finished run.
fn line(sweep: &Sweep, k: usize, outcome: &Outcome) -> String {
    let p = &sweep.points[k];
    let head: Vec<String> = sweep.keys.iter().zip(&p.values).map(|(key, v)| format!("{key}={v}")).collect();
    let head = head.join(" ");
    match outcome {
        Outcome::Done(v) => {
            let get = |name: &str| {
                sweep.columns.iter().position(|c| c.name == name).and_then(|i| v[i]).map_or("n/a".into(), table::cell)
            };
            format!("{head}: {} steps, {} s wall, in {}", get("steps"), get("wall_time_s"), p.dir.display())
        }
        Outcome::Failed(m) => format!("{head}: failed: {m}"),
        Outcome::Pending => format!("{head}: pending"),
    }
}

/// Writes sweep.csv, sweep.md and the plots; a plot that cannot be drawn is a warning (kept once, at the `last`
/// write), never a failed sweep.
fn write(sweep: &mut Sweep, dir: &Path, last: bool) -> Result<()> {
    let io = |path: &Path, e: std::io::Error| Error::Output(format!("{}: {e}", path.display()));
    let csv = dir.join(CSV);
    crate::output::write_atomic(&csv, table::csv(sweep).as_bytes()).map_err(|e| io(&csv, e))?;
    let md = dir.join(MARKDOWN);
    crate::output::write_atomic(&md, table::markdown(sweep).as_bytes()).map_err(|e| io(&md, e))?;
    let warnings = plot::draw_all(sweep, dir);
    if last {
        sweep.warnings = warnings;
    }
    Ok(())
}
