//! Backends: where kernels run. [`Backend`] is memory, graphs and one generic launch of a pass
//! (`kernels::pass::Pass`), plus the two algorithms whose GPU form is block-cooperative (the cell list's counting
//! sort and the prefix sum). The passes are written once against it, in [`passes`]: the CPU backend runs a pass's
//! per-particle twin in a rayon loop, the CUDA backend launches the same function compiled to PTX.

pub mod args;
pub mod cpu;
pub mod cuda;
pub mod passes;
pub mod tool;

use crate::Result;
use crate::kernels::damage::DamageParams;
use crate::kernels::neighbour::{GatherField, GridParams};
use crate::kernels::pass::Pass;
use crate::kernels::sph::heat::{HeatParams, ThermalMaterial};
use crate::kernels::sph::step::StepScalars;
use crate::kernels::sph::{SphParams, Stabilisers};
use crate::kernels::{Dim, Real};
use bytemuck::Pod;

pub use cpu::CpuBackend;
pub use cuda::CudaBackend;
pub use passes::Passes;
pub use tool::{DeviceMesh, DeviceShapes, DeviceTools};

/// A typed array in the backend's memory.
pub trait Buffer<T>: Send + Sync {
    fn len(&self) -> usize;
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Plain data that may live in a backend buffer.
pub trait Element: Pod + Send + Sync {}
impl<T: Pod + Send + Sync> Element for T {}

/// What a backend runs on, for `swarf info` and every report.
#[derive(Clone, Debug, Default)]
pub struct DeviceInfo {
    /// "cpu" or "gpu".
    pub backend: &'static str,
    pub name: String,
    /// Compute capability (GPU only).
    pub compute_capability: Option<(i32, i32)>,
    pub memory_bytes: usize,
    /// CUDA driver API version, e.g. 13000 (GPU only).
    pub driver_version: Option<i32>,
    /// Multiprocessors (GPU) or worker threads (CPU).
    pub units: usize,
    /// The PTX target loaded (GPU only).
    pub ptx_target: Option<&'static str>,
}

pub trait Backend: Sized + Send + Sync {
    type Buf<T: Element>: Buffer<T> + 'static;
    /// A captured sequence of launches (CUDA graph); `()` where the backend has none.
    type Graph;

    fn info(&self) -> &DeviceInfo;

    /// A zero-filled buffer of `n` elements.
    fn alloc<T: Element>(&self, n: usize, what: &'static str) -> Result<Self::Buf<T>>;
    /// A buffer holding a copy of `data`.
    fn upload<T: Element>(&self, data: &[T], what: &'static str) -> Result<Self::Buf<T>>;
    /// Overwrites the first `data.len()` elements of `buf`.
    fn write<T: Element>(&self, buf: &mut Self::Buf<T>, data: &[T]) -> Result<()>;
    /// A host copy of the whole buffer (waits for pending work).
    fn read<T: Element>(&self, buf: &Self::Buf<T>) -> Result<Vec<T>>;
    /// A host copy of element `i` (waits for pending work).
    fn read_one<T: Element>(&self, buf: &Self::Buf<T>, i: usize) -> Result<T>;
    /// Zeroes the first `n` elements.
    fn fill_zero<T: Element>(&self, buf: &mut Self::Buf<T>, n: usize) -> Result<()>;
    /// Waits until all submitted work is done.
    fn synchronize(&self) -> Result<()>;
    /// Wall time of `f` in milliseconds as the device sees it (CUDA events on the GPU).
    fn time_ms(&self, f: &mut dyn FnMut() -> Result<()>) -> Result<f64>;

    /// The backend's buffer as a host slice, where its memory is the host's (None on the GPU): the passes check
    /// buffer contents (cell starts, body indices) where they can.
    fn host_slice<'a, T: Element>(&self, buf: &'a Self::Buf<T>) -> Option<&'a [T]>;
    /// The address of a buffer's first element, for the passes' argument structs and [`Backend::gather_fields`].
    fn address<T: Element>(&self, buf: &Self::Buf<T>) -> u64;
    /// The same for a buffer that will be written.
    fn address_mut<T: Element>(&self, buf: &mut Self::Buf<T>) -> u64;
    /// dst[i] = src[perm[i]] for i < n.
    fn gather<T: Element>(
        &self,
        n: usize,
        perm: &Self::Buf<u32>,
        src: &Self::Buf<T>,
        dst: &mut Self::Buf<T>,
    ) -> Result<()>;
    /// dst_f[i] = src_f[perm[i]] for every field f, i < n, in one pass (src_f[i] without a permutation); with a
    /// gate, only when that step rebuilds.
    ///
    /// # Safety
    /// Each field names two distinct live buffers of this backend (addresses from [`Backend::address`] and
    /// [`Backend::address_mut`]) of at least n elements of `bytes` bytes (a multiple of 4), and no destination
    /// appears twice or as a source.
    unsafe fn gather_fields(
        &self,
        n: usize,
        perm: Option<&Self::Buf<u32>>,
        fields: &[GatherField],
        gate: Option<ScalarsAt<'_, Self>>,
    ) -> Result<()>;

    /// Runs pass `P` (`kernels::pass::Pass`) with its argument struct: the GPU launches the pass's entry of the
    /// table with the struct by value, the CPU runs its per-particle twin over the particles in parallel. The
    /// passes themselves, which build the structs, are [`Passes`]'s.
    ///
    /// # Safety
    /// The struct's pointers name live buffers of this backend holding what the pass reads and writes (the
    /// builders of [`args`] check the lengths).
    unsafe fn launch<P: Pass>(&self, args: &P::Args) -> Result<()>;

    /// The cell list's counting sort (`neighbour::CellList`): the counts zeroed, each particle hashed to its cell
    /// (`GridParams::key`) and counted, the exclusive prefix sum of the counts (the cell starts), the scatter into
    /// the permutation and the per-cell sort that makes it the stable one. With a gate (inside the step loop) it
    /// does nothing when the step's rebuild flag is 0 (every launch is still submitted, so a captured step holds
    /// them) and counts the rebuild in `cells.rebuilds`. `vel`: the velocities, which blanking's rest speed reads
    /// (required with `cells.blank`).
    fn bin_cells<R: Real, D: Dim>(
        &self,
        n: usize,
        gate: Option<ScalarsAt<'_, Self>>,
        pos: &Self::Buf<D::Vec<R>>,
        vel: Option<&Self::Buf<D::Vec<R>>>,
        cells: CellBuffers<'_, Self>,
    ) -> Result<()>;
    /// In-place exclusive prefix sum of data[..n]; `levels` is the workspace from [`scan_levels`].
    fn exclusive_scan(&self, n: usize, data: &mut Self::Buf<u32>, levels: &mut [Self::Buf<u32>]) -> Result<()>;

    /// Records the work that `f` submits as a replayable graph without running it; None where the backend has no
    /// graphs, and then the work has run.
    fn capture(&self, f: &mut dyn FnMut() -> Result<()>) -> Result<Option<Self::Graph>>;
    /// Runs a captured graph.
    fn replay(&self, g: &Self::Graph) -> Result<()>;
    /// The handle of a conditional node for the rebuild of the step being captured, which that step's predictor
    /// sets where it sets the rebuild flag ([`SkinTest::condition`]); 0 where the backend has none (not
    /// capturing, no conditional nodes).
    fn rebuild_condition(&self) -> Result<u64> {
        Ok(0)
    }
    /// Submits `body`: the launches of a step's cell-list rebuild, each gated on the step's rebuild flag. With a
    /// nonzero `condition` ([`Backend::rebuild_condition`]) they go in a conditional node that skips them all
    /// when the step does not rebuild (the CUDA backend's IF node); otherwise they run as submitted.
    fn rebuild_gated(&self, condition: u64, body: &mut dyn FnMut() -> Result<()>) -> Result<()> {
        let _ = condition;
        body()
    }
}

/// The integrated fields x, v, ρ, S of the SPH solver (their values, start-of-step copies or rates), borrowed
/// mutably.
pub struct FieldsMut<'a, B: Backend, R: Real, D: Dim> {
    pub pos: &'a mut B::Buf<D::Vec<R>>,
    pub vel: &'a mut B::Buf<D::Vec<R>>,
    pub rho: &'a mut B::Buf<R>,
    pub stress: &'a mut B::Buf<D::Sym<R>>,
}

/// The same, borrowed read-only.
pub struct FieldsRef<'a, B: Backend, R: Real, D: Dim> {
    pub pos: &'a B::Buf<D::Vec<R>>,
    pub vel: &'a B::Buf<D::Vec<R>>,
    pub rho: &'a B::Buf<R>,
    pub stress: &'a B::Buf<D::Sym<R>>,
}

/// Read-only inputs of the SPH pair interaction, all in sorted order.
pub struct SphInputs<'a, B: Backend, R: Real, D: Dim> {
    pub pos: &'a B::Buf<D::Vec<R>>,
    pub vel: &'a B::Buf<D::Vec<R>>,
    pub rho: &'a B::Buf<R>,
    /// Mechanical masses (zero for the tool's thermal-only particles).
    pub mass: &'a B::Buf<R>,
    /// V = m/ρ from the pre-pass (full masses).
    pub vol: &'a B::Buf<R>,
    pub stress: &'a B::Buf<D::Sym<R>>,
    /// σ/ρ² from the pre-pass.
    pub sig: &'a B::Buf<D::Sym<R>>,
    /// Artificial stress (present iff the artificial stress is on).
    pub art: Option<&'a B::Buf<D::Sym<R>>>,
    /// Sound speeds (present iff the viscosity is on).
    pub sound: Option<&'a B::Buf<R>>,
    pub flags: &'a B::Buf<u32>,
    /// Prescribed velocities, indexed by the flags' velocity index.
    pub bc_vel: &'a B::Buf<D::Vec<R>>,
    /// The tool's normal and friction forces from the last contact pass (present iff the scene has a tool).
    pub contact: Option<ContactForces<'a, B, R, D>>,
    /// The damage's interaction mask of the pre-pass (present iff the run models damage).
    pub mask: Option<&'a B::Buf<f64>>,
    /// The kernel-gradient correction B⁻¹ of [`passes::Passes::sph_correction`] (present iff CSPM is on).
    pub correction: Option<&'a B::Buf<D::Sym<R>>>,
    /// A cohesive path: no continuum pair across it (the flags' side bits; the `_cut` entries).
    pub cut: bool,
}

/// The cohesive path's buffers ([`passes::Passes::bonds`]; `kernels::sph::bond`), all in sorted order except
/// `index` (one entry per id).
pub struct BondBufs<'a, B: Backend, R: Real, D: Dim> {
    pub params: crate::kernels::sph::bond::BondParams,
    pub id: &'a B::Buf<u32>,
    pub index: &'a mut B::Buf<u32>,
    pub partner: &'a B::Buf<u32>,
    pub reference: &'a B::Buf<D::Vec<R>>,
    pub state: &'a mut B::Buf<crate::kernels::sph::bond::BondState<R>>,
    pub onset: &'a mut B::Buf<crate::kernels::sph::bond::OnsetState<R>>,
    pub column: &'a B::Buf<u32>,
    pub work: &'a mut B::Buf<f64>,
    pub damping: &'a mut B::Buf<f64>,
    pub pos: &'a B::Buf<D::Vec<R>>,
    pub vel: &'a B::Buf<D::Vec<R>>,
    pub mass: &'a B::Buf<R>,
    /// σ/ρ² and ρ of the pair interaction (the onset's traction under `coupling = "continuum"`).
    pub sig: &'a B::Buf<D::Sym<R>>,
    pub rho: &'a B::Buf<R>,
    /// Written by the opening pass under `coupling = "continuum"` only.
    pub flags: &'a mut B::Buf<u32>,
}

/// The normal and friction force buffers of the contact pass.
pub type ContactForces<'a, B, R, D> =
    (&'a <B as Backend>::Buf<<D as Dim>::Vec<R>>, &'a <B as Backend>::Buf<<D as Dim>::Vec<R>>);

/// Read-only inputs of the conduction pass, all in sorted order.
pub struct HeatInputs<'a, B: Backend, R: Real, D: Dim> {
    pub pos: &'a B::Buf<D::Vec<R>>,
    pub rho: &'a B::Buf<R>,
    /// V = m/ρ from the pre-pass, with the full masses (the tool's particles conduct).
    pub vol: &'a B::Buf<R>,
    pub temp: &'a B::Buf<f64>,
    pub flags: &'a B::Buf<u32>,
    pub materials: &'a B::Buf<ThermalMaterial>,
}

/// The Brookshaw conduction of the fused interaction: its constants, inputs (volumes from the full masses, the
/// tool's included) and the Ṫ it writes.
pub struct FusedHeat<'a, B: Backend, R: Real, D: Dim> {
    pub params: &'a HeatParams,
    pub input: HeatInputs<'a, B, R, D>,
    pub temp_t: &'a mut B::Buf<f64>,
}

/// Per-particle state of the plastic pass, sorted order.
pub struct PlasticInputs<'a, B: Backend, R: Real, D: Dim> {
    pub stress: &'a mut B::Buf<D::Sym<R>>,
    pub rho: &'a B::Buf<R>,
    pub eps: &'a mut B::Buf<f64>,
    pub rate: &'a mut B::Buf<f64>,
    pub temp: &'a mut B::Buf<f64>,
    pub flags: &'a B::Buf<u32>,
    /// Thermal materials by body (needed when t_q > 0).
    pub materials: Option<&'a B::Buf<ThermalMaterial>>,
    /// Receives σ_y after the update (only when the friction cap uses the current yield stress).
    pub yield_stress: Option<&'a mut B::Buf<f64>>,
    /// Accumulates the specific plastic work Σ σ_y Δε̄/ρ (energy balance), when tracked.
    pub work: Option<&'a mut B::Buf<f64>>,
    /// The damage update after the return (present iff the run models damage).
    pub damage: Option<DamageBufs<'a, B, R>>,
}

/// The damage's buffers in the plastic pass (`kernels::damage`): its constants (one element), ω and D, the
/// particles' full masses (the volume m/ρ of L_char), and where tracked the specific energy the degradation has
/// released (`kernels::sph::plastic::DamageArrays`).
pub struct DamageBufs<'a, B: Backend, R: Real> {
    pub params: &'a B::Buf<DamageParams>,
    pub omega: &'a mut B::Buf<f64>,
    pub damage: &'a mut B::Buf<f64>,
    pub mass: &'a B::Buf<R>,
    pub work: Option<&'a mut B::Buf<f64>>,
}

/// The damage's buffers in the pre-pass: D, the mask it writes and the `damage::switches`.
pub struct PrepassDamageBufs<'a, B: Backend> {
    pub damage: &'a B::Buf<f64>,
    pub mask: &'a mut B::Buf<f64>,
    pub flags: u32,
}

/// The particles a per-particle pass runs over (`kernels::pass::Span`): the first n, or with blanking the first
/// `buf[index]` of them, the cell starts' entry n_cells (the count of unblanked particles, which the cell list
/// sorts first; docs/3d.md, "Blanking"), read where the pass runs. A plain count converts into it.
pub struct Count<'a, B: Backend> {
    pub n: usize,
    pub active: Option<(&'a B::Buf<u32>, usize)>,
}

impl<B: Backend> Clone for Count<'_, B> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<B: Backend> Copy for Count<'_, B> {}

impl<B: Backend> From<usize> for Count<'_, B> {
    fn from(n: usize) -> Self {
        Count { n, active: None }
    }
}

/// Where a step's scalars are: entry `index` of `buf`.
pub struct ScalarsAt<'a, B: Backend> {
    pub buf: &'a B::Buf<StepScalars>,
    pub index: usize,
}

impl<B: Backend> Clone for ScalarsAt<'_, B> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<B: Backend> Copy for ScalarsAt<'_, B> {}

/// Where a step's tool states are: `count` states (one per tool) from entry `index · count` of `buf`.
pub struct ToolStatesAt<'a, B: Backend> {
    pub buf: &'a B::Buf<crate::kernels::contact::ToolState>,
    pub index: usize,
    pub count: usize,
}

/// The fields a step integrates, in sorted order: the state y, its start-of-step copy y0, the rates, and the
/// temperature (present with heat or plasticity) with its start copy and rate (present with conduction).
pub struct StepFields<'a, B: Backend, R: Real, D: Dim> {
    pub y: FieldsMut<'a, B, R, D>,
    pub y0: FieldsMut<'a, B, R, D>,
    pub rates: FieldsRef<'a, B, R, D>,
    pub temp: Option<&'a mut B::Buf<f64>>,
    pub conduction: Option<Conduction<'a, B>>,
    /// The artificial viscosity's accumulated dissipation and its rate from the interaction (with AV; the
    /// corrector integrates it, the predictor ignores it).
    pub dissipation: Option<Dissipation<'a, B, R>>,
    /// The low part of the start position x0 = y0.pos + pos_lo, in the mixed precision: the corrector's position
    /// sum is compensated (`sph::integrate::advance_compensated`); the predictor ignores it.
    pub pos_lo: Option<&'a mut B::Buf<D::Vec<R>>>,
}

/// The accumulated dissipation per unit mass [J/kg] and its rate.
pub type Dissipation<'a, B, R> = (&'a mut <B as Backend>::Buf<f64>, &'a <B as Backend>::Buf<R>);

/// The conduction predictor–corrector's start copy T0 and rate Ṫ.
pub type Conduction<'a, B> = (&'a mut <B as Backend>::Buf<f64>, &'a <B as Backend>::Buf<f64>);

/// Where a step's scalars are, for a kernel that sets their rebuild flag (the predictor).
pub struct ScalarsMut<'a, B: Backend> {
    pub buf: &'a mut B::Buf<StepScalars>,
    pub index: usize,
}

/// The predictor's skin test: the grid (with its skin) and each particle's position when the cell list was built.
pub struct SkinTest<'a, B: Backend, R: Real, D: Dim> {
    pub grid: &'a B::Buf<GridParams>,
    pub pos_ref: &'a B::Buf<D::Vec<R>>,
    /// The step's rebuild condition ([`Backend::rebuild_condition`]; 0: none), set with the rebuild flag.
    pub condition: u64,
}

/// The buffers of a cell list's build (`neighbour::CellList`).
pub struct CellBuffers<'a, B: Backend> {
    pub grid: &'a B::Buf<GridParams>,
    /// The grid's cells plus the void bucket; with blanking the grid's cells twice (the active particles', the
    /// blanked ones') and then the void bucket (`GridParams::key_blanked`).
    pub n_buckets: usize,
    /// The step scalars whose blanking box the hash applies (None: no blanking).
    pub blank: Option<ScalarsAt<'a, B>>,
    pub keys: &'a mut B::Buf<u32>,
    pub slots: &'a mut B::Buf<u32>,
    /// Counts, then (scanned) the cell starts: n_buckets + 1 entries.
    pub starts: &'a mut B::Buf<u32>,
    pub perm: &'a mut B::Buf<u32>,
    pub scan: &'a mut [B::Buf<u32>],
    /// rebuilds[0] counts the gated rebuilds that ran (None: not counted, a build outside the step loop).
    pub rebuilds: Option<&'a mut B::Buf<u32>>,
}

impl<B: Backend> CellBuffers<'_, B> {
    /// The buckets whose slices the per-cell sort orders: the cells, not the void bucket after them. Its particles
    /// (non-finite positions) are nobody's neighbour, and the run stops after the batch that made them, so their
    /// order is never used. Sorting it cost one GPU thread O(k²) per step for k such particles (O(k log k) with
    /// the heap sort): the JC micro-milling run did not return from its batch after its blow-up (docs/3d.md).
    pub fn sorted_buckets(&self) -> usize {
        self.n_buckets - 1
    }
}

/// The plastic update fused into the corrector (stress, density and temperature come from [`StepFields`]).
pub struct PlasticPass<'a, B: Backend, R: Real> {
    pub model: &'a crate::material::FlowModel,
    pub shear: f64,
    pub taylor_quinney: f64,
    /// `PlasticConsts::flags`: the original code's return (`model = "mfree_iwf"`); 0: swarf's.
    pub return_flags: u32,
    pub eps: &'a mut B::Buf<f64>,
    pub rate: &'a mut B::Buf<f64>,
    pub flags: &'a B::Buf<u32>,
    pub materials: Option<&'a B::Buf<ThermalMaterial>>,
    pub yield_stress: Option<&'a mut B::Buf<f64>>,
    pub work: Option<&'a mut B::Buf<f64>>,
    /// The damage update after the return (present iff the run models damage).
    pub damage: Option<DamageBufs<'a, B, R>>,
}

/// What the pre-pass writes, standalone ([`Passes::sph_prepare`]) or fused ([`FusedPrepare`]): σ/ρ², the
/// artificial stress and the viscosity's sound speed (present iff their stabiliser is on), the volumes, and the
/// Balsara factors it reads (present iff the switch is on); the kernels' `sph::interact::PrepassArrays`.
pub struct PrepassBufs<'a, B: Backend, R: Real, D: Dim> {
    pub sig: &'a mut B::Buf<D::Sym<R>>,
    pub art: Option<&'a mut B::Buf<D::Sym<R>>>,
    pub sound: Option<&'a mut B::Buf<R>>,
    pub vol: &'a mut B::Buf<R>,
    pub av_switch: Option<&'a B::Buf<R>>,
}

/// The pre-pass fused into the predictor ([`Passes::step_predict`]; no thermal expansion). Its other inputs are
/// the predictor's own: the predicted densities and stresses.
pub struct FusedPrepare<'a, B: Backend, R: Real, D: Dim> {
    pub stab: Stabilisers,
    pub params: &'a SphParams<R>,
    /// The particles' full masses.
    pub mass: &'a B::Buf<R>,
    pub out: PrepassBufs<'a, B, R, D>,
    /// The damage (present iff the run models damage).
    pub damage: Option<PrepassDamageBufs<'a, B>>,
}

/// The contact pass fused into the plastic corrector ([`Passes::step_finish`]). Its other inputs are the
/// corrector's own: positions, velocities, densities and temperatures after the corrector and the plastic update,
/// the plastic pass's flags and (with `yield_stress`) its yield stresses.
pub struct FusedContact<'a, B: Backend, R: Real, D: Dim> {
    pub params: &'a B::Buf<crate::kernels::contact::ContactParams>,
    /// The tool's shape (one element) and its state this step.
    pub tool: &'a B::Buf<crate::kernels::contact::Tool2d>,
    pub state: ToolStatesAt<'a, B>,
    /// The particles' own masses.
    pub mass: &'a B::Buf<R>,
    pub normal: &'a mut B::Buf<D::Vec<R>>,
    /// Friction force: read as the history, overwritten with the new force.
    pub friction: &'a mut B::Buf<D::Vec<R>>,
    /// Thermal materials by body (with friction heating).
    pub materials: Option<&'a B::Buf<ThermalMaterial>>,
    /// The friction cap reads the plastic pass's yield stresses (the CURRENT cap).
    pub yield_stress: bool,
    /// Usui wear-rate output, when on.
    pub wear: Option<&'a mut B::Buf<f64>>,
}

/// Per-particle state of the contact pass, sorted order.
pub struct ContactInputs<'a, B: Backend, R: Real, D: Dim> {
    pub pos: &'a B::Buf<D::Vec<R>>,
    pub vel: &'a B::Buf<D::Vec<R>>,
    /// The particles' own masses.
    pub mass: &'a B::Buf<R>,
    pub rho: &'a B::Buf<R>,
    pub flags: &'a B::Buf<u32>,
    pub normal: &'a mut B::Buf<D::Vec<R>>,
    /// Friction force: read as the history, overwritten with the new force.
    pub friction: &'a mut B::Buf<D::Vec<R>>,
    /// Temperature (friction heating, wear law), where modelled.
    pub temp: Option<&'a mut B::Buf<f64>>,
    /// Thermal materials by body (needed with friction heating).
    pub materials: Option<&'a B::Buf<ThermalMaterial>>,
    /// Current yield stresses (the CURRENT friction cap).
    pub yield_stress: Option<&'a B::Buf<f64>>,
    /// Usui wear-rate output, when on.
    pub wear: Option<&'a mut B::Buf<f64>>,
}

/// Elements per tile of the GPU scan (kernels/src/ptx/scan.rs).
pub const SCAN_TILE: usize = 1024;

/// Workspace of the multi-level scan: one buffer of tile sums per level, down to a single tile.
pub fn scan_levels<B: Backend>(b: &B, n: usize) -> Result<Vec<B::Buf<u32>>> {
    let mut levels = Vec::new();
    let mut len = n;
    loop {
        let tiles = len.div_ceil(SCAN_TILE).max(1);
        levels.push(b.alloc::<u32>(tiles, "scan workspace")?);
        if tiles == 1 {
            return Ok(levels);
        }
        len = tiles;
    }
}

/// Which backend to use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum BackendChoice {
    /// The GPU when a CUDA driver and device are present, the CPU otherwise.
    Auto,
    Cpu,
    Gpu,
}

/// A backend chosen at run time.
pub enum AnyBackend {
    Cpu(CpuBackend),
    Cuda(Box<CudaBackend>),
}

impl AnyBackend {
    /// Chooses the backend; returns it and a one-line statement of the choice.
    pub fn select(choice: BackendChoice) -> Result<(AnyBackend, String)> {
        match choice {
            BackendChoice::Cpu => {
                let b = CpuBackend::new();
                let line = format!("backend: cpu ({}, {} threads), as requested", b.info().name, b.info().units);
                Ok((AnyBackend::Cpu(b), line))
            }
            BackendChoice::Gpu => {
                let b = CudaBackend::new(0)?;
                let line = gpu_line(b.info());
                Ok((AnyBackend::Cuda(Box::new(b)), line))
            }
            BackendChoice::Auto => match CudaBackend::new(0) {
                Ok(b) => {
                    let line = gpu_line(b.info());
                    Ok((AnyBackend::Cuda(Box::new(b)), line))
                }
                Err(e) => {
                    let b = CpuBackend::new();
                    let line = format!(
                        "backend: cpu ({}, {} threads); no GPU: {}",
                        b.info().name,
                        b.info().units,
                        first_line(&e.to_string())
                    );
                    Ok((AnyBackend::Cpu(b), line))
                }
            },
        }
    }

    /// Another backend of the same kind on the same device, for one more member of an ensemble (host/ensemble):
    /// on the GPU a stream of its own sharing the loaded kernels ([`CudaBackend::sibling`]); on the CPU a backend
    /// on the same thread pool.
    pub fn sibling(&self) -> Result<AnyBackend> {
        Ok(match self {
            AnyBackend::Cpu(_) => AnyBackend::Cpu(CpuBackend::new()),
            AnyBackend::Cuda(b) => AnyBackend::Cuda(Box::new(b.sibling()?)),
        })
    }

    pub fn info(&self) -> &DeviceInfo {
        match self {
            AnyBackend::Cpu(b) => b.info(),
            AnyBackend::Cuda(b) => b.info(),
        }
    }
}

fn gpu_line(i: &DeviceInfo) -> String {
    let (ma, mi) = i.compute_capability.unwrap_or((0, 0));
    format!("backend: gpu ({}, compute capability {ma}.{mi}, PTX {})", i.name, i.ptx_target.unwrap_or("?"))
}

fn first_line(s: &str) -> &str {
    s.lines().next().unwrap_or(s)
}

/// Runs `$body` with `$b` bound to the concrete backend inside an [`AnyBackend`].
#[macro_export]
macro_rules! with_backend {
    ($any:expr, $b:ident => $body:expr) => {
        match $any {
            $crate::backend::AnyBackend::Cpu($b) => $body,
            $crate::backend::AnyBackend::Cuda($b) => {
                let $b = &**$b;
                $body
            }
        }
    };
}
