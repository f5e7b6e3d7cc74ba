//! The cell-list rebuild of a captured step inside a conditional graph node (docs/architecture.md, "The rebuild
//! in a conditional node").
//!
//! A rebuild's launches (zero, hash and count, the scan's levels, scatter, per-cell sort, the reorder's gather and
//! copy-back, the Verlet list) are gated on the step's rebuild flag, which the predictor of the same step sets on
//! the device. Captured as plain kernel nodes, a step that does not rebuild (85 of 86 inside the 150k reference
//! cut) still pays for each of them: a launch whose blocks read the flag and return. Captured in the body of an
//! IF node whose handle one single-thread kernel sets from the flag, they cost nothing when the flag is 0.
//!
//! That kernel calls the device runtime's `cudaGraphSetConditional`, which the driver resolves when it compiles the
//! PTX. It is hand-written PTX in a module of its own (not an entry of `swarf-kernels`): a driver that cannot
//! resolve the call fails to load this module only, and the steps are captured with the plain gated nodes as
//! before, the same launches and the same bits.

use cudarc::driver::sys::{
    self, CUDA_CONDITIONAL_NODE_PARAMS, CUgraph, CUgraphConditionalNodeType, CUgraphNode, CUgraphNodeParams,
    CUgraphNodeType, CUstream, CUstreamCaptureMode, CUstreamCaptureStatus, CUstreamUpdateCaptureDependencies_flags,
};
use cudarc::driver::{CudaContext, CudaFunction, CudaModule, CudaStream, DriverError};
use std::sync::Arc;

use crate::{Error, Result};

/// The kernel `swarf_rebuild_condition(handle, gate)`: one thread sets the IF node's handle to 1 when the u32 at
/// `gate` (a step's `StepScalars::rebuild`) is nonzero, else to 0.
const PTX: &str = r#"
.version 7.0
.target sm_60
.address_size 64

.extern .func cudaGraphSetConditional
(
    .param .b64 cudaGraphSetConditional_handle,
    .param .b32 cudaGraphSetConditional_value
)
;

.visible .entry swarf_rebuild_condition(
    .param .u64 swarf_rebuild_condition_handle,
    .param .u64 swarf_rebuild_condition_gate
)
{
    .reg .pred %p<2>;
    .reg .b32 %r<3>;
    .reg .b64 %rd<4>;

    ld.param.u64 %rd1, [swarf_rebuild_condition_handle];
    ld.param.u64 %rd2, [swarf_rebuild_condition_gate];
    cvta.to.global.u64 %rd3, %rd2;
    ld.volatile.global.u32 %r1, [%rd3];
    setp.ne.u32 %p1, %r1, 0;
    selp.u32 %r2, 1, 0, %p1;
    {
    .param .b64 param0;
    st.param.b64 [param0+0], %rd1;
    .param .b32 param1;
    st.param.b32 [param1+0], %r2;
    call.uni cudaGraphSetConditional, (param0, param1);
    }
    ret;
}
"#;

/// The oldest driver with conditional nodes filled by stream capture (`cuStreamBeginCaptureToGraph`): CUDA 12.4.
const MIN_DRIVER: i32 = 12040;

/// The loaded condition kernel and the stream that captures the IF nodes' bodies.
pub(super) struct Conditional {
    _module: Arc<CudaModule>,
    set: CudaFunction,
    body: Arc<CudaStream>,
}

/// A driver call's status as the crate's error, naming the call.
fn check(op: &'static str, r: sys::CUresult) -> Result<()> {
    r.result().map_err(|source| Error::Cuda { op, source })
}

impl Conditional {
    /// Loads the condition kernel and creates the body stream; says why not where the driver is older than
    /// [`MIN_DRIVER`] or cannot compile the kernel (the steps then keep their plain gated nodes).
    pub(super) fn load(ctx: &Arc<CudaContext>, driver: i32) -> std::result::Result<Self, String> {
        if driver < MIN_DRIVER {
            return Err(format!("driver {driver} is older than {MIN_DRIVER} (conditional nodes by capture)"));
        }
        let module = ctx
            .load_module(cudarc::nvrtc::Ptx::from_src(PTX))
            .map_err(|e| format!("the condition kernel did not load: {e}"))?;
        let set = module.load_function("swarf_rebuild_condition").map_err(|e| format!("{e}"))?;
        let body = ctx.new_stream().map_err(|e| format!("stream: {e}"))?;
        Ok(Conditional { _module: module, set, body })
    }

    /// The kernel that sets a handle from a gate (launched with one thread by the caller).
    pub(super) fn set_kernel(&self) -> &CudaFunction {
        &self.set
    }

    /// The stream that captures the IF node's body.
    pub(super) fn body_stream(&self) -> CUstream {
        self.body.cu_stream()
    }

    /// A new IF handle of the graph that `stream` is capturing, default 0.
    ///
    /// # Safety
    /// `stream` is capturing (`cuStreamBeginCapture`) in `ctx`.
    pub(super) unsafe fn handle(ctx: &CudaContext, stream: CUstream) -> Result<sys::CUgraphConditionalHandle> {
        let (graph, _) = unsafe { capture_state(stream)? };
        let mut h = 0;
        check("cuGraphConditionalHandleCreate", unsafe {
            sys::cuGraphConditionalHandleCreate(&mut h, graph, ctx.cu_ctx(), 0, 0)
        })?;
        Ok(h)
    }

    /// Appends an IF node on `handle` after the work captured so far on `stream`, captures what `body` submits to
    /// the body stream into it, and makes the node the dependency of what `stream` captures next. `in_body`
    /// switches the backend's launches to the body stream while `body` runs.
    ///
    /// # Safety
    /// `stream` is capturing in `ctx`; `handle` belongs to its graph and was set by a node already captured.
    pub(super) unsafe fn capture_if(
        &self,
        ctx: &CudaContext,
        stream: CUstream,
        handle: sys::CUgraphConditionalHandle,
        in_body: &dyn Fn(bool),
        body: &mut dyn FnMut() -> Result<()>,
    ) -> Result<()> {
        let (graph, deps) = unsafe { capture_state(stream)? };
        // SAFETY: a zeroed parameter union is the documented starting point; the conditional arm is filled.
        let mut p: CUgraphNodeParams = unsafe { std::mem::zeroed() };
        p.type_ = CUgraphNodeType::CU_GRAPH_NODE_TYPE_CONDITIONAL;
        p.__bindgen_anon_1.conditional = CUDA_CONDITIONAL_NODE_PARAMS {
            handle,
            type_: CUgraphConditionalNodeType::CU_GRAPH_COND_TYPE_IF,
            size: 1,
            phGraph_out: std::ptr::null_mut(),
            ctx: ctx.cu_ctx(),
        };
        let mut node: CUgraphNode = std::ptr::null_mut();
        check("cuGraphAddNode (IF)", unsafe {
            sys::cuGraphAddNode(&mut node, graph, deps.as_ptr(), deps.len(), &mut p)
        })?;
        // SAFETY: the driver filled phGraph_out with `size` (1) body graphs.
        let body_graph: CUgraph = unsafe { *p.__bindgen_anon_1.conditional.phGraph_out };
        let bs = self.body.cu_stream();
        check("cuStreamBeginCaptureToGraph", unsafe {
            sys::cuStreamBeginCaptureToGraph(
                bs,
                body_graph,
                std::ptr::null(),
                std::ptr::null(),
                0,
                CUstreamCaptureMode::CU_STREAM_CAPTURE_MODE_THREAD_LOCAL,
            )
        })?;
        in_body(true);
        let recorded = body();
        in_body(false);
        // End the body's capture whatever happened, so that the stream is usable again.
        let mut out: CUgraph = std::ptr::null_mut();
        let ended = check("cuStreamEndCapture (IF body)", unsafe { sys::cuStreamEndCapture(bs, &mut out) });
        recorded?;
        ended?;
        check("cuStreamUpdateCaptureDependencies", unsafe {
            sys::cuStreamUpdateCaptureDependencies(
                stream,
                &mut node,
                1,
                CUstreamUpdateCaptureDependencies_flags::CU_STREAM_SET_CAPTURE_DEPENDENCIES as u32,
            )
        })
    }
}

/// The graph `stream` is capturing into and the nodes its next capture depends on (copied: the driver's array
/// lives only until the next call on the stream).
///
/// # Safety
/// `stream` is a valid stream of the current context.
unsafe fn capture_state(stream: CUstream) -> Result<(CUgraph, Vec<CUgraphNode>)> {
    let mut status = CUstreamCaptureStatus::CU_STREAM_CAPTURE_STATUS_NONE;
    let mut graph: CUgraph = std::ptr::null_mut();
    let mut deps: *const CUgraphNode = std::ptr::null();
    let mut n = 0usize;
    check("cuStreamGetCaptureInfo", unsafe {
        sys::cuStreamGetCaptureInfo_v2(stream, &mut status, std::ptr::null_mut(), &mut graph, &mut deps, &mut n)
    })?;
    if status != CUstreamCaptureStatus::CU_STREAM_CAPTURE_STATUS_ACTIVE || graph.is_null() {
        let source = DriverError(sys::CUresult::CUDA_ERROR_ILLEGAL_STATE);
        return Err(Error::Cuda { op: "cuStreamGetCaptureInfo (the stream is not capturing)", source });
    }
    let deps =
        if n == 0 || deps.is_null() { Vec::new() } else { unsafe { std::slice::from_raw_parts(deps, n) }.to_vec() };
    Ok((graph, deps))
}
