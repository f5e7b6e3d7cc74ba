//! `swarf study <scene>`: a scene run over resolution levels × precisions (× backends), and what each run costs
//! (wall time) against what it gets wrong (error), as a table (`study.csv`, `study.md`) and a plot (`study.png`).
//!
//! The method (docs/measurements/notebook.md, "Studies"):
//!
//! - A **level** is a factor on the scene's `discretisation.dx`, applied as one more override
//!   `discretisation.dx=<factor · dx>` after the user's `--set` arguments: the same machinery as `swarf run --set`,
//!   and recorded in each run's summary.json. Everything derived from dx follows (h, Δt, masses, lattices, the
//!   thermal tool's particles); `tool.depth_of_cut` keeps a cut's depth where an absolute `tool.position` would
//!   not. A body whose box is not a whole number of the scaled dx gets a different shape at that level: warned.
//! - Each run is an ordinary `swarf run` without frames ([`crate::run::RunOptions::quiet`]) in its own folder under
//!   the study folder (`level<k>-<precision>-<backend>`), which keeps its energy.csv, summary.json, run.log and,
//!   for a cut, forces.csv.
//! - **Observables** are the scene's scalar results ([`observe`]): a cut's steady forces, chip thickness and
//!   segmentation; otherwise the final energies and body extents.
//! - **Errors** are relative, |a − r|/|r|, against the finest-level f64 run of the study on the first backend
//!   (the reference), and against the scene's `[experiment]` values where it has them ([`table`]).
//! - A run that fails (a non-finite value, a blow-up, a tool that never meets the workpiece at that level) is
//!   recorded as failed with its message; the study goes on. The tables and the plot are rewritten (atomically)
//!   after every run, so an interrupted study leaves the results so far.
//! - **An MPM scene** (`method = "mpm"`, docs/mpm.md) is studied the same way, with its own resolution key: a
//!   level scales its particle spacing through [`MpmScene::level_override`] (a cut's `cut.particles_across`, the
//!   nearest odd count; a bond's `bond.cell`), and its observables are the run's summary.json results
//!   ([`observe::mpm_catalogue`]: the mode-I share, a cut's steady forces beside Nairn's models, a bond's released
//!   energy). A level whose rounded count does not give the factor exactly is warned, and its spacing recorded.

/// The observables moved below the scene reader (which checks `[experiment]` against them).
pub use crate::scene::observe;
pub mod plot;
pub mod table;

use std::fmt;
use std::path::{Path, PathBuf};

use crate::backend::AnyBackend;
use crate::mpm::run::MpmRunOptions;
use crate::run::RunOptions;
use crate::scene::mpm::{MpmScene, Setup as MpmSetup};
use crate::scene::{Measurement, Precision, Scene, Shape};
use crate::{Error, Result};
use observe::Observable;

/// A resolution level: dx = factor · the scene's dx, the factor given as a decimal (`0.5`) or a fraction (`1/3`,
/// so that dx/3 is computed as such and a lattice that fits at dx fits at dx/3 without a rounded factor).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Level {
    num: f64,
    den: f64,
}

impl Level {
    /// Parses `0.5`, `1/3`, `2`: a positive, finite factor.
    pub fn parse(text: &str) -> std::result::Result<Level, String> {
        let bad = || format!("'{text}' is not a resolution level (expected a positive factor on dx: 1, 0.5, 1/3)");
        let number = |s: &str| s.trim().parse::<f64>().ok().filter(|v| v.is_finite() && *v > 0.0);
        let (num, den) = match text.split_once('/') {
            Some((a, b)) => (number(a).ok_or_else(bad)?, number(b).ok_or_else(bad)?),
            None => (number(text).ok_or_else(bad)?, 1.0),
        };
        let level = Level { num, den };
        if level.factor().is_finite() && level.factor() > 0.0 { Ok(level) } else { Err(bad()) }
    }

    /// The factor on dx.
    pub fn factor(&self) -> f64 {
        self.num / self.den
    }

    /// The level's dx from the scene's: dx · num / den.
    pub fn apply(&self, dx: f64) -> f64 {
        dx * self.num / self.den
    }
}

impl fmt::Display for Level {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.den == 1.0 { write!(f, "{}", self.num) } else { write!(f, "{}/{}", self.num, self.den) }
    }
}

/// What to study.
#[derive(Clone, Debug)]
pub struct StudyOptions {
    /// The scene file.
    pub scene: PathBuf,
    /// The user's `--set` overrides, applied before each level's dx.
    pub overrides: Vec<String>,
    pub levels: Vec<Level>,
    pub precisions: Vec<Precision>,
    /// The study folder (`runs/study-<scene name>` on the command line).
    pub out_dir: PathBuf,
    /// Print nothing but errors (the runs' progress lines and the study's line per run are silenced).
    pub quiet: bool,
}

/// What became of one run.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// Not run yet (the study was interrupted before it, or is still going).
    Pending,
    Done(RunStats),
    /// The run stopped with this message (a non-finite value, a blow-up, a refused set-up ...).
    Failed(String),
}

/// A finished run's size, cost and observables.
#[derive(Clone, Debug, PartialEq)]
pub struct RunStats {
    pub particles: usize,
    pub steps: u64,
    /// Wall time of the time loop [s] (the run's report: set-up and the final summary excluded).
    pub wall_s: f64,
    /// The study's observables, in [`Study::observables`] order (`None`: not measured by this run).
    pub values: Vec<Option<f64>>,
}

/// One run of the study.
#[derive(Clone, Debug)]
pub struct Run {
    pub level: Level,
    pub dx: f64,
    pub precision: Precision,
    /// "cpu" or "gpu".
    pub backend: String,
    /// The device's name.
    pub device: String,
    /// The run folder.
    pub dir: PathBuf,
    pub outcome: Outcome,
}

/// A study: its runs (levels × precisions × backends, in that nesting), the reference among them, the observables
/// and the experiment.
#[derive(Clone, Debug)]
pub struct Study {
    /// The scene's name and file.
    pub scene: String,
    pub file: String,
    pub observables: Vec<Observable>,
    pub experiment: Vec<Measurement>,
    pub runs: Vec<Run>,
    /// Index into `runs` of the reference: the finest level, f64 (else the first precision), first backend.
    pub reference: usize,
    /// Lattice-fit warnings (see [`lattice_warnings`]) and a plot that could not be drawn.
    pub warnings: Vec<String>,
}

impl Study {
    /// The measured value of observable `i`, if `[experiment]` has one.
    pub fn measured(&self, i: usize) -> Option<&Measurement> {
        let name = &self.observables[i].name;
        self.experiment.iter().find(|m| &m.name == name)
    }
}

/// Files of the study folder.
pub const CSV: &str = "study.csv";
pub const MARKDOWN: &str = "study.md";
pub const PNG: &str = "study.png";

/// Runs the study on `backends` (at least one; their order is the table's, the first holds the reference) and
/// writes study.csv, study.md and study.png into `opts.out_dir`. Scene errors at any level are refused before
/// the first run; a failing run is recorded and the study goes on; an interruption (Ctrl-C) writes the tables of
/// the runs so far and returns [`Error::Interrupted`].
pub fn study(backends: &[AnyBackend], opts: &StudyOptions) -> Result<Study> {
    let (mut study, scenes) = plan(backends, opts)?;
    std::fs::create_dir_all(&opts.out_dir).map_err(|e| Error::Output(format!("{}: {e}", opts.out_dir.display())))?;
    if !opts.quiet {
        for w in &study.warnings {
            eprintln!("warning: {w}");
        }
    }
    let per_level = opts.precisions.len() * backends.len();
    for k in 0..study.runs.len() {
        let level = k / per_level;
        let backend = &backends[k % backends.len()];
        let run = &study.runs[k];
        let (outcome, stop) = match run_level(backend, &scenes[level], run, opts.quiet) {
            Ok((particles, steps, wall_s)) => match observe::measure(&run.dir, &study.observables, run.dx) {
                Ok(values) => (Outcome::Done(RunStats { particles, steps, wall_s, values }), None),
                Err(e) => (Outcome::Failed(format!("observables not read: {e}")), None),
            },
            // Ctrl-C: the run wrote its checkpoint; the study records it, writes its tables and stops.
            Err(e @ Error::Interrupted { .. }) => (Outcome::Failed(e.to_string()), Some(e)),
            Err(e) => (Outcome::Failed(e.to_string()), None),
        };
        if !opts.quiet {
            eprintln!("{}", run_line(&study.runs[k], &outcome));
        }
        study.runs[k].outcome = outcome;
        write(&mut study, &opts.out_dir, false)?;
        if let Some(e) = stop {
            return Err(e);
        }
    }
    write(&mut study, &opts.out_dir, true)?;
    if !opts.quiet {
        for w in study.warnings.iter().filter(|w| w.starts_with(PNG)) {
            eprintln!("warning: {w}");
        }
    }
    Ok(study)
}

/// A level's scene and the overrides it was loaded with (the user's, then its resolution), recorded in its runs'
/// summaries.
struct LevelScene {
    scene: LevelKind,
    overrides: Vec<String>,
}

/// A level's scene, by method.
enum LevelKind {
    Sph(Box<Scene>),
    Mpm(Box<MpmScene>),
}

impl LevelScene {
    /// The level's particle spacing: an SPH scene's dx, an MPM scene's [`MpmScene::spacing`].
    fn dx(&self) -> f64 {
        match &self.scene {
            LevelKind::Sph(s) => s.discretisation.dx,
            LevelKind::Mpm(s) => s.spacing(),
        }
    }
}

/// Runs one run of the study: an SPH run, or an MPM run at the run's precision (without frames, as an SPH study's
/// runs). Its particles, steps and the time loop's wall time.
fn run_level(backend: &AnyBackend, level: &LevelScene, run: &Run, quiet: bool) -> Result<(usize, u64, f64)> {
    match &level.scene {
        LevelKind::Sph(scene) => {
            let ropts = RunOptions {
                precision: Some(run.precision),
                quiet,
                overrides: level.overrides.clone(),
                ..RunOptions::quiet(run.dir.clone())
            };
            crate::run::run(backend, scene, &ropts).map(|r| (r.particles, r.steps, r.wall_s))
        }
        LevelKind::Mpm(scene) => {
            let scene = MpmScene { precision: run.precision, ..(**scene).clone() };
            let mopts = MpmRunOptions {
                frames: false,
                quiet,
                overrides: level.overrides.clone(),
                ..MpmRunOptions::new(run.dir.clone())
            };
            crate::mpm::run::run(backend, &scene, &mopts).map(|r| (r.particles, r.steps, r.wall_s))
        }
    }
}

/// What a study's plan takes from its scene, whatever the method.
struct Planned {
    name: String,
    file: String,
    observables: Vec<Observable>,
    experiment: Vec<Measurement>,
    /// Each level's scene.
    scenes: Vec<LevelScene>,
    warnings: Vec<String>,
}

/// An SPH scene's levels: `discretisation.dx` scaled, lattice-fit warnings.
fn plan_sph(opts: &StudyOptions) -> Result<Planned> {
    let base = Scene::load(&opts.scene, &opts.overrides).map_err(|e| Error::Scene(e.to_string()))?;
    let dx0 = base.discretisation.dx;
    let mut scenes = Vec::new();
    let mut warnings = Vec::new();
    for level in &opts.levels {
        let dx = level.apply(dx0);
        let mut sets = opts.overrides.clone();
        sets.push(format!("discretisation.dx={dx:e}"));
        let scene = Scene::load(&opts.scene, &sets)
            .map_err(|e| Error::Scene(format!("study level {level} (dx = {dx:e} m): {e}")))?;
        warnings.extend(lattice_warnings(&scene).into_iter().map(|w| format!("level {level}: {w}")));
        scenes.push(LevelScene { scene: LevelKind::Sph(Box::new(scene)), overrides: sets });
    }
    Ok(Planned {
        name: base.name.clone(),
        file: base.origin.clone(),
        observables: observe::catalogue(base.dim, base.tool.is_some(), &base.bodies),
        experiment: base.experiment.clone(),
        scenes,
        warnings,
    })
}

/// An MPM scene's levels: the particle spacing scaled through [`MpmScene::level_override`], each level's set-up
/// checked (as `swarf sweep` does) before any run; a level whose spacing is not the factor's (a cut's odd count)
/// is warned.
fn plan_mpm(opts: &StudyOptions) -> Result<Planned> {
    let base = MpmScene::load(&opts.scene, &opts.overrides).map_err(|e| Error::Scene(e.to_string()))?;
    let dx0 = base.spacing();
    let mut scenes = Vec::new();
    let mut warnings = Vec::new();
    for level in &opts.levels {
        let mut sets = opts.overrides.clone();
        sets.push(base.level_override(level.factor()));
        let failed =
            |e: &dyn fmt::Display| Error::Scene(format!("study level {level} ({}): {e}", sets[sets.len() - 1]));
        let scene = MpmScene::load(&opts.scene, &sets).map_err(|e| failed(&e))?;
        crate::mpm::setup::setup(&scene).map_err(|e| failed(&e))?;
        let dx = scene.spacing();
        if (dx / level.apply(dx0) - 1.0).abs() > 1e-9 {
            warnings.push(format!(
                "level {level}: {} gives a particle spacing of {dx:e} m, {:.4} of the scene's, not {}",
                sets[sets.len() - 1],
                dx / dx0,
                level.factor()
            ));
        }
        scenes.push(LevelScene { scene: LevelKind::Mpm(Box::new(scene)), overrides: sets });
    }
    Ok(Planned {
        name: base.name.clone(),
        file: opts.scene.display().to_string(),
        observables: observe::mpm_catalogue(matches!(base.setup, MpmSetup::Cut(_))),
        experiment: Vec::new(),
        scenes,
        warnings,
    })
}

/// The scenes of every level (validated: a bad scene or level is refused here, before any run) and the study with
/// every run pending.
fn plan(backends: &[AnyBackend], opts: &StudyOptions) -> Result<(Study, Vec<LevelScene>)> {
    let refuse = |m: String| Err(Error::Scene(m));
    if backends.is_empty() {
        return refuse("study: no backend".into());
    }
    if opts.levels.is_empty() || opts.precisions.is_empty() {
        return refuse("study: expected at least one level (--levels) and one precision (--precisions)".into());
    }
    for (k, l) in opts.levels.iter().enumerate() {
        if opts.levels[..k].iter().any(|m| m.factor() == l.factor()) {
            return refuse(format!("--levels: {l} is given twice"));
        }
    }
    for (k, p) in opts.precisions.iter().enumerate() {
        if opts.precisions[..k].contains(p) {
            return refuse(format!("--precisions: {} is given twice", p.as_str()));
        }
    }
    for (k, b) in backends.iter().enumerate() {
        if backends[..k].iter().any(|c| c.info().backend == b.info().backend) {
            return refuse(format!("--backends: {} is given twice", b.info().backend));
        }
    }
    let mpm = crate::scene::mpm::is_mpm_file(&opts.scene).map_err(|e| Error::Scene(e.to_string()))?;
    let planned = if mpm { plan_mpm(opts)? } else { plan_sph(opts)? };
    let mut runs = Vec::new();
    for (k, level) in opts.levels.iter().enumerate() {
        for &precision in &opts.precisions {
            for b in backends {
                let backend = b.info().backend.to_string();
                runs.push(Run {
                    level: *level,
                    dx: planned.scenes[k].dx(),
                    precision,
                    dir: opts.out_dir.join(format!("level{k}-{}-{backend}", precision.as_str())),
                    backend,
                    device: b.info().name.clone(),
                    outcome: Outcome::Pending,
                });
            }
        }
    }
    let finest = opts.levels.iter().map(Level::factor).fold(f64::INFINITY, f64::min);
    let level = opts.levels.iter().position(|l| l.factor() == finest).unwrap_or(0);
    let precision = if opts.precisions.contains(&Precision::F64) { Precision::F64 } else { opts.precisions[0] };
    let p = opts.precisions.iter().position(|q| *q == precision).unwrap_or(0);
    let reference = (level * opts.precisions.len() + p) * backends.len();
    let study = Study {
        scene: planned.name,
        file: planned.file,
        observables: planned.observables,
        experiment: planned.experiment,
        runs,
        reference,
        warnings: planned.warnings,
    };
    Ok((study, planned.scenes))
}

/// Bodies whose lattice box is not a whole number of dx (to 1e-6 dx) on some axis: rectangle and box sides, the
/// diameter of round shapes and a cylinder's height. Such a body's outline moves by up to dx with the level, so
/// the levels do not model the same geometry (V0060's 1.87 mm × 0.29 mm fits dx/1, /2, /3, /4; dx × 0.333 does
/// not).
pub fn lattice_warnings(scene: &Scene) -> Vec<String> {
    let dx = scene.discretisation.dx;
    let mut out = Vec::new();
    for b in &scene.bodies {
        let sides: Vec<(&str, f64)> = match b.shape {
            Shape::Rectangle { min, max } => vec![("x", max[0] - min[0]), ("y", max[1] - min[1])],
            Shape::Box { min, max } => vec![("x", max[0] - min[0]), ("y", max[1] - min[1]), ("z", max[2] - min[2])],
            Shape::Disk { radius, .. } => vec![("diameter", 2.0 * radius)],
            Shape::Ring { outer_radius, .. } | Shape::SphericalShell { outer_radius, .. } => {
                vec![("outer diameter", 2.0 * outer_radius)]
            }
            Shape::Cylinder { radius, height, .. } => vec![("diameter", 2.0 * radius), ("height", height)],
        };
        for (what, length) in sides {
            let cells = length / dx;
            if (cells - cells.round()).abs() > 1e-6 {
                out.push(format!(
                    "body '{}': its {what} {length:e} m is {cells:.6} dx at dx = {dx:e} m, not a whole number: its \
                     lattice does not fill the same shape as at the other levels",
                    b.name
                ));
            }
        }
    }
    out
}

/// The study's line about a finished run.
fn run_line(run: &Run, outcome: &Outcome) -> String {
    let head = format!("study: level {} (dx = {:e} m), {}, {}", run.level, run.dx, run.precision.as_str(), run.backend);
    match outcome {
        Outcome::Done(s) => format!(
            "{head}: {} particles, {} steps, {:.2} s wall, {:.3} ms/step",
            s.particles,
            s.steps,
            s.wall_s,
            table::ms_per_step(s)
        ),
        Outcome::Failed(m) => format!("{head}: failed: {m}"),
        Outcome::Pending => format!("{head}: pending"),
    }
}

/// Writes study.csv and study.md, and study.png; a plot that cannot be drawn is a warning (in `warnings` once, at
/// the `last` write), never a failed study.
fn write(study: &mut Study, dir: &Path, last: bool) -> Result<()> {
    let io = |path: PathBuf, e: std::io::Error| Error::Output(format!("{}: {e}", path.display()));
    let csv = dir.join(CSV);
    crate::output::write_atomic(&csv, table::csv(study).as_bytes()).map_err(|e| io(csv.clone(), e))?;
    let md = dir.join(MARKDOWN);
    crate::output::write_atomic(&md, table::markdown(study).as_bytes()).map_err(|e| io(md.clone(), e))?;
    let result = plot::draw(study, &dir.join(PNG));
    if last && let Err(why) = result {
        study.warnings.push(format!("{PNG} not drawn: {why}"));
    }
    Ok(())
}
