//! `swarf check <scene>`: validates a scene (everything `swarf run` checks before it starts) and prints what
//! the run will be: particles, h, c0, Δt, steps, the memory the backend needs, and the expected run time on this
//! backend, measured by timing a few steps of the real solver.

use crate::Result;
use crate::backend::{AnyBackend, Backend};
use crate::method::{Method, MethodFn};
use crate::scene::{Precision, Scene};
use crate::tuning::Tuning;
use std::fmt::Write;

/// What a scene will cost.
#[derive(Clone, Debug)]
pub struct CheckReport {
    pub particles: usize,
    pub h: f64,
    pub c0: f64,
    pub dt: f64,
    pub steps: u64,
    /// Device memory the solver allocates (state, scratch, cell list) [bytes].
    pub memory_bytes: usize,
    /// Measured time per step on this backend [s] (after one warm-up step).
    pub seconds_per_step: f64,
    pub backend: String,
    pub precision: &'static str,
    /// Input that runs but whose result is not meaningful.
    pub warnings: Vec<String>,
}

impl CheckReport {
    pub fn expected_run_time(&self) -> f64 {
        self.seconds_per_step * self.steps as f64
    }
}

pub use crate::method::sph::memory_estimate;

/// The default of `time.max_steps` (declared with the scene keys).
pub use crate::scene::DEFAULT_MAX_STEPS as MAX_STEPS;

/// The steps a run at `dt` takes to `time.end`, and a warning where `output.every` is below `dt` (every step is
/// then cut short at the next output time: the run takes end/every steps, not end/dt). Refuses, before any work,
/// a count above `time.max_steps` (a velocity of 1e300 m/s or `time.dt = 1e-30` gave 18446744073709551615 steps
/// and a run that never ended), naming Δt and where it comes from (`h`, `c0`: the plan's).
pub fn steps(scene: &Scene, dt: f64, h: f64, c0: f64) -> Result<(u64, Option<String>)> {
    let (end, every) = (scene.time.end, scene.output.every);
    let steps = (end / dt).ceil().max((end / every).ceil());
    let warning = (every < dt).then(|| {
        format!(
            "output.every = {every:e} s is below dt = {dt:e} s: every step is cut short to it, so the run takes {steps} \
             steps and writes {steps} frames, not {}; raise output.every to at least dt",
            (end / dt).ceil()
        )
    });
    let max = scene.time.max_steps;
    if steps.is_nan() || steps > max {
        let why = match scene.time.dt {
            Some(_) => "time.dt".to_string(),
            // dt = cfl·h/(c0 + |v|max): the speeds of the scene are what make it this small.
            None => {
                let tool = scene.tool.as_ref().map(|t| t.velocity);
                let v = scene.bodies.iter().flat_map(|b| b.velocity).chain(tool.into_iter().flatten());
                let vmax = v.fold(0.0f64, |m, x| m.max(x.abs()));
                format!("the CFL condition: h = {h:e} m, c0 = {c0:.1} m/s, largest velocity component {vmax:e} m/s")
            }
        };
        let per = if every < dt { format!("output.every = {every:e} s") } else { format!("dt = {dt:e} s ({why})") };
        return Err(crate::Error::Scene(format!(
            "{}: time.end = {end:e} s at {per} is {steps:e} steps: expected at most time.max_steps = {max:e}; check \
             time.end, time.dt, output.every and the velocities, or raise time.max_steps",
            scene.origin
        )));
    }
    Ok((steps as u64, warning))
}

/// Refuses a run that cannot fit the GPU's memory, or on the CPU the host memory available now, naming the bytes
/// needed and available: before anything is allocated, instead of an allocation failure that aborts the process
/// (issue 27). Where the host's available memory cannot be read, the CPU run is not checked.
pub fn fits(needed: usize, info: &crate::backend::DeviceInfo) -> Result<()> {
    if info.backend == "gpu" && needed > info.memory_bytes {
        return Err(crate::Error::OutOfMemory { what: "the scene", bytes: needed, free: 0, total: info.memory_bytes });
    }
    if info.backend == "cpu"
        && let Some((free, total)) = host_memory()
        && needed > free
    {
        return Err(crate::Error::OutOfMemory { what: "the scene in host memory", bytes: needed, free, total });
    }
    Ok(())
}

/// (available, total) host memory in bytes, from /proc/meminfo (Linux); None elsewhere.
pub fn host_memory() -> Option<(usize, usize)> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let field = |key: &str| -> Option<usize> {
        let line = info.lines().find(|l| l.starts_with(key))?;
        let kib: usize = line[key.len()..].trim().trim_end_matches("kB").trim().parse().ok()?;
        Some(kib * 1024)
    };
    Some((field("MemAvailable:")?, field("MemTotal:")?))
}

pub fn check(any: &AnyBackend, scene: &Scene, precision: Option<Precision>, probe_steps: u64) -> Result<CheckReport> {
    let scene = &*scene.with_precision(precision);
    crate::method::with_method(any, scene, Probe(probe_steps))
}

/// `check` for [`crate::method::with_method`]: times this many steps after one warm-up step.
struct Probe(u64);

impl MethodFn for Probe {
    type Out = CheckReport;
    fn call<B: Backend, M: Method<B>>(self, b: &B, scene: &Scene) -> Result<CheckReport> {
        let s = M::setup(scene, Tuning::current()?)?;
        let mut plan = M::plan(&s);
        let info = b.info();
        fits(plan.memory_bytes, info)?;
        let (steps, warning) = self::steps(scene, plan.dt, plan.h, plan.c0)?;
        plan.warnings.extend(warning);
        let mut method = M::new(b, &s)?;
        method.step(b, plan.dt)?;
        b.synchronize()?;
        let probe = self.0.clamp(1, steps.max(1));
        let t = std::time::Instant::now();
        for _ in 0..probe {
            method.step(b, plan.dt)?;
        }
        b.synchronize()?;
        Ok(CheckReport {
            particles: plan.particles,
            h: plan.h,
            c0: plan.c0,
            dt: plan.dt,
            steps,
            memory_bytes: plan.memory_bytes,
            seconds_per_step: t.elapsed().as_secs_f64() / probe as f64,
            backend: format!("{} ({})", info.backend, info.name),
            precision: plan.precision,
            warnings: plan.warnings,
        })
    }
}

pub fn format(scene: &Scene, r: &CheckReport) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "{}: ok", scene.origin);
    let _ = writeln!(s, "particles:          {}", r.particles);
    let _ = writeln!(s, "h:                  {:.4e} m (h/dx = {})", r.h, scene.discretisation.h_over_dx);
    let _ = writeln!(s, "c0:                 {:.1} m/s", r.c0);
    if !scene.model.is_swarf() {
        let list: Vec<&str> = scene.model.switches().list().into_iter().map(|w| w.name()).collect();
        let _ = writeln!(
            s,
            "model:              the original 2D code's (MFREE_IWF), bugs included, in: {}",
            list.join(", ")
        );
    }
    let _ = writeln!(s, "dt:                 {:.4e} s", r.dt);
    let _ = writeln!(s, "steps:              {} (to t = {:e} s)", r.steps, scene.time.end);
    let _ = writeln!(s, "memory:             {:.1} MiB", r.memory_bytes as f64 / (1u64 << 20) as f64);
    let _ = writeln!(
        s,
        "expected run time:  {:.1} s on {} in {} ({:.3} ms/step, measured over a few steps)",
        r.expected_run_time(),
        r.backend,
        r.precision,
        r.seconds_per_step * 1e3
    );
    for w in &r.warnings {
        let _ = writeln!(s, "warning:            {w}");
    }
    s
}
