//! `swarf info`: what this build and machine offer.

use crate::Result;
use crate::backend::{AnyBackend, BackendChoice};
use std::fmt::Write;

/// The report of `swarf info`; with `kernels`, the GPU compiler's report of every kernel.
pub fn report(choice: BackendChoice, kernels: bool) -> Result<String> {
    let mut s = String::new();
    let _ = writeln!(s, "swarf {}", crate::run::VERSION);
    // A bad switch is refused here too, naming the variable, before any backend is chosen.
    let tuning = crate::tuning::Tuning::current()?;
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
    let _ = writeln!(s, "precisions:    f64 (reference), f32, mixed (f32 with compensated positions)");
    let _ = writeln!(s, "tuning:        {}", tuning.line());
    if let AnyBackend::Cuda(c) = &b {
        // docs/architecture.md, "The rebuild in a conditional node".
        let _ = match c.conditional_rebuild() {
            Ok(()) => writeln!(s, "graph steps:   rebuilds in IF nodes"),
            Err(why) => writeln!(s, "graph steps:   rebuilds in gated launches ({why})"),
        };
    }
    if kernels {
        match &b {
            AnyBackend::Cuda(c) => s.push_str(&kernel_table(&c.kernel_report()?)),
            AnyBackend::Cpu(_) => {
                let _ = writeln!(s, "kernels:       no compiler report on the CPU backend");
            }
        }
    }
    Ok(s)
}

/// The compiler report as a Markdown table, spilling kernels first noted.
fn kernel_table(rows: &[crate::backend::cuda::KernelReport]) -> String {
    let mut s = String::from(
        "\n| kernel | registers | local bytes (spills) | shared bytes | blocks/SM | occupancy |\n|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {:.0} % |",
            r.name,
            r.registers,
            r.local_bytes,
            r.shared_bytes,
            r.blocks_per_sm,
            100.0 * r.occupancy
        );
    }
    let spilling = rows.iter().filter(|r| r.local_bytes > 0).count();
    let _ = writeln!(s, "\n{} kernels, {spilling} with local memory (spills or stack arrays)", rows.len());
    s
}
