//! Checkpoints: `checkpoint.bin` in a run folder holds everything needed to continue the run bit for bit on the
//! same backend and precision: the stateful solver buffers (`Solver::save_state`) and the loop's counters. The
//! scene is the run folder's `scene.toml` with the recorded `--set` overrides. Format: the 8 bytes `SWARFCK1`, a
//! little-endian u64 header length, a JSON header, then the buffers' bytes in header order. Written atomically.
//! The header's f64 values must round-trip exactly (serde_json's `float_roundtrip`): a last-bit change of the
//! time would change every later step's length and break the bitwise continuation.
//!
//! The header also records the swarf version, what the run was ([`Provenance`]: the resolved scene and its
//! materials) and an FNV-1a 64 checksum of each buffer; [`read`] verifies the checksums and [`validate`] the
//! header's values and the particle ids and positions, so that a damaged or edited checkpoint is refused with what
//! is wrong before any work (issue 27). Checkpoints of an older swarf, without them, are still read (`swarf bench
//! step --from`); `swarf run --resume` refuses them (`resume`).

use crate::hash::fnv1a64;
use crate::provenance::Provenance;
use crate::solver::StateBlobs;
use crate::{Error, Result};
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::Path;

const MAGIC: &[u8; 8] = b"SWARFCK1";

/// The run loop's position, stored with the buffers.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Header {
    pub overrides: Vec<String>,
    pub precision: String,
    pub dim: usize,
    pub particles: usize,
    pub time: f64,
    pub steps: u64,
    /// The time step in force (the CFL re-check may have lowered it).
    pub dt: f64,
    /// Frames written and the time of the next one.
    pub frame: usize,
    pub next_out: f64,
    /// The time of the next periodic checkpoint (None: only on Ctrl-C).
    pub next_checkpoint: Option<f64>,
    /// (name, bytes) of each buffer, in file order.
    pub fields: Vec<(String, usize)>,
    /// The swarf version that wrote it (empty: an older swarf).
    #[serde(default)]
    pub version: String,
    /// The scene and materials of the run (None: an older swarf).
    #[serde(default)]
    pub provenance: Option<Provenance>,
    /// Cell-list rebuilds before the checkpoint (a resumed run's summary counts the whole run).
    #[serde(default)]
    pub rebuilds: u64,
    /// FNV-1a 64 of each buffer, in file order (empty: an older swarf).
    #[serde(default)]
    pub checksums: Vec<u64>,
}

/// The version written into checkpoints.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

pub fn write(path: &Path, mut h: Header, state: &StateBlobs) -> Result<()> {
    h.fields = state.iter().map(|(n, v)| (n.clone(), v.len())).collect();
    h.checksums = state.iter().map(|(_, v)| fnv1a64(v)).collect();
    h.version = VERSION.to_string();
    let json = serde_json::to_vec(&h).map_err(|e| Error::Checkpoint(e.to_string()))?;
    crate::output::write_atomic_with(path, |w: &mut dyn Write| {
        w.write_all(MAGIC)?;
        w.write_all(&(json.len() as u64).to_le_bytes())?;
        w.write_all(&json)?;
        for (_, v) in state {
            w.write_all(v)?;
        }
        Ok(())
    })
    // The atomic write's error names the path already.
    .map_err(|e| Error::Checkpoint(e.to_string()))
}

pub fn read(path: &Path) -> Result<(Header, StateBlobs)> {
    let bytes = std::fs::read(path).map_err(|e| Error::Checkpoint(format!("{}: {e}", path.display())))?;
    let bad = |what: &str| Error::Checkpoint(format!("{}: {what}", path.display()));
    let len = header_len(path, &bytes)?;
    let json = 16usize.checked_add(len).and_then(|e| bytes.get(16..e)).ok_or_else(|| bad("truncated header"))?;
    let h: Header = serde_json::from_slice(json).map_err(|e| bad(&format!("header: {e}")))?;
    let mut at = 16 + len;
    let mut state = Vec::with_capacity(h.fields.len());
    for (name, n) in &h.fields {
        let end = at.checked_add(*n).ok_or_else(|| bad(&format!("field '{name}' truncated")))?;
        let v = bytes.get(at..end).ok_or_else(|| bad(&format!("field '{name}' truncated")))?;
        state.push((name.clone(), v.to_vec()));
        at = end;
    }
    if at != bytes.len() {
        return Err(bad("trailing bytes after the last field"));
    }
    verify_checksums(&h, &state).map_err(|e| bad(&e))?;
    Ok((h, state))
}

/// The header alone, without reading (or checking) the buffers: what a run is resumed with, before the run reads
/// the whole file.
pub fn read_header(path: &Path) -> Result<Header> {
    use std::io::Read;
    let bad = |what: &str| Error::Checkpoint(format!("{}: {what}", path.display()));
    let mut f = std::fs::File::open(path).map_err(|e| bad(&e.to_string()))?;
    let size = f.metadata().map_err(|e| bad(&e.to_string()))?.len();
    let mut prefix = [0u8; 16];
    f.read_exact(&mut prefix).map_err(|_| bad(NOT_A_CHECKPOINT))?;
    let len = header_len(path, &prefix)?;
    if 16 + len as u64 > size {
        return Err(bad("truncated header"));
    }
    let mut json = vec![0u8; len];
    f.read_exact(&mut json).map_err(|_| bad("truncated header"))?;
    serde_json::from_slice(&json).map_err(|e| bad(&format!("header: {e}")))
}

const NOT_A_CHECKPOINT: &str = "not a swarf checkpoint (expected the signature SWARFCK1)";

/// The header's length from a checkpoint's first 16 bytes (the signature, then the length).
fn header_len(path: &Path, bytes: &[u8]) -> Result<usize> {
    let bad = |what: &str| Error::Checkpoint(format!("{}: {what}", path.display()));
    if bytes.len() < 16 || &bytes[..8] != MAGIC {
        return Err(bad(NOT_A_CHECKPOINT));
    }
    Ok(u64::from_le_bytes(bytes[8..16].try_into().map_err(|_| bad("truncated header length"))?) as usize)
}

/// Each buffer's checksum against the header's (none recorded: an older swarf, checked by the caller).
fn verify_checksums(h: &Header, state: &StateBlobs) -> std::result::Result<(), String> {
    if h.checksums.is_empty() {
        return Ok(());
    }
    if h.checksums.len() != state.len() {
        return Err(format!("{} checksums for {} fields: the header is damaged", h.checksums.len(), state.len()));
    }
    for ((name, v), want) in state.iter().zip(&h.checksums) {
        let got = fnv1a64(v);
        if got != *want {
            return Err(format!(
                "field '{name}': checksum {got:#018x}, expected {want:#018x} (recorded when it was written): the \
                 file was damaged or changed since"
            ));
        }
    }
    Ok(())
}

/// The header's values and the state's particle ids and positions: what a run can continue from. Names the
/// value, what it is and what is expected.
pub fn validate(h: &Header, state: &StateBlobs) -> std::result::Result<(), String> {
    let finite_at_least = |what: &str, v: f64, min: f64, strict: bool| {
        let ok = v.is_finite() && if strict { v > min } else { v >= min };
        let rel = if strict { ">" } else { ">=" };
        if ok { Ok(()) } else { Err(format!("header: {what} = {v:e}: expected a finite value {rel} {min}")) }
    };
    finite_at_least("dt", h.dt, 0.0, true)?;
    finite_at_least("time", h.time, 0.0, false)?;
    finite_at_least("next_out", h.next_out, 0.0, false)?;
    if let Some(c) = h.next_checkpoint {
        finite_at_least("next_checkpoint", c, 0.0, true)?;
    }
    // One frame at t = 0, then at most one per step.
    let frames = h.steps.saturating_add(1);
    if h.frame == 0 || h.frame as u64 > frames {
        return Err(format!("header: frame = {}: expected 1 to {frames} (steps = {})", h.frame, h.steps));
    }
    if h.particles == 0 || h.particles > u32::MAX as usize {
        return Err(format!("header: particles = {}: expected 1 to {}", h.particles, u32::MAX));
    }
    let blob = |name: &str| state.iter().find(|(n, _)| n == name).map(|(_, v)| v.as_slice());
    let ids = blob("id").ok_or("no field 'id'")?;
    if ids.len() != 4 * h.particles {
        return Err(format!("field 'id': {} bytes, expected {} (4 per particle)", ids.len(), 4 * h.particles));
    }
    let mut seen = vec![false; h.particles];
    for (k, c) in ids.chunks_exact(4).enumerate() {
        let id = u32::from_le_bytes([c[0], c[1], c[2], c[3]]) as usize;
        if id >= h.particles || std::mem::replace(&mut seen[id], true) {
            return Err(format!(
                "field 'id': entry {k} is {id}: expected each particle id 0 to {} exactly once",
                h.particles - 1
            ));
        }
    }
    let width = if h.precision == "f64" { 8 } else { 4 };
    for name in ["pos", "pos0", "pos_lo", "vel", "vel0"] {
        if let Some(v) = blob(name)
            && let Some(k) = v.chunks_exact(width).position(|c| !finite(c))
        {
            return Err(format!("field '{name}': value {k} is not finite: expected finite positions and velocities"));
        }
    }
    Ok(())
}

/// Whether a little-endian f64 (8 bytes) or f32 (4 bytes) is finite.
fn finite(c: &[u8]) -> bool {
    match c.len() {
        8 => f64::from_le_bytes(c.try_into().unwrap_or([0; 8])).is_finite(),
        _ => f32::from_le_bytes(c.try_into().unwrap_or([0; 4])).is_finite(),
    }
}
