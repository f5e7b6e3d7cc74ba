//! `swarf run` of an MPM scene (docs/mpm.md "Output"): steps the solver to the scene's end, samples the tool's
//! and the grip's forces (each the mean over its interval: the impulses the contact and the boundary gave the
//! specimen, divided by the interval), writes the frames, and reports the steady forces beside Nairn's models or,
//! for a bonded block, the energy released per unit crack area. Ctrl-C stops it with a checkpoint
//! (`super::checkpoint`), from which `MpmRunOptions::resume` continues bit for bit.

use super::output::FrameScratch;
use super::setup::{MpmSetup, setup};
use super::solver::{MpmSolver, Tallies};
use crate::analytic::nairn::{self, Specimen};
use crate::backend::{AnyBackend, Backend};
use crate::kernels::Real;
use crate::kernels::cohesive::{FAILED, MODE_I};
use crate::kernels::mpm::grid::ABOVE;
use crate::output::csv::TimeSeries;
use crate::output::{atomic, pvd, vtu};
use crate::scene::Precision;
use crate::scene::mpm::{MpmScene, Setup};
use crate::{Error, Result};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Where and how an MPM run writes.
#[derive(Clone, Debug)]
pub struct MpmRunOptions {
    pub out_dir: PathBuf,
    /// Particle frames (particles.pvd and frames/).
    pub frames: bool,
    pub quiet: bool,
    /// The `--set` overrides the scene was loaded with (kept in a checkpoint, for its resumption).
    pub overrides: Vec<String>,
    /// Continue from `out_dir`'s checkpoint (`super::checkpoint`), its forces.csv and its particles.pvd.
    pub resume: bool,
}

impl MpmRunOptions {
    /// A fresh run into `out_dir`, with frames, quiet, without overrides.
    pub fn new(out_dir: PathBuf) -> Self {
        MpmRunOptions { out_dir, frames: true, quiet: true, overrides: Vec::new(), resume: false }
    }
}

/// One force sample: the means over the interval that ends at `t`.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Sample {
    pub t: f64,
    /// The tool's travel [m].
    pub tool_x: f64,
    /// The cutting force F_c and the transverse force F_t (positive into the workpiece) per unit width [N/m].
    pub fc: f64,
    pub ft: f64,
    /// The force the grip put on the specimen [N/m] and its work so far [J/m].
    pub grip: [f64; 2],
    pub work: f64,
    /// Crack points failed (the starter's included).
    pub failed: usize,
    /// The specimen's kinetic and strain energies [J/m] (a bond's samples; NaN in a cut's, which would read
    /// the particles back at every sample).
    pub kinetic: f64,
    pub strain: f64,
}

/// The steady cut: means over the second half of the run after the ramp, and both of Nairn's models with the
/// rubbing force back-calculated from the simulated forces (Eq. 12): the touching model (Eq. 14; Eq. 15 at μ = 0)
/// and the plastic-bending model (Eqs. 18–22 with e = E_T/E′, χ = 0.64; V8 of nairn-mpm.md §6.2).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Steady {
    pub from: f64,
    pub to: f64,
    pub fc: f64,
    pub ft: f64,
    /// sd/mean of F_c over the window's samples.
    pub fc_cov: f64,
    pub rubbing: f64,
    pub eta: f64,
    pub touching_model: f64,
    /// F_c over the touching model.
    pub fc_over_model: f64,
    /// The bending model's F_c/b [N/m] (None where Eq. 19 has no root, e.g. μ > tan α).
    pub bending_model: Option<f64>,
    /// F_c over the bending model.
    pub fc_over_bending: Option<f64>,
}

/// A bonded block at the first sample after its last cohesive point failed: the grip's work, the energies the
/// specimen holds, and what the crack took per unit area.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Released {
    /// The sample's time [s].
    pub t: f64,
    pub work: f64,
    pub kinetic: f64,
    pub strain: f64,
    /// The crack's area per unit thickness (the block's width) [m].
    pub area: f64,
    /// (work − kinetic − strain)/area [J/m²].
    pub per_area: f64,
}

/// What `summary.json` holds.
#[derive(Clone, Debug, Serialize)]
pub struct MpmReport {
    pub name: String,
    pub method: &'static str,
    pub backend: String,
    pub precision: &'static str,
    pub particles: usize,
    pub specimen: usize,
    pub nodes: usize,
    pub crack_points: usize,
    pub dt: f64,
    pub steps: u64,
    pub end_time: f64,
    pub wall_s: f64,
    pub ms_per_step: f64,
    pub failed_points: usize,
    /// The mean mode-I share J_I/J_c at failure over the failed cohesive points (Fig. 16).
    pub mode_i_share: Option<f64>,
    pub steady: Option<Steady>,
    pub released: Option<Released>,
    /// The particles' deformed domains at the end (`coverage`; V14): the specimen's, and a cut's chip's (the
    /// particles above the cut plane that the tool's edge has passed).
    pub coverage: Option<super::coverage::Coverage>,
    pub chip_coverage: Option<super::coverage::Coverage>,
    pub scene: MpmScene,
    #[serde(skip)]
    pub samples: Vec<Sample>,
}

/// Runs `scene` on `any` (its precision) and writes its output in `opts.out_dir`.
pub fn run(any: &AnyBackend, scene: &MpmScene, opts: &MpmRunOptions) -> Result<MpmReport> {
    let s = setup(scene)?;
    crate::with_backend!(any, b => match scene.precision {
        Precision::F32 => run_on::<_, f32>(b, scene, &s, opts),
        _ => run_on::<_, f64>(b, scene, &s, opts),
    })
}

/// The run on backend `b` in precision `R`.
pub fn run_on<B: Backend, R: Real>(b: &B, scene: &MpmScene, s: &MpmSetup, opts: &MpmRunOptions) -> Result<MpmReport> {
    let out = &opts.out_dir;
    let io = |p: &Path, e: std::io::Error| Error::Output(format!("{}: {e}", p.display()));
    std::fs::create_dir_all(out).map_err(|e| io(out, e))?;
    if !opts.resume
        && let Ok(text) = std::fs::read_to_string(&scene.origin)
    {
        atomic::write_atomic(&out.join("scene.toml"), text.as_bytes()).map_err(|e| io(out, e))?;
    }
    let mut solver = MpmSolver::<B, R>::new(b, s, scene.damping.pic)?;
    let mut rec = Record::open(out, opts.resume)?;
    let every = (s.steps / scene.time.samples.max(1) as u64).max(1);
    let frame_every =
        if opts.frames && scene.time.frames > 0 { (s.steps / scene.time.frames as u64).max(1) } else { 0 };
    let start = std::time::Instant::now();
    let mut scratch = FrameScratch::default();
    if opts.resume {
        rec.last = super::checkpoint::restore(b, &mut solver, out)?;
    } else if frame_every > 0 {
        write_frame(b, &solver, out, &mut rec.frames, &mut scratch)?;
    }
    while solver.steps < s.steps {
        // To the next sample or frame, in captured batches.
        let next = |every: u64| solver.steps.checked_div(every).map_or(u64::MAX, |k| (k + 1) * every);
        solver.advance(b, next(every).min(next(frame_every)).min(s.steps) - solver.steps)?;
        let k = solver.steps;
        if k % every == 0 || k == s.steps {
            if let Err(e) = check_flags(b, &mut solver, scene) {
                // Keep what was good: the samples so far (the frames are already written).
                rec.series.write().map_err(|e| io(rec.series.path(), e))?;
                return Err(e);
            }
            let sample = sample(b, &solver, &mut rec.last)?;
            rec.series.push(&sample.row()).map_err(|e| io(rec.series.path(), e))?;
            rec.samples.push(sample);
            if !opts.quiet && k % (every * (scene.time.samples as u64 / 10).max(1)) == 0 {
                let done = 100.0 * k as f64 / s.steps as f64;
                eprintln!("mpm: t = {:.4e} s ({done:.0} %), F_c = {:.4e} N/m", solver.time, sample.fc);
            }
        }
        if frame_every > 0 && (k % frame_every == 0 || k == s.steps) {
            write_frame(b, &solver, out, &mut rec.frames, &mut scratch)?;
        }
        if crate::run::INTERRUPTED.load(std::sync::atomic::Ordering::Relaxed) && k < s.steps {
            // Ctrl-C: the samples so far and a checkpoint to resume from (`swarf run --resume`).
            rec.series.write().map_err(|e| io(rec.series.path(), e))?;
            let frames = rec.frames.entries().len();
            let path = super::checkpoint::save(b, &solver, out, &opts.overrides, frames, &rec.last)?;
            let (path, dir) = (path.display().to_string(), out.display().to_string());
            return Err(Error::Interrupted { time: solver.time, step: k, path, dir });
        }
    }
    b.synchronize()?;
    let wall = start.elapsed().as_secs_f64();
    rec.series.write().map_err(|e| io(rec.series.path(), e))?;
    let report = report(b, &solver, scene, s, std::mem::take(&mut rec.samples), wall)?;
    let json = serde_json::to_string_pretty(&report).map_err(|e| Error::Output(e.to_string()))?;
    atomic::write_atomic(&out.join("summary.json"), json.as_bytes()).map_err(|e| io(out, e))?;
    Ok(report)
}

/// What a run has recorded: its force samples (forces.csv), its frames (particles.pvd) and the last sample's time
/// and tallies.
struct Record {
    series: TimeSeries,
    frames: pvd::Collection,
    samples: Vec<Sample>,
    last: (f64, Tallies),
}

impl Record {
    const COLUMNS: [&str; 10] =
        ["t", "tool_x", "F_c", "F_t", "grip_x", "grip_y", "grip_work", "failed", "kinetic", "strain"];

    /// A new record in `out`, or (`resume`) the one `out` holds: forces.csv's rows and particles.pvd's entries.
    fn open(out: &Path, resume: bool) -> Result<Record> {
        let mut rec = Record {
            series: TimeSeries::new(out.join("forces.csv"), &Self::COLUMNS),
            frames: pvd::Collection::new(out.join("particles.pvd")),
            samples: Vec::new(),
            last: (0.0, Tallies::default()),
        };
        if !resume {
            return Ok(rec);
        }
        let bad = |e: std::io::Error| Error::Checkpoint(e.to_string());
        let (head, rows) = crate::output::csv::read(&out.join("forces.csv")).map_err(bad)?;
        if head != Self::COLUMNS {
            let path = out.join("forces.csv");
            return Err(Error::Checkpoint(format!(
                "{}: columns {head:?}, expected {:?}",
                path.display(),
                Self::COLUMNS
            )));
        }
        for r in rows {
            rec.series.push(&r).map_err(bad)?;
            rec.samples.push(Sample::of_row(&r));
        }
        if out.join("particles.pvd").exists() {
            for (t, f) in pvd::read(&out.join("particles.pvd")).map_err(bad)? {
                rec.frames.push(t, f).map_err(bad)?;
            }
        }
        Ok(rec)
    }
}

impl Sample {
    fn row(&self) -> [f64; 10] {
        let (t, g) = (self, self.grip);
        [t.t, t.tool_x, t.fc, t.ft, g[0], g[1], t.work, t.failed as f64, t.kinetic, t.strain]
    }

    /// The sample of a forces.csv row (`row`'s inverse; ten values).
    fn of_row(r: &[f64]) -> Sample {
        let (fc, ft, grip, work, failed) = (r[2], r[3], [r[4], r[5]], r[6], r[7] as usize);
        Sample { t: r[0], tool_x: r[1], fc, ft, grip, work, failed, kinetic: r[8], strain: r[9] }
    }
}

/// Stops the run on a flagged step: a non-finite particle (naming the first) or one that left the grid.
fn check_flags<B: Backend, R: Real>(b: &B, solver: &mut MpmSolver<B, R>, scene: &MpmScene) -> Result<()> {
    let (non_finite, escaped) = solver.take_flags(b)?;
    if !(non_finite || escaped) {
        return Ok(());
    }
    let snap = solver.snapshot(b)?;
    let bad = |x: &[f64; 2]| !(x[0].is_finite() && x[1].is_finite());
    if non_finite {
        // One pass: the first non-finite particle is the one named, and every one joins the region.
        let (mut id, mut region) = (None, crate::solver::diagnostics::NonFiniteRegion::new(2));
        for (i, (x, _)) in snap.pos.iter().zip(&snap.vel).enumerate().filter(|(_, (x, v))| bad(x) || bad(v)) {
            id.get_or_insert(i);
            region.note((!bad(x)).then_some([x[0], x[1], 0.0]));
        }
        return Err(Error::NonFinite {
            id: id.unwrap_or(0) as u32,
            field: "position or velocity",
            time: solver.time,
            step: solver.steps,
            flagged: None,
            region: region.describe(),
        });
    }
    let p = &solver.params;
    let (lo, hi) = (
        [p.origin[0] + p.dx, p.origin[1] + p.dx],
        [p.origin[0] + (p.nodes[0] - 3) as f64 * p.dx, p.origin[1] + (p.nodes[1] - 3) as f64 * p.dx],
    );
    let out = |x: &[f64; 2]| x[0] < lo[0] || x[1] < lo[1] || x[0] >= hi[0] || x[1] >= hi[1];
    let (id, at) = (0..snap.pos.len()).find(|&i| out(&snap.pos[i])).map_or((0, [f64::NAN; 2]), |i| (i, snap.pos[i]));
    Err(Error::Scene(format!(
        "{}: particle {id} left the MPM grid at ({:.4e}, {:.4e}) m, t = {:.4e} s (step {}): the grid spans \
         ({:.4e}, {:.4e}) to ({:.4e}, {:.4e}) m; enlarge cut.room or shorten time.end",
        scene.origin, at[0], at[1], solver.time, solver.steps, lo[0], lo[1], hi[0], hi[1]
    )))
}

/// The forces over the interval since `last` (updated).
fn sample<B: Backend, R: Real>(b: &B, solver: &MpmSolver<B, R>, last: &mut (f64, Tallies)) -> Result<Sample> {
    let now = solver.tallies(b)?;
    let span = solver.time - last.0;
    let (dt_, dt_b) = (
        [now.tool[0] - last.1.tool[0], now.tool[1] - last.1.tool[1]],
        [now.grip[0] - last.1.grip[0], now.grip[1] - last.1.grip[1]],
    );
    let failed = solver.crack_state(b)?.iter().filter(|s| s[FAILED] != 0.0).count();
    let tool_x = solver.tool.map_or(0.0, |(r, _)| r.displacement(solver.time)[0]);
    let (kinetic, strain) = if solver.grip.is_some() {
        solver.snapshot(b)?.energies(&solver.params.material)
    } else {
        (f64::NAN, f64::NAN)
    };
    *last = (solver.time, now);
    Ok(Sample {
        t: solver.time,
        tool_x,
        fc: dt_[0] / span,
        ft: -dt_[1] / span,
        grip: [dt_b[0] / span, dt_b[1] / span],
        work: now.work,
        failed,
        kinetic,
        strain,
    })
}

fn write_frame<B: Backend, R: Real>(
    b: &B,
    solver: &MpmSolver<B, R>,
    out: &Path,
    frames: &mut pvd::Collection,
    scratch: &mut FrameScratch,
) -> Result<()> {
    let snap = solver.snapshot(b)?;
    let dir = out.join("frames");
    std::fs::create_dir_all(&dir).map_err(|e| Error::Output(format!("{}: {e}", dir.display())))?;
    let name = format!("frames/mpm_{:04}.vtu", frames.entries().len());
    let path = out.join(&name);
    vtu::write(&path, &snap.frame(solver.time, scratch))
        .map_err(|e| Error::Output(format!("{}: {e}", path.display())))?;
    frames.push(solver.time, name).map_err(|e| Error::Output(format!("{}: {e}", frames.path().display())))?;
    frames.write().map_err(|e| Error::Output(format!("{}: {e}", frames.path().display())))
}

/// The summary of a finished run.
fn report<B: Backend, R: Real>(
    b: &B,
    solver: &MpmSolver<B, R>,
    scene: &MpmScene,
    s: &MpmSetup,
    samples: Vec<Sample>,
    wall: f64,
) -> Result<MpmReport> {
    let crack = solver.crack_state(b)?;
    let snap = solver.snapshot(b)?;
    let p = &s.params;
    let cohesive_failed: Vec<f64> = (0..crack.len())
        .filter(|&k| crack[k][FAILED] != 0.0 && p.crack_x(k as u32) >= s.starter_end)
        .map(|k| crack[k][MODE_I])
        .collect();
    let released = match scene.setup {
        Setup::Bond(bond) => samples.iter().find(|x| x.failed == crack.len()).map(|x| {
            let area = (bond.width / bond.cell).round() * bond.cell;
            let (work, kinetic, strain) = (x.work, x.kinetic, x.strain);
            Released { t: x.t, work, kinetic, strain, area, per_area: (work - kinetic - strain) / area }
        }),
        Setup::Cut(_) => None,
    };
    Ok(MpmReport {
        name: scene.name.clone(),
        method: "mpm",
        backend: b.info().name.clone(),
        precision: R::NAME,
        particles: solver.particles(),
        specimen: s.specimen,
        nodes: solver.node_count(),
        crack_points: crack.len(),
        dt: s.dt,
        steps: solver.steps,
        end_time: solver.time,
        wall_s: wall,
        ms_per_step: 1e3 * wall / solver.steps.max(1) as f64,
        failed_points: crack.iter().filter(|c| c[FAILED] != 0.0).count(),
        mode_i_share: (!cohesive_failed.is_empty())
            .then(|| cohesive_failed.iter().sum::<f64>() / cohesive_failed.len() as f64),
        steady: steady(scene, &samples),
        released,
        coverage: super::coverage::coverage(&snap, |_| true),
        chip_coverage: s.tool.and_then(|(ramp, tip)| {
            let edge = tip[0] + ramp.displacement(solver.time)[0];
            super::coverage::coverage(&snap, |i| snap.kind[i] == ABOVE && s.points.pos[i][0] < edge)
        }),
        scene: scene.clone(),
        samples,
    })
}

/// The steady window's means and both models (a cut only).
fn steady(scene: &MpmScene, samples: &[Sample]) -> Option<Steady> {
    let Setup::Cut(c) = scene.setup else { return None };
    let ramp_end = c.ramp * scene.time.end;
    let from = ramp_end + 0.5 * (scene.time.end - ramp_end);
    let w: Vec<&Sample> = samples.iter().filter(|x| x.t > from).collect();
    if w.is_empty() {
        return None;
    }
    let n = w.len() as f64;
    let fc = w.iter().map(|x| x.fc).sum::<f64>() / n;
    let ft = w.iter().map(|x| x.ft).sum::<f64>() / n;
    let sd = (w.iter().map(|x| (x.fc - fc).powi(2)).sum::<f64>() / n).sqrt();
    let spec = specimen(scene);
    let alpha = c.rake.to_radians();
    let rubbing = nairn::rubbing_force(fc, ft, c.friction, alpha);
    let touching_model = nairn::touching(c.depth, alpha, c.friction, rubbing, &spec);
    let e = scene.material.tangent_modulus / spec.plane_modulus;
    let bending_model =
        nairn::bending(spec.eta(c.depth), alpha, c.friction, e, rubbing / spec.toughness, &spec, nairn::CHI)
            .map(|b| b.force * spec.toughness);
    Some(Steady {
        from,
        to: scene.time.end,
        fc,
        ft,
        fc_cov: sd / fc.abs(),
        rubbing,
        eta: spec.eta(c.depth),
        touching_model,
        fc_over_model: fc / touching_model,
        bending_model,
        fc_over_bending: bending_model.map(|b| fc / b),
    })
}

/// The scene's specimen as Nairn's models take it (von Mises: Y = √3).
pub fn specimen(scene: &MpmScene) -> Specimen {
    let (k, g) = (scene.material.bulk_modulus, scene.material.shear_modulus);
    let e = scene.young();
    let nu = (3.0 * k - 2.0 * g) / (2.0 * (3.0 * k + g));
    Specimen {
        yield_stress: scene.material.yield_stress,
        plane_modulus: e / (1.0 - nu * nu),
        toughness: scene.cohesive.toughness,
        yield_ratio: 3f64.sqrt(),
    }
}

/// `swarf check` of an MPM scene: the set-up's sizes, Δt and steps, the memory the solver allocates, and the run
/// time extrapolated from 100 timed steps on `any`.
pub fn check(any: &AnyBackend, scene: &MpmScene) -> Result<String> {
    let s = setup(scene)?;
    let ms = crate::with_backend!(any, b => match scene.precision {
        Precision::F32 => time_steps::<_, f32>(b, scene, &s),
        _ => time_steps::<_, f64>(b, scene, &s),
    })?;
    let n = s.points.pos.len();
    // The bytes the solver allocates, counted by the CPU backend (the same buffers on every backend).
    let cpu = crate::backend::CpuBackend::new();
    match scene.precision {
        Precision::F32 => MpmSolver::<_, f32>::new(&cpu, &s, scene.damping.pic).map(drop)?,
        _ => MpmSolver::<_, f64>::new(&cpu, &s, scene.damping.pic).map(drop)?,
    }
    let bytes = cpu.allocated_bytes();
    Ok(format!(
        "{}: MPM ({}), {} particles ({} specimen, {} tool), {} x {} nodes of {:.4e} m, {} crack points\n\
         dt = {:.4e} s (cfl {}), {} steps to {:.4e} s, about {:.1} MB on the device\n\
         {:.4} ms/step on this backend (100 steps): the run takes about {:.0} s\n",
        scene.name,
        scene.precision.as_str(),
        n,
        s.specimen,
        n - s.specimen,
        s.params.nodes[0],
        s.params.nodes[1],
        s.params.dx,
        s.params.crack_points,
        s.dt,
        scene.time.cfl,
        s.steps,
        scene.time.end,
        bytes as f64 / 1e6,
        ms,
        ms * s.steps as f64 / 1e3
    ))
}

/// Milliseconds per step of `s` over 100 steps (after one untimed step).
fn time_steps<B: Backend, R: Real>(b: &B, scene: &MpmScene, s: &MpmSetup) -> Result<f64> {
    let mut solver = MpmSolver::<B, R>::new(b, s, scene.damping.pic)?;
    solver.step(b)?;
    let mut run = || solver.advance(b, 100);
    Ok(b.time_ms(&mut run)? / 100.0)
}
