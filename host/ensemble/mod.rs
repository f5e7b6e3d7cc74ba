//! Batched ensembles: many independent scenes run in one process, up to `width` at once, each on its own
//! backend sibling ([`AnyBackend::sibling`]): on a GPU, a CUDA stream of its own in the one context, with its own
//! captured graphs, sharing the loaded kernels; on the CPU, the one thread pool.
//!
//! Why streams and not one packed particle set: a member keeps everything a run has (its Δt, tool, forces,
//! steady-state analysis, summary.json, its non-finite stop) because a member *is* a run ([`Member`]: an SPH run,
//! [`crate::run::run`], or an MPM run, [`crate::mpm::run::run`]), unchanged. Its launches are those of a run alone, with the same arguments, in the same order on its own
//! stream, so its results are the same bits alone or in a batch (tests/ensemble.rs on the CPU, tests/gpu.rs on a
//! GPU). A 5 640-particle cut fills a small part of an H100/H200 (a few dozen blocks per launch against 132
//! multiprocessors); concurrent streams fill the rest, where separate processes time-slice the device.
//! docs/identification.md gives the measured throughput.
//!
//! Scheduling: `width` worker threads take the next unstarted member as they finish one (members of unequal length
//! do not wait for each other); each result goes to the caller's `done` on the calling thread, in completion order.
//! A member that fails (a non-finite stop, a bad scene) is reported and the others go on. A Ctrl-C
//! ([`crate::run::INTERRUPTED`]) stops every running member at its next batch of steps with a checkpoint; no new
//! member starts, and [`run`] returns [`Error::Interrupted`] after every running member has reported.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc;

use crate::backend::AnyBackend;
use crate::mpm::run::{MpmReport, MpmRunOptions};
use crate::run::{RunOptions, RunReport};
use crate::scene::Scene;
use crate::scene::mpm::MpmScene;
use crate::{Error, Result};

/// What an ensemble runs: one whole run of any method, on the backend it is given.
pub trait Member: Sync {
    /// What the run reports.
    type Report: Send;
    fn run(&self, backend: &AnyBackend) -> Result<Self::Report>;
}

/// Where an ensemble hands each member's index and result, as it finishes.
pub type Done<'a, T> = &'a mut dyn FnMut(usize, &Result<T>) -> Result<()>;

/// One SPH member: everything [`crate::run::run`] needs.
pub struct Job {
    pub scene: Scene,
    pub options: RunOptions,
}

impl Member for Job {
    type Report = RunReport;
    fn run(&self, backend: &AnyBackend) -> Result<RunReport> {
        crate::run::run(backend, &self.scene, &self.options)
    }
}

/// One MPM member: everything [`crate::mpm::run::run`] needs.
pub struct MpmJob {
    pub scene: MpmScene,
    pub options: MpmRunOptions,
}

impl Member for MpmJob {
    type Report = MpmReport;
    fn run(&self, backend: &AnyBackend) -> Result<MpmReport> {
        crate::mpm::run::run(backend, &self.scene, &self.options)
    }
}

/// Members run at once by default on a GPU. Whole V0060 runs (5 640 particles, 110 619 steps) on an H200, 40 s per
/// width side by side in one process: 1 at once 14 040 runs/day, 8 63 880, 16 58 407, 32 60 515; 8 for 608 s:
/// 69 516 (docs/identification.md, "Batched ensembles"; docs/measurements/h200-issue23-ensemble-*.log).
pub const GPU_WIDTH: usize = 8;

/// The default width on `backend`: [`GPU_WIDTH`] on a GPU; 1 on the CPU, whose one run already uses every core.
pub fn default_width(backend: &AnyBackend) -> usize {
    match backend {
        AnyBackend::Cuda(_) => GPU_WIDTH,
        AnyBackend::Cpu(_) => 1,
    }
}

/// Runs `jobs`, up to `width` (≥ 1) at once on siblings of `backend`, handing each member's index and result to
/// `done` as it finishes. When `done` fails, no new member starts; the running ones finish and are handed over,
/// and the first such error is returned. A member interrupted by Ctrl-C likewise stops new members, and
/// [`Error::Interrupted`] is returned once the running ones have reported.
pub fn run<J: Member>(backend: &AnyBackend, jobs: &[J], width: usize, done: Done<'_, J::Report>) -> Result<()> {
    let width = width.max(1).min(jobs.len());
    if width <= 1 {
        return run_serial(backend, jobs, done);
    }
    // The siblings are made here, before any member starts, so that a device that cannot give them fails the
    // ensemble at once. The first member runs on `backend` itself.
    let mut backends = Vec::with_capacity(width - 1);
    for _ in 1..width {
        backends.push(backend.sibling()?);
    }
    let next = AtomicUsize::new(0);
    let stop = AtomicBool::new(false);
    let (tx, rx) = mpsc::channel::<(usize, Result<J::Report>)>();
    std::thread::scope(|s| {
        for b in std::iter::once(backend).chain(backends.iter()) {
            let (tx, next, stop) = (tx.clone(), &next, &stop);
            s.spawn(move || worker(b, jobs, next, stop, tx));
        }
        drop(tx);
        collect(&rx, &stop, done)
    })
}

/// A worker: takes members in order until none is left or the ensemble stops, and sends each result.
fn worker<J: Member>(
    b: &AnyBackend,
    jobs: &[J],
    next: &AtomicUsize,
    stop: &AtomicBool,
    tx: mpsc::Sender<(usize, Result<J::Report>)>,
) {
    while !stop.load(Ordering::Relaxed) {
        let k = next.fetch_add(1, Ordering::Relaxed);
        let Some(job) = jobs.get(k) else { return };
        let result = job.run(b);
        if tx.send((k, result)).is_err() {
            return;
        }
    }
}

/// Hands results to `done` as they arrive; sets `stop` on the first failure of `done` or interruption.
fn collect<T>(rx: &mpsc::Receiver<(usize, Result<T>)>, stop: &AtomicBool, done: Done<'_, T>) -> Result<()> {
    let mut first_error = None;
    for (k, result) in rx {
        if let Err(e) = done(k, &result) {
            stop.store(true, Ordering::Relaxed);
            first_error.get_or_insert(e);
        }
        if let Err(e @ Error::Interrupted { .. }) = result {
            stop.store(true, Ordering::Relaxed);
            first_error.get_or_insert(e);
        }
    }
    first_error.map_or(Ok(()), Err)
}

/// Runs `jobs` one after another on `backend`, handing each result to `done` as it comes; stops at the first
/// interruption (Ctrl-C), after `done` has recorded it, or when `done` fails.
pub fn run_serial<J: Member>(backend: &AnyBackend, jobs: &[J], done: Done<'_, J::Report>) -> Result<()> {
    for (k, job) in jobs.iter().enumerate() {
        let result = job.run(backend);
        done(k, &result)?;
        if let Err(e @ Error::Interrupted { .. }) = result {
            return Err(e);
        }
    }
    Ok(())
}
