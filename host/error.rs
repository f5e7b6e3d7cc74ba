//! Typed errors with the context a user needs to act on them.

use thiserror::Error;

pub type Result<T, E = Error> = std::result::Result<T, E>;

#[derive(Debug, Error)]
pub enum Error {
    /// The GPU backend was requested (or probed) but cannot be used; the text says why.
    #[error("GPU backend unavailable: {0}")]
    GpuUnavailable(String),
    /// A CUDA driver call failed.
    #[error("CUDA error in {op}: {source}")]
    Cuda {
        op: &'static str,
        #[source]
        source: cudarc::driver::DriverError,
    },
    /// Device (or, for a CPU run, host) memory cannot hold what is asked for.
    #[error("out of memory allocating {what}: {bytes} bytes requested ({free} of {total} bytes free)")]
    OutOfMemory { what: &'static str, bytes: usize, free: usize, total: usize },
    /// A grid that cannot be built (empty box, too many cells, bad cell size).
    #[error("invalid neighbour grid: {0}")]
    Grid(String),
    /// Buffers of inconsistent lengths were passed to an operation.
    #[error("{op}: buffer length {got}, expected {expected}")]
    Length { op: &'static str, expected: usize, got: usize },
    /// A scene that cannot be run (the message names the file and key).
    #[error("{0}")]
    Scene(String),
    /// An output file could not be written (the message names the path).
    #[error("output: {0}")]
    Output(String),
    /// The run produced a non-finite value; the last good frame was written before it. `flagged`: the steps
    /// (first, last) of the batch in which the predictor first saw a non-finite position, where it did (a
    /// batch's flags are read once, after it). `region`: how many particles are non-finite and where
    /// (`solver::diagnostics::NonFiniteRegion::describe`).
    #[error(
        "non-finite {field} at particle {id}, t = {time:e} s, step {step}{}{region}; the last good frame is kept",
        flagged_steps(.flagged)
    )]
    NonFinite { id: u32, field: &'static str, time: f64, step: u64, flagged: Option<(u64, u64)>, region: String },
    /// The largest speed grew so much that the stable time step collapsed: a numerical blow-up.
    #[error(
        "unstable: |v|max = {vmax:.3e} m/s needs dt = {dt:.3e} s, below 1 % of the initial {dt0:.3e} s (t = {time:e} s, step {step}); the last good frame is kept"
    )]
    Unstable { vmax: f64, dt: f64, dt0: f64, time: f64, step: u64 },
    /// A checkpoint that cannot be read or does not fit the scene.
    #[error("checkpoint: {0}")]
    Checkpoint(String),
    /// The run was interrupted (Ctrl-C); its state is in the checkpoint.
    #[error(
        "interrupted at t = {time:e} s, step {step}; checkpoint written to {path}; continue with `swarf run --resume {dir}`"
    )]
    Interrupted { time: f64, step: u64, path: String, dir: String },
    /// The chip analysis of a frame cannot run (no tool, a 3D or rotating cut, a frame without the fields it
    /// needs); the message names the scene or the file.
    #[error("chip analysis: {0}")]
    Chip(String),
    /// A `SWARF_*` tuning switch with a value it does not accept (the message names it and what it accepts).
    #[error("tuning switch: {0}")]
    Tuning(#[from] crate::tuning::TuningError),
    #[error("{0}")]
    Io(#[from] std::io::Error),
}

/// The part of [`Error::NonFinite`]'s message that says where a position first went non-finite.
fn flagged_steps(flagged: &Option<(u64, u64)>) -> String {
    match flagged {
        Some((a, b)) if a == b => format!(" (a position first went non-finite at step {a})"),
        Some((a, b)) => format!(" (a position first went non-finite in steps {a} to {b})"),
        None => String::new(),
    }
}

/// The 1-based line of a byte offset in a file's text (for the line a TOML parse error or key is at).
pub fn line_of(text: &str, offset: usize) -> usize {
    let offset = offset.min(text.len());
    text.as_bytes()[..offset].iter().filter(|&&b| b == b'\n').count() + 1
}

/// A TOML parse error of `file` as a message: the file, the line and the parser's text.
pub fn toml_parse_message(file: &std::path::Path, text: &str, e: &toml::de::Error) -> String {
    match e.span() {
        Some(s) => format!("{}, line {}: {}", file.display(), line_of(text, s.start), e.message().trim()),
        None => format!("{}: {}", file.display(), e.message().trim()),
    }
}
