//! The cell-list rebuild of a captured step inside a conditional graph node (docs/architecture.md, "The rebuild
//! in a conditional node").
//!
//! A rebuild's launches (zero, hash and count, the scan's levels, scatter, per-cell sort, the reorder's gather and
//! copy-back, the Verlet list, the pre-pass again) are gated on the step's rebuild flag, which the predictor of the
//! same step sets on the device. Captured as plain kernel nodes, a step that does not rebuild (88 of 89 inside the
//! 150k reference cut) still pays for each of them: a launch whose blocks read the flag and return. Captured in
//! the body of an IF node, they cost nothing when the step does not rebuild. The node's handle is created with
//! default 0, reset at each launch of the graph, and the step's predictor sets it to 1 where it sets the flag
//! (`ptx::sph`, predict_entry: the device runtime's `cudaGraphSetConditional`, which the driver resolves when it
//! compiles the PTX; `strip_graph_conditional` removes the call where it cannot, and the steps then keep the plain
//! gated nodes: the same launches and the same bits).

use cudarc::driver::sys::{
    self, CUDA_CONDITIONAL_NODE_PARAMS, CUgraph, CUgraphConditionalNodeType, CUgraphNode, CUgraphNodeParams,
    CUgraphNodeType, CUstream, CUstreamCaptureMode, CUstreamCaptureStatus, CUstreamUpdateCaptureDependencies_flags,
};
use cudarc::driver::{CudaContext, CudaStream, DriverError};
use std::sync::Arc;

use crate::{Error, Result};

/// The oldest driver with conditional nodes filled by stream capture (`cuStreamBeginCaptureToGraph`): CUDA 12.4.
pub(super) const MIN_DRIVER: i32 = 12040;

/// `CU_GRAPH_COND_ASSIGN_DEFAULT`: the handle takes its default value at every launch of the graph.
const ASSIGN_DEFAULT: u32 = 1;

/// The device runtime function whose calls the predictor makes.
const SET_CONDITIONAL: &str = "cudaGraphSetConditional";

/// The stream that captures the IF nodes' bodies.
pub(super) struct Conditional {
    body: Arc<CudaStream>,
}

/// A driver call's status as the crate's error, naming the call.
fn check(op: &'static str, r: sys::CUresult) -> Result<()> {
    r.result().map_err(|source| Error::Cuda { op, source })
}

impl Conditional {
    /// The body stream; says why not where the driver is older than [`MIN_DRIVER`].
    pub(super) fn new(ctx: &Arc<CudaContext>, driver: i32) -> std::result::Result<Self, String> {
        if driver < MIN_DRIVER {
            return Err(format!("driver {driver} is older than {MIN_DRIVER} (conditional nodes by capture)"));
        }
        let body = ctx.new_stream().map_err(|e| format!("stream: {e}"))?;
        Ok(Conditional { body })
    }

    /// The stream that captures the IF node's body.
    pub(super) fn body_stream(&self) -> CUstream {
        self.body.cu_stream()
    }

    /// A new IF handle of the graph that `stream` is capturing, 0 at every launch of the graph.
    ///
    /// # Safety
    /// `stream` is capturing (`cuStreamBeginCapture`) in `ctx`.
    pub(super) unsafe fn handle(ctx: &CudaContext, stream: CUstream) -> Result<sys::CUgraphConditionalHandle> {
        let (graph, _) = unsafe { capture_state(stream)? };
        let mut h = 0;
        check("cuGraphConditionalHandleCreate", unsafe {
            sys::cuGraphConditionalHandleCreate(&mut h, graph, ctx.cu_ctx(), 0, ASSIGN_DEFAULT)
        })?;
        Ok(h)
    }

    /// Appends an IF node on `handle` after the work captured so far on `stream`, captures what `body` submits to
    /// the body stream into it, and makes the node the dependency of what `stream` captures next. `in_body`
    /// switches the backend's launches to the body stream while `body` runs.
    ///
    /// # Safety
    /// `stream` is capturing in `ctx`; `handle` belongs to its graph and is set by a node already captured.
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

/// The PTX without the device runtime's `cudaGraphSetConditional`: its `.extern` declaration and every call
/// block (`{ // callseq … }`) that calls it removed, for a driver that cannot resolve it. The calls only set IF
/// nodes' handles, which such a driver's graphs do not have; nothing else in the kernels changes.
pub fn strip_graph_conditional(ptx: &str) -> String {
    let mut out = String::with_capacity(ptx.len());
    let mut lines = ptx.lines().peekable();
    while let Some(line) = lines.next() {
        let t = line.trim_start();
        if t.starts_with(".extern .func") && t.contains(SET_CONDITIONAL) {
            // The declaration runs to its closing ';'.
            let mut l = line;
            while !l.trim_end().ends_with(';') {
                match lines.next() {
                    Some(next) => l = next,
                    None => break,
                }
            }
            continue;
        }
        if t.starts_with("{ // callseq") {
            let mut block = vec![line];
            for next in lines.by_ref() {
                block.push(next);
                if next.trim_start().starts_with("} // callseq") {
                    break;
                }
            }
            if !block.iter().any(|l| l.contains(SET_CONDITIONAL)) {
                for l in block {
                    out.push_str(l);
                    out.push('\n');
                }
            }
            continue;
        }
        out.push_str(line);
        out.push('\n');
    }
    out
}
