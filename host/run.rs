//! `swarf run`: a scene from file to output folder. Builds the particles, chooses Δt, steps the solver and writes,
//! every output interval, a binary VTU frame (indexed by `particles.pvd`) and a row of `energy.csv`. A
//! non-finite value stops the run with its particle, field, time and step, after the last good frame.

use crate::backend::{AnyBackend, Backend};
use crate::grid::grid_with_skin;
use crate::kernels::sph::heat::{HeatParams, ThermalMaterial};
use crate::kernels::sph::params::flags;
use crate::kernels::sph::{SphParams, TensorOps};
use crate::kernels::{Dim2, Dim3, Real, Vector};
use crate::output::{Array, Collection, Frame, TimeSeries, Values, vtu};
use crate::scene::{Bc, Conduction, Precision, Scene};
use crate::solver::Solver;
use crate::solver::diagnostics::{Diagnostics, compute};
use crate::solver::params::{StabiliserSettings, cfl_time_step, sph_params};
use crate::solver::{PlasticSetup, ThermalSetup};
use crate::state::HostParticles;
use crate::{Error, Result, with_backend};
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
        }
    }
}

/// The columns of `energy.csv`, in order (read by `plot::plot_run` and by tools that post-process runs).
pub const ENERGY_COLUMNS: &[&str] = &[
    "time",
    "step",
    "kinetic",
    "elastic",
    "total",
    "momentum_x",
    "momentum_y",
    "momentum_z",
    "angular_x",
    "angular_y",
    "angular_z",
    "vmax",
    "temperature_max",
    "plastic_strain_max",
    "plastic_work",
    "viscous_dissipation",
    "balance",
    "min_pair_distance",
    "min_contact_distance",
    "min_contact_x",
    "min_contact_y",
    "min_contact_z",
    "min_contact_id_a",
    "min_contact_id_b",
];

/// The built-in default scene, `swarf run` without a scene: the V0060 orthogonal cut (cases/cutting/v0060.toml),
/// from the working directory if it has the repository's `cases/`, else from the source tree swarf was built from.
pub fn default_scene() -> PathBuf {
    let rel = Path::new("cases").join("cutting").join("v0060.toml");
    if rel.is_file() { rel } else { Path::new(env!("CARGO_MANIFEST_DIR")).join(rel) }
}

/// Set by the Ctrl-C handler: the run writes a checkpoint before its next step and stops.
pub static INTERRUPTED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// The scene of a run folder to resume: its `scene.toml` with the overrides recorded in its checkpoint.
pub fn resume_scene(dir: &Path) -> Result<(Scene, Vec<String>)> {
    let (h, _) = crate::checkpoint::read(&dir.join("checkpoint.bin"))?;
    let scene = Scene::load(dir.join("scene.toml"), &h.overrides).map_err(|e| Error::Scene(e.to_string()))?;
    Ok((scene, h.overrides))
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
    let obs = observer;
    with_backend!(any, b => match (scene.dim, scene.precision) {
        (2, Precision::F32 | Precision::Mixed) => run_typed::<_, f32, Dim2>(b, scene, opts, obs),
        (2, Precision::F64) => run_typed::<_, f64, Dim2>(b, scene, opts, obs),
        (_, Precision::F32 | Precision::Mixed) => run_typed::<_, f32, Dim3>(b, scene, opts, obs),
        (_, Precision::F64) => run_typed::<_, f64, Dim3>(b, scene, opts, obs),
    })
}

pub use crate::solver::Setup;

/// The index of prescribed velocity `v` in the table the flags point into, adding it if new.
fn velocity_index(table: &mut Vec<[f64; 3]>, v: [f64; 3], scene: &Scene) -> Result<usize> {
    let k = table.iter().position(|t| *t == v).unwrap_or_else(|| {
        table.push(v);
        table.len() - 1
    });
    if k > flags::VEL_INDEX_MASK as usize {
        return Err(Error::Scene(format!(
            "{}: more than {} distinct prescribed velocities",
            scene.origin,
            flags::VEL_INDEX_MASK + 1
        )));
    }
    Ok(k)
}

/// Builds the particles, parameters, grid and time step of `scene`.
pub fn setup<R: Real, D: TensorOps<R>>(scene: &Scene) -> Result<Setup<R, D>> {
    let set = scene.generate().map_err(|e| Error::Scene(e.to_string()))?;
    let warnings = crate::scene::degenerate_input_warnings(scene, &set);
    let n = set.len();
    let mut table: Vec<[f64; 3]> = Vec::new();
    let mut fl = Vec::with_capacity(n);
    for i in 0..n {
        let (kind, idx) = match set.bc[i] {
            Bc::Free => (flags::FREE, 0),
            Bc::Fixed => (flags::FIXED, 0),
            Bc::Velocity(v) => (flags::VELOCITY, velocity_index(&mut table, v, scene)? as u32),
        };
        let thermal_fix = if set.fixed_temperature[i] { flags::FIXED_TEMPERATURE } else { 0 };
        fl.push(kind | thermal_fix | idx << flags::VEL_INDEX_SHIFT | set.body[i] << flags::BODY_SHIFT);
    }
    let conv = |c: &[f64; 3]| D::Vec::<R>::new(std::array::from_fn(|k| R::from_f64(c[k])));
    let m = &scene.material;
    let mut pos: Vec<[f64; 3]> = set.pos.clone();
    let mut vel: Vec<[f64; 3]> = set.vel.clone();
    let mut mass = vec![set.mass; n];
    let mut density = vec![m.density; n];
    let mut temperature = set.temperature.clone();
    // The cutting tool: its contact set-up, and its thermal-only particles appended as one more body.
    let mut contact = None;
    let mut tool_thermal = None;
    if let Some(t) = &scene.tool {
        let tool = crate::cutting::setup::build_tool(t)?;
        let motion = crate::cutting::setup::motion(t);
        crate::cutting::setup::check_engagement(scene, &tool, &motion, &set.pos, &set.vel)?;
        let model = scene.material.library.as_ref().and_then(|l| l.flow_stress);
        let mut tool_velocity_index = None;
        if let Some(th) = &t.thermal
            && let Some(mat) = th.material.as_ref().and_then(|m| m.thermal)
        {
            let dx = scene.discretisation.dx;
            let tp = crate::cutting::setup::tool_particles(&tool, t, dx, th.fixed_width);
            let v0 = motion.velocity_at(0.0);
            let v = [t.velocity[0], t.velocity[1], 0.0];
            let k = velocity_index(&mut table, v, scene)?;
            tool_velocity_index = (t.ramp > 0.0).then_some(k);
            let body = scene.bodies.len() as u32;
            let rho_t = mat.density.unwrap_or(m.density);
            for (p, held) in tp.pos.iter().zip(&tp.held) {
                let hold = if *held { flags::FIXED_TEMPERATURE } else { 0 };
                fl.push(
                    flags::VELOCITY
                        | flags::THERMAL_ONLY
                        | hold
                        | (k as u32) << flags::VEL_INDEX_SHIFT
                        | body << flags::BODY_SHIFT,
                );
                pos.push([p[0], p[1], 0.0]);
                vel.push([v0[0], v0[1], 0.0]);
                mass.push(rho_t * set.volume);
                density.push(rho_t);
                temperature.push(th.temperature);
            }
            tool_thermal = Some(ThermalMaterial {
                conductivity: mat.conductivity.unwrap_or(0.0),
                specific_heat: mat.specific_heat.unwrap_or(1.0),
            });
        }
        contact = Some(crate::solver::ContactSetup {
            params: crate::cutting::setup::contact_params(scene, t, model.as_ref()),
            tool,
            motion,
            tool_velocity_index,
            wear: t.usui.is_some(),
        });
    }
    let n = pos.len();
    // The mixed precision keeps each coordinate as a pair hi + lo in R: lo is what rounding it to R dropped.
    // f32's only: the f64 corrector has no compensated sum (`sph::step::correct_particle`).
    let pos_lo = (scene.precision == Precision::Mixed && size_of::<R>() == 4).then(|| {
        let lo =
            |c: &[f64; 3]| D::Vec::<R>::new(std::array::from_fn(|k| R::from_f64(c[k] - R::from_f64(c[k]).to_f64())));
        pos.iter().map(lo).collect()
    });
    let particles = HostParticles::<R, D> {
        id: (0..n as u32).collect(),
        flags: fl,
        pos: pos.iter().map(conv).collect(),
        vel: vel.iter().map(conv).collect(),
        mass: mass.iter().map(|&x| R::from_f64(x)).collect(),
        rho: density.iter().map(|&x| R::from_f64(x)).collect(),
        stress: vec![Default::default(); n],
    };
    let st = &scene.stabilisation;
    let stabilisers = StabiliserSettings {
        viscosity: st.artificial_viscosity.as_ref().map(|a| (a.alpha, a.beta, a.eta)),
        stress: st.artificial_stress.as_ref().map(|a| (a.epsilon, a.exponent)),
        xsph: st.xsph.as_ref().map(|x| x.epsilon),
    };
    let elastic = m.elastic();
    let dx = scene.discretisation.dx;
    let h = scene.h();
    let mut params = sph_params::<R>(&elastic, dx, h, scene.dim, &stabilisers);
    params.expansion = R::from_f64(3.0 * scene.physics.thermal_expansion);
    params.expansion_t0 = R::from_f64(scene.physics.expansion_reference);
    // A fixed ("locked") grid over the initial bodies with room to move; particles leaving it are clamped into
    // its boundary cells, which keeps the search exact (docs/neighbour-search.md).
    let mut corners: Vec<crate::kernels::vector::V3f64> =
        pos.iter().map(|p| crate::kernels::vector::V3f64([p[0], p[1], p[2], 0.0])).collect();
    if let (Some(t), Some(c)) = (&scene.tool, &contact) {
        // The tool's path, and room above the workpiece for the chip (a tool height): cutting runs keep their
        // particles inside the grid instead of clamping the chip into boundary cells.
        let end = c.motion.offset_at(scene.time.end);
        let top = pos.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max);
        for o in [c.motion.start, end] {
            corners.push(crate::kernels::vector::V3f64([o[0] - t.length, o[1], 0.0, 0.0]));
            corners.push(crate::kernels::vector::V3f64([o[0], o[1] + t.height, 0.0, 0.0]));
        }
        corners.push(crate::kernels::vector::V3f64([end[0], top + t.height, 0.0, 0.0]));
    }
    let (lo, hi) = crate::grid::bounding_box::<f64, _>(&corners);
    let mut glo = [0.0; 3];
    let mut ghi = [0.0; 3];
    for k in 0..scene.dim {
        let margin = 0.25 * (hi[k] - lo[k]) + 4.0 * h;
        glo[k] = lo[k] - margin;
        ghi[k] = hi[k] + margin;
    }
    let mut grid = grid_with_skin(glo, ghi, scene.dim, 2.0 * h, scene.discretisation.skin_over_h * h)?;
    if scene.discretisation.verlet_list {
        grid.list_capacity = crate::neighbour::verlet_capacity(&grid, scene.discretisation.dx);
    }
    let vmax0 = vel.iter().map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()).fold(0.0, f64::max);
    let c0 = elastic.sound_speed();
    let mut limit = cfl_time_step(scene.time.cfl, h, c0, vmax0);
    // Explicit conduction is stable for Δt ≤ 0.1 h² ρ c / k (Cleary & Monaghan's bound for the Brookshaw form;
    // PSE is no less restrictive): the largest diffusivity of the scene's bodies decides.
    if scene.physics.conduction != Conduction::Off {
        let lib_th = m.library.as_ref().and_then(|l| l.thermal);
        for bd in &scene.bodies {
            let t = bd.material.as_ref().and_then(|l| l.thermal).or(lib_th);
            if let (Some(k), Some(c)) = (t.and_then(|t| t.conductivity), t.and_then(|t| t.specific_heat)) {
                limit = limit.min(0.1 * h * h * m.density * c / k);
            }
        }
        if let Some(tm) = scene.tool.as_ref().and_then(|t| t.thermal.as_ref()).and_then(|t| t.material.as_ref())
            && let Some(t) = tm.thermal
            && let (Some(rho), Some(c), Some(k)) = (t.density, t.specific_heat, t.conductivity)
        {
            limit = limit.min(0.1 * h * h * rho * c / k);
        }
    }
    let dt = match scene.time.dt {
        Some(dt) if dt > limit => {
            return Err(Error::Scene(format!(
                "{}: time.dt = {dt:e} s is above the stability limit {limit:e} s (cfl {} · h {h:e} m / (c0 {c0:.1} m/s + |v|max {vmax0:.1} m/s), and 0.1 h² ρ c / k with conduction)",
                scene.origin, scene.time.cfl
            )));
        }
        Some(dt) => dt,
        None => limit,
    };
    // Heat and plasticity, from [physics] and the library material (scene validation already checked that the
    // data they need exist).
    let ph = &scene.physics;
    let lib = m.library.as_ref();
    let th = lib.and_then(|l| l.thermal);
    let friction_heat = scene.tool.as_ref().is_some_and(|t| t.friction_heating > 0.0);
    let needs_heat = ph.conduction != Conduction::Off || ph.plastic_heating || friction_heat;
    let thermal = if needs_heat {
        // Each body's thermal data: its own library material if it names one, else the scene material's.
        let mut materials: Vec<ThermalMaterial> = scene
            .bodies
            .iter()
            .map(|bd| {
                let t = bd.material.as_ref().and_then(|m| m.thermal).or(th);
                ThermalMaterial {
                    conductivity: t.and_then(|t| t.conductivity).unwrap_or(0.0),
                    specific_heat: t.and_then(|t| t.specific_heat).unwrap_or(1.0),
                }
            })
            .collect();
        materials.extend(tool_thermal);
        Some(ThermalSetup {
            materials,
            conduction: match ph.conduction {
                Conduction::Off => None,
                Conduction::Brookshaw => Some(false),
                Conduction::Pse => Some(true),
            },
            heat: HeatParams::new(h, scene.dim),
        })
    } else {
        None
    };
    let plastic = match (ph.plasticity, lib.and_then(|l| l.flow_stress)) {
        (true, Some(model)) => {
            Some(PlasticSetup { model, taylor_quinney: if ph.plastic_heating { ph.taylor_quinney } else { 0.0 } })
        }
        _ => None,
    };
    let expands = ph.thermal_expansion > 0.0;
    let temperature = if thermal.is_some() || plastic.is_some() || expands { Some(temperature) } else { None };
    Ok(Setup {
        particles,
        pos_lo,
        params,
        stabilisers,
        bc_velocities: table.iter().map(conv).collect(),
        grid,
        dt,
        c0,
        h,
        shear: elastic.shear_modulus(),
        temperature,
        thermal,
        plastic,
        contact,
        warnings,
    })
}

fn run_typed<B: Backend, R: Real, D: TensorOps<R>>(
    b: &B,
    scene: &Scene,
    opts: &RunOptions,
    mut observer: Option<&mut dyn FnMut(&Snapshot) -> bool>,
) -> Result<RunReport> {
    let s = setup::<R, D>(scene)?;
    let n = s.particles.len();
    // Refuse before allocating when the GPU cannot hold the run, saying how much it needs.
    crate::check::fits(crate::check::memory_estimate(&s), b.info())?;
    std::fs::create_dir_all(&opts.out_dir).map_err(|e| io_err(&opts.out_dir, e))?;
    // The run folder keeps the scene it ran (as given, with the overrides recorded in summary.json).
    if let Ok(text) = std::fs::read(&scene.origin) {
        let copy = opts.out_dir.join("scene.toml");
        crate::output::write_atomic(&copy, &text).map_err(|e| io_err(&copy, e))?;
    }
    let mut log = RunLog::new(opts.out_dir.join("run.log"));
    if opts.resume {
        log.text = std::fs::read_to_string(&log.path).unwrap_or_default();
    }
    let mut solver = Solver::<B, R, D>::new(b, &s)?;
    let mut csv = TimeSeries::new(opts.out_dir.join("energy.csv"), ENERGY_COLUMNS);
    let mut pvd = Collection::new(opts.out_dir.join("particles.pvd"));
    // Temperatures over time (drawn as temperature.png), when the run models them.
    let mut tcsv = s
        .temperature
        .as_ref()
        .map(|_| TimeSeries::new(opts.out_dir.join("temperature.csv"), &["time", "step", "temperature_max"]));
    let mut h5 = open_hdf5(opts)?;
    // Cutting runs record the tool force and the chip (forces.csv, and the analysis in summary.json).
    let workpiece: Vec<[f64; 3]> = {
        let host = &s.particles;
        (0..n)
            .filter(|&i| host.flags[i] & flags::THERMAL_ONLY == 0)
            .map(|i| std::array::from_fn(|k| if k < D::D { host.pos[i].get(k).to_f64() } else { 0.0 }))
            .collect()
    };
    let mut cut = match &scene.tool {
        Some(t) => crate::cutting::record::CutRecorder::new(
            scene,
            crate::cutting::setup::build_tool(t)?,
            &workpiece,
            &opts.out_dir,
        ),
        None => None,
    };
    let mut next_ckpt = opts.checkpoint_every.unwrap_or(f64::INFINITY);
    let ckpt_path = opts.out_dir.join("checkpoint.bin");
    let mut history = Vec::new();
    // Every particle's position at t = 0 by id, for the contact distance of the diagnostics.
    let initial: Vec<[f64; 3]> = {
        let p = crate::analysis::positions_f64::<R, _>(&s.particles.pos);
        let mut v = vec![[0.0; 3]; p.len()];
        for (k, &id) in s.particles.id.iter().enumerate() {
            if let Some(slot) = v.get_mut(id as usize) {
                *slot = p[k];
            }
        }
        v
    };
    let t0 = Instant::now();
    let end = scene.time.end;
    let every = scene.output.every;
    let mut dt = s.dt;
    let mut frame = 0usize;
    let mut next_out = 0.0;
    if opts.resume {
        let (h, blobs) = crate::checkpoint::read(&ckpt_path)?;
        if h.precision != s.precision() || h.dim != D::D || h.particles != n {
            return Err(Error::Checkpoint(format!(
                "{} holds a {}D {} run of {} particles; this scene is {}D {} with {n}",
                ckpt_path.display(),
                h.dim,
                h.precision,
                h.particles,
                D::D,
                s.precision()
            )));
        }
        solver.load_state(b, &blobs)?;
        solver.time = h.time;
        solver.steps = h.steps;
        dt = h.dt;
        solver.set_nominal_dt(dt);
        frame = h.frame;
        next_out = h.next_out;
        next_ckpt = h.next_checkpoint.unwrap_or(f64::INFINITY);
        // Continue the time series and the frame index up to the checkpoint.
        for series in std::iter::once(&mut csv).chain(tcsv.as_mut()) {
            if let Ok((_, rows)) = crate::output::csv::read(series.path()) {
                for r in rows.into_iter().filter(|r| r[0] <= h.time) {
                    series.push(&r).map_err(|e| io_err(series.path(), e))?;
                }
            }
        }
        if let Some(c) = cut.as_mut() {
            c.resume(h.time)?;
        }
        if let Ok(entries) = crate::output::pvd::read(pvd.path()) {
            for (t, f) in entries.into_iter().filter(|(t, _)| *t <= h.time) {
                pvd.push(t, f).map_err(|e| io_err(pvd.path(), e))?;
            }
        }
        log.line(&format!("resumed from {} at t = {:e} s, step {}", ckpt_path.display(), h.time, h.steps))?;
    }
    // Where this process started (a resumed run's rates and time left count its own steps only).
    let (steps0, time0) = (solver.steps, solver.time);
    let head = format!(
        "{}: {n} particles, {}D {}, h = {:.4e} m, c0 = {:.1} m/s, dt = {:.4e} s, about {} steps, {} ({})",
        scene.name,
        scene.dim,
        s.precision(),
        s.h,
        s.c0,
        dt,
        (end / dt).ceil(),
        b.info().backend,
        b.info().name
    );
    if !opts.quiet {
        eprintln!("{head}");
    }
    log.line(&head)?;
    for w in &s.warnings {
        if !opts.quiet {
            eprintln!("warning: {w}");
        }
        log.line(&format!("warning: {w}"))?;
    }
    // The output step's file writing in the background while the next steps run (one job at a time).
    let initial = std::sync::Arc::new(initial);
    let mut files = OutputFiles { csv, tcsv, pvd };
    let mut pending = PendingOutput::default();
    loop {
        if solver.time >= next_out - 1e-9 * dt || solver.time >= end - 1e-9 * dt {
            // The previous output's files are complete before this one's are started.
            if let Some(d) = pending.join(&mut files)? {
                history.push(d);
            }
            let host = solver.download(b)?;
            let (temp, eps, rate) = solver.download_internal(b)?;
            let mut d = compute(&host, &solver.host_params, solver.time, solver.steps, temp.as_deref());
            crate::solver::diagnostics::internal(&mut d, &host.id, temp.as_deref(), eps.as_deref());
            let (work, diss) = solver.download_dissipated(b)?;
            crate::solver::diagnostics::dissipated(&mut d, &host, work.as_deref(), diss.as_deref());
            if let Some((id, field)) = d.non_finite {
                return Err(Error::NonFinite { id, field, time: solver.time, step: solver.steps });
            }
            let mut now = crate::analysis::positions_f64::<R, _>(&host.pos);
            // The mixed precision's positions are hi + lo: the observers and the displacements see them whole.
            if let Some(lo) = solver.download_pos_lo(b)? {
                for (x, l) in now.iter_mut().zip(crate::analysis::positions_f64::<R, _>(&lo)) {
                    for (c, d) in x.iter_mut().zip(l) {
                        *c += d;
                    }
                }
            }
            if let Some(c) = cut.as_mut() {
                if c.due(solver.time) {
                    c.sample(b, &solver)?;
                }
                c.write()?;
            }
            // Written now where anything reads them before the next output (an observer, a checkpoint, the end,
            // the HDF5 file), else by a thread while the next steps run.
            let last = solver.time >= end - 1e-9 * dt;
            let ckpt_due = solver.time >= next_ckpt - 1e-9 * dt && !last;
            let background = observer.is_none() && h5.is_none() && !ckpt_due && !last;
            let mut job = OutputJob {
                d,
                host,
                internal: [temp, eps, rate],
                fields: if opts.frames { solver.download_frame_fields(b)? } else { Vec::new() },
                now,
                initial: initial.clone(),
                radius: 2.0 * s.h,
                params: solver.host_params,
                frame: opts.frames.then(|| (opts.out_dir.clone(), frame)),
                time: solver.time,
                steps: solver.steps,
            };
            // The written job keeps the state for the observer and the end of the run; a job in the background is
            // never read again here (no observer, not the last step).
            let d = job.d.clone();
            let kept = if background {
                pending.start(job, &mut files);
                None
            } else {
                job.write(&mut files, &mut h5)?;
                Some(job)
            };
            frame += 1;
            next_out = frame as f64 * every;
            // Re-check the CFL condition with the current largest speed.
            if scene.time.dt.is_none() {
                let limit = cfl_time_step(scene.time.cfl, s.h, s.c0, d.vmax);
                if limit < dt {
                    dt = limit;
                    solver.set_nominal_dt(dt);
                }
                // A speed that has grown by orders of magnitude is a blow-up, not physics: stop instead of crawling.
                if dt < MIN_DT_FRACTION * s.dt {
                    return Err(Error::Unstable { vmax: d.vmax, dt, dt0: s.dt, time: solver.time, step: solver.steps });
                }
            }
            let el = t0.elapsed().as_secs_f64();
            let rate = d.step.saturating_sub(steps0) as f64 / el.max(1e-9);
            let line = format!(
                "t = {:.4e} s  step {}  E_kin {:.4e}  E_el {:.4e}  {:.0} steps/s  {:.3e} particle-steps/s",
                d.time,
                d.step,
                d.kinetic,
                d.elastic,
                rate,
                rate * n as f64
            );
            log.line(&line)?;
            if opts.verbose {
                eprintln!("{line}");
            } else if !opts.quiet {
                // One progress line, rewritten in place: simulated time, rates and the time left.
                let frac = (d.time / end).clamp(0.0, 1.0);
                let done = (d.time - time0) / (end - time0);
                let eta = if done > 0.0 { el * (1.0 - done) / done } else { f64::NAN };
                eprint!(
                    "\r[{:<30}] {:5.1} %  t = {:.3e} s  {:.0} steps/s  {:.2e} particle-steps/s  ETA {:.0} s   ",
                    "#".repeat((frac * 30.0) as usize),
                    100.0 * frac,
                    d.time,
                    rate,
                    rate * n as f64,
                    eta
                );
                if frac >= 1.0 {
                    eprintln!();
                }
            }
            if solver.time >= next_ckpt - 1e-9 * dt && solver.time < end - 1e-9 * dt {
                while next_ckpt <= solver.time + 1e-9 * dt {
                    next_ckpt += opts.checkpoint_every.unwrap_or(f64::INFINITY);
                }
                save_checkpoint(b, &solver, &ckpt_path, opts, dt, frame, next_out, next_ckpt)?;
                log.line(&format!("checkpoint at t = {:e} s, step {}", solver.time, solver.steps))?;
            }
            let keep_going = match (observer.as_deref_mut(), kept.as_ref()) {
                (Some(f), Some(j)) => f(&Snapshot {
                    diagnostics: &j.d,
                    id: &j.host.id,
                    pos: j.now.clone(),
                    vel: crate::analysis::positions_f64::<R, _>(&j.host.vel),
                    body: j.host.flags.iter().map(|f| f >> flags::BODY_SHIFT).collect(),
                    temperature: j.internal[0].as_deref(),
                    plastic_strain: j.internal[1].as_deref(),
                }),
                _ => true,
            };
            if let Some(j) = kept.as_ref() {
                history.push(j.d.clone());
            }
            if (!keep_going || solver.time >= end - 1e-9 * dt)
                && let Some(OutputJob { host, now, .. }) = kept
            {
                b.synchronize()?;
                let pos = now;
                let body: Vec<u32> = host.flags.iter().map(|f| f >> flags::BODY_SHIFT).collect();
                let wall = t0.elapsed().as_secs_f64();
                let cutting = cut.as_ref().map(|c| c.analysis());
                if let (Some(a), false) = (&cutting, opts.quiet) {
                    eprintln!("{}", cutting_line(a));
                }
                if let Some(a) = &cutting {
                    log.line(&cutting_line(a))?;
                }
                write_summary(
                    &opts.out_dir,
                    &opts.overrides,
                    scene,
                    b.info(),
                    s.precision(),
                    n,
                    (solver.steps, solver.cell_rebuilds(b)?),
                    s.dt,
                    wall,
                    &pos,
                    &body,
                    &set_centres(scene),
                    cutting.map(|a| a.json()),
                )?;
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
                break;
            }
        }
        if INTERRUPTED.load(std::sync::atomic::Ordering::Relaxed) {
            if let Some(d) = pending.join(&mut files)? {
                history.push(d);
            }
            save_checkpoint(b, &solver, &ckpt_path, opts, dt, frame, next_out, next_ckpt)?;
            log.line(&format!("interrupted at t = {:e} s, step {}; checkpoint written", solver.time, solver.steps))?;
            return Err(Error::Interrupted {
                time: solver.time,
                step: solver.steps,
                path: ckpt_path.display().to_string(),
                dir: opts.out_dir.display().to_string(),
            });
        }
        // Full steps up to the next event (an output, the end, a force sample) run as one batch; the step that
        // lands on an output time is cut short.
        let full = full_steps(solver.time, dt, next_out, end, cut.as_ref().map(|c| c.next()), MAX_BATCH);
        if full > 0 {
            solver.advance(b, dt, full)?;
        } else {
            solver.step(b, dt.min(end - solver.time).min(next_out - solver.time).max(1e-12 * dt))?;
        }
        if solver.non_finite_seen(b)? {
            // Report now, not at the next output: non-finite particles rebuild the cell list every step and pile
            // into its void bucket, which slows every step down (the 150k f32 cut stalled for minutes).
            next_out = solver.time;
            continue;
        }
        if let Some(c) = cut.as_mut()
            && c.due(solver.time)
        {
            c.sample(b, &solver)?;
        }
    }
    Ok(RunReport {
        particles: n,
        steps: solver.steps,
        dt: s.dt,
        wall_s: t0.elapsed().as_secs_f64(),
        precision: s.precision(),
        backend: b.info().backend.to_string(),
        history,
    })
}

/// Most steps between two checks for an interrupt.
const MAX_BATCH: usize = 4096;

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

fn io_err(path: &Path, e: std::io::Error) -> Error {
    Error::Output(format!("{}: {e}", path.display()))
}

/// One VTU frame: positions, id, body, boundary kind, velocity, density, pressure, stress (VTK order xx, yy, zz,
/// xy, yz, xz) and von Mises stress.
#[allow(clippy::too_many_arguments)]
fn save_checkpoint<B: Backend, R: Real, D: TensorOps<R>>(
    b: &B,
    solver: &Solver<B, R, D>,
    path: &Path,
    opts: &RunOptions,
    dt: f64,
    frame: usize,
    next_out: f64,
    next_checkpoint: f64,
) -> Result<()> {
    let state = solver.save_state(b)?;
    let h = crate::checkpoint::Header {
        overrides: opts.overrides.clone(),
        precision: solver.precision().to_string(),
        dim: D::D,
        particles: solver.n,
        time: solver.time,
        steps: solver.steps,
        dt,
        frame,
        next_out,
        next_checkpoint: next_checkpoint.is_finite().then_some(next_checkpoint),
        fields: Vec::new(),
    };
    crate::checkpoint::write(path, h, &state)
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

/// The f64 internal variables of a frame, where modelled.
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
    fields: Vec<(&'static str, Vec<f64>)>,
    now: Vec<[f64; 3]>,
    /// Every particle's position at t = 0 by id.
    initial: std::sync::Arc<Vec<[f64; 3]>>,
    /// The closest-pair search radius (2h).
    radius: f64,
    params: SphParams<R>,
    /// The run folder and frame index, when frames are written.
    frame: Option<(PathBuf, usize)>,
    time: f64,
    steps: u64,
}

impl<R: Real, D: TensorOps<R>> OutputJob<R, D> {
    /// Completes the diagnostics (`d`) and writes the rows and the frame.
    fn write(&mut self, f: &mut OutputFiles, h5: &mut Option<H5>) -> Result<()> {
        let OutputJob { d, host, internal, fields, now, initial, radius, params, frame, time, steps } = self;
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
        csv.push(&[
            d.time,
            d.step as f64,
            d.kinetic,
            d.elastic,
            d.total(),
            d.momentum[0],
            d.momentum[1],
            d.momentum[2],
            d.angular[0],
            d.angular[1],
            d.angular[2],
            d.vmax,
            d.temperature_max,
            d.plastic_strain_max,
            d.plastic_work,
            d.viscous_dissipation,
            d.balance(),
            d.min_pair_distance,
            d.min_contact_distance,
            d.min_contact_midpoint[0],
            d.min_contact_midpoint[1],
            d.min_contact_midpoint[2],
            d.min_contact_ids.map_or(f64::NAN, |p| f64::from(p[0])),
            d.min_contact_ids.map_or(f64::NAN, |p| f64::from(p[1])),
        ])
        .map_err(|e| io_err(csv.path(), e))?;
        csv.write().map_err(|e| io_err(csv.path(), e))?;
        if let Some(t) = tcsv.as_mut() {
            t.push(&[d.time, d.step as f64, d.temperature_max]).map_err(|e| io_err(t.path(), e))?;
            t.write().map_err(|e| io_err(t.path(), e))?;
        }
        if let Some((dir, index)) = frame {
            let name = format!("frame_{index:05}.vtu");
            let temp = internal[0].as_deref();
            write_frame(&dir.join(&name), h5, host, temp, fields, params, time, steps)?;
            f.pvd.push(time, name).map_err(|e| io_err(f.pvd.path(), e))?;
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

#[allow(clippy::too_many_arguments)]
fn write_frame<R: Real, D: TensorOps<R>>(
    path: &Path,
    h5: &mut Option<H5>,
    p: &HostParticles<R, D>,
    temp: Option<&[f64]>,
    fields: &[(&'static str, Vec<f64>)],
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
    for (name, v) in fields {
        point_data.push(Array { name, components: 1, values: Values::F64(v) });
    }
    let frame = Frame { time, points: Values::F64(&pts), point_data, field_data: vec![("STEP", step as f64)] };
    vtu::write(path, &frame).map_err(|e| io_err(path, e))?;
    #[cfg(feature = "hdf5")]
    if let Some(w) = h5.as_mut() {
        let p = w.path().to_path_buf();
        w.write_frame(&frame).map_err(|e| io_err(&p, e))?;
    }
    #[cfg(not(feature = "hdf5"))]
    let _ = h5;
    Ok(())
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
    )
}

/// Each body's initial centre (the axis for the footprint radius).
fn set_centres(scene: &Scene) -> Vec<[f64; 3]> {
    scene.bodies.iter().map(|b| b.shape.centre()).collect()
}

/// `summary.json` of the run folder: what ran, on what, how long (steps, and cell-list rebuilds since the run or
/// its last resume started), and each body's final extent (bounding box,
/// and the largest distance from the body's initial centre axis in the x–y plane: a Taylor bar's footprint
/// radius).
#[allow(clippy::too_many_arguments)]
fn write_summary(
    dir: &Path,
    overrides: &[String],
    scene: &Scene,
    info: &crate::backend::DeviceInfo,
    precision: &str,
    particles: usize,
    (steps, rebuilds): (u64, u32),
    dt: f64,
    wall: f64,
    pos: &[[f64; 3]],
    body: &[u32],
    centres: &[[f64; 3]],
    cutting: Option<serde_json::Value>,
) -> Result<()> {
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
        "scene": scene.name,
        "scene_file": scene.origin,
        "overrides": overrides,
        "particles": particles,
        "steps": steps,
        "cell_list_rebuilds": rebuilds,
        "dt_s": dt,
        "end_time_s": scene.time.end,
        "wall_time_s": wall,
        "backend": info.backend,
        "device": info.name,
        "precision": precision,
        "bodies": bodies,
    });
    if let (Some(serde_json::Value::Object(extra)), Some(obj)) = (cutting, v.as_object_mut()) {
        obj.extend(extra);
    }
    let text = serde_json::to_string_pretty(&v).map_err(|e| Error::Output(e.to_string()))?;
    let path = dir.join("summary.json");
    crate::output::write_atomic(&path, text.as_bytes()).map_err(|e| io_err(&path, e))
}
