//! What the criterion benchmarks share.

use swarf::backend::CudaBackend;

/// The GPU of device 0, or None with a note on stderr: on a machine without one the GPU benchmarks are skipped.
pub fn gpu() -> Option<CudaBackend> {
    match CudaBackend::new(0) {
        Ok(b) => Some(b),
        Err(e) => {
            eprintln!("GPU benchmarks skipped: {e}");
            None
        }
    }
}
