//! Backends: where kernels run. The solver is written once against [`Backend`]; the CPU backend calls the
//! kernel crate's functions in rayon loops, the CUDA backend launches the same functions compiled to PTX.
//! Each method of the trait is one kernel (or one block-cooperative algorithm) and has the same meaning on both.

pub mod args;
pub mod cpu;
pub mod cuda;

use crate::Result;
use crate::kernels::neighbour::{GatherField, GridParams};
use crate::kernels::sph::heat::{HeatParams, ThermalMaterial};
use crate::kernels::sph::step::StepScalars;
use crate::kernels::sph::{CubicSpline, SphParams, Stabilisers, TensorOps};
use crate::kernels::{Dim, Real};
use bytemuck::Pod;

pub use cpu::CpuBackend;
pub use cuda::CudaBackend;

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
    type Buf<T: Element>: Buffer<T>;
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
    /// Zeroes the first `n` elements.
    fn fill_zero<T: Element>(&self, buf: &mut Self::Buf<T>, n: usize) -> Result<()>;
    /// Waits until all submitted work is done.
    fn synchronize(&self) -> Result<()>;
    /// Wall time of `f` in milliseconds as the device sees it (CUDA events on the GPU).
    fn time_ms(&self, f: &mut dyn FnMut() -> Result<()>) -> Result<f64>;

    /// keys[i] = cell key of pos[i] (`GridParams::key`), for i < n.
    fn hash<R: Real, D: Dim>(
        &self,
        n: usize,
        pos: &Self::Buf<D::Vec<R>>,
        grid: &Self::Buf<GridParams>,
        keys: &mut Self::Buf<u32>,
    ) -> Result<()>;
    /// counts[keys[i]] += 1 and slots[i] = the particle's arrival order in its bucket.
    fn count_cells(
        &self,
        n: usize,
        keys: &Self::Buf<u32>,
        counts: &mut Self::Buf<u32>,
        slots: &mut Self::Buf<u32>,
    ) -> Result<()>;
    /// In-place exclusive prefix sum of data[..n]; `levels` is the workspace from [`scan_levels`].
    fn exclusive_scan(&self, n: usize, data: &mut Self::Buf<u32>, levels: &mut [Self::Buf<u32>]) -> Result<()>;
    /// perm[starts[keys[i]] + slots[i]] = i.
    fn scatter(
        &self,
        n: usize,
        keys: &Self::Buf<u32>,
        slots: &Self::Buf<u32>,
        starts: &Self::Buf<u32>,
        perm: &mut Self::Buf<u32>,
    ) -> Result<()>;
    /// Sorts each bucket's slice perm[starts[c] .. starts[c+1]] ascending, c < n_buckets.
    fn sort_cells(&self, n_buckets: usize, starts: &Self::Buf<u32>, perm: &mut Self::Buf<u32>) -> Result<()>;
    /// dst[i] = src[perm[i]] for i < n.
    fn gather<T: Element>(
        &self,
        n: usize,
        perm: &Self::Buf<u32>,
        src: &Self::Buf<T>,
        dst: &mut Self::Buf<T>,
    ) -> Result<()>;
    /// Neighbour lists (j ≠ i, |x_ij|² < support2) of sorted particles in CSR form: counts[i] always, and the
    /// indices at list[offsets[i]..] when `offsets` is given (the exclusive scan of a counting pass).
    #[allow(clippy::too_many_arguments)]
    fn neighbour_list<R: Real, D: Dim>(
        &self,
        n: usize,
        pos: &Self::Buf<D::Vec<R>>,
        grid: &Self::Buf<GridParams>,
        starts: &Self::Buf<u32>,
        support2: R,
        offsets: Option<&Self::Buf<u32>>,
        counts: &mut Self::Buf<u32>,
        list: &mut Self::Buf<u32>,
    ) -> Result<()>;
    /// ρ_i = Σ_j m_j W(|x_ij|) over sorted particles (`sph::density::density_sum`).
    #[allow(clippy::too_many_arguments)]
    fn density<R: Real, D: Dim>(
        &self,
        n: usize,
        pos: &Self::Buf<D::Vec<R>>,
        mass: &Self::Buf<R>,
        grid: &Self::Buf<GridParams>,
        starts: &Self::Buf<u32>,
        kernel: &Self::Buf<CubicSpline<R>>,
        rho: &mut Self::Buf<R>,
    ) -> Result<()>;

    /// SPH pre-pass (`sph::interact::prepare`): sig = σ/ρ², art = artificial stress (if on), sound = √(K/ρ)
    /// (if the viscosity is on), vol = m/ρ with `mass` the particles' full masses (the thermal-only ones
    /// included: they conduct); `temp` is given when the EOS has thermal expansion. With `gate` it runs only when
    /// the step's rebuild flag is set (the predictor ran the pre-pass; a rebuild's reorder needs it again).
    #[allow(clippy::too_many_arguments)]
    fn sph_prepare<R: Real, D: TensorOps<R>>(
        &self,
        n: usize,
        stab: Stabilisers,
        params: &Self::Buf<SphParams<R>>,
        rho: &Self::Buf<R>,
        mass: &Self::Buf<R>,
        stress: &Self::Buf<D::Sym<R>>,
        sig: &mut Self::Buf<D::Sym<R>>,
        art: Option<&mut Self::Buf<D::Sym<R>>>,
        sound: Option<&mut Self::Buf<R>>,
        vol: &mut Self::Buf<R>,
        temp: Option<&Self::Buf<f64>>,
        gate: Option<ScalarsAt<'_, Self>>,
    ) -> Result<()>;
    /// SPH pair interaction (`sph::interact::rates`): the rates of every sorted particle, each summed by `lanes`
    /// lanes (1, 2, 4 or 8; the sums' order depends on it, equally on every backend). With `heat`, the same
    /// neighbour walk also sums the Brookshaw conduction (`sph::interact::rates_heat`), equal bit for bit to
    /// [`Backend::heat_rates`] on this cell list. With `list` (built by [`Backend::verlet_build`] on this cell
    /// list) the pair loops read it instead of walking the stencil.
    #[allow(clippy::too_many_arguments)]
    fn sph_rates<R: Real, D: TensorOps<R>>(
        &self,
        n: usize,
        lanes: u32,
        stab: Stabilisers,
        params: &SphParams<R>,
        grid: &Self::Buf<GridParams>,
        starts: &Self::Buf<u32>,
        list: Option<&Self::Buf<u32>>,
        input: &SphInputs<'_, Self, R, D>,
        out: FieldsMut<'_, Self, R, D>,
        dissipation: Option<&mut Self::Buf<R>>,
        heat: Option<FusedHeat<'_, Self, R, D>>,
    ) -> Result<()>;
    /// The predictor (`sph::step::predict_particle`): y0 ← y, y ← y0 + ½Δt ẏ (x, v, ρ, S and, with conduction,
    /// T), with the skin test of each predicted position: a particle farther than the grid's skin from where the
    /// cell list binned it (`GridParams::beyond_skin`) sets the step's rebuild flag.
    /// With `prepare`, each particle's pre-pass follows its prediction in the same pass
    /// (`sph::interact::prepare_particle`; the same results as [`Backend::sph_prepare`] after the predictor).
    fn step_predict<R: Real, D: TensorOps<R>>(
        &self,
        n: usize,
        s: ScalarsMut<'_, Self>,
        f: StepFields<'_, Self, R, D>,
        skin: SkinTest<'_, Self, R, D>,
        prepare: Option<FusedPrepare<'_, Self, R, D>>,
    ) -> Result<()>;
    /// The cell list's rebuild inside the step loop, gated by the step's rebuild flag: counts zeroed (with
    /// `rebuilds[0] += 1`), hash and count, prefix sum, scatter and per-cell sort, as `CellList::build`; each
    /// launch does nothing when the flag is 0 (a captured step holds every launch).
    fn rebuild_cells<R: Real, D: Dim>(
        &self,
        n: usize,
        gate: ScalarsAt<'_, Self>,
        pos: &Self::Buf<D::Vec<R>>,
        cells: CellBuffers<'_, Self>,
    ) -> Result<()>;
    /// The Verlet list (`neighbour::verlet::verlet_row`) of the n sorted particles at `pos` on the cell list
    /// `grid`/`starts`, into `list` (`GridParams::list_words` entries);
    /// with a gate, only when that step rebuilds.
    fn verlet_build<R: Real, D: Dim>(
        &self,
        n: usize,
        gate: Option<ScalarsAt<'_, Self>>,
        grid: &Self::Buf<GridParams>,
        starts: &Self::Buf<u32>,
        pos: &Self::Buf<D::Vec<R>>,
        list: &mut Self::Buf<u32>,
    ) -> Result<()>;
    /// The fused corrector (`sph::step::correct_particle`) y ← y0 + Δt ẏ, followed by the plastic update of the
    /// same particle when `plastic` is given (`sph::plastic::plastic_particle`), and then by the tool's contact
    /// pass of the same particle when `contact` is given (`contact::penalty::contact_particle`, 2D; needs
    /// `plastic`): the same results as [`Backend::contact`] after the corrector, without a pass of its own.
    fn step_finish<R: Real, D: TensorOps<R>>(
        &self,
        n: usize,
        s: ScalarsAt<'_, Self>,
        f: StepFields<'_, Self, R, D>,
        plastic: Option<PlasticPass<'_, Self>>,
        contact: Option<FusedContact<'_, Self, R, D>>,
    ) -> Result<()>;
    /// The address of a buffer's first element, for [`Backend::gather_fields`].
    fn address<T: Element>(&self, buf: &Self::Buf<T>) -> u64;
    /// The same for a buffer that will be written.
    fn address_mut<T: Element>(&self, buf: &mut Self::Buf<T>) -> u64;
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
    /// Conduction rates Ṫ (`sph::heat::heat_rate`), Brookshaw or (`pse`) PSE; `grid` has stencil 2 for
    /// Brookshaw and 3 for PSE; `list` the Verlet list of `grid` (Brookshaw only: PSE reaches farther).
    #[allow(clippy::too_many_arguments)]
    fn heat_rates<R: Real, D: Dim>(
        &self,
        n: usize,
        lanes: u32,
        pse: bool,
        hp: &HeatParams,
        params: &SphParams<R>,
        grid: &Self::Buf<GridParams>,
        starts: &Self::Buf<u32>,
        list: Option<&Self::Buf<u32>>,
        input: &HeatInputs<'_, Self, R, D>,
        temp_t: &mut Self::Buf<f64>,
    ) -> Result<()>;
    /// The plastic update of every particle (`sph::plastic::plastic_particle`) with the flow-stress `model` (its
    /// parameters go to the GPU by value, with the launch).
    fn plastic_step<R: Real, D: TensorOps<R>>(
        &self,
        n: usize,
        model: &crate::material::FlowModel,
        consts: crate::kernels::sph::plastic::PlasticConsts,
        a: PlasticInputs<'_, Self, R, D>,
    ) -> Result<()>;
    /// The contact pass with the rigid 2D tool (`contact::penalty::contact_particle`); 2D only.
    fn contact<R: Real, D: Dim>(
        &self,
        n: usize,
        params: &Self::Buf<crate::kernels::contact::ContactParams>,
        tool: &Self::Buf<crate::kernels::contact::Tool2d>,
        s: ScalarsAt<'_, Self>,
        a: ContactInputs<'_, Self, R, D>,
    ) -> Result<()>;
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
}

/// Where a step's scalars are: entry `index` of `buf`.
pub struct ScalarsAt<'a, B: Backend> {
    pub buf: &'a B::Buf<StepScalars>,
    pub index: usize,
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
    /// The grid's cells plus the void bucket.
    pub n_buckets: usize,
    pub keys: &'a mut B::Buf<u32>,
    pub slots: &'a mut B::Buf<u32>,
    /// Counts, then (scanned) the cell starts: n_buckets + 1 entries.
    pub starts: &'a mut B::Buf<u32>,
    pub perm: &'a mut B::Buf<u32>,
    pub scan: &'a mut [B::Buf<u32>],
    /// rebuilds[0] counts the gated rebuilds that ran.
    pub rebuilds: &'a mut B::Buf<u32>,
}

/// The plastic update fused into the corrector (stress, density and temperature come from [`StepFields`]).
pub struct PlasticPass<'a, B: Backend> {
    pub model: &'a crate::material::FlowModel,
    pub shear: f64,
    pub taylor_quinney: f64,
    pub eps: &'a mut B::Buf<f64>,
    pub rate: &'a mut B::Buf<f64>,
    pub flags: &'a B::Buf<u32>,
    pub materials: Option<&'a B::Buf<ThermalMaterial>>,
    pub yield_stress: Option<&'a mut B::Buf<f64>>,
    pub work: Option<&'a mut B::Buf<f64>>,
}

/// The pre-pass fused into the predictor ([`Backend::step_predict`]; no thermal expansion). Its other inputs are
/// the predictor's own: the predicted densities and stresses.
pub struct FusedPrepare<'a, B: Backend, R: Real, D: Dim> {
    pub stab: Stabilisers,
    pub params: &'a SphParams<R>,
    /// The particles' full masses.
    pub mass: &'a B::Buf<R>,
    pub sig: &'a mut B::Buf<D::Sym<R>>,
    pub art: Option<&'a mut B::Buf<D::Sym<R>>>,
    pub sound: Option<&'a mut B::Buf<R>>,
    pub vol: &'a mut B::Buf<R>,
}

/// The contact pass fused into the plastic corrector ([`Backend::step_finish`]). Its other inputs are the
/// corrector's own: positions, velocities, densities and temperatures after the corrector and the plastic update,
/// the plastic pass's flags and (with `yield_stress`) its yield stresses.
pub struct FusedContact<'a, B: Backend, R: Real, D: Dim> {
    pub params: &'a B::Buf<crate::kernels::contact::ContactParams>,
    /// The tool's shape (one element).
    pub tool: &'a B::Buf<crate::kernels::contact::Tool2d>,
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
