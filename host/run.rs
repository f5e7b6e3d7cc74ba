//! `swarf run`: a scene from file to output folder. Builds the particles, chooses Δt, steps the solver and writes,
//! every output interval, a binary VTU frame (indexed by `particles.pvd`) and a row of `energy.csv`. A
//! non-finite value stops the run with its particle, field, time and step, after the last good frame.

use crate::backend::{AnyBackend, Backend};
use crate::kernels::sph::params::flags;
use crate::kernels::sph::{SphParams, TensorOps};
use crate::kernels::{Real, Vector};
use crate::method::{Method, MethodFn, Plan};
use crate::output::{Array, Collection, Frame, TimeSeries, Values, io_err, vtu};
use crate::scene::{Precision, Scene};
use crate::solver::diagnostics::Diagnostics;
/// The header of `energy.csv` (its columns: `solver::diagnostics::ENERGY_COLUMNS`).
pub use crate::solver::diagnostics::energy_header;
use crate::solver::fields::FrameField;
use crate::solver::params::cfl_time_step;
use crate::state::HostParticles;
use crate::tuning::Tuning;
use crate::{Error, Result};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The run stops as unstable when the CFL step falls below this fraction of the initial one.
pub const MIN_DT_FRACTION: f64 = 0.01;

/// What `swarf run` was asked to do besides the scene.
#[derive(Clone, Debug)]
pub struct RunOptions {
    pub out_dir: PathBuf,
    /// Overrides the scene's precision.
    pub precision: Option<Precision>,
    /// Write frames (VTU + PVD); the energy CSV is always written.
    pub frames: bool,
    /// Also write the frames as HDF5 + XDMF (`particles.h5`, `particles.xmf`; needs the `hdf5` feature).
    pub hdf5: bool,
    pub quiet: bool,
    /// Print the diagnostics of every output step instead of a progress line.
    pub verbose: bool,
    /// The `--set` overrides the scene was loaded with (recorded in summary.json and the checkpoint).
    pub overrides: Vec<String>,
    /// Write `checkpoint.bin` every this much simulated time [s] (at the first output step past it).
    pub checkpoint_every: Option<f64>,
    /// Continue from `out_dir/checkpoint.bin` (the scene must be the run folder's, see [`resume_scene`]).
    pub resume: bool,
    /// Also write `checkpoint.bin` every this many seconds of wall time, between output steps too (None: never).
    pub checkpoint_wall: Option<f64>,
    /// Step counts, sorted, after which the per-particle state table `states/state_NNNNNN.csv` is written
    /// (`--state-at`; [`crate::state_table`]): the batches end exactly there.
    pub state_at: Vec<u64>,
}

impl RunOptions {
    /// A quiet run into `out_dir` that writes no frames (energy, force and summary files only): the options tests
    /// and analyses use.
    pub fn quiet(out_dir: PathBuf) -> Self {
        RunOptions {
            out_dir,
            precision: None,
            frames: false,
            hdf5: false,
            quiet: true,
            verbose: false,
            overrides: Vec::new(),
            checkpoint_every: None,
            resume: false,
            checkpoint_wall: None,
            state_at: Vec::new(),
        }
    }
}

/// The built-in default scene, `swarf run` without a scene: the V0060 orthogonal cut (cases/cutting/v0060.toml),
/// embedded at build time so that an installed swarf runs it from any folder.
pub const DEFAULT_SCENE: &str = include_str!("../cases/cutting/v0060.toml");

/// The default scene's origin (messages, summary.json's `scene_file`).
pub const DEFAULT_SCENE_ORIGIN: &str = "built-in:cases/cutting/v0060.toml";

/// The default scene with `overrides`; its material names come from `SWARF_MATERIALS` and the built-in library.
pub fn default_scene(overrides: &[String]) -> Result<Scene> {
    let search = crate::material::search::Search::without_scene();
    Scene::from_str_in(DEFAULT_SCENE, DEFAULT_SCENE_ORIGIN, overrides, search).map_err(|e| Error::Scene(e.to_string()))
}

/// The version of `swarf --version`, `swarf info` and run.log: the package version and the git commit it was
/// built from (build.rs; "unknown" where the source had no git). summary.json has both as keys.
pub const VERSION: &str = concat!(env!("CARGO_PKG_VERSION"), " (commit ", env!("SWARF_GIT_COMMIT"), ")");

/// Set by the Ctrl-C (and SIGTERM) handler: the run writes a checkpoint before its next batch of steps and stops.
pub static INTERRUPTED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// What a Ctrl-C (SIGINT, SIGTERM, SIGHUP) asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SignalAction {
    /// The first: the run writes a checkpoint after its current batch and stops ([`INTERRUPTED`]).
    Checkpoint,
    /// A later one: exit at once.
    Exit,
    /// A copy of the first (within [`SIGNAL_ECHO_MS`] of it): ignored.
    Echo,
}

/// Signals this soon after the first are the same Ctrl-C: `kill -INT` of a command can reach it twice (the
/// command and its process group). A person's second press comes later; before issue 27 the window was a whole
/// second, so pressing Ctrl-C twice in quick succession did not force the exit.
pub const SIGNAL_ECHO_MS: u64 = 200;

/// The signal handler's decision for a signal at `now_ms` (any monotonic milliseconds, above 0), given the time of
/// the first (`first_ms`, 0 before any, which this sets): the first asks for a checkpoint (and sets
/// [`INTERRUPTED`]), an echo within [`SIGNAL_ECHO_MS`] is ignored, any later one forces the exit.
pub fn on_signal(first_ms: &std::sync::atomic::AtomicU64, now_ms: u64) -> SignalAction {
    use std::sync::atomic::Ordering;
    match first_ms.compare_exchange(0, now_ms.max(1), Ordering::Relaxed, Ordering::Relaxed) {
        Ok(_) => {
            INTERRUPTED.store(true, Ordering::Relaxed);
            SignalAction::Checkpoint
        }
        Err(first) if now_ms.saturating_sub(first) < SIGNAL_ECHO_MS => SignalAction::Echo,
        Err(_) => SignalAction::Exit,
    }
}

/// The scene of a run folder to resume: its `scene.toml` with the overrides recorded in its checkpoint, refused
/// where it, its materials or the checkpoint differ from the run the checkpoint was written by ([`crate::resume`]).
pub fn resume_scene(dir: &Path) -> Result<(Scene, Vec<String>)> {
    let r = crate::resume::open(dir, false)?;
    Ok((r.scene, r.overrides))
}

/// Writes the scene's text (`scene.toml`), the library materials it names (`materials/<name>.toml`, the files'
/// text) and its tools' mesh files (`meshes/`) into the run folder, so that the folder holds every value it ran and
/// resumes from anywhere.
fn record_inputs(scene: &Scene, dir: &Path) -> Result<()> {
    let text = match std::fs::read(&scene.origin) {
        Ok(t) => Some(t),
        Err(_) => (scene.origin == DEFAULT_SCENE_ORIGIN).then(|| DEFAULT_SCENE.as_bytes().to_vec()),
    };
    if let Some(text) = text {
        let copy = dir.join("scene.toml");
        crate::output::write_atomic(&copy, &text).map_err(|e| io_err(&copy, e))?;
    }
    record_meshes(scene, dir)?;
    let materials = scene.library_materials();
    if materials.is_empty() {
        return Ok(());
    }
    let folder = dir.join(crate::material::search::FOLDER);
    std::fs::create_dir_all(&folder).map_err(|e| io_err(&folder, e))?;
    for m in materials {
        let path = folder.join(format!("{}.toml", m.name));
        crate::output::write_atomic(&path, m.text.as_bytes()).map_err(|e| io_err(&path, e))?;
    }
    Ok(())
}

/// Copies every mesh file the scene's tools read into `meshes/` of the run folder
/// ([`crate::scene::recorded_mesh_name`]), where a resumed run finds them ([`crate::scene::mesh_file_path`]).
fn record_meshes(scene: &Scene, dir: &Path) -> Result<()> {
    let meshes: Vec<&str> =
        scene.tool.iter().chain(&scene.more_tools).filter_map(|t| t.mesh.as_ref()).map(|m| m.file.as_str()).collect();
    if meshes.is_empty() {
        return Ok(());
    }
    let folder = dir.join(crate::scene::RECORDED_MESHES);
    std::fs::create_dir_all(&folder).map_err(|e| io_err(&folder, e))?;
    for file in meshes {
        let src = crate::scene::mesh_file_path(&scene.origin, file);
        let bytes = std::fs::read(&src).map_err(|e| io_err(&src, e))?;
        let copy = folder.join(crate::scene::recorded_mesh_name(file));
        crate::output::write_atomic(&copy, &bytes).map_err(|e| io_err(&copy, e))?;
    }
    Ok(())
}

/// The outcome of a run.
#[derive(Clone, Debug)]
pub struct RunReport {
    pub particles: usize,
    pub steps: u64,
    pub dt: f64,
    pub wall_s: f64,
    pub precision: &'static str,
    pub backend: String,
    /// Diagnostics at every output step, the first at t = 0.
    pub history: Vec<Diagnostics>,
}

/// The state at an output step, widened to f64, for observers (tests, analyses).
pub struct Snapshot<'a> {
    pub diagnostics: &'a Diagnostics,
    pub id: &'a [u32],
    pub pos: Vec<[f64; 3]>,
    pub vel: Vec<[f64; 3]>,
    /// Body index of each particle.
    pub body: Vec<u32>,
    /// Temperature and equivalent plastic strain, where modelled.
    pub temperature: Option<&'a [f64]>,
    pub plastic_strain: Option<&'a [f64]>,
}

/// Runs `scene` on the chosen backend.
pub fn run(any: &AnyBackend, scene: &Scene, opts: &RunOptions) -> Result<RunReport> {
    run_observed(any, scene, opts, None)
}

/// Runs `scene`, calling `observer` at every output step (after the frame is written); the observer returns
/// `false` to stop the run there.
pub fn run_observed(
    any: &AnyBackend,
    scene: &Scene,
    opts: &RunOptions,
    observer: Option<&mut dyn FnMut(&Snapshot) -> bool>,
) -> Result<RunReport> {
    let scene = &*scene.with_precision(opts.precision);
    crate::method::with_method(any, scene, RunWith { opts, observer })
}

pub use crate::method::sph::{Setup, setup};

/// `run_typed` for [`crate::method::with_method`].
struct RunWith<'a, 'o> {
    opts: &'a RunOptions,
    observer: Option<&'o mut dyn FnMut(&Snapshot) -> bool>,
}

impl MethodFn for RunWith<'_, '_> {
    type Out = RunReport;
    fn call<B: Backend, M: Method<B>>(self, b: &B, scene: &Scene) -> Result<RunReport> {
        run_typed::<B, M>(b, scene, self.opts, self.observer)
    }
}

/// A run in progress: the method, its clocks and the files it writes.
struct Run<'a, B: Backend, M: Method<B>> {
    b: &'a B,
    scene: &'a Scene,
    opts: &'a RunOptions,
    method: M,
    plan: Plan,
    tuning: &'static Tuning,
    log: RunLog,
    files: OutputFiles,
    pending: PendingOutput,
    h5: Option<H5>,
    cut: Option<crate::cutting::record::CutRecorder>,
    /// Every particle's position at t = 0 by id, for the contact distance of the diagnostics.
    initial: std::sync::Arc<Vec<[f64; 3]>>,
    ckpt_path: PathBuf,
    history: Vec<Diagnostics>,
    t0: Instant,
    dt: f64,
    frame: usize,
    next_out: f64,
    next_ckpt: f64,
    /// Where this process started (a resumed run's rates and time left count its own steps only).
    start: (u64, f64),
    /// Cell-list rebuilds before this process started (a resumed run's, from its checkpoint).
    rebuilds0: u64,
    /// When the last checkpoint was written (or the run started), for the wall-time cadence.
    last_ckpt: Instant,
    /// Most steps of the next batch: adapted so that a batch takes about [`BATCH_WALL_S`].
    batch: usize,
    /// The next entry of `opts.state_at` to write.
    next_state: usize,
    /// The steps (first, last) of the batch whose predictor flagged a non-finite position (for the report).
    flagged: Option<(u64, u64)>,
    /// The progress line's state (a terminal or a log).
    progress_out: crate::output::progress::Progress,
}

fn run_typed<B: Backend, M: Method<B>>(
    b: &B,
    scene: &Scene,
    opts: &RunOptions,
    mut observer: Option<&mut dyn FnMut(&Snapshot) -> bool>,
) -> Result<RunReport> {
    let mut run = Run::<B, M>::start(b, scene, opts)?;
    if opts.resume {
        run.resume()?;
    }
    run.start = (run.method.steps(), run.method.time());
    run.header()?;
    loop {
        run.write_states()?;
        if run.output_due() && run.output_step(&mut observer)? {
            break;
        }
        if INTERRUPTED.load(std::sync::atomic::Ordering::Relaxed) {
            return Err(run.interrupt()?);
        }
        run.wall_checkpoint()?;
        run.advance()?;
    }
    Ok(RunReport {
        particles: run.plan.particles,
        steps: run.method.steps(),
        dt: run.plan.dt,
        wall_s: run.t0.elapsed().as_secs_f64(),
        precision: run.plan.precision,
        backend: b.info().backend.to_string(),
        history: run.history,
    })
}

impl<'a, B: Backend, M: Method<B>> Run<'a, B, M> {
    /// Sets the method up (refusing, before it allocates, a run the GPU cannot hold), creates the run folder and
    /// opens its files.
    fn start(b: &'a B, scene: &'a Scene, opts: &'a RunOptions) -> Result<Self> {
        let tuning = Tuning::current()?;
        let s = M::setup(scene, tuning)?;
        let mut plan = M::plan(&s);
        crate::check::fits(plan.memory_bytes, b.info())?;
        plan.warnings.extend(crate::check::steps(scene, plan.dt, plan.h, plan.c0)?.1);
        std::fs::create_dir_all(&opts.out_dir).map_err(|e| io_err(&opts.out_dir, e))?;
        // The run folder keeps the scene it ran (as given, with the overrides recorded in summary.json).
        record_inputs(scene, &opts.out_dir)?;
        let mut log = RunLog::new(opts.out_dir.join("run.log"));
        if opts.resume {
            log.text = std::fs::read_to_string(&log.path).unwrap_or_default();
        }
        let method = M::new(b, &s)?;
        drop(s);
        let files = OutputFiles {
            csv: TimeSeries::new(opts.out_dir.join("energy.csv"), &energy_header()),
            // Temperatures over time (drawn as temperature.png), when the run models them.
            tcsv: plan
                .temperature
                .then(|| TimeSeries::new(opts.out_dir.join("temperature.csv"), &["time", "step", "temperature_max"])),
            pvd: Collection::new(opts.out_dir.join("particles.pvd")),
        };
        let h5 = open_hdf5(opts)?;
        // Cutting runs record the tool force and the chip (forces.csv, and the analysis in summary.json).
        let cut = match &scene.tool {
            Some(t) => crate::cutting::record::CutRecorder::new(
                scene,
                t.mesh.is_none().then(|| crate::tool::setup::build_tool(t)).transpose()?,
                &plan.workpiece,
                &opts.out_dir,
            ),
            None => None,
        };
        Ok(Run {
            b,
            scene,
            opts,
            method,
            initial: std::sync::Arc::new(plan.initial.clone()),
            dt: plan.dt,
            plan,
            tuning,
            log,
            files,
            pending: PendingOutput::default(),
            h5,
            cut,
            ckpt_path: opts.out_dir.join("checkpoint.bin"),
            history: Vec::new(),
            t0: Instant::now(),
            frame: 0,
            next_out: 0.0,
            next_ckpt: opts.checkpoint_every.unwrap_or(f64::INFINITY),
            start: (0, 0.0),
            rebuilds0: 0,
            last_ckpt: Instant::now(),
            batch: GRAPH_BATCH,
            next_state: 0,
            flagged: None,
            progress_out: crate::output::progress::Progress::new(std::io::IsTerminal::is_terminal(&std::io::stderr())),
        })
    }

    /// Continues from the run folder's checkpoint: the state, the clocks, and the files up to its time.
    fn resume(&mut self) -> Result<()> {
        let (h, blobs) = crate::checkpoint::read(&self.ckpt_path)?;
        let (n, dim, precision) = (self.plan.particles, self.method.dim(), self.plan.precision);
        if h.precision != precision || h.dim != dim || h.particles != n {
            return Err(Error::Checkpoint(format!(
                "{} holds a {}D {} run of {} particles; this scene is {dim}D {precision} with {n}",
                self.ckpt_path.display(),
                h.dim,
                h.precision,
                h.particles,
            )));
        }
        let bad = |e: String| Error::Checkpoint(format!("{}: {e}", self.ckpt_path.display()));
        crate::checkpoint::validate(&h, &blobs).map_err(bad)?;
        // The CFL re-check only lowers Δt, and stops the run below this fraction of the initial one.
        let dt0 = self.plan.dt;
        if h.dt < MIN_DT_FRACTION * dt0 {
            return Err(bad(format!("header: dt = {:e} s: expected at least {:e} s (1 % of the scene's)", h.dt, dt0)));
        }
        // The clock first: the state's time decides the tool's ramp, the load reversals' signs and the blanking's
        // box that `load_state` restores.
        self.method.set_clock(h.time, h.steps);
        self.method.load_state(self.b, &blobs)?;
        // An accepted change of the scene (--accept-changes) may have lowered the stable step.
        self.dt = h.dt.min(dt0);
        self.rebuilds0 = h.rebuilds;
        self.method.set_nominal_dt(self.dt);
        self.frame = h.frame;
        self.next_out = h.next_out;
        self.next_ckpt = h.next_checkpoint.unwrap_or(f64::INFINITY);
        // Continue the time series and the frame index up to the checkpoint.
        let f = &mut self.files;
        for series in std::iter::once(&mut f.csv).chain(f.tcsv.as_mut()) {
            if let Ok((_, rows)) = crate::output::csv::read(series.path()) {
                for r in rows.into_iter().filter(|r| r[0] <= h.time) {
                    series.push(&r).map_err(|e| io_err(series.path(), e))?;
                }
            }
        }
        if let Some(c) = self.cut.as_mut() {
            c.resume(h.time)?;
        }
        if let Ok(entries) = crate::output::pvd::read_parts(f.pvd.path()) {
            let kept: Vec<_> = entries.into_iter().filter(|e| e.0 <= h.time).collect();
            // The checkpoint is written after its step's frame: the index holds exactly its frame count (part 0;
            // part 1 is the tool's outline beside a frame).
            let frames = kept.iter().filter(|e| e.1 == 0).count();
            if self.opts.frames && frames != h.frame {
                return Err(Error::Checkpoint(format!(
                    "{}: header: frame = {}: expected {}, the frames of particles.pvd up to t = {:e} s",
                    self.ckpt_path.display(),
                    h.frame,
                    frames,
                    h.time
                )));
            }
            for (t, part, name) in kept {
                f.pvd.push_part(t, part, name).map_err(|e| io_err(f.pvd.path(), e))?;
            }
        }
        self.log.line(&format!("resumed from {} at t = {:e} s, step {}", self.ckpt_path.display(), h.time, h.steps))
    }

    /// The run's first lines (printed unless quiet, and logged): what runs, and the scene's warnings.
    fn header(&mut self) -> Result<()> {
        let (scene, p, info) = (self.scene, &self.plan, self.b.info());
        let head = format!(
            "{}: {} particles, {}D {}, h = {:.4e} m, c0 = {:.1} m/s, dt = {:.4e} s, about {} steps, {} ({})",
            scene.name,
            p.particles,
            scene.dim,
            p.precision,
            p.h,
            p.c0,
            self.dt,
            crate::check::steps(scene, self.dt, p.h, p.c0).map_or("too many".into(), |s| s.0.to_string()),
            info.backend,
            info.name
        );
        // Where the run can be continued from (checkpoints only at output steps went unwritten with sparse frames).
        let (every, wall) = (self.opts.checkpoint_every, self.opts.checkpoint_wall);
        let head = format!(
            "{head}; checkpoints{}{}{} and on Ctrl-C or SIGTERM",
            every.map_or(String::new(), |e| format!(" every {e:e} s of simulated time")),
            if every.is_some() && wall.is_some() { "," } else { "" },
            wall.map_or(String::new(), |w| format!(" every {w} s of wall time"))
        );
        if !self.opts.quiet {
            eprintln!("{head}");
        }
        self.log.line(&format!("swarf {VERSION}"))?;
        self.log.line(&head)?;
        if !scene.model.is_swarf() {
            // Not swarf's model: say so wherever the run's results go (docs/validation.md, "The original model").
            let list: Vec<&str> = scene.model.switches().list().into_iter().map(|s| s.name()).collect();
            let line = format!(
                "model: the original 2D code's (MFREE_IWF), bugs included, in: {} (docs/validation.md)",
                list.join(", ")
            );
            if !self.opts.quiet {
                eprintln!("{line}");
            }
            self.log.line(&line)?;
        }
        for w in &p.warnings {
            if !self.opts.quiet {
                eprintln!("warning: {w}");
            }
            self.log.line(&format!("warning: {w}"))?;
        }
        Ok(())
    }

    /// Whether `t` is at or past `at`, within the loop's 1e-9 Δt tolerance.
    fn reached(&self, at: f64) -> bool {
        self.method.time() >= at - 1e-9 * self.dt
    }

    fn output_due(&self) -> bool {
        self.reached(self.next_out) || self.reached(self.scene.time.end)
    }

    /// An output step: the diagnostics, the force sample, the files (in the background where nothing reads them
    /// before the next output), the CFL re-check, the progress line, a due checkpoint and the observer. Returns
    /// whether the run ends here (the end, or the observer asked to stop), after writing its summary.
    fn output_step(&mut self, observer: &mut Option<&mut dyn FnMut(&Snapshot) -> bool>) -> Result<bool> {
        let (b, opts) = (self.b, self.opts);
        // The previous output's files are complete before this one's are started.
        if let Some(d) = self.pending.join(&mut self.files)? {
            self.history.push(d);
        }
        let out = self.method.output(b)?;
        let (time, steps) = (self.method.time(), self.method.steps());
        if let Some((id, field)) = out.diagnostics.non_finite {
            let region = out.diagnostics.non_finite_region.describe();
            return Err(Error::NonFinite { id, field, time, step: steps, flagged: self.flagged, region });
        }
        let mut stop_early = false;
        if let Some(c) = self.cut.as_mut() {
            if c.due(time)
                && let Some(sample) = self.method.tool_sample(b)?
            {
                c.sample(&sample)?;
            }
            c.write()?;
            // `[analysis] early_stop`: F_c and F_f steady to its tolerance ends the run here, as its end would.
            stop_early = c.early_stop_due(time, steps);
        }
        // Written now where anything reads them before the next output (an observer, a checkpoint, the end, the
        // HDF5 file), else by a thread while the next steps run.
        let last = self.reached(self.scene.time.end) || stop_early;
        let ckpt_due = self.reached(self.next_ckpt) && !last;
        let background = observer.is_none() && self.h5.is_none() && !ckpt_due && !last;
        let mut job = OutputJob {
            d: out.diagnostics,
            host: out.host,
            internal: out.internal,
            fields: if opts.frames { out.fields } else { Vec::new() },
            now: out.positions,
            tools: if opts.frames { out.tools } else { Vec::new() },
            initial: self.initial.clone(),
            radius: 2.0 * self.plan.h,
            params: out.params,
            frame: opts.frames.then(|| (opts.out_dir.clone(), self.frame, self.scene.output.vtu_encoding)),
            time,
            steps,
        };
        // The written job keeps the state for the observer and the end of the run; a job in the background is
        // never read again here (no observer, not the last step).
        let d = job.d.clone();
        let kept = if background {
            self.pending.start(job, &mut self.files);
            None
        } else {
            job.write(&mut self.files, &mut self.h5)?;
            Some(job)
        };
        self.frame += 1;
        self.next_out = self.frame as f64 * self.scene.output.every;
        self.recheck_cfl(&d)?;
        self.progress(&d)?;
        // After the CFL re-check: its Δt sets the tolerance, as for the steps that follow.
        let end = self.scene.time.end;
        if self.reached(self.next_ckpt) && !self.reached(end) && !stop_early {
            while self.next_ckpt <= time + 1e-9 * self.dt {
                self.next_ckpt += opts.checkpoint_every.unwrap_or(f64::INFINITY);
            }
            self.save_checkpoint()?;
            self.last_ckpt = Instant::now();
            self.log.line(&format!("checkpoint at t = {time:e} s, step {steps}"))?;
        }
        let keep_going = match (observer.as_deref_mut(), kept.as_ref()) {
            (Some(f), Some(j)) => f(&j.snapshot()),
            _ => true,
        };
        if let Some(j) = kept.as_ref() {
            self.history.push(j.d.clone());
        }
        if (!keep_going || stop_early || self.reached(end))
            && let Some(j) = kept
        {
            self.finish(j)?;
            return Ok(true);
        }
        Ok(false)
    }

    /// Re-checks the CFL condition with the current largest speed (unless the scene fixes Δt).
    fn recheck_cfl(&mut self, d: &Diagnostics) -> Result<()> {
        let scene = self.scene;
        if scene.time.dt.is_some() {
            return Ok(());
        }
        let (h, c0, dt0) = (self.plan.h, self.plan.c0, self.plan.dt);
        let limit = cfl_time_step(scene.time.cfl, h, c0, d.vmax);
        if limit < self.dt {
            self.dt = limit;
            self.method.set_nominal_dt(self.dt);
        }
        // A speed that has grown by orders of magnitude is a blow-up, not physics: stop instead of crawling.
        if self.dt < MIN_DT_FRACTION * dt0 {
            let (time, step) = (self.method.time(), self.method.steps());
            return Err(Error::Unstable { vmax: d.vmax, dt: self.dt, dt0, time, step });
        }
        Ok(())
    }

    /// The output step's log line, and the progress line (or the log line with `--verbose`).
    fn progress(&mut self, d: &Diagnostics) -> Result<()> {
        let n = self.plan.particles as f64;
        let end = self.scene.time.end;
        let (steps0, time0) = self.start;
        let el = self.t0.elapsed().as_secs_f64();
        let rate = d.step.saturating_sub(steps0) as f64 / el.max(1e-9);
        let line = format!(
            "t = {:.4e} s  step {}  E_kin {:.4e}  E_el {:.4e}  {:.0} steps/s  {:.3e} particle-steps/s",
            d.time,
            d.step,
            d.kinetic,
            d.elastic,
            rate,
            rate * n
        );
        self.log.line(&line)?;
        if self.opts.verbose {
            eprintln!("{line}");
        } else if !self.opts.quiet {
            // Simulated time, rates and the time left: rewritten in place on a terminal, plain lines in a log.
            let frac = (d.time / end).clamp(0.0, 1.0);
            let done = (d.time - time0) / (end - time0);
            let eta = (done > 0.0).then(|| el * (1.0 - done) / done);
            if let Some(text) = self.progress_out.update(frac, d.time, rate, n, eta) {
                eprint!("{text}");
            }
        }
        Ok(())
    }

    /// The end of the run: the cutting analysis, `summary.json` and the plots.
    fn finish(&mut self, j: OutputJob<M::R, M::D>) -> Result<()> {
        let (b, opts, scene) = (self.b, self.opts, self.scene);
        b.synchronize()?;
        let body: Vec<u32> = j.host.flags.iter().map(|f| f >> flags::BODY_SHIFT).collect();
        let wall = self.t0.elapsed().as_secs_f64();
        // A resting tool (a rigid wall, a target dropped onto) cuts nothing, and a rotating one (a milling cutter, a
        // wheel) makes no steady orthogonal cut: forces.csv only, no cutting analysis.
        let orthogonal =
            scene.tool.as_ref().is_some_and(|t| t.velocity.iter().any(|v| *v != 0.0) && t.rotation.is_none());
        let cutting = self.cut.as_ref().filter(|_| orthogonal).map(|c| c.analysis());
        if let (Some(a), false) = (&cutting, opts.quiet) {
            eprintln!("{}", cutting_line(a));
        }
        if let Some(a) = &cutting {
            self.log.line(&cutting_line(a))?;
        }
        let chip = self.cut.as_ref().filter(|_| orthogonal).and_then(|c| last_chip(c, scene, &j));
        if let Some(c) = &chip {
            let line = crate::cutting::chip_report::line(c);
            if !opts.quiet {
                eprintln!("{line}");
            }
            self.log.line(&line)?;
        }
        let cutting = cutting.map(|a| with_chip_frame(a.json(), chip.as_ref(), j.time));
        let cohesive = cohesive_entry(scene, &j.d);
        let audit = self.cut.as_ref().map(|c| {
            let booked = booked_energy(&self.files, &j.d);
            (c.energy.line(booked), c.energy.json(booked))
        });
        for (line, _) in cohesive.iter().chain(&audit) {
            if !opts.quiet {
                eprintln!("{line}");
            }
            self.log.line(line)?;
        }
        let summary = Summary {
            dir: &opts.out_dir,
            overrides: &opts.overrides,
            scene,
            info: b.info(),
            precision: self.plan.precision,
            particles: self.plan.particles,
            steps: self.method.steps(),
            rebuilds: self.rebuilds0 + u64::from(self.method.rebuilds(b)?),
            dt: self.plan.dt,
            wall,
            tuning: self.tuning,
            cohesive: cohesive.map(|(_, v)| v),
            energy_audit: audit.map(|(_, v)| v),
        };
        summary.write(&j.now, &body, &set_centres(scene), cutting)?;
        if opts.frames {
            // The plots are a convenience: a failure is reported, never fatal to a finished run.
            match crate::plot::plot_run(&opts.out_dir) {
                Ok(drawn) => {
                    for d in drawn.iter().filter_map(|d| d.warning()) {
                        eprintln!("warning: {d}");
                    }
                }
                Err(e) => eprintln!("warning: plots not drawn: {e}"),
            }
        }
        Ok(())
    }

    /// Ctrl-C: finishes the pending files, writes a checkpoint and returns the error that stops the run.
    fn interrupt(&mut self) -> Result<Error> {
        if let Some(d) = self.pending.join(&mut self.files)? {
            self.history.push(d);
        }
        self.save_checkpoint_between_outputs()?;
        let (time, step) = (self.method.time(), self.method.steps());
        self.log.line(&format!("interrupted at t = {time:e} s, step {step}; checkpoint written"))?;
        Ok(Error::Interrupted {
            time,
            step,
            path: self.ckpt_path.display().to_string(),
            dir: self.opts.out_dir.display().to_string(),
        })
    }

    /// The wall-time cadence (`checkpoint_wall`): a checkpoint between output steps too, so that a run with sparse
    /// frames has one.
    fn wall_checkpoint(&mut self) -> Result<()> {
        let Some(every) = self.opts.checkpoint_wall else { return Ok(()) };
        if self.last_ckpt.elapsed().as_secs_f64() < every {
            return Ok(());
        }
        if let Some(d) = self.pending.join(&mut self.files)? {
            self.history.push(d);
        }
        self.save_checkpoint_between_outputs()?;
        self.last_ckpt = Instant::now();
        let (time, step) = (self.method.time(), self.method.steps());
        self.log.line(&format!("checkpoint at t = {time:e} s, step {step} ({every} s of wall time since the last)"))
    }

    /// Full steps up to the next event (an output, the end, a force sample) run as one batch of at most
    /// `self.batch` steps, halved when a batch takes longer than [`BATCH_WALL_S`] and doubled (up to
    /// [`MAX_BATCH`]) when one takes under a quarter of it, so that Ctrl-C acts within about a second on any
    /// backend (with batches of 4096 steps it took 15 s on a CPU); the step that lands on an output time is cut
    /// short. A non-finite value is reported at once, not at the next output:
    /// non-finite particles rebuild the cell list every step and pile into its void bucket, which slows every
    /// step down (the 150k f32 cut stalled for minutes).
    fn advance(&mut self) -> Result<()> {
        let (b, dt, end) = (self.b, self.dt, self.scene.time.end);
        let t = self.method.time();
        let clock = Instant::now();
        // A state table's step ends the batch (`write_states` wrote the ones at the current step).
        let max = match self.opts.state_at.get(self.next_state) {
            Some(&at) => self.batch.min(at.saturating_sub(self.method.steps()).max(1) as usize),
            None => self.batch,
        };
        let full = full_steps(t, dt, self.next_out, end, self.cut.as_ref().map(|c| c.next()), max);
        let first = self.method.steps() + 1;
        if full > 0 {
            self.method.advance(b, dt, full)?;
        } else {
            self.method.step(b, dt.min(end - t).min(self.next_out - t).max(1e-12 * dt))?;
        }
        if self.method.non_finite_seen(b)? {
            self.flagged = Some((first, self.method.steps()));
            self.next_out = self.method.time();
            return Ok(());
        }
        // Timed after the flag's read, which waits for the device.
        let took = clock.elapsed().as_secs_f64();
        if took > BATCH_WALL_S {
            self.batch = (self.batch / 2).max(1);
        } else if took < BATCH_WALL_S / 4.0 && full == self.batch {
            self.batch = (2 * self.batch).min(MAX_BATCH);
        }
        if let Some(c) = self.cut.as_mut()
            && c.due(self.method.time())
            && let Some(sample) = self.method.tool_sample(b)?
        {
            c.sample(&sample)?;
        }
        Ok(())
    }

    /// Writes the state tables due at the current step (`RunOptions::state_at`; those of steps already passed, e.g.
    /// before a resumed run's checkpoint, are skipped).
    fn write_states(&mut self) -> Result<()> {
        let steps = self.method.steps();
        while let Some(&at) = self.opts.state_at.get(self.next_state) {
            if at > steps {
                break;
            }
            if at == steps {
                let out = self.method.output(self.b)?;
                let path = crate::state_table::path(&self.opts.out_dir, steps);
                crate::state_table::write(&path, &out.host, &out.positions, &self.initial, &out.fields)?;
            }
            self.next_state += 1;
        }
        Ok(())
    }

    /// Writes `forces.csv` and then, atomically, `checkpoint.bin` with the clocks to continue from: a resume keeps
    /// the file's samples up to the checkpoint's time, and those taken since the last output step were held only
    /// in memory (an interrupted 2 M grain lost 0.7 µs of them). For the checkpoints between output steps (Ctrl-C,
    /// the wall-time cadence); an output step has just written `forces.csv` itself.
    fn save_checkpoint_between_outputs(&self) -> Result<()> {
        if let Some(c) = self.cut.as_ref() {
            c.write()?;
        }
        self.save_checkpoint()
    }

    /// Writes `checkpoint.bin` (atomically) with the clocks to continue from.
    fn save_checkpoint(&self) -> Result<()> {
        let state = self.method.save_state(self.b)?;
        let h = crate::checkpoint::Header {
            overrides: self.opts.overrides.clone(),
            precision: self.method.precision().to_string(),
            dim: self.method.dim(),
            particles: self.method.particles(),
            time: self.method.time(),
            steps: self.method.steps(),
            dt: self.dt,
            frame: self.frame,
            next_out: self.next_out,
            next_checkpoint: self.next_ckpt.is_finite().then_some(self.next_ckpt),
            fields: Vec::new(),
            version: String::new(),
            provenance: Some(crate::provenance::Provenance::of(self.scene)),
            rebuilds: self.rebuilds0 + u64::from(self.method.rebuilds(self.b)?),
            checksums: Vec::new(),
        };
        crate::checkpoint::write(&self.ckpt_path, h, &state)
    }
}

/// Most steps between two checks for an interrupt.
const MAX_BATCH: usize = 4096;
/// The first batch's steps (a whole number of the GPU's captured batches).
const GRAPH_BATCH: usize = 2 * crate::solver::GRAPH_STEPS;
/// The wall time a batch of steps aims at [s].
const BATCH_WALL_S: f64 = 0.5;

/// How many steps of exactly `dt` the run loop takes from `t` before its next event: each must fit before the
/// output time and the end (else the step is cut short), and the batch stops after the step that reaches an output
/// time (within the loop's 1e-9 Δt tolerance), the end, or the next force sample `sample`. Replays the host's
/// `t += dt`, so the batch ends exactly where single steps would.
pub fn full_steps(t: f64, dt: f64, next_out: f64, end: f64, sample: Option<f64>, max: usize) -> usize {
    let mut t = t;
    let mut k = 0;
    while k < max && dt <= end - t && dt <= next_out - t {
        t += dt;
        k += 1;
        if t >= next_out - 1e-9 * dt || t >= end - 1e-9 * dt || sample.is_some_and(|s| t >= s) {
            break;
        }
    }
    k
}

/// `run.log` of the run folder: the header and one line per output step, rewritten atomically each time.
struct RunLog {
    path: PathBuf,
    text: String,
}

impl RunLog {
    fn new(path: PathBuf) -> Self {
        RunLog { path, text: String::new() }
    }

    fn line(&mut self, l: &str) -> Result<()> {
        self.text.push_str(l);
        self.text.push('\n');
        crate::output::write_atomic(&self.path, self.text.as_bytes()).map_err(|e| io_err(&self.path, e))
    }
}

/// The files of a run that output steps append to: energy (and temperature) rows and the frame collection.
struct OutputFiles {
    csv: TimeSeries,
    tcsv: Option<TimeSeries>,
    pvd: Collection,
}

/// What an output step writes once the state is on the host: the closest-pair diagnostics (`analysis::
/// min_pair_distances`), the energy and temperature rows, and the frame with its collection entry. Owns its data,
/// so that a thread can write it while the next steps run ([`PendingOutput`]).
struct OutputJob<R: Real, D: TensorOps<R>> {
    d: Diagnostics,
    host: HostParticles<R, D>,
    /// Temperature, plastic strain and its rate, where modelled.
    internal: [Option<Vec<f64>>; 3],
    /// The field registry's frame fields (`Solver::download_frame_fields`), when frames are written.
    fields: Vec<FrameField>,
    now: Vec<[f64; 3]>,
    /// The tools in the world (written beside the frame: `tool_*.vtp`, then `tool2_*.vtp`, …).
    tools: Vec<crate::tool::Picture>,
    /// Every particle's position at t = 0 by id.
    initial: std::sync::Arc<Vec<[f64; 3]>>,
    /// The closest-pair search radius (2h).
    radius: f64,
    params: SphParams<R>,
    /// The run folder, frame index and VTU encoding, when frames are written.
    frame: Option<(PathBuf, usize, vtu::Encoding)>,
    time: f64,
    steps: u64,
}

impl<R: Real, D: TensorOps<R>> OutputJob<R, D> {
    /// The state for an observer, widened to f64.
    fn snapshot(&self) -> Snapshot<'_> {
        Snapshot {
            diagnostics: &self.d,
            id: &self.host.id,
            pos: self.now.clone(),
            vel: crate::analysis::positions_f64::<R, _>(&self.host.vel),
            body: self.host.flags.iter().map(|f| f >> flags::BODY_SHIFT).collect(),
            temperature: self.internal[0].as_deref(),
            plastic_strain: self.internal[1].as_deref(),
        }
    }

    /// Completes the diagnostics (`d`) and writes the rows and the frame.
    fn write(&mut self, f: &mut OutputFiles, h5: &mut Option<H5>) -> Result<()> {
        let OutputJob { d, host, internal, fields, now, tools, initial, radius, params, frame, time, steps } = self;
        let (radius, time, steps) = (*radius, *time, *steps);
        // Closest approach of two mechanical particles (within 2h): pairing and interpenetration show here.
        // Of pairs that started at least 2h apart: contact between material that was apart (chip self-contact),
        // with where it is and which particles, to tell the tool face from the chip's back or the boundary.
        let mech: Vec<bool> = host.flags.iter().map(|f| f & flags::THERMAL_ONLY == 0).collect();
        let start: Vec<[f64; 3]> = host.id.iter().map(|&i| initial[i as usize]).collect();
        let (all, apart) = crate::analysis::min_pair_distances(now, &mech, radius, &start, &host.id)?;
        d.min_pair_distance = all.unwrap_or(f64::NAN);
        if let Some(c) = apart {
            d.min_contact_distance = c.distance;
            d.min_contact_midpoint = c.midpoint;
            d.min_contact_ids = Some(c.ids);
        }
        let (csv, tcsv) = (&mut f.csv, &mut f.tcsv);
        csv.push(&d.energy_row()).map_err(|e| io_err(csv.path(), e))?;
        csv.write().map_err(|e| io_err(csv.path(), e))?;
        if let Some(t) = tcsv.as_mut() {
            t.push(&[d.time, d.step as f64, d.temperature_max]).map_err(|e| io_err(t.path(), e))?;
            t.write().map_err(|e| io_err(t.path(), e))?;
        }
        if let Some((dir, index, encoding)) = frame {
            let name = format!("frame_{index:05}.vtu");
            let temp = internal[0].as_deref();
            write_frame(&dir.join(&name), *encoding, h5, host, temp, fields, params, time, steps)?;
            f.pvd.push(time, name).map_err(|e| io_err(f.pvd.path(), e))?;
            for (k, picture) in tools.iter().enumerate() {
                let name =
                    if k == 0 { format!("tool_{index:05}.vtp") } else { format!("tool{}_{index:05}.vtp", k + 1) };
                let written = match picture {
                    crate::tool::Picture::Outline(p) => crate::output::vtp::write_outline(&dir.join(&name), time, p),
                    crate::tool::Picture::Surface(p) => crate::output::vtp::write_surface(&dir.join(&name), time, p),
                };
                written.map_err(|e| io_err(&dir.join(&name), e))?;
                f.pvd.push_part(time, k as u32 + 1, name).map_err(|e| io_err(f.pvd.path(), e))?;
            }
            f.pvd.write().map_err(|e| io_err(f.pvd.path(), e))?;
        }
        Ok(())
    }
}

/// The output job writing in the background, if any.
#[derive(Default)]
struct PendingOutput {
    job: Option<std::thread::JoinHandle<(OutputFiles, Result<Diagnostics>)>>,
}

impl PendingOutput {
    /// Starts `job` on a thread of its own with the run's files (handed back by [`PendingOutput::join`]).
    fn start<R: Real, D: TensorOps<R>>(&mut self, job: OutputJob<R, D>, files: &mut OutputFiles)
    where
        HostParticles<R, D>: Send + 'static,
    {
        let mut f = std::mem::replace(files, OutputFiles::empty());
        self.job = Some(std::thread::spawn(move || {
            let mut job = job;
            let r = job.write(&mut f, &mut None).map(|()| job.d);
            (f, r)
        }));
    }

    /// Waits for the job, puts the files back and returns its diagnostics (None: nothing was pending).
    fn join(&mut self, files: &mut OutputFiles) -> Result<Option<Diagnostics>> {
        let Some(h) = self.job.take() else { return Ok(None) };
        let (f, r) = h.join().map_err(|_| Error::Output("the output thread panicked".into()))?;
        *files = f;
        r.map(Some)
    }
}

impl Drop for PendingOutput {
    /// A run that stops early (an error) still finishes the files it started.
    fn drop(&mut self) {
        if let Some(h) = self.job.take() {
            let _ = h.join();
        }
    }
}

impl OutputFiles {
    /// Placeholders while the files are with the output thread.
    fn empty() -> Self {
        OutputFiles { csv: TimeSeries::new(PathBuf::new(), &[]), tcsv: None, pvd: Collection::new(PathBuf::new()) }
    }
}

#[cfg(feature = "hdf5")]
type H5 = crate::output::hdf5::H5Writer;
/// Without the `hdf5` feature there is no HDF5 writer.
#[cfg(not(feature = "hdf5"))]
type H5 = std::convert::Infallible;

/// The HDF5 writer of a run that asked for one.
fn open_hdf5(opts: &RunOptions) -> Result<Option<H5>> {
    if !opts.hdf5 || !opts.frames {
        return Ok(None);
    }
    #[cfg(feature = "hdf5")]
    {
        let path = opts.out_dir.join("particles.h5");
        crate::output::hdf5::H5Writer::create(&path).map(Some).map_err(|e| io_err(&path, e))
    }
    #[cfg(not(feature = "hdf5"))]
    {
        Err(Error::Output(
            "--hdf5: this swarf was built without HDF5 support; rebuild with `cargo build --release --features hdf5` \
             (needs the system HDF5 library, e.g. Debian's libhdf5-dev)"
                .into(),
        ))
    }
}

/// One VTU frame: positions, id, body, boundary kind, velocity, density, pressure, stress (VTK order xx, yy, zz,
/// xy, yz, xz) and von Mises stress.
#[allow(clippy::too_many_arguments)]
fn write_frame<R: Real, D: TensorOps<R>>(
    path: &Path,
    encoding: vtu::Encoding,
    h5: &mut Option<H5>,
    p: &HostParticles<R, D>,
    temp: Option<&[f64]>,
    fields: &[FrameField],
    params: &SphParams<R>,
    time: f64,
    step: u64,
) -> Result<()> {
    let n = p.len();
    let pts: Vec<f64> = p.pos.iter().flat_map(|x| (0..3).map(|k| x.get(k).to_f64())).collect();
    let vel: Vec<f64> = p.vel.iter().flat_map(|x| (0..3).map(|k| x.get(k).to_f64())).collect();
    let rho: Vec<f64> = p.rho.iter().map(|r| r.to_f64()).collect();
    let pressure: Vec<f64> = p
        .rho
        .iter()
        .enumerate()
        .map(|(i, r)| crate::kernels::sph::interact::pressure_at(params, *r, temp.map_or(0.0, |t| t[i])).to_f64())
        .collect();
    let mut stress = Vec::with_capacity(6 * n);
    let mut vm = Vec::with_capacity(n);
    for s in &p.stress {
        let c: &[R] = bytemuck::cast_slice(std::slice::from_ref(s));
        let c: Vec<f64> = c.iter().map(|x| x.to_f64()).collect();
        // Stored 2D (xx, xy, yy, zz), 3D (xx, xy, xz, yy, yz, zz) → VTK (xx, yy, zz, xy, yz, xz).
        let v = if D::D == 2 { [c[0], c[2], c[3], c[1], 0.0, 0.0] } else { [c[0], c[3], c[5], c[1], c[4], c[2]] };
        stress.extend_from_slice(&v);
        vm.push(crate::kernels::sph::energy::von_mises::<R, D>(s).to_f64());
    }
    let body: Vec<u32> = p.flags.iter().map(|f| f >> flags::BODY_SHIFT).collect();
    let bc: Vec<u32> = p.flags.iter().map(|f| f & flags::KIND_MASK).collect();
    let mut point_data = vec![
        Array { name: "id", components: 1, values: Values::U32(&p.id) },
        Array { name: "body", components: 1, values: Values::U32(&body) },
        Array { name: "boundary", components: 1, values: Values::U32(&bc) },
        Array { name: "velocity", components: 3, values: Values::F64(&vel) },
        Array { name: "density", components: 1, values: Values::F64(&rho) },
        Array { name: "pressure", components: 1, values: Values::F64(&pressure) },
        Array { name: "stress", components: 6, values: Values::F64(&stress) },
        Array { name: "von_mises", components: 1, values: Values::F64(&vm) },
    ];
    for f in fields {
        point_data.push(Array { name: f.name, components: f.components, values: Values::F64(&f.values) });
    }
    let acting = fields.iter().find(|f| f.name == "damage").map(|f| acting_stress(&f.values, &vm, &pressure));
    if let Some((vm_acting, p_acting)) = &acting {
        point_data.push(Array { name: "von_mises_acting", components: 1, values: Values::F64(vm_acting) });
        point_data.push(Array { name: "pressure_acting", components: 1, values: Values::F64(p_acting) });
    }
    let frame = Frame { time, points: Values::F64(&pts), point_data, field_data: vec![("STEP", step as f64)] };
    vtu::write_encoded(path, &frame, encoding).map_err(|e| io_err(path, e))?;
    #[cfg(feature = "hdf5")]
    if let Some(w) = h5.as_mut() {
        let p = w.path().to_path_buf();
        w.write_frame(&frame).map_err(|e| io_err(&p, e))?;
    }
    #[cfg(not(feature = "hdf5"))]
    let _ = h5;
    Ok(())
}

/// The von Mises stress and the pressure a damaged particle acts with, from its damage D and its stored ones: the
/// deviator times e^{−D} and the pressure degraded in tension only (klippel-constitutive.md §2.6, Eqs. 7.27–7.28;
/// `kernels::damage::multiplier`, `degraded_pressure`). A fully damaged particle has none in tension and only its
/// pressure in compression, what Klippel's figures show; the frames' `stress`, `von_mises` and `pressure` stay the
/// stored state that the damage acts on.
fn acting_stress(damage: &[f64], vm: &[f64], pressure: &[f64]) -> (Vec<f64>, Vec<f64>) {
    use crate::kernels::damage::{degraded_pressure, multiplier};
    let m: Vec<f64> = damage.iter().map(|&d| multiplier(d)).collect();
    let vm = m.iter().zip(vm).map(|(m, s)| m * s).collect();
    let p = m.iter().zip(pressure).map(|(&m, &p)| degraded_pressure(m, p)).collect();
    (vm, p)
}

/// The one-line result of a cutting run.
fn cutting_line(a: &crate::cutting::record::CutAnalysis) -> String {
    let f = |x: Option<f64>| x.map_or("n/a".to_string(), |v| format!("{v:.1}"));
    format!(
        "cutting: F_c = {} N/mm, F_f = {} N/mm ({}), chip thickness {} um, segmentation {}",
        f(a.fc),
        f(a.ff),
        match a.steady {
            Some(s) if s.steady => format!("steady from {:.3e} s", s.start_time),
            Some(_) => "no steady state: mean of the steady candidate".to_string(),
            None => "too few samples: mean of the second half".to_string(),
        },
        f(a.chip.map(|c| c.h_avg * 1e6)),
        a.chip.map_or("n/a".to_string(), |c| format!("{:.2}", c.segmentation))
    ) + &a
        .early_stop
        .as_ref()
        .and_then(|e| e.at)
        .map_or(String::new(), |(t, s)| format!("; stopped early at t = {t:.3e} s, step {s} (analysis.early_stop)"))
}

/// The chip geometry of the run's last state along the whole chip (`cutting::chip_frame`), where the run cuts in
/// 2D with a translating tool and a chip has formed.
fn last_chip<R: Real, D: TensorOps<R>>(
    cut: &crate::cutting::record::CutRecorder,
    scene: &Scene,
    j: &OutputJob<R, D>,
) -> Option<crate::cutting::chip_frame::FrameChip> {
    let setup = cut.frame_setup(scene, j.time).ok()?;
    let keep: Vec<usize> = (0..j.now.len()).filter(|&i| j.host.flags[i] & flags::THERMAL_ONLY == 0).collect();
    let pos: Vec<[f64; 2]> = keep.iter().map(|&i| [j.now[i][0], j.now[i][1]]).collect();
    let eps: Option<Vec<f64>> = j.internal[1].as_ref().map(|e| keep.iter().map(|&i| e[i]).collect());
    crate::cutting::chip_frame::analyse(&setup, &pos, eps.as_deref())
}

/// The cutting entries of summary.json with `cutting.chip_frame` (the last state's chip, null without one).
fn with_chip_frame(
    mut v: serde_json::Value,
    chip: Option<&crate::cutting::chip_frame::FrameChip>,
    time: f64,
) -> serde_json::Value {
    if let Some(serde_json::Value::Object(c)) = v.get_mut("cutting") {
        c.insert("chip_frame".into(), crate::cutting::chip_report::json(chip, time));
    }
    v
}

/// Each body's initial centre (the axis for the footprint radius).
fn set_centres(scene: &Scene) -> Vec<[f64; 3]> {
    scene.bodies.iter().map(|b| b.shape.centre()).collect()
}

/// `summary.json` of the run folder: what ran, on what, with which tuning switches, how long (steps, and cell-list
/// rebuilds, a resumed run's included), and each body's final extent (bounding box, and the
/// largest distance from the body's initial centre axis in the x–y plane: a Taylor bar's footprint radius).
struct Summary<'a> {
    dir: &'a Path,
    overrides: &'a [String],
    scene: &'a Scene,
    info: &'a crate::backend::DeviceInfo,
    precision: &'a str,
    particles: usize,
    steps: u64,
    rebuilds: u64,
    dt: f64,
    wall: f64,
    tuning: &'a Tuning,
    /// The cohesive path's tally at the end ([`cohesive_entry`]), where the scene has one.
    cohesive: Option<serde_json::Value>,
    /// The energy audit ([`crate::cutting::energy_audit`]), where the scene has a tool.
    energy_audit: Option<serde_json::Value>,
}

/// The energy the run booked: the change of energy.csv's `balance` from its first row (t = 0, or the first of a
/// resumed run's restored rows) to the end state `d`.
fn booked_energy(files: &OutputFiles, d: &Diagnostics) -> f64 {
    let column = energy_header().iter().position(|c| *c == "balance");
    let first = column.and_then(|k| files.csv.rows().first().and_then(|r| r.get(k).copied()));
    d.balance() - first.unwrap_or(0.0)
}

/// The cohesive path's line for the log and its `cohesive` entry of summary.json at the end state `d` (None without
/// a path): the failed bonds, the bonds' work and damping, the work per unit area of the failed bonds (a bond's
/// area Δx per unit depth in 2D, Δx² in 3D; the unfailed bonds' work, stored, is counted too) and the mode-I share.
fn cohesive_entry(scene: &Scene, d: &Diagnostics) -> Option<(String, serde_json::Value)> {
    scene.cohesive.as_ref()?;
    let per_area = if d.bonds_failed > 0.0 { d.cohesive_work / (d.bonds_failed * scene.bond_area()) } else { f64::NAN };
    let line = format!(
        "cohesive path: {} bonds failed, bonds' work {:.4e} J/m, {per_area:.1} J/m² per failed bond's area, mode-I \
         share {:.3}, dampers {:.3e} J/m",
        d.bonds_failed, d.cohesive_work, d.mode_i_share, d.bond_damping
    );
    let finite = |x: f64| if x.is_finite() { serde_json::json!(x) } else { serde_json::Value::Null };
    let v = serde_json::json!({
        "bonds_failed": d.bonds_failed,
        "work_j": d.cohesive_work,
        "damping_j": d.bond_damping,
        "work_per_failed_area_j_per_m2": finite(per_area),
        "mode_i_share": finite(d.mode_i_share),
    });
    Some((line, v))
}

impl Summary<'_> {
    /// Writes it with the final positions `pos`, each particle's `body`, the bodies' initial `centres` and the
    /// cutting analysis' entries.
    fn write(
        &self,
        pos: &[[f64; 3]],
        body: &[u32],
        centres: &[[f64; 3]],
        cutting: Option<serde_json::Value>,
    ) -> Result<()> {
        let scene = self.scene;
        let bodies: Vec<serde_json::Value> = scene
            .bodies
            .iter()
            .enumerate()
            .map(|(k, bd)| {
                let mut lo = [f64::INFINITY; 3];
                let mut hi = [f64::NEG_INFINITY; 3];
                let mut rmax = 0.0f64;
                for (p, _) in pos.iter().zip(body).filter(|(_, b)| **b as usize == k) {
                    for a in 0..3 {
                        lo[a] = lo[a].min(p[a]);
                        hi[a] = hi[a].max(p[a]);
                    }
                    rmax = rmax.max((p[0] - centres[k][0]).hypot(p[1] - centres[k][1]));
                }
                serde_json::json!({
                    "name": bd.name,
                    "min_m": &lo[..scene.dim],
                    "max_m": &hi[..scene.dim],
                    "extent_m": (0..scene.dim).map(|a| hi[a] - lo[a]).collect::<Vec<_>>(),
                    "radius_xy_max_m": rmax,
                })
            })
            .collect();
        let mut v = serde_json::json!({
            "swarf_version": env!("CARGO_PKG_VERSION"),
            "git_commit": env!("SWARF_GIT_COMMIT"),
            "scene": scene.name,
            "scene_file": scene.origin,
            "overrides": self.overrides,
            "particles": self.particles,
            "steps": self.steps,
            "cell_list_rebuilds": self.rebuilds,
            "dt_s": self.dt,
            "end_time_s": scene.time.end,
            "wall_time_s": self.wall,
            "backend": self.info.backend,
            "device": self.info.name,
            "precision": self.precision,
            "tuning": self.tuning.json(),
            "bodies": bodies,
        });
        if let (Some(serde_json::Value::Object(extra)), Some(obj)) = (cutting, v.as_object_mut()) {
            obj.extend(extra);
        }
        for (key, entry) in [("cohesive", &self.cohesive), ("energy_audit", &self.energy_audit)] {
            if let (Some(c), Some(obj)) = (entry, v.as_object_mut()) {
                obj.insert(key.into(), c.clone());
            }
        }
        // The model only where it is not swarf's, so the default's summary is what it was.
        if !scene.model.is_swarf()
            && let Some(obj) = v.as_object_mut()
        {
            obj.insert("model".into(), serde_json::to_value(&scene.model).unwrap_or_default());
        }
        let text = serde_json::to_string_pretty(&v).map_err(|e| Error::Output(e.to_string()))?;
        let path = self.dir.join("summary.json");
        crate::output::write_atomic(&path, text.as_bytes()).map_err(|e| io_err(&path, e))
    }
}
