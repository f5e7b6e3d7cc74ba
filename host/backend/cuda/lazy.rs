//! Entry points loaded on first use: each as its own module ([`split`](super::split)), so that the driver
//! JIT-compiles only the kernels a run launches. A [`Kernel`] caches its function, so a launch looks nothing up
//! by name once the kernel is loaded.

use super::split::SplitPtx;
use crate::{Error, Result};
use cudarc::driver::{CudaContext, CudaFunction};
use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

/// One entry point: its name and, once loaded, its function (the default: no name, a slot not yet filled).
#[derive(Default)]
pub(super) struct Kernel {
    pub(super) name: String,
    pub(super) f: OnceLock<CudaFunction>,
}

impl Kernel {
    pub(super) fn new(name: &str) -> Self {
        Kernel { name: name.to_string(), f: OnceLock::new() }
    }
}

/// The PTX (with its register caps) split by entry, and the functions loaded so far.
pub(super) struct Loader {
    ctx: Arc<CudaContext>,
    ptx: String,
    split: SplitPtx,
    /// Load each module without the device runtime's `cudaGraphSetConditional` (`strip_graph_conditional`): the
    /// driver did not resolve it.
    pub(super) strip: bool,
    loaded: Mutex<HashMap<String, CudaFunction>>,
}

impl Loader {
    pub(super) fn new(ctx: Arc<CudaContext>, ptx: String) -> Result<Self> {
        let split = SplitPtx::parse(&ptx)
            .ok_or_else(|| Error::GpuUnavailable("the embedded PTX has no header or an unnamed item".into()))?;
        Ok(Loader { ctx, ptx, split, strip: false, loaded: Mutex::new(HashMap::new()) })
    }

    /// Whether the PTX has the entry point `name`.
    pub(super) fn has(&self, name: &str) -> bool {
        self.split.items(&self.ptx).any(|i| i.entry && i.name == name)
    }

    /// The entry point `name`, loading its module on first use (the driver JIT-compiles it then).
    pub(super) fn load(&self, name: &str) -> Result<CudaFunction> {
        let mut loaded = self.loaded.lock().map_err(|_| Error::GpuUnavailable("kernel loader poisoned".into()))?;
        if let Some(f) = loaded.get(name) {
            return Ok(f.clone());
        }
        let mut text = self
            .split
            .module(&self.ptx, name)
            .ok_or_else(|| Error::GpuUnavailable(format!("no entry point {name} in the embedded PTX")))?;
        if self.strip {
            text = super::strip_graph_conditional(&text);
        }
        let module = self
            .ctx
            .load_module(cudarc::nvrtc::Ptx::from_src(text))
            .map_err(|source| Error::Cuda { op: "loading a kernel's PTX module", source })?;
        let f = module.load_function(name).map_err(|source| Error::Cuda { op: "loading a kernel", source })?;
        loaded.insert(name.to_string(), f.clone());
        Ok(f)
    }
}
