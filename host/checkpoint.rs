//! Checkpoints: `checkpoint.bin` in a run folder holds everything needed to continue the run bit for bit on the
//! same backend and precision: the stateful solver buffers (`Solver::save_state`) and the loop's counters. The
//! scene is the run folder's `scene.toml` with the recorded `--set` overrides. Format: the 8 bytes `SWARFCK1`, a
//! little-endian u64 header length, a JSON header, then the buffers' bytes in header order. Written atomically.
//! The header's f64 values must round-trip exactly (serde_json's `float_roundtrip`): a last-bit change of the
//! time would change every later step's length and break the bitwise continuation.

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
}

pub fn write(path: &Path, mut h: Header, state: &StateBlobs) -> Result<()> {
    h.fields = state.iter().map(|(n, v)| (n.clone(), v.len())).collect();
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
    .map_err(|e| Error::Checkpoint(format!("{}: {e}", path.display())))
}

pub fn read(path: &Path) -> Result<(Header, StateBlobs)> {
    let bytes = std::fs::read(path).map_err(|e| Error::Checkpoint(format!("{}: {e}", path.display())))?;
    let bad = |what: &str| Error::Checkpoint(format!("{}: {what}", path.display()));
    if bytes.len() < 16 || &bytes[..8] != MAGIC {
        return Err(bad("not a swarf checkpoint (expected the signature SWARFCK1)"));
    }
    let len = u64::from_le_bytes(bytes[8..16].try_into().map_err(|_| bad("truncated header length"))?) as usize;
    let json = bytes.get(16..16 + len).ok_or_else(|| bad("truncated header"))?;
    let h: Header = serde_json::from_slice(json).map_err(|e| bad(&format!("header: {e}")))?;
    let mut at = 16 + len;
    let mut state = Vec::with_capacity(h.fields.len());
    for (name, n) in &h.fields {
        let v = bytes.get(at..at + n).ok_or_else(|| bad(&format!("field '{name}' truncated")))?;
        state.push((name.clone(), v.to_vec()));
        at += n;
    }
    if at != bytes.len() {
        return Err(bad("trailing bytes after the last field"));
    }
    Ok((h, state))
}
