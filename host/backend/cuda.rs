//! The CUDA backend: launches the PTX of `swarf-kernels` through cudarc, which loads libcuda at run time, so the
//! binary builds and runs without any CUDA installation and uses the GPU where a driver and device exist.
//! One stream, no event tracking: every launch is ordered after the previous one.

use super::{Backend, Buffer, CellBuffers, DeviceInfo, Element, SCAN_TILE, ScalarsAt};
use crate::kernels::neighbour::GatherField;
use crate::kernels::pass::{
    ENTRY_COUNT, ENTRY_NAMES, GatherArgs, GatherFieldsArgs, Grid, HashCountArgs, Pass, ScanApplyArgs, ScanReduceArgs,
    ScatterArgs, SortArgs, ZeroArgs, entry_index, single_index,
};
use crate::kernels::sph::step::StepScalars;
use crate::kernels::{Dim, Real};
use crate::{Error, Result};
use cudarc::driver::sys::{CUdevice_attribute, CUevent_flags, CUresult};
use cudarc::driver::{CudaContext, CudaFunction, CudaSlice, CudaStream, DevicePtr, DevicePtrMut, DriverError, result};
use std::collections::HashMap;
use std::ffi::c_void;
use std::marker::PhantomData;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

mod conditional;
mod lazy;
pub mod split;
use conditional::Conditional;
pub use conditional::strip_graph_conditional;
use lazy::{Kernel, Loader};

/// The entry whose module decides whether the driver resolves `cudaGraphSetConditional` (the predictor calls it),
/// loaded when the backend starts.
const PROBE: &str = "swarf_step_predict_2d_f64";

/// Every PTX entry point the backend loads (the pass table, `kernels::pass::table`); the PTX test checks that
/// each is present.
pub fn kernel_names() -> &'static [&'static str] {
    &ENTRY_NAMES
}

/// Threads per block of the per-particle kernels.
const BLOCK: u32 = 256;
/// Most blocks of a grid-stride launch (`CudaBackend::launch_strided`): eight per multiprocessor of an H100 or
/// H200 fill the device; more only add blocks that a closed gate returns at once.
const GATED_BLOCKS: usize = 1056;

/// A typed device array; the bytes live in a `CudaSlice<u8>` so that any `Pod` type can be stored.
pub struct CudaBuf<T> {
    raw: CudaSlice<u8>,
    len: usize,
    _t: PhantomData<T>,
}

// SAFETY: the device memory is only touched through the backend's single stream.
unsafe impl<T> Send for CudaBuf<T> {}
unsafe impl<T> Sync for CudaBuf<T> {}

impl<T> Buffer<T> for CudaBuf<T> {
    fn len(&self) -> usize {
        self.len
    }
}

/// The kernel slots, one per entry of the pass table (`kernels::pass::table`), in table order: a pass launches
/// slot `Pass::ENTRY`.
struct Kernels(Vec<Kernel>);

/// The table positions of the entries the backend's own algorithms launch (the counting sort, the scan, the
/// gathers of a reorder).
mod slot {
    use super::single_index;
    pub const ZERO_GATED: usize = single_index("zero_gated");
    pub const SCAN_REDUCE: usize = single_index("scan_reduce");
    pub const SCAN_APPLY: usize = single_index("scan_apply");
    pub const SCATTER: usize = single_index("scatter");
    pub const SORT_CELLS: usize = single_index("sort_cells");
    pub const GATHER_B4: usize = single_index("gather_b4");
    pub const GATHER_B8: usize = single_index("gather_b8");
    pub const GATHER_B16: usize = single_index("gather_b16");
    pub const GATHER_FIELDS: usize = single_index("gather_fields");
}

/// The table position of the gated rebuild's fused hash and count for (R, D).
fn hash_count<R: Real, D: Dim>() -> usize {
    entry_index("hash_count", D::D, size_of::<R>(), 0)
}

pub struct CudaBackend {
    ctx: Arc<CudaContext>,
    /// Loads each entry point as its own module on its first launch; shared with the backend's siblings, so that
    /// an ensemble's members JIT-compile each entry once.
    loader: Arc<Loader>,
    stream: Arc<CudaStream>,
    k: Arc<Kernels>,
    info: DeviceInfo,
    /// Device copies of the field tables of `gather_fields`, by content (a solver alternates between two).
    gather_tables: Mutex<HashMap<Vec<GatherField>, CudaBuf<GatherField>>>,
    /// A graph is being captured: nothing may be uploaded or synchronised.
    capturing: AtomicBool,
    /// Threads per block of the neighbour passes (`SWARF_PAIR_BLOCK`) and of the corrector with the plastic update
    /// (`SWARF_PLASTIC_BLOCK`); [`BLOCK`] unless set. Per-thread arithmetic does not depend on them (lanes stay
    /// within a warp), so results are the same bits at any block size.
    pair_block: u32,
    plastic_block: u32,
    /// Block order (0 forward, 1 reverse: `ptx::ordered_index`) of the pair interaction (`SWARF_PAIR_ORDER`) and
    /// of the corrector with the plastic update (`SWARF_PLASTIC_ORDER`); like the block sizes they change no bit.
    pair_reverse: u32,
    plastic_reverse: u32,
    /// The IF nodes of captured rebuilds (`conditional`), or why there are none.
    conditional: std::result::Result<Conditional, String>,
    /// Captured rebuilds go in IF nodes (default; `SWARF_NO_CONDITIONAL=1` or `set_conditional_rebuild` turn it
    /// off: plain gated nodes, the same launches and bits).
    use_conditional: AtomicBool,
    /// Launches go to the IF body's stream (while a rebuild's body is captured).
    in_body: AtomicBool,
}

/// Threads per block of the neighbour passes by default: inside the 150k reference cut on an H200, with the
/// interaction's blocks reversed, 64 took 0.2087–0.2093 ms per step, 128 0.2097–0.2098, 256 0.2113–0.2117 (t = 0:
/// 0.1501–0.1505, 0.1502, 0.1512–0.1519; the 6k cut unchanged; docs/measurements/notebook.md, "Block order and a packed Verlet
/// list"). Smaller blocks let the multiprocessors take the last blocks of the launch in finer pieces.
const PAIR_BLOCK: u32 = 64;

/// Whether the pair interaction and the plastic corrector take their blocks in reverse order by default
/// (`ptx::ordered_index`). Measured inside the 150k reference cut on an H200 (docs/measurements/notebook.md, "Block order"):
/// the interaction reversed 0.1270–0.1273 ms against 0.1298–0.1306 forward, the step −1.0 %, nothing at t = 0
/// or at 6k; the corrector reversed −0.2 % (noise), so it stays forward.
const PAIR_REVERSE: bool = true;
const PLASTIC_REVERSE: bool = false;

/// `block` if it is a multiple of 32 from 32 to 1024 (whole warps: the lanes of a particle stay in one), else an
/// error naming `what`.
fn check_block(what: &str, block: u32) -> Result<u32> {
    if (32..=1024).contains(&block) && block.is_multiple_of(32) { Ok(block) } else { Err(bad_block(what, &block)) }
}

fn bad_block(what: &str, got: &dyn std::fmt::Display) -> Error {
    Error::GpuUnavailable(format!("{what} = {got}: expected a block size, a multiple of 32 from 32 to 1024"))
}

/// What the driver's JIT compiler made of one entry point (`cuFuncGetAttribute`,
/// `cuOccupancyMaxActiveBlocksPerMultiprocessor` at the backend's block size).
#[derive(Clone, Debug)]
pub struct KernelReport {
    pub name: String,
    /// Registers per thread.
    pub registers: i32,
    /// Local memory per thread in bytes: register spills and stack arrays.
    pub local_bytes: i32,
    /// Static shared memory per block in bytes.
    pub shared_bytes: i32,
    /// Resident blocks of [`BLOCK`] threads per multiprocessor.
    pub blocks_per_sm: u32,
    /// Resident threads against the multiprocessor's maximum.
    pub occupancy: f64,
}

/// A captured CUDA graph.
pub struct Graph(cudarc::driver::CudaGraph);

fn cuda(op: &'static str) -> impl FnOnce(DriverError) -> Error {
    move |source| Error::Cuda { op, source }
}

impl CudaBackend {
    /// The compiler report of every entry point in [`kernel_names`] order: registers, local memory (spills),
    /// shared memory and the occupancy at the launch block size.
    pub fn kernel_report(&self) -> Result<Vec<KernelReport>> {
        let max_threads = self
            .ctx
            .attribute(CUdevice_attribute::CU_DEVICE_ATTRIBUTE_MAX_THREADS_PER_MULTIPROCESSOR)
            .map_err(cuda("device attribute"))?;
        kernel_names()
            .iter()
            .map(|&name| {
                let f = self.loader.load(name)?;
                let blocks =
                    f.occupancy_max_active_blocks_per_multiprocessor(BLOCK, 0, None).map_err(cuda("occupancy"))?;
                Ok(KernelReport {
                    registers: f.num_regs().map_err(cuda("function attribute"))?,
                    local_bytes: f.local_size_bytes().map_err(cuda("function attribute"))?,
                    shared_bytes: f.shared_size_bytes().map_err(cuda("function attribute"))?,
                    blocks_per_sm: blocks,
                    occupancy: (blocks * BLOCK) as f64 / max_threads.max(1) as f64,
                    name: name.to_string(),
                })
            })
            .collect()
    }

    /// Whether captured steps put their rebuild in IF nodes (`Ok`), or why not: the driver cannot, or it was
    /// turned off (`SWARF_NO_CONDITIONAL=1`, [`CudaBackend::set_conditional_rebuild`]).
    pub fn conditional_rebuild(&self) -> std::result::Result<(), String> {
        match &self.conditional {
            Err(why) => Err(why.clone()),
            Ok(_) if !self.use_conditional.load(Ordering::Relaxed) => Err("turned off".into()),
            Ok(_) => Ok(()),
        }
    }

    /// Turns the IF nodes of captured rebuilds on or off (for graphs captured from now on).
    pub fn set_conditional_rebuild(&mut self, on: bool) {
        self.use_conditional.store(on, Ordering::Relaxed);
    }

    /// Sets the threads per block of the neighbour passes and of the plastic corrector (what `SWARF_PAIR_BLOCK` and
    /// `SWARF_PLASTIC_BLOCK` set at start-up); an error for a size that is not a multiple of 32 from 32 to 1024.
    pub fn set_blocks(&mut self, pair: u32, plastic: u32) -> Result<()> {
        self.pair_block = check_block("pair block", pair)?;
        self.plastic_block = check_block("plastic block", plastic)?;
        Ok(())
    }

    /// Sets the block order of the pair interaction and of the plastic corrector (true: reverse; what
    /// `SWARF_PAIR_ORDER` and `SWARF_PLASTIC_ORDER` set at start-up).
    pub fn set_block_order(&mut self, pair_reverse: bool, plastic_reverse: bool) {
        self.pair_reverse = pair_reverse as u32;
        self.plastic_reverse = plastic_reverse as u32;
    }

    /// Opens device `ordinal` and loads the embedded PTX; says why if that is impossible.
    pub fn new(ordinal: usize) -> Result<Self> {
        let (ctx, stream) = open_device(ordinal)?;
        let cc = ctx.compute_capability().map_err(cuda("compute capability"))?;
        let tuning = crate::tuning::Tuning::current()?;
        let (target, loader, conditional, driver) = load_ptx(&ctx, cc, tuning)?;
        let k = Arc::new(kernel_table(&loader)?);
        let info = DeviceInfo {
            backend: "gpu",
            name: ctx.name().map_err(cuda("device name"))?,
            compute_capability: Some(cc),
            memory_bytes: ctx.total_mem().map_err(cuda("device memory"))?,
            driver_version: Some(driver),
            units: ctx
                .attribute(CUdevice_attribute::CU_DEVICE_ATTRIBUTE_MULTIPROCESSOR_COUNT)
                .map_err(cuda("multiprocessor count"))? as usize,
            ptx_target: Some(target),
        };
        let no_conditional = tuning.no_conditional;
        Ok(CudaBackend {
            conditional,
            use_conditional: AtomicBool::new(!no_conditional),
            in_body: AtomicBool::new(false),
            loader: Arc::new(loader),
            ctx,
            stream,
            k,
            info,
            gather_tables: Mutex::new(HashMap::new()),
            capturing: AtomicBool::new(false),
            pair_block: tuning.pair_block.unwrap_or(PAIR_BLOCK),
            plastic_block: tuning.plastic_block.unwrap_or(BLOCK),
            pair_reverse: tuning.pair_order.map_or(PAIR_REVERSE, |o| o == crate::tuning::Order::Reverse) as u32,
            plastic_reverse: tuning.plastic_order.map_or(PLASTIC_REVERSE, |o| o == crate::tuning::Order::Reverse)
                as u32,
        })
    }
}

impl CudaBackend {
    /// Another backend on the same device and context with a stream of its own (and an IF-body stream of its own
    /// where conditional rebuilds are used), sharing the loaded kernels and the settings of this one: an ensemble's
    /// members run on siblings, concurrently, one host thread each (host/ensemble). Its launches run the same
    /// kernels with the same arguments, so a member's bits do not depend on its siblings.
    pub fn sibling(&self) -> Result<CudaBackend> {
        let stream = self.ctx.new_stream().map_err(cuda("cuStreamCreate"))?;
        let conditional = match &self.conditional {
            Ok(_) => {
                let driver = self.info.driver_version.unwrap_or(0);
                Conditional::new(&self.ctx, driver)
            }
            Err(why) => Err(why.clone()),
        };
        Ok(CudaBackend {
            conditional,
            use_conditional: AtomicBool::new(self.use_conditional.load(Ordering::Relaxed)),
            in_body: AtomicBool::new(false),
            loader: self.loader.clone(),
            ctx: self.ctx.clone(),
            stream,
            k: self.k.clone(),
            info: self.info.clone(),
            gather_tables: Mutex::new(HashMap::new()),
            capturing: AtomicBool::new(false),
            pair_block: self.pair_block,
            plastic_block: self.plastic_block,
            pair_reverse: self.pair_reverse,
            plastic_reverse: self.plastic_reverse,
        })
    }
}

/// The context and stream of device `ordinal`, after checking that this build has PTX and the machine a driver
/// and the device.
fn open_device(ordinal: usize) -> Result<(Arc<CudaContext>, Arc<CudaStream>)> {
    if crate::ptx::PTX.is_empty() {
        let why = crate::ptx::PTX_MISSING.unwrap_or("no PTX embedded");
        return Err(Error::GpuUnavailable(format!("this build has no GPU kernels ({})", first_line(why))));
    }
    // SAFETY: probing for the shared library has no side effects beyond loading it.
    if !unsafe { cudarc::driver::sys::is_culib_present() } {
        return Err(Error::GpuUnavailable("no CUDA driver (libcuda.so) found".into()));
    }
    let count = CudaContext::device_count().map_err(cuda("cuDeviceGetCount"))?;
    if count as usize <= ordinal {
        return Err(Error::GpuUnavailable(format!("no CUDA device {ordinal} ({count} present)")));
    }
    let ctx = CudaContext::new(ordinal).map_err(cuda("cuCtxCreate"))?;
    // SAFETY: a single stream orders all work; cross-stream event tracking is not needed.
    unsafe { ctx.disable_event_tracking() };
    // A stream of its own: the legacy default stream cannot be captured into a graph.
    let stream = ctx.new_stream().map_err(cuda("cuStreamCreate"))?;
    Ok((ctx, stream))
}

/// The embedded PTX target for compute capability `cc` with its register caps, its loader with the predictor's
/// module loaded (which decides whether the driver resolves `cudaGraphSetConditional`), and the driver version.
fn load_ptx(
    ctx: &Arc<CudaContext>,
    cc: (i32, i32),
    tuning: &crate::tuning::Tuning,
) -> Result<(&'static str, Loader, std::result::Result<Conditional, String>, i32)> {
    let fast = crate::ptx::fast_math();
    let (target, ptx) = crate::ptx::select(cc.0, cc.1, fast).ok_or_else(|| {
        Error::GpuUnavailable(format!(
            "no embedded PTX target runs on compute capability {}.{} (embedded: {:?})",
            cc.0,
            cc.1,
            crate::ptx::targets()
        ))
    })?;
    let ptx = register_caps(ptx, tuning.maxnreg, tuning.plastic_maxnreg);
    let mut driver = 0i32;
    // SAFETY: plain query into a local.
    unsafe { cudarc::driver::sys::cuDriverGetVersion(&mut driver) };
    // A driver that cannot resolve the predictor's `cudaGraphSetConditional` loads the kernels without it, and
    // the captured steps keep their rebuild in plain gated nodes. The predictor's module decides it, loaded
    // now; every other entry loads on its first launch (`Loader`).
    let mut loader = Loader::new(ctx.clone(), ptx)?;
    let conditional = match loader.load(PROBE) {
        Ok(_) => Conditional::new(ctx, driver),
        Err(e) => {
            loader.strip = true;
            loader.load(PROBE)?;
            Err(format!("the driver did not resolve cudaGraphSetConditional ({e})"))
        }
    };
    Ok((target, loader, conditional, driver))
}

/// Every kernel slot, from the pass table (`kernels::for_each_entry!`), each checked to name an entry of the PTX
/// (loaded on first use).
fn kernel_table(loader: &Loader) -> Result<Kernels> {
    let slots = ENTRY_NAMES
        .iter()
        .map(|&name| {
            if loader.has(name) {
                Ok(Kernel::new(name))
            } else {
                Err(Error::GpuUnavailable(format!("no entry point {name} in the embedded PTX")))
            }
        })
        .collect::<Result<Vec<_>>>()?;
    debug_assert_eq!(slots.len(), ENTRY_COUNT);
    Ok(Kernels(slots))
}

impl CudaBackend {
    fn ptr<T>(&self, b: &CudaBuf<T>) -> u64 {
        let (p, _sync) = b.raw.device_ptr(&self.stream);
        p
    }

    fn ptr_mut<T>(&self, b: &mut CudaBuf<T>) -> u64 {
        let (p, _sync) = b.raw.device_ptr_mut(&self.stream);
        p
    }

    /// Launches `f` over `threads` threads in blocks of `block`. Arguments live in a stack array for the call,
    /// so a launch allocates nothing.
    /// Launches `f`, an entry that takes the pass's argument struct `args` by value as its single parameter
    /// (`kernels::pass`; tests/ptx.rs checks its size and alignment against the entry's), over `threads` threads
    /// in blocks of `block`.
    fn launch_pass<A: Copy>(&self, f: &Kernel, threads: usize, block: u32, args: &A) -> Result<()> {
        if threads == 0 {
            return Ok(());
        }
        let f = self.function(f)?;
        let blocks = threads.div_ceil(block as usize);
        if blocks > i32::MAX as usize {
            return Err(Error::Length {
                op: "kernel launch (grid too large)",
                expected: i32::MAX as usize,
                got: blocks,
            });
        }
        // The driver copies the block's size (from the entry's signature: size_of::<A>(), A being `#[repr(C)]`
        // and plain) from here.
        let mut params = [args as *const A as *mut c_void];
        let stream = match (&self.conditional, self.in_body.load(Ordering::Relaxed)) {
            (Ok(c), true) => c.body_stream(),
            _ => self.stream.cu_stream(),
        };
        // SAFETY: the entry's single parameter is A (tests/ptx.rs); `args` outlives the call, which copies it.
        unsafe { result::launch_kernel(f.cu_function(), (blocks as u32, 1, 1), (block, 1, 1), 0, stream, &mut params) }
            .map_err(cuda("kernel launch"))
    }

    /// The function of `k`, loaded on its first use. A module load inside a graph capture would end the capture
    /// (and fail), so it is refused with a clear error: the solver's first step runs uncaptured and launches
    /// every pass a captured step launches.
    fn function<'k>(&self, k: &'k Kernel) -> Result<&'k CudaFunction> {
        if let Some(f) = k.f.get() {
            return Ok(f);
        }
        if self.capturing.load(Ordering::Relaxed) {
            return Err(Error::GpuUnavailable(format!(
                "kernel {} was first launched inside a graph capture; launch it once uncaptured first",
                k.name
            )));
        }
        let f = self.loader.load(&k.name)?;
        Ok(k.f.get_or_init(|| f))
    }

    /// [`Self::launch_pass`] of a grid-stride entry (a capped grid: GATED_BLOCKS blocks at most).
    fn launch_pass_strided<A: Copy>(&self, f: &Kernel, items: usize, args: &A) -> Result<()> {
        self.launch_pass(f, items.min(GATED_BLOCKS * BLOCK as usize), BLOCK, args)
    }

    /// A buffer's device address as a kernel's input pointer.
    fn input<T>(&self, b: &CudaBuf<T>) -> *const T {
        self.ptr(b) as *const T
    }

    /// A buffer's device address as a kernel's output pointer.
    fn output<T>(&self, b: &mut CudaBuf<T>) -> *mut T {
        self.ptr_mut(b) as *mut T
    }

    fn oom(&self, what: &'static str, bytes: usize, e: DriverError) -> Error {
        if e.0 == CUresult::CUDA_ERROR_OUT_OF_MEMORY {
            let (free, total) = self.ctx.mem_get_info().unwrap_or((0, 0));
            Error::OutOfMemory { what, bytes, free, total }
        } else {
            Error::Cuda { op: "cuMemAlloc", source: e }
        }
    }
}

/// The entry points that walk the neighbours (register-heavy, latency-bound): the ones `SWARF_MAXNREG` caps.
const NEIGHBOUR_KERNELS: [&str; 2] = ["swarf_sph_rates_", "swarf_heat_"];

/// The 2D entry points of [`NEIGHBOUR_KERNELS`] (their names carry the dimension after the prefix), capped at
/// [`NEIGHBOUR_MAXNREG`] by default.
const NEIGHBOUR_KERNELS_2D: [&str; 4] =
    ["swarf_sph_rates_2d_", "swarf_sph_rates_heat_2d_", "swarf_heat_brookshaw_2d_", "swarf_heat_pse_2d_"];

/// Registers per thread for [`NEIGHBOUR_KERNELS_2D`]: with the pair's data loaded at its head (`load::read`) the
/// fused 2D f64 interaction needs 142, one block of 256 threads per multiprocessor; 128 allow two (16 bytes of
/// spill) and save 21–26 % of the 150k reference cut's step (docs/measurements/notebook.md, "Loads at the head of the pair").
/// The 3D kernels (up to 202 registers) are not capped by default. `SWARF_MAXNREG=N` caps every neighbour kernel
/// at N instead, 0 none.
const NEIGHBOUR_MAXNREG: u32 = 128;

/// The entry points of the corrector with the plastic update (and the plastic pass alone): the return mapping's
/// f64 transcendentals need 132 registers uncapped, one block of 256 threads per multiprocessor (12 % occupancy);
/// [`PLASTIC_MAXNREG`] of them allow two. `SWARF_PLASTIC_MAXNREG` overrides it (0: no cap), for the benchmarks.
const PLASTIC_KERNELS: [&str; 2] = ["swarf_step_finish_", "swarf_plastic_"];

/// Registers per thread for [`PLASTIC_KERNELS`]: 65 536 / (2 × 256).
const PLASTIC_MAXNREG: u32 = 128;

/// The 2D Johnson–Cook corrector (the reference cuts' model) at [`JC_2D_MAXNREG`] instead: 65 536 / (3 × 256), three
/// blocks per multiprocessor. It needs 98–110; capped at 80 it took 0.0660–0.0675 ms against 0.0723–0.0730 inside
/// the 150k reference cut, the step 0.2460 against 0.2500 ms (+1 % inside the 6k cut; docs/measurements/notebook.md,
/// "Parameters by value"). The other models and 3D keep [`PLASTIC_MAXNREG`] (not measured at 80).
const JC_2D_KERNELS: [&str; 2] = ["swarf_step_finish_jc_2d_", "swarf_plastic_jc_2d_"];
const JC_2D_MAXNREG: u32 = 80;

/// `ptx` with the register caps the CUDA backend loads: the neighbour kernels at `neighbour` (`SWARF_MAXNREG`;
/// None: the 2D ones at [`NEIGHBOUR_MAXNREG`]; 0: none), the plastic corrector at `plastic`
/// (`SWARF_PLASTIC_MAXNREG`; None: the 2D Johnson–Cook ones at [`JC_2D_MAXNREG`], the others at
/// [`PLASTIC_MAXNREG`]; 0: none).
pub fn register_caps(ptx: &str, neighbour: Option<u32>, plastic: Option<u32>) -> String {
    let ptx = match neighbour {
        Some(0) => ptx.to_string(),
        Some(cap) => cap_registers(ptx, &NEIGHBOUR_KERNELS, cap),
        None => cap_registers(ptx, &NEIGHBOUR_KERNELS_2D, NEIGHBOUR_MAXNREG),
    };
    match plastic {
        Some(0) => ptx,
        Some(cap) => cap_registers(&ptx, &PLASTIC_KERNELS, cap),
        // An entry keeps the first cap it gets (`cap_registers`).
        None => cap_registers(&cap_registers(&ptx, &JC_2D_KERNELS, JC_2D_MAXNREG), &PLASTIC_KERNELS, PLASTIC_MAXNREG),
    }
}

/// `ptx` with a `.maxnreg cap` directive on every entry whose name starts with one of `prefixes` and has none yet
/// (PTX ISA "Performance-tuning directives": between the parameter list and the body). Fewer registers allow more
/// resident warps, at the price of spills; `swarf info --kernels` and `swarf bench step` measure both.
pub fn cap_registers(ptx: &str, prefixes: &[&str], cap: u32) -> String {
    let mut out = String::with_capacity(ptx.len() + 4096);
    let mut rest = ptx;
    while let Some(at) = rest.find(".entry ") {
        let (head, tail) = rest.split_at(at);
        out.push_str(head);
        let name = tail[".entry ".len()..].split('(').next().unwrap_or("");
        let capped = prefixes.iter().any(|p| name.starts_with(p));
        // The parameter list ends at the first line that is a lone ")"; an entry already capped keeps its cap.
        match (capped, tail.find("\n)\n")) {
            (true, Some(end)) if !tail[end + "\n)\n".len()..].starts_with(".maxnreg ") => {
                let end = end + "\n)\n".len();
                out.push_str(&tail[..end]);
                out.push_str(&format!(".maxnreg {cap}\n"));
                rest = &tail[end..];
            }
            _ => {
                out.push_str(&tail[..".entry ".len()]);
                rest = &tail[".entry ".len()..];
            }
        }
    }
    out.push_str(rest);
    out
}

fn first_line(s: &str) -> &str {
    s.lines().next().unwrap_or(s)
}

impl CudaBackend {
    /// The device address of the step's scalars.
    fn scalars(&self, s: &ScalarsAt<'_, Self>) -> Result<u64> {
        if s.index >= s.buf.len {
            return Err(Error::Length { op: "step scalars", expected: s.index + 1, got: s.buf.len });
        }
        Ok(self.ptr(s.buf) + (s.index * size_of::<StepScalars>()) as u64)
    }

    /// The device address of the step's rebuild flag (`StepScalars::rebuild`), the gate of a rebuild's launches.
    fn gate(&self, s: &ScalarsAt<'_, Self>) -> Result<u64> {
        Ok(self.scalars(s)? + std::mem::offset_of!(StepScalars, rebuild) as u64)
    }

    /// The exclusive scan of `Backend::exclusive_scan` with a gate (0: always).
    fn scan_gated(&self, gate: u64, n: usize, data: &mut CudaBuf<u32>, levels: &mut [CudaBuf<u32>]) -> Result<()> {
        let tiles = n.div_ceil(SCAN_TILE);
        if tiles == 0 {
            return Ok(());
        }
        let Some((sums, rest)) = levels.split_first_mut() else {
            return Err(Error::Length { op: "exclusive_scan workspace", expected: 1, got: 0 });
        };
        if sums.len < tiles {
            return Err(Error::Length { op: "exclusive_scan workspace", expected: tiles, got: sums.len });
        }
        let (g, d) = (gate as *const u32, self.output(data));
        let apply = |tile_offsets| ScanApplyArgs { gate: g, n: n as u32, input: d, output: d, tile_offsets };
        if tiles == 1 {
            // One tile: the apply pass alone, with offset 0 (no reduction, no memset).
            return self.launch_pass(&self.k.0[slot::SCAN_APPLY], 32, 128, &apply(std::ptr::null()));
        }
        let s = self.output(sums);
        // One warp per tile, four warps per block.
        let reduce = ScanReduceArgs { gate: g, n: n as u32, input: d, tile_sums: s };
        self.launch_pass(&self.k.0[slot::SCAN_REDUCE], tiles * 32, 128, &reduce)?;
        self.scan_gated(gate, tiles, sums, rest)?;
        self.launch_pass(&self.k.0[slot::SCAN_APPLY], tiles * 32, 128, &apply(s))
    }

    /// The scatter of `Backend::scatter` with a gate (0: always).
    fn scatter_gated(
        &self,
        gate: u64,
        n: usize,
        keys: &CudaBuf<u32>,
        slots: &CudaBuf<u32>,
        starts: &CudaBuf<u32>,
        perm: &mut CudaBuf<u32>,
    ) -> Result<()> {
        let args = ScatterArgs {
            gate: gate as *const u32,
            n: n as u32,
            keys: self.input(keys),
            slots: self.input(slots),
            starts: self.input(starts),
            perm: self.output(perm),
        };
        self.launch_pass_strided(&self.k.0[slot::SCATTER], n, &args)
    }

    /// The per-cell sort of `Backend::sort_cells` with a gate (0: always).
    fn sort_gated(&self, gate: u64, n_buckets: usize, starts: &CudaBuf<u32>, perm: &mut CudaBuf<u32>) -> Result<()> {
        let args = SortArgs {
            gate: gate as *const u32,
            n_buckets: n_buckets as u32,
            starts: self.input(starts),
            perm: self.output(perm),
        };
        self.launch_pass_strided(&self.k.0[slot::SORT_CELLS], n_buckets, &args)
    }
}

impl Backend for CudaBackend {
    type Buf<T: Element> = CudaBuf<T>;
    type Graph = Graph;

    fn info(&self) -> &DeviceInfo {
        &self.info
    }

    fn alloc<T: Element>(&self, n: usize, what: &'static str) -> Result<CudaBuf<T>> {
        let bytes = (n * size_of::<T>()).max(16);
        let raw = self.stream.alloc_zeros::<u8>(bytes).map_err(|e| self.oom(what, bytes, e))?;
        Ok(CudaBuf { raw, len: n, _t: PhantomData })
    }

    fn upload<T: Element>(&self, data: &[T], what: &'static str) -> Result<CudaBuf<T>> {
        let mut b = self.alloc::<T>(data.len(), what)?;
        self.write(&mut b, data)?;
        Ok(b)
    }

    fn write<T: Element>(&self, buf: &mut CudaBuf<T>, data: &[T]) -> Result<()> {
        if data.len() > buf.len {
            return Err(Error::Length { op: "write", expected: data.len(), got: buf.len });
        }
        if data.is_empty() {
            return Ok(());
        }
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let mut view = buf.raw.slice_mut(0..bytes.len());
        self.stream.memcpy_htod(bytes, &mut view).map_err(cuda("copy to device"))?;
        // Pageable host memory: make sure the copy has consumed `data` before returning.
        self.stream.synchronize().map_err(cuda("synchronize"))
    }

    fn read<T: Element>(&self, buf: &CudaBuf<T>) -> Result<Vec<T>> {
        let mut out = vec![T::zeroed(); buf.len];
        if buf.len > 0 {
            let bytes: &mut [u8] = bytemuck::cast_slice_mut(&mut out);
            let n = bytes.len();
            self.stream.memcpy_dtoh(&buf.raw.slice(0..n), bytes).map_err(cuda("copy to host"))?;
        }
        self.stream.synchronize().map_err(cuda("synchronize"))?;
        Ok(out)
    }

    fn read_one<T: Element>(&self, buf: &CudaBuf<T>, i: usize) -> Result<T> {
        if i >= buf.len {
            return Err(Error::Length { op: "read_one", expected: i + 1, got: buf.len });
        }
        let mut out = [T::zeroed()];
        let bytes: &mut [u8] = bytemuck::cast_slice_mut(&mut out);
        let at = i * size_of::<T>();
        self.stream.memcpy_dtoh(&buf.raw.slice(at..at + bytes.len()), bytes).map_err(cuda("copy to host"))?;
        self.stream.synchronize().map_err(cuda("synchronize"))?;
        Ok(out[0])
    }

    fn fill_zero<T: Element>(&self, buf: &mut CudaBuf<T>, n: usize) -> Result<()> {
        if n > buf.len {
            return Err(Error::Length { op: "fill_zero", expected: n, got: buf.len });
        }
        if n > 0 {
            let mut view = buf.raw.slice_mut(0..n * size_of::<T>());
            self.stream.memset_zeros(&mut view).map_err(cuda("memset"))?;
        }
        Ok(())
    }

    fn synchronize(&self) -> Result<()> {
        self.stream.synchronize().map_err(cuda("synchronize"))
    }

    fn time_ms(&self, f: &mut dyn FnMut() -> Result<()>) -> Result<f64> {
        let a = self.ctx.new_event(Some(CUevent_flags::CU_EVENT_DEFAULT)).map_err(cuda("event"))?;
        let b = self.ctx.new_event(Some(CUevent_flags::CU_EVENT_DEFAULT)).map_err(cuda("event"))?;
        a.record(&self.stream).map_err(cuda("event record"))?;
        f()?;
        b.record(&self.stream).map_err(cuda("event record"))?;
        b.synchronize().map_err(cuda("event synchronize"))?;
        Ok(a.elapsed_ms(&b).map_err(cuda("event elapsed"))? as f64)
    }

    fn exclusive_scan(&self, n: usize, data: &mut CudaBuf<u32>, levels: &mut [CudaBuf<u32>]) -> Result<()> {
        self.scan_gated(0, n, data, levels)
    }

    fn gather<T: Element>(&self, n: usize, perm: &CudaBuf<u32>, src: &CudaBuf<T>, dst: &mut CudaBuf<T>) -> Result<()> {
        let s = size_of::<T>();
        let (f, unit) = if s.is_multiple_of(16) {
            (&self.k.0[slot::GATHER_B16], 16)
        } else if s.is_multiple_of(8) {
            (&self.k.0[slot::GATHER_B8], 8)
        } else if s.is_multiple_of(4) {
            (&self.k.0[slot::GATHER_B4], 4)
        } else {
            return Err(Error::Length {
                op: "gather (element size must be a multiple of 4 bytes)",
                expected: 4,
                got: s,
            });
        };
        let k = s / unit;
        // The unit's type is the entry's; the struct's layout does not depend on it.
        let args = GatherArgs::<u8> {
            n: n as u32,
            k: k as u32,
            perm: self.input(perm),
            src: self.ptr(src) as *const u8,
            dst: self.ptr_mut(dst) as *mut u8,
        };
        self.launch_pass(f, n * k, BLOCK, &args)
    }

    fn address<T: Element>(&self, buf: &CudaBuf<T>) -> u64 {
        self.ptr(buf)
    }

    fn address_mut<T: Element>(&self, buf: &mut CudaBuf<T>) -> u64 {
        self.ptr_mut(buf)
    }

    unsafe fn gather_fields(
        &self,
        n: usize,
        perm: Option<&CudaBuf<u32>>,
        fields: &[GatherField],
        gate: Option<ScalarsAt<'_, Self>>,
    ) -> Result<()> {
        if let Some(p) = perm
            && p.len < n
        {
            return Err(Error::Length { op: "gather_fields perm", expected: n, got: p.len });
        }
        let gate = match gate {
            Some(g) => self.gate(&g)?,
            None => 0,
        };
        if let Some(f) = fields.iter().find(|f| f.bytes == 0 || !f.bytes.is_multiple_of(4)) {
            return Err(Error::Length { op: "gather_fields (element size)", expected: 4, got: f.bytes as usize });
        }
        let mut tables = self.gather_tables.lock().map_err(|_| Error::Length {
            op: "gather_fields (table cache poisoned)",
            expected: 0,
            got: 0,
        })?;
        let table = match tables.get(fields) {
            Some(t) => self.ptr(t),
            None => {
                if self.capturing.load(Ordering::Relaxed) {
                    return Err(Error::Length {
                        op: "gather_fields (new table while capturing a graph)",
                        expected: 0,
                        got: 1,
                    });
                }
                let t = self.upload(fields, "reorder table")?;
                let p = self.ptr(&t);
                tables.insert(fields.to_vec(), t);
                p
            }
        };
        let rows = fields.len();
        let args = GatherFieldsArgs {
            gate: gate as *const u32,
            n: n as u32,
            rows: rows as u32,
            perm: perm.map_or(std::ptr::null(), |p| self.input(p)),
            table: table as *const GatherField,
        };
        self.launch_pass_strided(&self.k.0[slot::GATHER_FIELDS], n * rows, &args)
    }

    fn capture(&self, f: &mut dyn FnMut() -> Result<()>) -> Result<Option<Graph>> {
        use cudarc::driver::sys::{CUgraphInstantiate_flags, CUstreamCaptureMode};
        self.stream
            .begin_capture(CUstreamCaptureMode::CU_STREAM_CAPTURE_MODE_THREAD_LOCAL)
            .map_err(cuda("cuStreamBeginCapture"))?;
        self.capturing.store(true, Ordering::Relaxed);
        let recorded = f();
        self.capturing.store(false, Ordering::Relaxed);
        // End the capture whatever happened, so that the stream is usable again.
        let graph = self.stream.end_capture(CUgraphInstantiate_flags(0)).map_err(cuda("cuStreamEndCapture"));
        recorded?;
        Ok(graph?.map(Graph))
    }

    fn replay(&self, g: &Graph) -> Result<()> {
        g.0.launch().map_err(cuda("cuGraphLaunch"))
    }

    fn rebuild_condition(&self) -> Result<u64> {
        match &self.conditional {
            Ok(_)
                if self.capturing.load(Ordering::Relaxed)
                    && self.use_conditional.load(Ordering::Relaxed)
                    && !self.in_body.load(Ordering::Relaxed) =>
            {
                // SAFETY: the stream is capturing (`capturing`), in this backend's context.
                unsafe { Conditional::handle(&self.ctx, self.stream.cu_stream()) }
            }
            _ => Ok(0),
        }
    }

    fn rebuild_gated(&self, condition: u64, body: &mut dyn FnMut() -> Result<()>) -> Result<()> {
        let c = match &self.conditional {
            Ok(c) if condition != 0 => c,
            _ => return body(),
        };
        // SAFETY: a nonzero handle came from `rebuild_condition` while this stream captures; the step's predictor,
        // captured before, sets it.
        unsafe {
            c.capture_if(
                &self.ctx,
                self.stream.cu_stream(),
                condition,
                &|on| self.in_body.store(on, Ordering::Relaxed),
                body,
            )
        }
    }

    fn host_slice<'a, T: Element>(&self, _buf: &'a CudaBuf<T>) -> Option<&'a [T]> {
        None
    }

    unsafe fn launch<P: Pass>(&self, args: &P::Args) -> Result<()> {
        let mut a = *args;
        let (block, reverse) = match P::GRID {
            Grid::Particles | Grid::Strided => (BLOCK, 0),
            Grid::Pair => (self.pair_block, self.pair_reverse),
            Grid::Plastic => (self.plastic_block, self.plastic_reverse),
        };
        if let Some(r) = P::order(&mut a) {
            *r = reverse;
        }
        let n = P::particles(&a);
        let threads = match P::GRID {
            Grid::Pair => n * P::lanes(&a) as usize,
            Grid::Strided => n.min(GATED_BLOCKS * BLOCK as usize),
            Grid::Particles | Grid::Plastic => n,
        };
        self.launch_pass(&self.k.0[P::ENTRY], threads, block, &a)
    }

    fn bin_cells<R: Real, D: Dim>(
        &self,
        n: usize,
        gate: Option<ScalarsAt<'_, Self>>,
        pos: &CudaBuf<D::Vec<R>>,
        vel: Option<&CudaBuf<D::Vec<R>>>,
        c: CellBuffers<'_, Self>,
    ) -> Result<()> {
        let lens = [pos.len, c.keys.len, c.slots.len, c.perm.len, vel.map_or(n, |v| v.len)];
        if lens.iter().any(|&l| l < n)
            || c.starts.len < c.n_buckets + 1
            || c.rebuilds.as_ref().is_some_and(|r| r.len < 1)
        {
            return Err(Error::Length { op: "bin_cells", expected: n, got: lens.into_iter().min().unwrap_or(0) });
        }
        let g = match &gate {
            Some(s) => self.gate(s)?,
            None => 0,
        };
        let (buckets, sorted) = (c.n_buckets + 1, c.sorted_buckets());
        let zero = ZeroArgs {
            gate: g as *const u32,
            n: buckets as u32,
            data: self.output(c.starts),
            rebuilds: c.rebuilds.map_or(std::ptr::null_mut(), |r| self.output(r)),
        };
        self.launch_pass_strided(&self.k.0[slot::ZERO_GATED], buckets, &zero)?;
        let args = HashCountArgs::<R, D> {
            gate: g as *const u32,
            n: n as u32,
            pos: self.input(pos),
            vel: super::args::blank_vel(self, c.blank.as_ref(), vel)?,
            grid: self.input(c.grid),
            blank: super::args::blank_ptr(self, c.blank.as_ref())?,
            keys: self.output(c.keys),
            counts: self.output(c.starts),
            slots: self.output(c.slots),
        };
        self.launch_pass_strided(&self.k.0[hash_count::<R, D>()], n, &args)?;
        self.scan_gated(g, buckets, c.starts, c.scan)?;
        self.scatter_gated(g, n, c.keys, c.slots, c.starts, c.perm)?;
        self.sort_gated(g, sorted, c.starts, c.perm)
    }
}
