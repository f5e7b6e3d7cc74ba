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
//!   on a GPU, one at a time on the CPU), each result recorded as it comes. A failed run is recorded with its message and the sweep goes on; Ctrl-C stops it after writing the table of
//!   the runs so far. The table and plots are rewritten (atomically) after every run.

pub mod plot;
pub mod table;

use std::path::{Path, PathBuf};

use crate::backend::AnyBackend;
pub use crate::ensemble::Job;
use crate::run::RunOptions;
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

/// Runs the sweep on `backend` and writes the table and plots into `opts.out_dir`. Bad keys or values are
/// refused before any run; a failing run is recorded and the sweep goes on; Ctrl-C writes the table so far and
/// returns [`Error::Interrupted`].
pub fn sweep(backend: &AnyBackend, opts: &SweepOptions) -> Result<Sweep> {
    let (mut sweep, jobs) = plan(opts)?;
    std::fs::create_dir_all(&opts.out_dir).map_err(|e| Error::Output(format!("{}: {e}", opts.out_dir.display())))?;
    let width = opts.width.unwrap_or_else(|| crate::ensemble::default_width(backend));
    let result = crate::ensemble::run(backend, &jobs, width, &mut |k, result| {
        let dx = jobs[k].scene.discretisation.dx;
        let outcome = match result {
            Ok(_) => match observe::measure(&sweep.points[k].dir, &sweep.columns, dx) {
                Ok(values) => Outcome::Done(values),
                Err(e) => Outcome::Failed(format!("summary values not read: {e}")),
            },
            Err(e) => Outcome::Failed(e.to_string()),
        };
        if !opts.quiet {
            eprintln!("sweep: {} of {}: {}", k + 1, jobs.len(), line(&sweep, k, &outcome));
        }
        sweep.points[k].outcome = outcome;
        write(&mut sweep, &opts.out_dir, false)
    });
    write(&mut sweep, &opts.out_dir, true)?;
    result.map(|()| sweep)
}

/// The points of the grid (every scene loaded, so a bad key or value is refused here) and their jobs.
fn plan(opts: &SweepOptions) -> Result<(Sweep, Vec<Job>)> {
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
    let base = Scene::load(&opts.scene, &opts.overrides).map_err(|e| Error::Scene(e.to_string()))?;
    let mut columns = run_columns();
    for o in observe::catalogue(base.dim, base.tool.is_some(), &base.bodies) {
        if !columns.iter().any(|c| c.name == o.name) {
            columns.push(o);
        }
    }
    let mut points = Vec::new();
    let mut jobs = Vec::new();
    for (index, values) in product(&opts.grids).into_iter().enumerate() {
        let pairs: Vec<String> = opts.grids.iter().zip(&values).map(|(g, v)| format!("{}={v}", g.key)).collect();
        let mut sets = opts.overrides.clone();
        sets.extend(pairs.iter().cloned());
        let scene = Scene::load(&opts.scene, &sets)
            .map_err(|e| Error::Scene(format!("sweep: --grid {}: {e}", pairs.join(" --grid "))))?;
        let dir = opts.out_dir.join(folder(index, &opts.grids, &values));
        let options = RunOptions {
            precision: opts.precision,
            frames: opts.frames,
            quiet: opts.quiet,
            overrides: sets,
            ..RunOptions::quiet(dir.clone())
        };
        points.push(Point { values, dir, outcome: Outcome::Pending });
        jobs.push(Job { scene, options });
    }
    let sweep = Sweep {
        scene: base.name.clone(),
        file: base.origin.clone(),
        keys: opts.grids.iter().map(|g| g.key.clone()).collect(),
        columns,
        points,
        warnings: Vec::new(),
    };
    Ok((sweep, jobs))
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
