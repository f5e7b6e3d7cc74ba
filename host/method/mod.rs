//! The seam between a particle method and what drives it: `swarf run`, `swarf check`, the benchmarks, the
//! checkpoints and the studies use a method only through [`Method`], and choose it in one place
//! ([`with_method`]). A second method (MPM) implements [`Method`] and adds its line to [`dispatch`]; nothing in
//! run, check, bench or study changes.
//!
//! Layering: a method sits above the state, the backends and its solver, and below cutting, the analyses, run,
//! study, bench and the CLI.

pub mod sph;

use crate::Result;
use crate::backend::{AnyBackend, Backend};
use crate::kernels::sph::{SphParams, TensorOps};
use crate::kernels::{Dim2, Dim3, Real};
use crate::scene::{Precision, Scene};
use crate::solver::diagnostics::Diagnostics;
use crate::state::HostParticles;
use crate::tuning::Tuning;

/// Named copies of every stateful buffer of a method, for a checkpoint.
pub type StateBlobs = crate::solver::StateBlobs;

/// What a driver needs to know of a method's set-up before it allocates anything: plain data, the same for every
/// method.
#[derive(Clone, Debug)]
pub struct Plan {
    pub particles: usize,
    /// The initial (CFL and conduction) time step [s].
    pub dt: f64,
    /// Smoothing length h [m] (the closest-pair search radius is 2h).
    pub h: f64,
    /// Reference sound speed c0 [m/s] (the run's CFL re-check).
    pub c0: f64,
    /// The precision label of reports: "f32", "f64" or "mixed".
    pub precision: &'static str,
    /// Device memory the method allocates [bytes].
    pub memory_bytes: usize,
    /// Whether the run models temperatures (temperature.csv).
    pub temperature: bool,
    /// Input that runs but whose result is not meaningful.
    pub warnings: Vec<String>,
    /// Every particle's initial position by id, widened to f64 (z = 0 in 2D).
    pub initial: Vec<[f64; 3]>,
    /// The initial positions of the workpiece (not the tool's thermal-only particles), f64.
    pub workpiece: Vec<[f64; 3]>,
}

/// The state an output step writes, on the host: the frame's particle fields, the internal variables, the
/// diagnostics (energies, momenta, dissipated work; without the closest-pair distances, which the writer adds)
/// and the positions whole, in f64 (the mixed precision's hi + lo).
pub struct Output<R: Real, D: TensorOps<R>> {
    pub diagnostics: Diagnostics,
    pub host: HostParticles<R, D>,
    /// Temperature, plastic strain and its rate, where modelled.
    pub internal: [Option<Vec<f64>>; 3],
    /// The frame's per-particle f64 fields (the SPH field registry's frame entries: name, components, values).
    pub fields: Vec<crate::solver::fields::FrameField>,
    pub positions: Vec<[f64; 3]>,
    /// Each tool in the world at this instant (an outline or a surface), in the scene's order.
    pub tools: Vec<crate::tool::Picture>,
    /// The equation-of-state parameters the frame's pressure is computed with.
    pub params: SphParams<R>,
}

/// The tool's state at one instant (declared with the cutting record that takes it).
pub use crate::tool::{ToolLoad, ToolSample};

/// A particle method as the drivers use it: built from a scene, advanced by steps of Δt, read back at output
/// steps, saved to and restored from checkpoints.
pub trait Method<B: Backend>: Sized {
    type R: Real;
    type D: TensorOps<Self::R>;
    /// The method's own set-up of a scene (particles, parameters, grid, Δt), built before anything is allocated.
    type Setup;

    /// Builds the set-up of `scene` with the tuning switches `tuning`.
    fn setup(scene: &Scene, tuning: &Tuning) -> Result<Self::Setup>;
    /// The plain facts of a set-up.
    fn plan(setup: &Self::Setup) -> Plan;
    /// Allocates and uploads the state.
    fn new(b: &B, setup: &Self::Setup) -> Result<Self>;

    /// Simulated time [s] and steps taken.
    fn time(&self) -> f64;
    fn steps(&self) -> u64;
    /// Sets the clock (a resumed run).
    fn set_clock(&mut self, time: f64, steps: u64);
    /// Particles in the state.
    fn particles(&self) -> usize;
    /// The precision label ("f32", "f64", "mixed") and the dimension.
    fn precision(&self) -> &'static str;
    fn dim(&self) -> usize {
        <Self::D as crate::kernels::Dim>::D
    }

    /// Sets the run's nominal time step (after a CFL reduction).
    fn set_nominal_dt(&mut self, dt: f64);
    /// One step of `dt`.
    fn step(&mut self, b: &B, dt: f64) -> Result<()>;
    /// `count` steps of `dt`.
    fn advance(&mut self, b: &B, dt: f64, count: usize) -> Result<()>;
    /// Whether a step since the last check saw a non-finite value (a small read).
    fn non_finite_seen(&self, b: &B) -> Result<bool>;
    /// How many times the neighbour structure was rebuilt.
    fn rebuilds(&self, b: &B) -> Result<u32>;

    /// The state an output step writes.
    fn output(&self, b: &B) -> Result<Output<Self::R, Self::D>>;
    /// The tool's force and position now; None without a tool.
    fn tool_sample(&self, b: &B) -> Result<Option<ToolSample>>;
    /// Every stateful buffer, and its restoration (checkpoints).
    fn save_state(&self, b: &B) -> Result<StateBlobs>;
    fn load_state(&mut self, b: &B, state: &StateBlobs) -> Result<()>;
}

/// Work generic in the backend and the method: [`with_method`] calls it with the method a scene asks for.
pub trait MethodFn {
    type Out;
    fn call<B: Backend, M: Method<B>>(self, b: &B, scene: &Scene) -> Result<Self::Out>;
}

/// Runs `f` with the backend of `any` and the method, dimension and precision of `scene`: the one place methods
/// are chosen.
pub fn with_method<F: MethodFn>(any: &AnyBackend, scene: &Scene, f: F) -> Result<F::Out> {
    crate::with_backend!(any, b => dispatch(b, scene, f))
}

/// The method of `scene` on backend `b` (SPH, the only one today; the mixed precision is f32 with compensated
/// positions).
pub fn dispatch<B: Backend, F: MethodFn>(b: &B, scene: &Scene, f: F) -> Result<F::Out> {
    use crate::solver::Solver;
    match (scene.dim, scene.precision) {
        (2, Precision::F32 | Precision::Mixed) => f.call::<B, Solver<B, f32, Dim2>>(b, scene),
        (2, Precision::F64) => f.call::<B, Solver<B, f64, Dim2>>(b, scene),
        (_, Precision::F32 | Precision::Mixed) => f.call::<B, Solver<B, f32, Dim3>>(b, scene),
        (_, Precision::F64) => f.call::<B, Solver<B, f64, Dim3>>(b, scene),
    }
}
