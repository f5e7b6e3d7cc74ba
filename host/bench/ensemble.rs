//! `swarf bench ensemble`: the throughput of one scene run many times as a batched ensemble (host/ensemble), in
//! whole runs per hour and per day, at each width asked for, side by side in one process.
//!
//! Each width runs copies of the scene, `width` at once, until `duration` seconds of wall time have passed and
//! then lets the running members finish: every counted run is a full run of the scene (with whatever early stop
//! the scene's overrides ask for). Runs per hour = completed runs / wall time from the first start to the last
//! completion × 3600. The members are the same scene, so they take the same steps; an identification's members
//! differ in their parameters and so in their step counts by a few per cent.

use std::path::Path;
use std::time::Instant;

use crate::backend::AnyBackend;
use crate::ensemble::Job;
use crate::run::RunOptions;
use crate::scene::Scene;
use crate::{Error, Result};

/// One width's figures.
#[derive(Clone, Debug)]
pub struct Throughput {
    pub width: usize,
    pub runs: usize,
    pub failed: usize,
    pub wall_s: f64,
    /// Steps of one run (the first to finish), for steps per second.
    pub steps: u64,
}

impl Throughput {
    pub fn runs_per_hour(&self) -> f64 {
        self.runs as f64 / self.wall_s * 3600.0
    }
}

/// The table's header.
pub fn header() -> &'static str {
    "| width | runs | failed | wall [s] | s/run | runs/hour | runs/day | steps/run | member steps/s |\n|---|---|---|---|---|---|---|---|---|"
}

/// A row of the table.
pub fn row(t: &Throughput) -> String {
    let per_day = t.runs_per_hour() * 24.0;
    format!(
        "| {} | {} | {} | {:.1} | {:.3} | {:.0} | {:.0} | {} | {:.0} |",
        t.width,
        t.runs,
        t.failed,
        t.wall_s,
        t.wall_s / t.runs.max(1) as f64,
        t.runs_per_hour(),
        per_day,
        t.steps,
        t.steps as f64 * t.runs as f64 / t.wall_s
    )
}

/// Runs `scene` as an ensemble of `width` at once for at least `duration` seconds (at least `width` runs), each
/// run in its own folder under `out` (removed after it is counted, frames off).
pub fn throughput(backend: &AnyBackend, scene: &Scene, width: usize, duration: f64, out: &Path) -> Result<Throughput> {
    // Enough jobs for the longest plausible measurement; the callback stops handing out new ones once the
    // duration has passed.
    let count = 100_000;
    let options = |k: usize| RunOptions::quiet(out.join(format!("w{width}-{k:06}")));
    let jobs: Vec<Job> = (0..count).map(|k| Job { scene: scene.clone(), options: options(k) }).collect();
    let t0 = Instant::now();
    let (mut runs, mut failed, mut steps, mut last) = (0usize, 0usize, 0u64, 0.0f64);
    let result = crate::ensemble::run(backend, &jobs, width, &mut |k, r| {
        match r {
            Ok(rep) => {
                runs += 1;
                if steps == 0 {
                    steps = rep.steps;
                }
            }
            Err(_) => failed += 1,
        }
        last = t0.elapsed().as_secs_f64();
        let _ = std::fs::remove_dir_all(&jobs[k].options.out_dir);
        if last >= duration && runs + failed >= width { Err(Error::Output(STOP.into())) } else { Ok(()) }
    });
    match result {
        Err(Error::Output(m)) if m == STOP => {}
        Err(e) => return Err(e),
        Ok(()) => {}
    }
    Ok(Throughput { width, runs, failed, wall_s: last, steps })
}

/// The callback's way to end the measurement (not an error of the runs).
const STOP: &str = "bench ensemble: duration reached";
