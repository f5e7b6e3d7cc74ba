//! The SPH solver loop, written once against [`Backend`]. One step (roethlin-solver.md §5.2, reordered so that
//! the neighbour search is exact at the positions where the rates are evaluated):
//!
//! 1. predictor: y0 ← y, y ← y0 + ½Δt ẏ (ẏ from the previous step's midpoint; zero at the first step), with the
//!    skin test: a particle farther than the grid's skin from where the cell list binned it flags a rebuild;
//! 2. when flagged (or forced: the first step), the cell list on the predicted positions and the reorder of y,
//!    y0 and the per-particle constants (mass, id, flags), in place; otherwise the last list stays exact, since
//!    its cells are sized for the support plus the skin (docs/neighbour-search.md, "Skin");
//! 3. pre-pass: σ/ρ², artificial stress, sound speed (these two only when their stabiliser is on), volume m/ρ;
//! 4. pair interaction: ẏ at the midpoint, with the boundary conditions imposed on the rates;
//! 5. corrector: y ← y0 + Δt ẏ;
//! 6. plasticity (if on): radial return of S with ε̄, ε̄̇, T and plastic heating (operator split, §5.2 step 13).
//!
//! With heat conduction on, T joins x, v, ρ, S in the predictor–corrector and its rate comes from the conduction
//! pass after the interaction. Temperature, ε̄ and ε̄̇ are f64 in every precision; they exist only when the scene
//! models plasticity or heat.
//!
//! The rates are not reordered: the predictor consumes them in the order the corrector left, and the interaction
//! rewrites them. Buffers of a stabiliser that is off are not allocated.

pub mod blanking;
pub mod diagnostics;
pub mod fields;
pub mod params;

pub use crate::tool::motion::ToolMotion;

use crate::Result;
use crate::backend::{
    Backend, BondBufs, Conduction, ContactInputs, DamageBufs, DeviceTools, FieldsMut, FieldsRef, FusedContact,
    FusedHeat, FusedPrepare, HeatInputs, Passes, PlasticPass, PrepassBufs, PrepassDamageBufs, ScalarsAt, ScalarsMut,
    SkinTest, SphInputs, StepFields, ToolStatesAt,
};
use crate::kernels::contact::{ContactParams, ToolState};
use crate::kernels::damage::DamageParams;
use crate::kernels::neighbour::GridParams;
use crate::kernels::sph::heat::{HeatParams, ThermalMaterial};
use crate::kernels::sph::params::flags;
use crate::kernels::sph::step::StepScalars;
use crate::kernels::sph::{SphParams, Stabilisers, TensorOps};
use crate::kernels::{Dim, Real, Vector};
use crate::material::FlowModel;
use crate::neighbour::CellList;
use crate::state::{Field, HostParticles, Particles, ReorderBatch};
use crate::tool::ContactPower;
use fields::When;

/// Heat physics of a run.
#[derive(Clone, Debug)]
pub struct ThermalSetup {
    /// Thermal constants by body index.
    pub materials: Vec<ThermalMaterial>,
    /// Conduction: None (off), Some(false) Brookshaw, Some(true) PSE.
    pub conduction: Option<bool>,
    pub heat: HeatParams,
}

/// Plasticity of a run.
#[derive(Clone, Debug)]
pub struct PlasticSetup {
    pub model: FlowModel,
    /// Taylor–Quinney coefficient (0: no plastic heating).
    pub taylor_quinney: f64,
    /// `PlasticConsts::flags` (the scene's `model`; 0: swarf's return).
    pub return_flags: u32,
}

/// Damage of a run (`kernels::damage`, docs/damage.md).
#[derive(Clone, Debug)]
pub struct DamageSetup {
    /// The constants (fracture-strain model, G_f, switches).
    pub params: DamageParams,
    /// Initial ω and D of each particle, in the scene's order (the pre-crack; zero elsewhere).
    pub omega: Vec<f64>,
    pub damage: Vec<f64>,
}

/// The cohesive path of a run (`kernels::sph::bond`; docs/mpm.md "The cohesive path in SPH"): the particles'
/// side flags are set in the particles' flags; each bond is held by its owner, in the scene's order.
#[derive(Clone, Debug)]
pub struct CohesiveSetup {
    pub params: crate::kernels::sph::bond::BondParams,
    /// The partner's id of each particle owning a bond (`bond::NONE` elsewhere).
    pub partner: Vec<u32>,
    /// X_owner − X_partner of each owner's bond [m] (zero elsewhere).
    pub reference: Vec<[f64; 3]>,
    /// The id of the bond owner whose column each particle belongs to under `coupling = "continuum"` (`bond::NONE`
    /// for a particle of none, and for every particle under `"bonds"`).
    pub column: Vec<u32>,
}

/// One rigid tool of a run: its contact law, shape and motion.
#[derive(Clone, Debug)]
pub struct ToolSetup {
    /// The contact law's constants.
    pub params: ContactParams,
    /// The tool's shape: the parametric tool (2D, or its prism in 3D) or a mesh (3D).
    pub shape: crate::tool::Shape,
    pub motion: ToolMotion,
}

/// The rigid tools of a run (one or more; the first is the cutting run's tool, whose forces are F_c and F_f).
#[derive(Clone, Debug)]
pub struct ContactSetup {
    /// The tools, in the scene's order (all parametric or all meshes): a particle inside several is taken by the
    /// first (`contact::penalty::contact_particle`).
    pub tools: Vec<ToolSetup>,
    /// Index of the (lone) tool's thermal particles' velocity in the prescribed-velocity table (rewritten during a
    /// start-up ramp).
    pub tool_velocity_index: Option<usize>,
    /// Record the Usui wear rate.
    pub wear: bool,
}

/// Everything a solver needs, in the run's precision (built from a scene by `run::setup`).
#[derive(Clone)]
pub struct Setup<R: Real, D: TensorOps<R>> {
    pub particles: HostParticles<R, D>,
    /// The mixed precision's low parts of the positions (x = pos + pos_lo, each rounded to R; `run::setup` with
    /// `Precision::Mixed`), None otherwise.
    pub pos_lo: Option<Vec<D::Vec<R>>>,
    pub params: SphParams<R>,
    pub stabilisers: params::StabiliserSettings,
    pub bc_velocities: Vec<D::Vec<R>>,
    /// Each `bc_velocities` entry's reversal times (a boundary's `reverse_at`; empty: constant).
    pub bc_reversals: Vec<Vec<f64>>,
    pub grid: GridParams,
    pub dt: f64,
    pub c0: f64,
    pub h: f64,
    /// Shear modulus G [Pa] (f64 for the return map).
    pub shear: f64,
    /// Initial temperature of each particle; present when the run models heat or plasticity.
    pub temperature: Option<Vec<f64>>,
    pub thermal: Option<ThermalSetup>,
    pub plastic: Option<PlasticSetup>,
    /// Damage (needs plasticity); None: no damage, the code path of an undamaged run.
    pub damage: Option<DamageSetup>,
    /// The cohesive path (None: none, the code path of a run without one).
    pub cohesive: Option<CohesiveSetup>,
    pub contact: Option<ContactSetup>,
    /// The blanking's moving box (None: every particle is integrated).
    pub blanking: Option<blanking::Blanking>,
    /// Input that runs but whose result is not meaningful (`scene::degenerate_input_warnings`).
    pub warnings: Vec<String>,
    /// The tuning switches the solver takes its lanes, graphs and fusions from.
    pub tuning: crate::tuning::Tuning,
}

impl<R: Real, D: TensorOps<R>> Setup<R, D> {
    /// The run's precision as reports name it (as [`Solver::precision`]).
    pub fn precision(&self) -> &'static str {
        precision_name::<R>(self.pos_lo.is_some())
    }
}

/// "mixed" for an R state with compensated positions, else R's name.
fn precision_name<R: Real>(compensated: bool) -> &'static str {
    if compensated { crate::scene::Precision::Mixed.as_str() } else { R::NAME }
}

struct ThermalState<B: Backend> {
    temp0: Option<Field<B, f64>>,
    temp_t: Option<B::Buf<f64>>,
    materials: B::Buf<ThermalMaterial>,
    heat: HeatParams,
    conduction: Option<bool>,
    /// The cell list's grid with the ±3 stencil PSE needs.
    grid_pse: B::Buf<GridParams>,
}

/// The CSPM correction B⁻¹ per particle (`kernels::sph::correction`), det B below which it is the identity, and
/// whether only the cohesive path's faces are corrected.
struct Correction<B: Backend, R: Real, D: Dim> {
    buf: B::Buf<D::Sym<R>>,
    min_det: R,
    path_only: bool,
}

struct PlasticState<B: Backend> {
    eps: Field<B, f64>,
    rate: Field<B, f64>,
    /// Specific plastic work Σ σ_y Δε̄/ρ [J/kg], for the energy balance.
    work: Field<B, f64>,
    model: FlowModel,
    taylor_quinney: f64,
    return_flags: u32,
}

struct DamageState<B: Backend> {
    params: B::Buf<DamageParams>,
    /// `damage::switches`.
    flags: u32,
    /// ω (initiation) and D (evolution).
    omega: Field<B, f64>,
    damage: Field<B, f64>,
    /// The interaction mask of the last pre-pass (1 interacting, 0 masked, −1 deleted; rewritten every step).
    mask: B::Buf<f64>,
    /// The specific elastic energy the degradation has released [J/kg], for the energy balance.
    work: Field<B, f64>,
}

/// The cohesive path's bonds on the backend (registry entries "bond_*").
struct CohesiveState<B: Backend, R: Real, D: Dim> {
    params: crate::kernels::sph::bond::BondParams,
    partner: Field<B, u32>,
    reference: Field<B, D::Vec<R>>,
    state: Field<B, crate::kernels::sph::bond::BondState<R>>,
    onset: Field<B, crate::kernels::sph::bond::OnsetState<R>>,
    column: Field<B, u32>,
    work: Field<B, f64>,
    damping: Field<B, f64>,
    index: B::Buf<u32>,
}

struct ContactState<B: Backend, R: Real, D: Dim> {
    /// The tools' constants and shapes.
    tools: DeviceTools<B>,
    /// Each tool in its frame, for the frames' pictures (`tool::Shape::picture`).
    pictures: Vec<crate::tool::Picture>,
    motions: Vec<ToolMotion>,
    /// The tools' states of a batch: [`GRAPH_STEPS`] steps of one state per tool (step j's from j·tools), and the
    /// host copy they are written from.
    states: B::Buf<ToolState>,
    host_states: Vec<ToolState>,
    /// The tool each particle's friction history belongs to (several tools only).
    owner: Option<Field<B, u32>>,
    normal: Field<B, D::Vec<R>>,
    friction: Field<B, D::Vec<R>>,
    /// σ_y after the plastic update (CURRENT friction cap only; rewritten every step, never reordered).
    yield_stress: Option<B::Buf<f64>>,
    wear: Option<B::Buf<f64>>,
    tool_velocity_index: Option<usize>,
    /// Friction heating is on (for some tool).
    heating: bool,
    /// The run's time step, which scales the contact stiffness (a step shortened to land on an output time does
    /// not stiffen it).
    nominal_dt: f64,
    /// Host copy of the prescribed-velocity table, for the ramp's rewrites.
    bc_table: Vec<D::Vec<R>>,
}

/// The tool's force on the workpiece and its contact statistics at one instant.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactSample {
    /// Σ (f_c + f_t) over the particles the tool touches: its force on the workpiece [N per m of depth in 2D; z = 0].
    pub force: [f64; 3],
    /// Σ (x − p) × (f_c + f_t): its moment about the tool's reference point p, the point o + c of its rotation axis
    /// (a point of the axis, which does not turn), else its frame origin o [N·m; per m in 2D].
    pub moment: [f64; 3],
    /// Particles in contact.
    pub contacts: usize,
    /// Mean Usui wear rate over the contacting particles [m/s] (NaN when wear is off or nothing touches).
    pub wear_rate: f64,
    /// Σ|f_t| / Σ|f_c| over the contacting particles: the friction the contact carries against its normal force,
    /// μ where every contact slides (NaN when nothing touches).
    pub friction_ratio: f64,
    /// The power of its contact forces (the energy audit's integrand).
    pub power: ContactPower,
}

/// One particle's share of its tool's [`ContactPower`]: with v_T = `st.velocity_at(x)`, the tool's
/// power (f_c + f_t)·v_T, the friction's f_t·(v_T − v) and the penalty's f_c·(v_T − v) (f64, as the sample's sums).
fn contact_power<R: Real, V: Vector<R>>(st: &ToolState, x: &V, v: &V, fc: &V, ft: &V) -> ContactPower {
    let wide = |u: &V| -> [f64; 3] { std::array::from_fn(|k| u.get(k).to_f64()) };
    let (fc, ft, v) = (wide(fc), wide(ft), wide(v));
    let vt = st.velocity_at(wide(x));
    let dot = |a: &[f64; 3], b: &[f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let slip: [f64; 3] = std::array::from_fn(|k| vt[k] - v[k]);
    ContactPower { tool: dot(&fc, &vt) + dot(&ft, &vt), friction: dot(&ft, &slip), normal: dot(&fc, &slip) }
}

/// Start-of-step copies y0 (reordered with the state each step).
struct Start<B: Backend, R: Real, D: Dim> {
    pos: Field<B, D::Vec<R>>,
    vel: Field<B, D::Vec<R>>,
    rho: Field<B, R>,
    stress: Field<B, D::Sym<R>>,
}

impl<B: Backend, R: Real, D: Dim> Start<B, R, D> {
    fn fields(&mut self) -> FieldsMut<'_, B, R, D> {
        FieldsMut {
            pos: &mut self.pos.cur,
            vel: &mut self.vel.cur,
            rho: &mut self.rho.cur,
            stress: &mut self.stress.cur,
        }
    }
}

/// The integrated fields x, v, ρ, S of a `Particles` (a macro: the caller keeps its other fields borrowable).
macro_rules! state_mut {
    ($p:expr) => {
        FieldsMut { pos: &mut $p.pos.cur, vel: &mut $p.vel.cur, rho: &mut $p.rho.cur, stress: &mut $p.stress.cur }
    };
}

/// Rates ẏ (in the order of the last interaction).
pub struct Rates<B: Backend, R: Real, D: Dim> {
    pub pos: B::Buf<D::Vec<R>>,
    pub vel: B::Buf<D::Vec<R>>,
    pub rho: B::Buf<R>,
    pub stress: B::Buf<D::Sym<R>>,
}

impl<B: Backend, R: Real, D: Dim> Rates<B, R, D> {
    fn fields(&self) -> FieldsRef<'_, B, R, D> {
        FieldsRef { pos: &self.pos, vel: &self.vel, rho: &self.rho, stress: &self.stress }
    }
}

pub struct Solver<B: Backend, R: Real, D: TensorOps<R>> {
    pub particles: Particles<B, R, D>,
    pub rates: Rates<B, R, D>,
    start: Start<B, R, D>,
    sig: B::Buf<D::Sym<R>>,
    art: Option<B::Buf<D::Sym<R>>>,
    sound: Option<B::Buf<R>>,
    /// V = m/ρ of the pre-pass with the full masses, read by the interaction and the conduction instead of a
    /// division per pair.
    vol: B::Buf<R>,
    /// The viscosity's Balsara factors (with the switch): written by the interaction, read by the next pre-pass.
    av_switch: Option<Field<B, R>>,
    /// The CSPM correction of the step's correction pass (with CSPM).
    correction: Option<Correction<B, R, D>>,
    pub cells: CellList<B>,
    /// Each particle's predicted position when the cell list was last built (sorted order), for the skin test.
    pos_ref: B::Buf<D::Vec<R>>,
    /// With blanking: each particle's velocity when the cell list was last built, which its hash read (the box's
    /// rest speed), so that a restored state rebuilds the same cells.
    vel_ref: Option<B::Buf<D::Vec<R>>>,
    /// The next step rebuilds the cell list whatever the skin test says (the first step, a restored state
    /// without its reference positions).
    force_rebuild: bool,
    /// The blanking's box and the jumps it had made by the last step whose scalars were written.
    blanking: Option<(blanking::Blanking, i64)>,
    params: B::Buf<SphParams<R>>,
    pub host_params: SphParams<R>,
    bc_vel: B::Buf<D::Vec<R>>,
    /// Load reversals of the prescribed velocities (None when no boundary has `reverse_at`).
    reversal: Option<Reversal<R, D>>,
    /// Temperature (present with heat or plasticity).
    temp: Option<Field<B, f64>>,
    /// The low parts of the positions (mixed precision): the start position of a step is pos0 + pos_lo, its end
    /// pos + pos_lo, and the corrector's sum is compensated (`sph::integrate::advance_compensated`).
    pos_lo: Option<Field<B, D::Vec<R>>>,
    thermal: Option<ThermalState<B>>,
    plastic: Option<PlasticState<B>>,
    damage: Option<DamageState<B>>,
    cohesive: Option<CohesiveState<B, R, D>>,
    contact: Option<ContactState<B, R, D>>,
    /// Masses for the mechanics where they differ from the particles' masses: zero for thermal-only particles.
    mech_mass: Option<Field<B, R>>,
    /// The artificial viscosity's accumulated dissipation per unit mass [J/kg] and its rate (with AV), for the
    /// energy balance.
    dissipation: Option<(Field<B, f64>, B::Buf<R>)>,
    shear: f64,
    pub stab: Stabilisers,
    /// Scalars of the next steps (Δt, the tool), read by the step's kernels.
    scalars: B::Buf<StepScalars>,
    host_scalars: Vec<StepScalars>,
    /// Captured batches of GRAPH_STEPS steps, by the address of the position buffer they start from.
    graphs: Vec<(u64, B::Graph)>,
    /// Steps run one by one so far (the first uploads the reorder tables a capture needs).
    plain_steps: u64,
    /// Run batches as captured graphs where the backend has them (`SWARF_NO_GRAPHS=1` turns them off).
    pub use_graphs: bool,
    /// Threads (lanes) per particle in the pair interaction and the conduction pass: 1, 2, 4 or 8
    /// ([`default_lanes`]; `SWARF_LANES`). The order of the sums depends on it, the same on every backend.
    pub lanes: u32,
    /// Sum the Brookshaw conduction in the interaction's neighbour walk (`sph::interact::rates_heat`) instead of a
    /// pass of its own; the results are bitwise the same. On unless `SWARF_NO_FUSE=1` (benchmarks compare both).
    pub fuse_conduction: bool,
    /// The contact pass in the plastic corrector's launch ([`Passes::step_finish`]) rather than a pass of its own;
    /// the results are bitwise the same. On unless `SWARF_NO_FUSE_CONTACT=1` (benchmarks compare both).
    pub fuse_contact: bool,
    /// The pre-pass in the predictor's launch ([`Passes::step_predict`]), its own gated launch only after a
    /// rebuild; the results are bitwise the same. On unless `SWARF_NO_FUSE_PREPARE=1` (benchmarks compare both).
    pub fuse_prepare: bool,
    /// The IF node handle of the step being captured (`Backend::rebuild_condition`; 0 otherwise).
    condition: u64,
    pub n: usize,
    pub time: f64,
    pub steps: u64,
}

/// The load reversals of a run: the prescribed-velocity table as set up, each entry's reversal times, and the
/// signs in force (the table on the device is the base times these signs).
struct Reversal<R: Real, D: TensorOps<R>> {
    base: Vec<D::Vec<R>>,
    times: Vec<Vec<f64>>,
    signs: Vec<f64>,
}

impl<R: Real, D: TensorOps<R>> Reversal<R, D> {
    fn new(setup: &Setup<R, D>) -> Option<Self> {
        let times = setup.bc_reversals.clone();
        times.iter().any(|t| !t.is_empty()).then(|| Reversal {
            base: setup.bc_velocities.clone(),
            signs: vec![1.0; times.len()],
            times,
        })
    }

    /// Whether a reversal time lies in (t0, t1].
    fn any_in(&self, t0: f64, t1: f64) -> bool {
        self.times.iter().flatten().any(|&r| t0 < r && r <= t1)
    }
}

/// The phases of a step, in order (`Solver::profile_step` times each).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Predictor with the skin test.
    Predict,
    /// The cell list's gated rebuild: count, scan, scatter and per-cell sort (when the step rebuilds).
    CellList,
    /// Every per-particle field gathered and copied back, two launches, then the Verlet list built on the sorted
    /// particles (when the step rebuilds).
    Reorder,
    /// σ/ρ², artificial stress, sound speed, volume.
    Prepare,
    /// The pair interaction.
    Interact,
    /// Heat conduction (when on).
    Conduction,
    /// Corrector fused with the plastic update.
    Correct,
    /// The tool's contact pass (with a tool).
    Contact,
}

impl Phase {
    pub const ALL: [Phase; 8] = [
        Phase::Predict,
        Phase::CellList,
        Phase::Reorder,
        Phase::Prepare,
        Phase::Interact,
        Phase::Conduction,
        Phase::Correct,
        Phase::Contact,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Phase::Predict => "predict",
            Phase::CellList => "cell list",
            Phase::Reorder => "reorder",
            Phase::Prepare => "pre-pass",
            Phase::Interact => "interaction",
            Phase::Conduction => "conduction",
            Phase::Correct => "correct+plastic",
            Phase::Contact => "contact",
        }
    }
}

/// Lanes per particle of the pair interaction and the conduction pass for a run of `n` particles in `dim`
/// dimensions: eight below LANES_8_BELOW particles, where one thread per particle leaves the GPU idle
/// (docs/measurements/notebook.md, "Lanes per particle"); above it one in 2D, and two in 3D, whose 165 neighbours
/// per particle keep two lanes busy: on an H200 the 2 M and 107k single grains step 7 % and 11 % faster with two
/// than with one (docs/neighbour-search.md, "Wide offsets").
pub fn default_lanes(n: usize, dim: usize) -> u32 {
    match (n < LANES_8_BELOW, dim) {
        (true, _) => 8,
        (false, 3) => 2,
        (false, _) => 1,
    }
}

/// The particle count below which eight lanes per particle pay (measured: docs/measurements/notebook.md).
pub const LANES_8_BELOW: usize = 50_000;

/// Steps per captured graph (one graph launch for this many steps; the step scalars hold one entry per step).
pub const GRAPH_STEPS: usize = 32;

/// The thermal materials of a thermal state, and its conduction predictor–corrector's (T0, Ṫ) when it conducts.
#[allow(clippy::type_complexity)]
fn thermal_views<B: Backend>(
    th: Option<&mut ThermalState<B>>,
) -> (Option<&B::Buf<ThermalMaterial>>, Option<Conduction<'_, B>>) {
    match th {
        Some(ThermalState { materials, temp0, temp_t, .. }) => (
            Some(&*materials),
            match (temp0.as_mut(), temp_t.as_ref()) {
                (Some(t0), Some(tt)) => Some((&mut t0.cur, tt)),
                _ => None,
            },
        ),
        None => (None, None),
    }
}

/// The conduction inputs of the separate and the fused pass; `vol` from the pre-pass (full masses: the tool's
/// particles conduct).
fn heat_inputs<'a, B: Backend, R: Real, D: TensorOps<R>>(
    p: &'a Particles<B, R, D>,
    vol: &'a B::Buf<R>,
    temp: &'a B::Buf<f64>,
    materials: &'a B::Buf<ThermalMaterial>,
) -> HeatInputs<'a, B, R, D> {
    HeatInputs { pos: &p.pos.cur, rho: &p.rho.cur, vol, temp, flags: &p.flags.cur, materials }
}

/// The thermal state of a run with heat physics: the materials, the PSE grid (the ±3 stencil) and, when it
/// conducts, the conduction predictor–corrector's (T0, Ṫ).
fn thermal_state<B: Backend, R: Real, D: TensorOps<R>>(
    b: &B,
    setup: &Setup<R, D>,
    n: usize,
) -> Result<Option<ThermalState<B>>> {
    let Some(t) = &setup.thermal else { return Ok(None) };
    let mut g = setup.grid;
    g.stencil = 3;
    if g.period > 0.0 && g.dims[2] < 7 && t.conduction == Some(true) {
        return Err(crate::Error::Scene(format!(
            "PSE conduction's ±3 stencil needs a z period of at least 7 cells ({:e} m); this one has {}",
            7.0 * g.cell_size,
            g.dims[2]
        )));
    }
    // PSE reaches beyond the Verlet list: it walks the stencil.
    g.list_capacity = 0;
    let conducting = When::Conduction.holds(setup);
    let zeros_f = vec![0.0f64; n];
    Ok(Some(ThermalState {
        temp0: if conducting { Some(Field::upload(b, &zeros_f, "temperature")?) } else { None },
        temp_t: if conducting { Some(b.alloc(n, "temperature rate")?) } else { None },
        materials: b.upload(&t.materials, "thermal materials")?,
        heat: t.heat,
        conduction: t.conduction,
        grid_pse: b.upload(&[g], "grid")?,
    }))
}

/// The plastic state of a run with plasticity: ε̄, ε̄̇ and the plastic work, zero at the start.
fn plastic_state<B: Backend, R: Real, D: TensorOps<R>>(
    b: &B,
    setup: &Setup<R, D>,
    n: usize,
) -> Result<Option<PlasticState<B>>> {
    let Some(p) = &setup.plastic else { return Ok(None) };
    let zeros_f = vec![0.0f64; n];
    Ok(Some(PlasticState {
        eps: Field::upload(b, &zeros_f, "plastic strain")?,
        rate: Field::upload(b, &zeros_f, "plastic strain rate")?,
        work: Field::upload(b, &zeros_f, "plastic work")?,
        model: p.model,
        taylor_quinney: p.taylor_quinney,
        return_flags: p.return_flags,
    }))
}

/// The damage state of a run with damage: its constants on the device, ω and D from the set-up (the pre-crack),
/// the mask 1 until the first pre-pass.
fn damage_state<B: Backend, R: Real, D: TensorOps<R>>(
    b: &B,
    setup: &Setup<R, D>,
    n: usize,
) -> Result<Option<DamageState<B>>> {
    let Some(d) = &setup.damage else { return Ok(None) };
    if setup.plastic.is_none() {
        return Err(crate::Error::Scene("damage needs plasticity (a flow-stress model)".into()));
    }
    if d.omega.len() != n || d.damage.len() != n {
        return Err(crate::Error::Length { op: "damage initial state", expected: n, got: d.omega.len() });
    }
    Ok(Some(DamageState {
        params: b.upload(&[d.params], "damage parameters")?,
        flags: d.params.flags,
        omega: Field::upload(b, &d.omega, "damage initiation")?,
        damage: Field::upload(b, &d.damage, "damage")?,
        mask: b.upload(&vec![1.0f64; n], "damage mask")?,
        work: Field::upload(b, &vec![0.0f64; n], "damage work")?,
    }))
}

/// The cohesive path's state: the bonds as set up, a fresh history and no work.
fn cohesive_state<B: Backend, R: Real, D: TensorOps<R>>(
    b: &B,
    setup: &Setup<R, D>,
    n: usize,
) -> Result<Option<CohesiveState<B, R, D>>> {
    let Some(c) = &setup.cohesive else { return Ok(None) };
    if c.partner.len() != n || c.reference.len() != n {
        return Err(crate::Error::Length { op: "cohesive bonds", expected: n, got: c.partner.len() });
    }
    let reference: Vec<D::Vec<R>> =
        c.reference.iter().map(|x| D::Vec::<R>::new(std::array::from_fn(|k| R::from_f64(x[k])))).collect();
    Ok(Some(CohesiveState {
        params: c.params,
        partner: Field::upload(b, &c.partner, "bond partners")?,
        reference: Field::upload(b, &reference, "bond reference offsets")?,
        state: Field::upload(b, &vec![[R::ZERO; 8]; n], "bond states")?,
        onset: Field::upload(b, &vec![[R::ZERO; 4]; n], "bond onsets")?,
        column: Field::upload(b, &c.column, "bond columns")?,
        work: Field::upload(b, &vec![0.0f64; n], "bond work")?,
        damping: Field::upload(b, &vec![0.0f64; n], "bond damping")?,
        index: b.alloc(n, "bond index")?,
    }))
}

/// Refuses a contact set-up the run cannot honour: a mesh tool in a scene that is not 3D, the current-yield cap
/// without plasticity, friction heating without heat.
fn check_contact<R: Real, D: TensorOps<R>>(setup: &Setup<R, D>, c: &ContactSetup) -> Result<()> {
    if D::D != 3 && c.tools.iter().any(|t| t.shape.parametric().is_none()) {
        return Err(crate::Error::Scene("a mesh tool needs a 3D scene".into()));
    }
    if c.tools.is_empty() {
        return Err(crate::Error::Scene("a contact set-up needs a tool".into()));
    }
    if When::CurrentCap.holds(setup) && setup.plastic.is_none() {
        return Err(crate::Error::Scene("the current-yield friction cap needs plasticity".into()));
    }
    if c.tools.iter().any(|t| t.params.heat_fraction > 0.0) && (setup.thermal.is_none() || setup.temperature.is_none())
    {
        return Err(crate::Error::Scene("friction heating needs the thermal model".into()));
    }
    Ok(())
}

/// The contact state of a run with a tool: its constants, shape and motion on the device, the contact and
/// friction forces, and the fields only some laws need (σ_y for the current cap, the wear rate).
fn contact_state<B: Backend, R: Real, D: TensorOps<R>>(
    b: &B,
    setup: &Setup<R, D>,
    n: usize,
    bc_table: &[D::Vec<R>],
) -> Result<Option<ContactState<B, R, D>>> {
    let Some(c) = &setup.contact else { return Ok(None) };
    check_contact(setup, c)?;
    let zeros_v = vec![D::Vec::<R>::default(); n];
    let params: Vec<ContactParams> = c.tools.iter().map(|t| t.params).collect();
    let shapes: Vec<&crate::tool::Shape> = c.tools.iter().map(|t| &t.shape).collect();
    let k = c.tools.len();
    Ok(Some(ContactState {
        tools: DeviceTools::upload(b, &params, &shapes)?,
        pictures: c.tools.iter().map(|t| t.shape.picture()).collect(),
        motions: c.tools.iter().map(|t| t.motion).collect(),
        states: b.alloc(GRAPH_STEPS * k, "tool states")?,
        host_states: vec![ToolState::default(); GRAPH_STEPS * k],
        owner: if k > 1 { Some(Field::upload(b, &vec![0u32; n], "contact owners")?) } else { None },
        normal: Field::upload(b, &zeros_v, "contact forces")?,
        friction: Field::upload(b, &zeros_v, "friction forces")?,
        yield_stress: if When::CurrentCap.holds(setup) { Some(b.alloc(n, "yield stress")?) } else { None },
        wear: if When::Wear.holds(setup) { Some(b.alloc(n, "wear rate")?) } else { None },
        tool_velocity_index: c.tool_velocity_index,
        heating: c.tools.iter().any(|t| t.params.heat_fraction > 0.0),
        nominal_dt: setup.dt,
        bc_table: bc_table.to_vec(),
    }))
}

/// The mechanical mass, zero for the thermal-only particles (allocated only when such particles exist), so that
/// every pair term with one vanishes exactly.
fn mechanical_mass<B: Backend, R: Real, D: TensorOps<R>>(b: &B, setup: &Setup<R, D>) -> Result<Option<Field<B, R>>> {
    if !When::ThermalOnly.holds(setup) {
        return Ok(None);
    }
    let p = &setup.particles;
    let m: Vec<R> =
        p.mass.iter().zip(&p.flags).map(|(&m, &f)| if f & flags::THERMAL_ONLY != 0 { R::ZERO } else { m }).collect();
    Ok(Some(Field::upload(b, &m, "mechanical mass")?))
}

impl<B: Backend, R: Real, D: TensorOps<R>> Solver<B, R, D> {
    /// Uploads the particles and allocates what the chosen physics needs.
    pub fn new(b: &B, setup: &Setup<R, D>) -> Result<Self> {
        let particles = &setup.particles;
        let n = particles.len();
        let stab = setup.stabilisers.switches();
        let zeros_v = vec![D::Vec::<R>::default(); n];
        let zeros_r = vec![R::ZERO; n];
        let zeros_s = vec![D::Sym::<R>::default(); n];
        let zeros_f = vec![0.0f64; n];
        let bc_vel = &setup.bc_velocities;
        let table: Vec<D::Vec<R>> = if bc_vel.is_empty() { vec![Default::default()] } else { bc_vel.to_vec() };
        let temp = match &setup.temperature {
            Some(t) => Some(Field::upload(b, t, "temperature")?),
            None => None,
        };
        let thermal = thermal_state(b, setup, n)?;
        let plastic = plastic_state(b, setup, n)?;
        let damage = damage_state(b, setup, n)?;
        let cohesive = cohesive_state(b, setup, n)?;
        let contact = contact_state(b, setup, n, &table)?;
        let mech_mass = mechanical_mass(b, setup)?;
        if (plastic.is_some() || thermal.is_some()) && temp.is_none() {
            return Err(crate::Error::Scene("plasticity and heat need a temperature field".into()));
        }
        Ok(Solver {
            particles: Particles::upload(b, particles)?,
            rates: Rates {
                pos: b.alloc(n, "rates")?,
                vel: b.alloc(n, "rates")?,
                rho: b.alloc(n, "rates")?,
                stress: b.alloc(n, "rates")?,
            },
            start: Start {
                pos: Field::upload(b, &zeros_v, "start-of-step state")?,
                vel: Field::upload(b, &zeros_v, "start-of-step state")?,
                rho: Field::upload(b, &zeros_r, "start-of-step state")?,
                stress: Field::upload(b, &zeros_s, "start-of-step state")?,
            },
            sig: b.alloc(n, "stress over density squared")?,
            art: if When::ArtificialStress.holds(setup) { Some(b.alloc(n, "artificial stress")?) } else { None },
            sound: if When::Viscosity.holds(setup) { Some(b.alloc(n, "sound speed")?) } else { None },
            vol: b.alloc(n, "particle volume")?,
            // Full viscosity until the first interaction has a velocity gradient.
            av_switch: if When::AvSwitch.holds(setup) {
                Some(Field::upload(b, &vec![R::ONE; n], "viscosity switch")?)
            } else {
                None
            },
            correction: match setup.stabilisers.cspm {
                Some(c) => Some(Correction {
                    buf: b.alloc(n, "CSPM correction")?,
                    min_det: R::from_f64(c.min_det),
                    path_only: c.path_only,
                }),
                None => None,
            },
            cells: CellList::with_blanking(b, setup.grid, n, setup.blanking.is_some())?,
            pos_ref: b.alloc(n, "cell-list reference positions")?,
            vel_ref: if When::Blanking.holds(setup) {
                Some(b.alloc(n, "cell-list reference velocities")?)
            } else {
                None
            },
            force_rebuild: true,
            blanking: setup.blanking.map(|bl| (bl, 0)),
            params: b.upload(&[setup.params], "SPH parameters")?,
            host_params: setup.params,
            bc_vel: b.upload(&table, "boundary velocities")?,
            reversal: Reversal::new(setup),
            temp,
            pos_lo: match &setup.pos_lo {
                Some(lo) => Some(Field::upload(b, lo, "position low parts")?),
                None => None,
            },
            thermal,
            plastic,
            damage,
            cohesive,
            contact,
            mech_mass,
            dissipation: if When::Viscosity.holds(setup) {
                Some((Field::upload(b, &zeros_f, "viscous dissipation")?, b.alloc(n, "viscous dissipation rate")?))
            } else {
                None
            },
            shear: setup.shear,
            stab,
            scalars: b.alloc(GRAPH_STEPS, "step scalars")?,
            host_scalars: vec![StepScalars::default(); GRAPH_STEPS],
            graphs: Vec::new(),
            plain_steps: 0,
            use_graphs: !setup.tuning.no_graphs,
            fuse_conduction: !setup.tuning.no_fuse,
            fuse_contact: !setup.tuning.no_fuse_contact,
            fuse_prepare: !setup.tuning.no_fuse_prepare,
            condition: 0,
            lanes: setup.tuning.lanes.unwrap_or_else(|| default_lanes(n, D::D)),
            n,
            time: 0.0,
            steps: 0,
        })
    }

    /// The pre-pass runs inside the predictor's launch (`Passes::step_predict`; without thermal expansion, whose
    /// EOS reads the temperature), and its own launch only after a rebuild's reorder.
    fn fused_prepare(&self) -> bool {
        self.fuse_prepare && self.host_params.expansion == R::ZERO
    }

    /// The contact pass runs inside the plastic corrector's launch (`Passes::step_finish`; 2D with plasticity, the
    /// cutting runs), not in one of its own.
    fn fused_contact(&self) -> bool {
        self.fuse_contact
            && self.contact.as_ref().is_some_and(|c| c.tools.count() == 1 && c.tools.prisms().is_some())
            && self.plastic.is_some()
            && D::D == 2
    }

    /// Whether the interaction pass sums the conduction: Brookshaw conduction (on the interaction's own cell
    /// list; PSE needs the wider stencil) and fusion on.
    fn fused_conduction(&self) -> bool {
        self.fuse_conduction && self.thermal.as_ref().is_some_and(|th| th.conduction == Some(false))
    }

    /// One step of length `dt`.
    pub fn step(&mut self, b: &B, dt: f64) -> Result<()> {
        self.ramp_tool(b, dt)?;
        self.reverse_loads(b, self.time + 0.5 * dt)?;
        self.fill_scalars(b, dt, 1)?;
        self.step_at(b, dt, 0)?;
        self.plain_steps += 1;
        Ok(())
    }

    /// `count` steps of length `dt`, equal to `count` calls of [`Solver::step`]. On a backend with graphs the
    /// steps run in captured batches of [`GRAPH_STEPS`] (one launch per batch; captured once, after plain steps
    /// have uploaded the reorder tables: the in-place reorder keeps every buffer's address, so one graph serves).
    pub fn advance(&mut self, b: &B, dt: f64, mut count: usize) -> Result<()> {
        while count > 0 {
            let batch = (GRAPH_STEPS + 1) as f64 * dt;
            let reversing = self.reversal.as_ref().is_some_and(|r| r.any_in(self.time - dt, self.time + batch));
            if reversing || self.ramping() || count < GRAPH_STEPS || self.plain_steps < 2 || !self.use_graphs {
                self.step(b, dt)?;
                count -= 1;
                continue;
            }
            self.fill_scalars(b, dt, GRAPH_STEPS)?;
            let key = b.address(&self.particles.pos.cur);
            if let Some((_, g)) = self.graphs.iter().find(|(k, _)| *k == key) {
                b.replay(g)?;
                for _ in 0..GRAPH_STEPS {
                    self.time += dt;
                }
                self.steps += GRAPH_STEPS as u64;
            } else {
                let mut run = || -> Result<()> {
                    for j in 0..GRAPH_STEPS {
                        self.step_at(b, dt, j)?;
                    }
                    Ok(())
                };
                // A backend without graphs ran the steps; a capture only recorded them (and advanced the host's
                // bookkeeping), so the graph runs them now.
                if let Some(g) = b.capture(&mut run)? {
                    b.replay(&g)?;
                    self.graphs.push((key, g));
                }
                if b.address(&self.particles.pos.cur) != key {
                    return Err(crate::Error::Grid("a captured batch must leave the buffers as it found them".into()));
                }
            }
            count -= GRAPH_STEPS;
        }
        Ok(())
    }

    /// The tool's prescribed velocity is being ramped up, or its table entry does not yet hold the final velocity
    /// (the last ramp step wrote its own midpoint's): steps then run one by one, the table is rewritten.
    fn ramping(&self) -> bool {
        self.contact.as_ref().is_some_and(|c| {
            let m = &c.motions[0];
            c.tool_velocity_index.is_some_and(|k| {
                let final_held = (0..D::D).all(|i| c.bc_table[k].get(i) == R::from_f64(m.velocity[i]));
                m.ramp > 0.0 && (self.time < m.ramp || !final_held)
            })
        })
    }

    fn ramp_tool(&mut self, b: &B, dt: f64) -> Result<()> {
        if !self.ramping() {
            return Ok(());
        }
        if let Some(c) = self.contact.as_mut()
            && let Some(k) = c.tool_velocity_index
        {
            // The tool particles follow the ramp: their prescribed velocity at this step's midpoint (the final
            // velocity once the midpoint is past the ramp).
            let v = c.motions[0].velocity_at(self.time + 0.5 * dt);
            c.bc_table[k] = D::Vec::<R>::new(v.map(R::from_f64));
            b.write(&mut self.bc_vel, &c.bc_table)?;
        }
        Ok(())
    }

    /// The prescribed velocities with the signs of the boundaries' `reverse_at` at time `t` (a step's midpoint):
    /// the table is rewritten when a sign changed (in the contact's host copy too, which the ramp rewrites).
    fn reverse_loads(&mut self, b: &B, t: f64) -> Result<()> {
        let Some(r) = self.reversal.as_mut() else { return Ok(()) };
        let sign = |ts: &[f64]| crate::scene::Boundary::sign_at(ts, t);
        // Compared in place: no allocation on the steps without a reversal.
        if r.times.iter().zip(&r.signs).all(|(ts, &s)| sign(ts) == s) {
            return Ok(());
        }
        r.signs = r.times.iter().map(|ts| sign(ts)).collect();
        let mut table = self.contact.as_ref().map_or_else(|| r.base.clone(), |c| c.bc_table.clone());
        for k in (0..r.times.len()).filter(|&k| !r.times[k].is_empty()) {
            let v = r.base[k];
            table[k] = D::Vec::<R>::new(std::array::from_fn(|c| R::from_f64(v.get(c).to_f64() * r.signs[k])));
        }
        b.write(&mut self.bc_vel, &table)?;
        // The step moves a prescribed particle with the table's velocity but keeps its own (the initial one), which
        // its neighbours' velocity gradients read: the reversed particles get the new velocity too.
        let reversed: Vec<bool> = r.times.iter().map(|ts| !ts.is_empty()).collect();
        let fl = b.read(&self.particles.flags.cur)?;
        let mut vel = b.read(&self.particles.vel.cur)?;
        for (v, f) in vel.iter_mut().zip(&fl) {
            let k = ((f >> flags::VEL_INDEX_SHIFT) & flags::VEL_INDEX_MASK) as usize;
            if f & flags::KIND_MASK == flags::VELOCITY && reversed.get(k).copied().unwrap_or(false) {
                *v = table[k];
            }
        }
        b.write(&mut self.particles.vel.cur, &vel)?;
        if let Some(c) = self.contact.as_mut() {
            c.bc_table = table;
        }
        Ok(())
    }

    /// Writes the scalars of the next `count` steps of length `dt` (their Δt and the tool's state at each step's
    /// end, on the time line the host's `time += dt` makes).
    fn fill_scalars(&mut self, b: &B, dt: f64, count: usize) -> Result<()> {
        let force = std::mem::take(&mut self.force_rebuild);
        let mut contact = self.contact.as_mut();
        // Each step's end on the host's time line: its tool states, its blanking box (a step at which the box
        // jumps rebuilds).
        let mut t = self.time;
        for (j, s) in self.host_scalars[..count].iter_mut().enumerate() {
            t += dt;
            *s = StepScalars { dt, rebuild: (j == 0 && force) as u32, ..Default::default() };
            if let Some((bl, jumps)) = self.blanking.as_mut() {
                s.blank = bl.box_at(t);
                let now = bl.jumps(t);
                if now != *jumps {
                    s.rebuild = 1;
                    *jumps = now;
                }
            }
            if let Some(c) = contact.as_mut() {
                let k = c.motions.len();
                for (st, m) in c.host_states[j * k..(j + 1) * k].iter_mut().zip(&c.motions) {
                    *st = m.state_at(t, dt.max(c.nominal_dt), dt);
                }
            }
        }
        if let Some(c) = contact {
            b.write(&mut c.states, &c.host_states[..count * c.motions.len()])?;
        }
        b.write(&mut self.scalars, &self.host_scalars[..count])
    }

    /// One step of length `dt` whose scalars are entry `j` of the scalar buffer. Submits launches only (no copy,
    /// no synchronisation), so that it can be captured.
    fn step_at(&mut self, b: &B, dt: f64, j: usize) -> Result<()> {
        // The handle lives in the graph being captured: no launch outside it may see it.
        self.condition = b.rebuild_condition()?;
        let submitted = self.step_phases(b, j);
        self.condition = 0;
        submitted?;
        self.time += dt;
        self.steps += 1;
        Ok(())
    }

    /// The phases of the step whose scalars are entry `j`.
    fn step_phases(&mut self, b: &B, j: usize) -> Result<()> {
        for ph in Phase::ALL {
            match ph {
                // The rebuild's launches, gated on this step's flag, as one unit: a captured step skips them all
                // when the flag is 0 (`Backend::rebuild_gated`).
                Phase::CellList => {
                    let (condition, prepare) = (self.condition, self.fused_prepare());
                    b.rebuild_gated(condition, &mut || {
                        self.phase(b, Phase::CellList, j)?;
                        self.phase(b, Phase::Reorder, j)?;
                        // Fused into the predictor, the pre-pass is needed again only after the reorder.
                        if prepare { self.phase(b, Phase::Prepare, j) } else { Ok(()) }
                    })?;
                }
                Phase::Reorder => {}
                Phase::Prepare if self.fused_prepare() => {}
                _ => self.phase(b, ph, j)?,
            }
        }
        Ok(())
    }

    /// Submits one phase of the step whose scalars are entry `j`.
    fn phase(&mut self, b: &B, ph: Phase, j: usize) -> Result<()> {
        match ph {
            Phase::Predict => self.predict(b, j),
            Phase::CellList => {
                let gate = ScalarsAt { buf: &self.scalars, index: j };
                self.cells.rebuild::<R, D>(b, &self.particles.pos.cur, &self.particles.vel.cur, gate)
            }
            Phase::Reorder => {
                // On the stack, fixed capacity: the step loop allocates nothing.
                let mut batch = ReorderBatch::default();
                self.stage_fields(b, &mut batch);
                // The binned positions: the skin test's reference until the next rebuild.
                batch.snapshot(b, &self.particles.pos.cur, &mut self.pos_ref);
                if let Some(v) = self.vel_ref.as_mut() {
                    batch.snapshot(b, &self.particles.vel.cur, v);
                }
                batch.run(b, self.n, &self.cells.perm, ScalarsAt { buf: &self.scalars, index: j })?;
                self.cells.build_list::<R, D>(b, &self.pos_ref, Some(ScalarsAt { buf: &self.scalars, index: j }))
            }
            Phase::Prepare => self.prepare(b, j),
            Phase::Interact => self.interact(b),
            Phase::Conduction => self.conduction(b),
            Phase::Correct => self.correct(b, j),
            Phase::Contact => self.contact_pass(b, j),
        }
    }

    /// The predictor, with the pre-pass fused where [`Solver::fused_prepare`].
    fn predict(&mut self, b: &B, j: usize) -> Result<()> {
        let (n, fuse_prepare) = (self.cells.count(), self.fused_prepare());
        let (p, s) = (&mut self.particles, &mut self.start);
        let r = &self.rates;
        let (_, conduction) = thermal_views(self.thermal.as_mut());
        b.step_predict::<R, D>(
            n,
            ScalarsMut { buf: &mut self.scalars, index: j },
            StepFields {
                y: state_mut!(p),
                y0: s.fields(),
                rates: r.fields(),
                temp: if conduction.is_some() { self.temp.as_mut().map(|t| &mut t.cur) } else { None },
                conduction,
                dissipation: None,
                pos_lo: None,
            },
            SkinTest { grid: &self.cells.grid_buf, pos_ref: &self.pos_ref, condition: self.condition },
            fuse_prepare.then_some(FusedPrepare {
                stab: self.stab,
                params: &self.host_params,
                mass: &p.mass.cur,
                out: PrepassBufs {
                    sig: &mut self.sig,
                    art: self.art.as_mut(),
                    sound: self.sound.as_mut(),
                    vol: &mut self.vol,
                    av_switch: self.av_switch.as_ref().map(|f| &f.cur),
                },
                damage: self.damage.as_mut().map(|d| PrepassDamageBufs {
                    damage: &d.damage.cur,
                    mask: &mut d.mask,
                    flags: d.flags,
                }),
            }),
        )?;
        Ok(())
    }

    /// The pre-pass (σ/ρ², the stabilisers, the volumes).
    fn prepare(&mut self, b: &B, j: usize) -> Result<()> {
        let (n, fuse_prepare) = (self.cells.count(), self.fused_prepare());
        let p = &mut self.particles;
        b.sph_prepare::<R, D>(
            n,
            self.stab,
            &self.params,
            &p.rho.cur,
            // The full masses: the thermal-only particles' volumes serve the conduction.
            &p.mass.cur,
            &p.stress.cur,
            PrepassBufs {
                sig: &mut self.sig,
                art: self.art.as_mut(),
                sound: self.sound.as_mut(),
                vol: &mut self.vol,
                av_switch: self.av_switch.as_ref().map(|f| &f.cur),
            },
            if self.host_params.expansion != R::ZERO { self.temp.as_ref().map(|t| &t.cur) } else { None },
            // Fused into the predictor, the pass runs again only after a rebuild's reorder.
            fuse_prepare.then_some(ScalarsAt { buf: &self.scalars, index: j }),
            self.damage.as_mut().map(|d| PrepassDamageBufs {
                damage: &d.damage.cur,
                mask: &mut d.mask,
                flags: d.flags,
            }),
        )?;
        Ok(())
    }

    /// The pair interaction, with the conduction fused where [`Solver::fused_conduction`].
    fn interact(&mut self, b: &B) -> Result<()> {
        let (n, fused) = (self.cells.count(), self.fused_conduction());
        let p = &mut self.particles;
        let input = SphInputs::<B, R, D> {
            pos: &p.pos.cur,
            vel: &p.vel.cur,
            rho: &p.rho.cur,
            mass: self.mech_mass.as_ref().map_or(&p.mass.cur, |m| &m.cur),
            vol: &self.vol,
            stress: &p.stress.cur,
            sig: &self.sig,
            art: self.art.as_ref(),
            sound: self.sound.as_ref(),
            flags: &p.flags.cur,
            bc_vel: &self.bc_vel,
            contact: self.contact.as_ref().map(|c| (&c.normal.cur, &c.friction.cur)),
            mask: self.damage.as_ref().map(|d| &d.mask),
            correction: None,
            cut: self.cohesive.is_some(),
        };
        if let Some(Correction { buf: out, min_det, path_only }) = self.correction.as_mut() {
            b.sph_correction::<R, D>(
                n,
                self.lanes,
                &self.host_params,
                *min_det,
                *path_only,
                &self.cells.grid_buf,
                &self.cells.starts,
                self.cells.list.as_ref(),
                &input,
                out,
            )?;
        }
        let input = SphInputs { correction: self.correction.as_ref().map(|c| &c.buf), ..input };
        let r = &mut self.rates;
        let heat = match (fused, self.temp.as_ref(), self.thermal.as_mut()) {
            (true, Some(t), Some(th)) => th.temp_t.as_mut().map(|tt| FusedHeat {
                params: &th.heat,
                input: heat_inputs(p, &self.vol, &t.cur, &th.materials),
                temp_t: tt,
            }),
            _ => None,
        };
        b.sph_rates::<R, D>(
            n,
            self.lanes,
            self.stab,
            &self.host_params,
            &self.cells.grid_buf,
            &self.cells.starts,
            self.cells.list.as_ref(),
            &input,
            FieldsMut { pos: &mut r.pos, vel: &mut r.vel, rho: &mut r.rho, stress: &mut r.stress },
            self.dissipation.as_mut().map(|(_, rate)| rate),
            self.av_switch.as_mut().map(|f| &mut f.cur),
            heat,
        )?;
        if let Some(c) = self.cohesive.as_mut() {
            let bonds = BondBufs {
                params: c.params,
                id: &p.id.cur,
                index: &mut c.index,
                partner: &c.partner.cur,
                reference: &c.reference.cur,
                state: &mut c.state.cur,
                onset: &mut c.onset.cur,
                column: &c.column.cur,
                work: &mut c.work.cur,
                damping: &mut c.damping.cur,
                pos: &p.pos.cur,
                vel: &p.vel.cur,
                mass: self.mech_mass.as_ref().map_or(&p.mass.cur, |m| &m.cur),
                sig: &self.sig,
                rho: &p.rho.cur,
                flags: &mut p.flags.cur,
            };
            b.bonds::<R, D>(self.n, bonds, &mut r.vel)?;
        }
        Ok(())
    }

    /// The conduction pass where it is not fused into the pair interaction.
    fn conduction(&mut self, b: &B) -> Result<()> {
        let (n, fused) = (self.cells.count(), self.fused_conduction());
        let p = &mut self.particles;
        if fused {
            return Ok(());
        }
        if let (Some(t), Some(th)) = (self.temp.as_ref(), self.thermal.as_mut())
            && let (Some(pse), Some(tt)) = (th.conduction, th.temp_t.as_mut())
        {
            let grid = if pse { &th.grid_pse } else { &self.cells.grid_buf };
            let hin = heat_inputs(p, &self.vol, &t.cur, &th.materials);
            b.heat_rates::<R, D>(
                n,
                self.lanes,
                pse,
                &th.heat,
                &self.host_params,
                grid,
                &self.cells.starts,
                if pse { None } else { self.cells.list.as_ref() },
                &hin,
                tt,
            )?;
        }
        Ok(())
    }

    /// The corrector, with the plastic update and the fused contact where they are on.
    fn correct(&mut self, b: &B, j: usize) -> Result<()> {
        let (n, fuse_contact) = (self.cells.count(), self.fused_contact());
        let (p, s) = (&mut self.particles, &mut self.start);
        let (materials, conduction) = thermal_views(self.thermal.as_mut());
        let (yield_stress, contact) = match self.contact.as_mut() {
            Some(ContactState { tools, states, normal, friction, yield_stress, wear, heating, .. }) => {
                let cap = yield_stress.is_some();
                let fused = tools.prisms().filter(|_| fuse_contact).map(|tool| FusedContact {
                    params: &tools.params,
                    tool,
                    state: ToolStatesAt { buf: &*states, index: j, count: 1 },
                    mass: &p.mass.cur,
                    normal: &mut normal.cur,
                    friction: &mut friction.cur,
                    materials: if *heating { materials } else { None },
                    yield_stress: cap,
                    wear: wear.as_mut(),
                });
                (yield_stress.as_mut(), fused)
            }
            None => (None, None),
        };
        let shear = self.shear;
        let mass = &p.mass.cur;
        let damage = self.damage.as_mut().map(|d| DamageBufs {
            params: &d.params,
            omega: &mut d.omega.cur,
            damage: &mut d.damage.cur,
            mass,
            work: Some(&mut d.work.cur),
        });
        let plastic = self.plastic.as_mut().map(|pl| PlasticPass {
            model: &pl.model,
            shear,
            taylor_quinney: pl.taylor_quinney,
            return_flags: pl.return_flags,
            eps: &mut pl.eps.cur,
            rate: &mut pl.rate.cur,
            flags: &p.flags.cur,
            materials,
            yield_stress,
            work: Some(&mut pl.work.cur),
            damage,
        });
        let r = &self.rates;
        b.step_finish::<R, D>(
            n,
            ScalarsAt { buf: &self.scalars, index: j },
            StepFields {
                y: state_mut!(p),
                y0: s.fields(),
                rates: r.fields(),
                temp: self.temp.as_mut().map(|t| &mut t.cur),
                conduction,
                dissipation: self.dissipation.as_mut().map(|(d, rate)| (&mut d.cur, &*rate)),
                pos_lo: self.pos_lo.as_mut().map(|l| &mut l.cur),
            },
            plastic,
            contact,
        )?;
        Ok(())
    }

    /// The tool's contact pass where it is not fused into the corrector.
    fn contact_pass(&mut self, b: &B, j: usize) -> Result<()> {
        let (n, fuse_contact) = (self.cells.count(), self.fused_contact());
        let p = &mut self.particles;
        if fuse_contact {
            return Ok(());
        }
        if let Some(c) = self.contact.as_mut() {
            let heating = c.heating;
            b.contact::<R, D>(
                n,
                &c.tools,
                ToolStatesAt { buf: &c.states, index: j, count: c.tools.count() },
                c.owner.as_mut().map(|o| &mut o.cur),
                ContactInputs {
                    pos: &p.pos.cur,
                    vel: &p.vel.cur,
                    mass: &p.mass.cur,
                    rho: &p.rho.cur,
                    flags: &p.flags.cur,
                    normal: &mut c.normal.cur,
                    friction: &mut c.friction.cur,
                    temp: self.temp.as_mut().map(|t| &mut t.cur),
                    materials: if heating { self.thermal.as_ref().map(|th| &th.materials) } else { None },
                    yield_stress: c.yield_stress.as_ref(),
                    wear: c.wear.as_mut(),
                },
            )?;
        }
        Ok(())
    }

    /// Submits phase `ph` once more with the scalars of the last step (for kernel benchmarks: `benches/step.rs`);
    /// the state moves as that phase moves it, without the rest of the step.
    pub fn bench_phase(&mut self, b: &B, ph: Phase) -> Result<()> {
        self.phase(b, ph, 0)
    }

    /// One step of length `dt` with each phase timed by the backend (CUDA events around each phase on the GPU);
    /// returns the milliseconds of each phase of [`Phase::ALL`]. Slower than [`Solver::step`] (it waits after
    /// every phase) and equal to it in its results.
    pub fn profile_step(&mut self, b: &B, dt: f64) -> Result<[f64; 8]> {
        self.ramp_tool(b, dt)?;
        self.reverse_loads(b, self.time + 0.5 * dt)?;
        self.fill_scalars(b, dt, 1)?;
        let mut ms = [0.0; 8];
        for (k, ph) in Phase::ALL.into_iter().enumerate() {
            ms[k] = b.time_ms(&mut || self.phase(b, ph, 0))?;
        }
        self.time += dt;
        self.steps += 1;
        self.plain_steps += 1;
        Ok(ms)
    }

    /// The first tool's force on the workpiece now, summed in f64 in particle order (deterministic, equal on every
    /// backend); None without a tool.
    pub fn contact_sample(&self, b: &B) -> Result<Option<ContactSample>> {
        if self.contact.is_none() {
            return Ok(None);
        }
        Ok(self.contact_samples_at(b, &self.particles.pos.read(b)?)?.into_iter().next())
    }

    /// Each tool's force on the workpiece now (the scene's order; empty without a tool), with the positions (state
    /// order) the caller has already read, for the moments: tool k sums the particles it touches (its owners').
    pub fn contact_samples_at(&self, b: &B, pos: &[D::Vec<R>]) -> Result<Vec<ContactSample>> {
        let Some(c) = &self.contact else { return Ok(Vec::new()) };
        let (fc, ft) = (c.normal.read(b)?, c.friction.read(b)?);
        let owner = c.owner.as_ref().map(|o| o.read(b)).transpose()?;
        let wear = c.wear.as_ref().map(|w| b.read(w)).transpose()?;
        let vel = self.particles.vel.read(b)?;
        let mut samples = vec![ContactSample::default(); c.motions.len()];
        let mut sums = vec![(0.0, 0.0, 0.0); c.motions.len()];
        let states = self.tool_states();
        let refs: Vec<[f64; 3]> = states
            .iter()
            .map(|st| {
                let o = st.offset;
                if st.rotating != 0 { std::array::from_fn(|k| o[k] + st.centre[k]) } else { o }
            })
            .collect();
        let norm = |v: &D::Vec<R>| (0..D::D).map(|k| v.get(k).to_f64().powi(2)).sum::<f64>().sqrt();
        // Blanked particles (sorted last) keep the contact forces of their last active step: not summed.
        for i in 0..self.cells.active_count(b)? {
            let k = owner.as_ref().map_or(0, |o| o[i] as usize);
            let (Some(s), Some(sum), Some(p), Some(st)) =
                (samples.get_mut(k), sums.get_mut(k), refs.get(k), states.get(k))
            else {
                continue;
            };
            // Components past the dimension read as zero (`Vector::get`).
            let f: [f64; 3] = std::array::from_fn(|k| fc[i].get(k).to_f64() + ft[i].get(k).to_f64());
            s.power = s.power.plus(contact_power(st, &pos[i], &vel[i], &fc[i], &ft[i]));
            for (acc, fk) in s.force.iter_mut().zip(f) {
                *acc += fk;
            }
            let r: [f64; 3] = std::array::from_fn(|k| pos[i].get(k).to_f64() - if k < D::D { p[k] } else { 0.0 });
            let m = [r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2], r[0] * f[1] - r[1] * f[0]];
            for (acc, mk) in s.moment.iter_mut().zip(m) {
                *acc += mk;
            }
            if (0..D::D).any(|k| fc[i].get(k) != R::ZERO) {
                s.contacts += 1;
                sum.0 += norm(&fc[i]);
                sum.1 += norm(&ft[i]);
                if let Some(w) = &wear {
                    sum.2 += w[i];
                }
            }
        }
        for (s, (normal, friction, wear_sum)) in samples.iter_mut().zip(sums) {
            s.wear_rate = if wear.is_some() && s.contacts > 0 { wear_sum / s.contacts as f64 } else { f64::NAN };
            s.friction_ratio = if normal > 0.0 { friction / normal } else { f64::NAN };
        }
        Ok(samples)
    }

    /// Whether a predictor of the steps since the last scalars were written saw a non-finite position (one small
    /// read: the run loop checks it after each batch, so that a failing run stops within a batch).
    pub fn non_finite_seen(&self, b: &B) -> Result<bool> {
        Ok(b.read(&self.scalars)?.iter().any(|s| s.non_finite != 0))
    }

    /// How many times the cell list was rebuilt (and the particles reordered) so far: once per step without a
    /// skin, once per skin's worth of motion with one.
    pub fn cell_rebuilds(&self, b: &B) -> Result<u32> {
        Ok(b.read(&self.cells.rebuilds)?.first().copied().unwrap_or(0))
    }

    /// Sets the run's time step, which scales the contact stiffness (after a CFL reduction).
    pub fn set_nominal_dt(&mut self, dt: f64) {
        if let Some(c) = self.contact.as_mut() {
            c.nominal_dt = dt;
        }
    }

    /// Host copies of the positions and flags (state order).
    #[allow(clippy::type_complexity)]
    pub fn positions(&self, b: &B) -> Result<(Vec<D::Vec<R>>, Vec<u32>)> {
        Ok((self.particles.pos.read(b)?, self.particles.flags.read(b)?))
    }

    /// The tool as the contact pass sees it at the current time, with the run's nominal step (its translation and,
    /// for a rotating tool, its centre, angular velocity and rotation), with a tool.
    pub fn tool_state(&self) -> Option<ToolState> {
        self.tool_states().first().copied()
    }

    /// Every tool as [`Solver::tool_state`] gives the first, in the scene's order; empty without a tool.
    pub fn tool_states(&self) -> Vec<ToolState> {
        let Some(c) = &self.contact else { return Vec::new() };
        c.motions.iter().map(|m| m.state_at(self.time, c.nominal_dt, c.nominal_dt)).collect()
    }

    /// Each tool's picture in the world at the current time (the outline at z = 0, or a mesh's surface), in the
    /// scene's order; empty without a tool.
    pub fn tool_pictures(&self) -> Vec<crate::tool::Picture> {
        let Some(c) = &self.contact else { return Vec::new() };
        c.pictures.iter().zip(self.tool_states()).map(|(p, s)| p.in_world(&s)).collect()
    }

    /// Where the first tool's frame origin is at the current time (its translation; z = 0 in 2D), with a tool.
    pub fn tool_offset(&self) -> Option<[f64; 3]> {
        self.contact.as_ref().map(|c| c.motions[0].offset_at(self.time))
    }

    /// Host copies of the positions' low parts (mixed precision; state order): x = pos + pos_lo.
    pub fn download_pos_lo(&self, b: &B) -> Result<Option<Vec<D::Vec<R>>>> {
        self.pos_lo.as_ref().map(|l| l.read(b)).transpose()
    }

    /// The run's precision as reports name it: "mixed" with compensated positions, else R's name.
    pub fn precision(&self) -> &'static str {
        precision_name::<R>(self.pos_lo.is_some())
    }

    /// A host copy of the particle state (in the current sorted order).
    pub fn download(&self, b: &B) -> Result<HostParticles<R, D>> {
        self.particles.download(b)
    }

    /// Host copies of the temperature, plastic strain and plastic strain rate (in the state's order), where modelled.
    #[allow(clippy::type_complexity)]
    pub fn download_internal(&self, b: &B) -> Result<(Option<Vec<f64>>, Option<Vec<f64>>, Option<Vec<f64>>)> {
        let t = match &self.temp {
            Some(t) => Some(t.read(b)?),
            None => None,
        };
        let (e, r) = match &self.plastic {
            Some(p) => (Some(p.eps.read(b)?), Some(p.rate.read(b)?)),
            None => (None, None),
        };
        Ok((t, e, r))
    }

    /// The cohesive path's tally (None without one): the failed bonds, the bonds' work and damping, the mode-I share.
    pub fn bond_tally(&self, b: &B) -> Result<Option<diagnostics::BondTally>> {
        use crate::kernels::cohesive::{FAILED, MODE_I};
        let Some(c) = &self.cohesive else { return Ok(None) };
        let (partner, state, work) = (c.partner.read(b)?, c.state.read(b)?, c.work.read(b)?);
        let damping: f64 = c.damping.read(b)?.iter().sum();
        let mut t = diagnostics::BondTally { damping, ..Default::default() };
        let mut share = 0.0;
        for i in (0..partner.len()).filter(|&i| partner[i] != crate::kernels::sph::bond::NONE) {
            t.work += work[i];
            if state[i][FAILED] != R::ZERO {
                t.failed += 1;
                share += state[i][MODE_I].to_f64();
            }
        }
        t.mode_i_share = if t.failed > 0 { share / t.failed as f64 } else { f64::NAN };
        Ok(Some(t))
    }

    /// Host copies of the accumulated specific plastic work, viscous dissipation and damage release [J/kg] (state
    /// order), where modelled: the energy balance's dissipated terms.
    pub fn download_dissipated(&self, b: &B) -> Result<diagnostics::Dissipated> {
        Ok(diagnostics::Dissipated {
            plastic: self.plastic.as_ref().map(|p| p.work.read(b)).transpose()?,
            viscous: self.dissipation.as_ref().map(|(d, _)| d.read(b)).transpose()?,
            damage: self.damage.as_ref().map(|d| d.work.read(b)).transpose()?,
        })
    }

    /// Host copies of the rates of the last step (x, v, ρ, S), in the state's order.
    #[allow(clippy::type_complexity)]
    pub fn download_rates(&self, b: &B) -> Result<(Vec<D::Vec<R>>, Vec<D::Vec<R>>, Vec<R>, Vec<D::Sym<R>>)> {
        Ok((b.read(&self.rates.pos)?, b.read(&self.rates.vel)?, b.read(&self.rates.rho)?, b.read(&self.rates.stress)?))
    }
}

/// Named raw copies of every buffer that carries state from one step to the next (the particle state, the
/// start-of-step copies, the rates the next predictor uses, temperature and plastic fields, the cell list's
/// binned positions). Scratch buffers (pre-pass outputs, the cell list itself) are rebuilt and not included.
pub type StateBlobs = Vec<(String, Vec<u8>)>;

impl<B: Backend, R: Real, D: TensorOps<R>> Solver<B, R, D> {
    /// Copies of every stateful buffer, for a checkpoint: the registry's checkpointed fields
    /// ([`fields::FIELDS`]), in its order.
    pub fn save_state(&self, b: &B) -> Result<StateBlobs> {
        let mut o = Vec::new();
        self.save_fields(b, &mut o)?;
        Ok(o)
    }

    /// Restores the buffers saved by [`Solver::save_state`] (the solver must have been built from the same scene).
    pub fn load_state(&mut self, b: &B, s: &StateBlobs) -> Result<()> {
        self.load_fields(b, s)?;
        let saved = |f: &str| s.iter().any(|(name, _)| name == f);
        if self.cohesive.as_ref().is_some_and(|c| c.params.coupling == crate::kernels::sph::bond::BONDS)
            && !saved("bond_column")
        {
            // A checkpoint written before `flags::OPEN` existed: under "bonds" every sided particle is open.
            let p = &mut self.particles;
            let mut fl = b.read(&p.flags.cur)?;
            fl.iter_mut().filter(|f| **f & flags::SIDE_MASK != 0).for_each(|f| *f |= flags::OPEN);
            b.write(&mut p.flags.cur, &fl)?;
        }
        // The cell list of the saved state: the particles are in the order of its last build, so building it
        // again on the binned positions gives the same cells and the identity permutation, and the run goes on
        // bit for bit. A state saved without them (with blanking: and the velocities its hash read) rebuilds at
        // the next step.
        if saved("pos_ref") && (self.vel_ref.is_none() || saved("vel_ref")) {
            match (self.blanking.as_mut(), self.vel_ref.as_ref()) {
                // The box of the last rebuild is the box now: every jump rebuilt.
                (Some((bl, jumps)), Some(vel_ref)) => {
                    *jumps = bl.jumps(self.time);
                    self.host_scalars[0] = StepScalars { blank: bl.box_at(self.time), ..Default::default() };
                    b.write(&mut self.scalars, &self.host_scalars[..1])?;
                    let blank = ScalarsAt { buf: &self.scalars, index: 0 };
                    self.cells.build_blanked::<R, D>(b, &self.pos_ref, vel_ref, blank)?;
                }
                _ => self.cells.build::<R, D>(b, &self.pos_ref)?,
            }
            self.cells.build_list::<R, D>(b, &self.pos_ref, None)?;
            self.force_rebuild = false;
        } else {
            self.force_rebuild = true;
        }
        if let Some(c) = &mut self.contact {
            // The ramp's table entry is rewritten by the next step while the ramp lasts; after it, it is final.
            if let Some(k) = c.tool_velocity_index {
                let v = c.motions[0].velocity_at(self.time);
                c.bc_table[k] = D::Vec::<R>::new([R::from_f64(v[0]), R::from_f64(v[1]), R::ZERO]);
                b.write(&mut self.bc_vel, &c.bc_table)?;
            }
        }
        // The reversals' signs at the restored time (the table on the device is the base until then).
        if let Some(r) = self.reversal.as_mut() {
            r.signs.iter_mut().for_each(|s| *s = 0.0);
            self.reverse_loads(b, self.time)?;
        }
        Ok(())
    }
}
