//! `swarf info`: what this build and machine offer.

use crate::Result;
use crate::backend::{AnyBackend, BackendChoice};
use std::fmt::Write;

pub fn report(choice: BackendChoice) -> Result<String> {
    let mut s = String::new();
    let _ = writeln!(s, "swarf {}", env!("CARGO_PKG_VERSION"));
    let (b, line) = AnyBackend::select(choice)?;
    let _ = writeln!(s, "{line}");
    let i = b.info();
    let _ = writeln!(s, "device:        {}", i.name);
    match i.compute_capability {
        Some((ma, mi)) => {
            let _ = writeln!(s, "compute cap.:  {ma}.{mi} ({} multiprocessors)", i.units);
        }
        None => {
            let _ = writeln!(s, "threads:       {}", i.units);
        }
    }
    let _ = writeln!(s, "memory:        {:.1} GiB", i.memory_bytes as f64 / (1u64 << 30) as f64);
    if let Some(v) = i.driver_version {
        let _ = writeln!(s, "driver:        CUDA {}.{}", v / 1000, (v % 1000) / 10);
    }
    let targets = crate::ptx::targets();
    if targets.is_empty() {
        let why = crate::ptx::PTX_MISSING.unwrap_or("unknown");
        let _ = writeln!(s, "ptx:           none embedded ({})", why.lines().next().unwrap_or(why));
    } else {
        let _ = write!(s, "ptx:           {} embedded", targets.join(", "));
        if let Some(t) = i.ptx_target {
            let _ = write!(s, "; {t} loaded");
        }
        let _ = writeln!(s);
    }
    let _ = writeln!(s, "precisions:    f64 (reference), f32");
    Ok(s)
}
