//! The field registry: every per-particle buffer the solver allocates, declared once with its roles. The in-place
//! reorder (`Solver::stage_fields`), the checkpoint (`Solver::save_state`/`load_state`), the memory estimate
//! ([`memory_bytes`], `check::memory_estimate`) and the frame writer (`Solver::download_frame_fields`) iterate it.
//!
//! An entry reads `"name": type = storage [path] if condition, checkpoint role[, frame "vtu name"];`:
//! - `type`: the element type, in the run's `R` and `D`;
//! - `storage`: `field` (a [`Field`](crate::state::Field) with a spare buffer: reordered with the particles) or
//!   `buf` (one buffer, not reordered as a field: the rates, the scratch buffers, `pos_ref`);
//! - `[path]`: where the solver keeps it, as fields (`.name`) and options (`?`) from the solver;
//! - `condition`: the [`When`] under which `Solver::new` allocates it (`Solver::new` asks the same `When`);
//! - checkpoint role: `save` (saved under `name` and required on restore), `optional` (a restore without it goes
//!   on: `pos_ref`) or `scratch` (not saved; the path is then not read);
//! - `frame "vtu name"`: written to every frame under that name, as a Float64 scalar (f64 fields); `frame "vtu
//!   name" vector`: a vector field written as three Float64 components (z = 0 in 2D); `frame "vtu name" real`: an
//!   R field written as a Float64 scalar; `frame "vtu name" integer`: a u32 field.
//!
//! The order is the checkpoint's order (`checkpoint.bin` lists the saved fields in it) and the frames' order.
//!
//! Adding a per-particle field: its storage in `Solver` (or a sub-state), its allocation in `Solver::new` under a
//! [`When`] (a new condition: a variant, its `holds` arm and its place in `When::ALL`), and one entry here. A field of
//! the particle state itself is declared in `state::particle_fields!` and entered here (tests/fields.rs checks).
//! tests/fields.rs compares the estimate with the bytes the CPU backend allocates for every scene.

use super::{GRAPH_STEPS, Setup, Solver, StateBlobs};
use crate::Result;
use crate::backend::{Backend, SCAN_TILE};
use crate::kernels::contact::{ContactParams, penalty::cap};
use crate::kernels::neighbour::GridParams;
use crate::kernels::sph::heat::ThermalMaterial;
use crate::kernels::sph::params::flags;
use crate::kernels::sph::step::StepScalars;
use crate::kernels::sph::{SphParams, TensorOps};
use crate::kernels::{Dim, Real, Vector};
use crate::state::{ReorderBatch, load_blob};

/// A per-particle field of a frame, as the host writes it: its array name, components per particle (1, or 3 for
/// a vector) and values (f64).
#[derive(Clone, Debug, PartialEq)]
pub struct FrameField {
    pub name: &'static str,
    pub components: usize,
    pub values: Vec<f64>,
}

/// The physics under which a field exists (evaluated on the run's [`Setup`]; `Solver::new` allocates by it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum When {
    Always,
    /// A temperature field (heat or plasticity).
    Temperature,
    /// Heat conduction on: the thermal predictor–corrector's T0 and Ṫ.
    Conduction,
    Plastic,
    /// Damage (with plasticity).
    Damage,
    /// A rigid tool.
    Contact,
    /// The tool's friction capped by the current yield stress.
    CurrentCap,
    /// Several rigid tools.
    Tools,
    /// The tool's Usui wear rate recorded.
    Wear,
    /// Thermal-only particles present (their mechanical mass is zero).
    ThermalOnly,
    /// Artificial viscosity on.
    Viscosity,
    /// Artificial stress on.
    ArtificialStress,
    /// Mixed precision: the positions' low parts.
    Compensated,
    /// The CSPM kernel-gradient correction on.
    Cspm,
    /// A cohesive path (`[cohesive]`): its bonds.
    Cohesive,
    /// Blanking (`[blanking]`): the velocities its rest speed read at the last rebuild.
    Blanking,
    /// The viscosity's Balsara switch (`stabilisation.artificial_viscosity.switch = "balsara"`).
    AvSwitch,
}

impl When {
    pub const ALL: [When; 17] = [
        When::Always,
        When::Temperature,
        When::Conduction,
        When::Plastic,
        When::Damage,
        When::Contact,
        When::CurrentCap,
        When::Tools,
        When::Wear,
        When::ThermalOnly,
        When::Viscosity,
        When::ArtificialStress,
        When::Compensated,
        When::Cspm,
        When::Cohesive,
        When::Blanking,
        When::AvSwitch,
    ];

    pub fn holds<R: Real, D: TensorOps<R>>(self, s: &Setup<R, D>) -> bool {
        match self {
            When::Always => true,
            When::Temperature => s.temperature.is_some(),
            When::Conduction => s.thermal.as_ref().is_some_and(|t| t.conduction.is_some()),
            When::Plastic => s.plastic.is_some(),
            When::Damage => s.damage.is_some(),
            When::Contact => s.contact.is_some(),
            When::CurrentCap => {
                s.contact.as_ref().is_some_and(|c| c.tools.iter().any(|t| t.params.cap_mode == cap::CURRENT))
            }
            When::Tools => s.contact.as_ref().is_some_and(|c| c.tools.len() > 1),
            When::Wear => s.contact.as_ref().is_some_and(|c| c.wear),
            When::ThermalOnly => s.particles.flags.iter().any(|f| f & flags::THERMAL_ONLY != 0),
            When::Viscosity => s.stabilisers.switches().viscosity,
            When::ArtificialStress => s.stabilisers.switches().stress,
            When::Compensated => s.pos_lo.is_some(),
            When::Cspm => s.stabilisers.cspm.is_some(),
            When::Cohesive => s.cohesive.is_some(),
            When::Blanking => s.blanking.is_some(),
            When::AvSwitch => s.stabilisers.balsara_on(),
        }
    }
}

/// How a field travels through a checkpoint.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Checkpoint {
    /// Saved, and required on restore.
    Save,
    /// Saved; a restore without it goes on (the solver then rebuilds what it would have given).
    Optional,
    /// Not saved: rewritten before it is read.
    Scratch,
}

/// One registry entry, without its place in the solver (the table [`FIELDS`]).
#[derive(Clone, Copy, Debug)]
pub struct FieldInfo {
    /// The checkpoint name (and the registry's).
    pub name: &'static str,
    pub when: When,
    /// A spare buffer of the same size: the field is reordered with the particles (staged in the in-place batch).
    pub reordered: bool,
    pub checkpoint: Checkpoint,
    /// The array name in every frame (a Float64 scalar), if written.
    pub frame: Option<&'static str>,
}

/// Buffers per particle of a storage kind: a reordered field has a spare.
macro_rules! copies {
    (field) => {
        2
    };
    (buf) => {
        1
    };
}

/// `Option<&T>` (or `Option<&mut T>`) of the value at a path of fields (`.name`) and options (`?`) below `$o`.
macro_rules! reach {
    (ref $o:expr;) => { $o };
    (ref $o:expr; . $f:tt $($rest:tt)*) => { reach!(ref $o.map(|x| &x.$f); $($rest)*) };
    (ref $o:expr; ? $($rest:tt)*) => { reach!(ref $o.and_then(|x| x.as_ref()); $($rest)*) };
    (mut $o:expr;) => { $o };
    (mut $o:expr; . $f:tt $($rest:tt)*) => { reach!(mut $o.map(|x| &mut x.$f); $($rest)*) };
    (mut $o:expr; ? $($rest:tt)*) => { reach!(mut $o.and_then(|x| x.as_mut()); $($rest)*) };
}

/// The buffer a registry entry's storage holds its current values in.
macro_rules! cur {
    (field, $f:expr) => {
        &$f.cur
    };
    (buf, $f:expr) => {
        $f
    };
}

macro_rules! cur_mut {
    (field, $f:expr) => {
        &mut $f.cur
    };
    (buf, $f:expr) => {
        $f
    };
}

/// The statements of one entry in each generated pass (nothing where the entry has no such role).
macro_rules! stage_one {
    (field, $s:ident, $b:ident, $batch:ident, [$($path:tt)*]) => {
        if let Some(f) = reach!(mut Some(&mut *$s); $($path)*) {
            f.stage($b, $batch);
        }
    };
    (buf, $($rest:tt)*) => {};
}

macro_rules! save_one {
    (scratch, $($rest:tt)*) => {};
    ($ck:ident, $kind:ident, $name:literal, $s:ident, $b:ident, $out:ident, [$($path:tt)*]) => {
        if let Some(f) = reach!(ref Some($s); $($path)*) {
            let v = $b.read(cur!($kind, f))?;
            $out.push(($name.to_string(), bytemuck::cast_slice::<_, u8>(&v).to_vec()));
        }
    };
}

macro_rules! load_one {
    (scratch, $($rest:tt)*) => {};
    (save, $kind:ident, $name:literal, $s:ident, $b:ident, $blobs:ident, [$($path:tt)*]) => {
        if let Some(f) = reach!(mut Some(&mut *$s); $($path)*) {
            load_blob($b, $name, cur_mut!($kind, f), $blobs)?;
        }
    };
    (optional, $kind:ident, $name:literal, $s:ident, $b:ident, $blobs:ident, [$($path:tt)*]) => {
        if let Some(f) = reach!(mut Some(&mut *$s); $($path)*)
            && $blobs.iter().any(|(n, _)| n == $name)
        {
            load_blob($b, $name, cur_mut!($kind, f), $blobs)?;
        }
    };
}

macro_rules! frame_one {
    ($kind:ident, $s:ident, $b:ident, $out:ident, [$($path:tt)*], $vtu:literal) => {
        if let Some(f) = reach!(ref Some($s); $($path)*) {
            let v: Vec<f64> = $b.read(cur!($kind, f))?;
            $out.push(FrameField { name: $vtu, components: 1, values: v });
        }
    };
    ($kind:ident, $s:ident, $b:ident, $out:ident, [$($path:tt)*], $vtu:literal vector) => {
        if let Some(f) = reach!(ref Some($s); $($path)*) {
            // Components past the dimension read as zero (`Vector::get`).
            let v: Vec<f64> =
                $b.read(cur!($kind, f))?.iter().flat_map(|x| (0..3).map(move |k| x.get(k).to_f64())).collect();
            $out.push(FrameField { name: $vtu, components: 3, values: v });
        }
    };
    ($kind:ident, $s:ident, $b:ident, $out:ident, [$($path:tt)*], $vtu:literal real) => {
        if let Some(f) = reach!(ref Some($s); $($path)*) {
            let v: Vec<f64> = $b.read(cur!($kind, f))?.iter().map(|x: &R| x.to_f64()).collect();
            $out.push(FrameField { name: $vtu, components: 1, values: v });
        }
    };
    ($kind:ident, $s:ident, $b:ident, $out:ident, [$($path:tt)*], $vtu:literal integer) => {
        if let Some(f) = reach!(ref Some($s); $($path)*) {
            let v: Vec<f64> = $b.read(cur!($kind, f))?.iter().map(|&x: &u32| f64::from(x)).collect();
            $out.push(FrameField { name: $vtu, components: 1, values: v });
        }
    };
    ($kind:ident, $s:ident, $b:ident, $out:ident, [$($path:tt)*]) => {};
}

macro_rules! ck_role {
    (save) => {
        Checkpoint::Save
    };
    (optional) => {
        Checkpoint::Optional
    };
    (scratch) => {
        Checkpoint::Scratch
    };
}

macro_rules! frame_role {
    ($vtu:literal $($vector:ident)?) => {
        Some($vtu)
    };
    () => {
        None
    };
}

macro_rules! is_field {
    (field) => {
        true
    };
    (buf) => {
        false
    };
}

/// Generates the table [`FIELDS`] and, from the same entries, the solver's passes over its fields.
macro_rules! registry {
    ($( $(#[$doc:meta])* $name:literal : $t:ty = $kind:ident [$($path:tt)*] if $when:ident, $ck:ident
        $(, frame $vtu:literal $($vector:ident)?)? ; )*) => {
        /// Every per-particle buffer of the solver, in checkpoint order.
        pub const FIELDS: &[FieldInfo] = &[$(
            FieldInfo {
                name: $name,
                when: When::$when,
                reordered: is_field!($kind),
                checkpoint: ck_role!($ck),
                frame: frame_role!($($vtu $($vector)?)?),
            },
        )*];

        /// Bytes per particle of the fields a run with setup `s` allocates (a reordered field's spare included).
        pub fn per_particle_bytes<R: Real, D: TensorOps<R>>(s: &Setup<R, D>) -> usize {
            0 $( + if When::$when.holds(s) { copies!($kind) * size_of::<$t>() } else { 0 } )*
        }

        impl<B: Backend, R: Real, D: TensorOps<R>> Solver<B, R, D> {
            /// Stages every reordered field for the fused in-place reorder ([`crate::state::Field::stage`]).
            pub(super) fn stage_fields(&mut self, b: &B, batch: &mut ReorderBatch) {
                let s = self;
                $( stage_one!($kind, s, b, batch, [$($path)*]); )*
            }

            /// Appends a raw copy of every checkpointed field that exists, named as registered.
            pub(super) fn save_fields(&self, b: &B, out: &mut StateBlobs) -> Result<()> {
                let s = self;
                $( save_one!($ck, $kind, $name, s, b, out, [$($path)*]); )*
                Ok(())
            }

            /// Restores every checkpointed field that exists from [`Solver::save_fields`]'s copies.
            pub(super) fn load_fields(&mut self, b: &B, blobs: &StateBlobs) -> Result<()> {
                let s = self;
                $( load_one!($ck, $kind, $name, s, b, blobs, [$($path)*]); )*
                Ok(())
            }

            /// Host copies of every field written to frames that exists, with its array name, in registry order.
            pub fn download_frame_fields(&self, b: &B) -> Result<Vec<FrameField>> {
                let s = self;
                let mut out = Vec::new();
                $( frame_one!($kind, s, b, out, [$($path)*] $(, $vtu $($vector)?)?); )*
                Ok(out)
            }
        }
    };
}

registry! {
    /// Index of the particle in the scene as built.
    "id": u32 = field [.particles.id] if Always, save;
    /// Bit flags (`sph::params::flags`).
    "flags": u32 = field [.particles.flags] if Always, save;
    "pos": D::Vec<R> = field [.particles.pos] if Always, save;
    "vel": D::Vec<R> = field [.particles.vel] if Always, save;
    "mass": R = field [.particles.mass] if Always, save;
    "rho": R = field [.particles.rho] if Always, save;
    "stress": D::Sym<R> = field [.particles.stress] if Always, save;
    /// The start-of-step copies y0.
    "pos0": D::Vec<R> = field [.start.pos] if Always, save;
    /// Where the cell list binned each particle (the skin test's reference): not reordered as a field, the
    /// reorder snapshots the positions into it.
    "pos_ref": D::Vec<R> = buf [.pos_ref] if Always, optional;
    "vel0": D::Vec<R> = field [.start.vel] if Always, save;
    "rho0": R = field [.start.rho] if Always, save;
    "stress0": D::Sym<R> = field [.start.stress] if Always, save;
    /// The rates ẏ, in the order of the last interaction (the next predictor reads them).
    "pos_t": D::Vec<R> = buf [.rates.pos] if Always, save;
    "vel_t": D::Vec<R> = buf [.rates.vel] if Always, save;
    "rho_t": R = buf [.rates.rho] if Always, save;
    "stress_t": D::Sym<R> = buf [.rates.stress] if Always, save;
    "temp": f64 = field [.temp?] if Temperature, save, frame "temperature";
    "pos_lo": D::Vec<R> = field [.pos_lo?] if Compensated, save;
    "temp0": f64 = field [.thermal?.temp0?] if Conduction, save;
    "temp_t": f64 = buf [.thermal?.temp_t?] if Conduction, save;
    "eps": f64 = field [.plastic?.eps] if Plastic, save, frame "plastic_strain";
    "eps_rate": f64 = field [.plastic?.rate] if Plastic, save, frame "plastic_strain_rate";
    "plastic_work": f64 = field [.plastic?.work] if Plastic, save;
    "contact_normal": D::Vec<R> = field [.contact?.normal] if Contact, save, frame "contact_normal_force" vector;
    "contact_friction": D::Vec<R> = field [.contact?.friction] if Contact, save, frame "contact_friction_force" vector;
    "mech_mass": R = field [.mech_mass?] if ThermalOnly, save;
    "viscous_dissipation": f64 = field [.dissipation?.0] if Viscosity, save;
    /// Damage initiation ω and evolution D (`kernels::damage`), and the interaction mask of the last pre-pass (after
    /// the fields of the checkpoints written before them, tests/fields.rs).
    "damage_omega": f64 = field [.damage?.omega] if Damage, save, frame "damage_initiation";
    "damage": f64 = field [.damage?.damage] if Damage, save, frame "damage";
    /// The tool each particle's friction history belongs to (several tools).
    "contact_owner": u32 = field [.contact?.owner?] if Tools, save, frame "contact_tool" integer;
    "damage_mask": f64 = buf [.damage?.mask] if Damage, scratch, frame "damage_mask";
    /// The cohesive path's bonds (`kernels::sph::bond`), held by their owners: the partner's id, the reference
    /// offset, the history and the work the bond has absorbed [J per m of depth in 2D].
    "bond_partner": u32 = field [.cohesive?.partner] if Cohesive, save;
    "bond_reference": D::Vec<R> = field [.cohesive?.reference] if Cohesive, save;
    "bond_state": crate::kernels::sph::bond::BondState<R> = field [.cohesive?.state] if Cohesive, save;
    "bond_work": f64 = field [.cohesive?.work] if Cohesive, save, frame "cohesive_work";
    /// The energy the bond's damper has dissipated [J per m of depth in 2D].
    "bond_damping": f64 = field [.cohesive?.damping] if Cohesive, save;
    /// The sorted index of each id, rebuilt before the bonds each step.
    "bond_index": u32 = buf [.cohesive?.index] if Cohesive, scratch;
    /// The velocities the last rebuild's hash read (blanking's rest speed), snapshotted as `pos_ref` is: a restore
    /// rebuilds the same cells from both.
    "vel_ref": D::Vec<R> = buf [.vel_ref?] if Blanking, optional;
    /// The Balsara switch's factor f_i of the last interaction (`kernels::sph::interact::balsara`), which the next
    /// pre-pass scales the sound speed by: state from step to step (1 before the first interaction).
    "av_switch": R = field [.av_switch?] if AvSwitch, save, frame "av_switch" real;
    /// The specific elastic energy the damage's degradation has released [J/kg] (energy.csv's `damage_dissipation`);
    /// a checkpoint written before it resumes with zeros.
    "damage_work": f64 = field [.damage?.work] if Damage, optional;
    /// The bond's onset and the column each particle belongs to under `cohesive.coupling = "continuum"`; a
    /// checkpoint written before them (`coupling = "bonds"`, whose columns are all `bond::NONE` and onsets nil)
    /// resumes with the set-up's.
    "bond_onset": crate::kernels::sph::bond::OnsetState<R> = field [.cohesive?.onset] if Cohesive, optional;
    "bond_column": u32 = field [.cohesive?.column] if Cohesive, optional;
    /// The pre-pass outputs: σ/ρ², artificial stress, sound speed, volume.
    "sig": D::Sym<R> = buf [.sig] if Always, scratch;
    "art": D::Sym<R> = buf [.art?] if ArtificialStress, scratch;
    "sound": R = buf [.sound?] if Viscosity, scratch;
    "vol": R = buf [.vol] if Always, scratch;
    /// The CSPM correction B⁻¹, rewritten by each step's correction pass.
    "cspm_correction": D::Sym<R> = buf [.correction?.buf] if Cspm, scratch;
    "viscous_dissipation_rate": R = buf [.dissipation?.1] if Viscosity, scratch;
    /// σ_y after the plastic update, for the current-yield friction cap.
    "yield_stress": f64 = buf [.contact?.yield_stress?] if CurrentCap, scratch;
    "wear_rate": f64 = buf [.contact?.wear?] if Wear, scratch;
    /// The cell list's per-particle arrays: keys, slots, permutation.
    "cell_keys": u32 = buf [.cells.keys] if Always, scratch;
    "cell_slots": u32 = buf [.cells.slots] if Always, scratch;
    "cell_perm": u32 = buf [.cells.perm] if Always, scratch;
}

/// Words of the exclusive scan's workspace for `n` entries (`backend::scan_levels`: one word per tile, level by
/// level, down to one tile).
fn scan_words(n: usize) -> usize {
    let (mut len, mut words) = (n, 0);
    loop {
        let tiles = len.div_ceil(SCAN_TILE).max(1);
        words += tiles;
        if tiles == 1 {
            return words;
        }
        len = tiles;
    }
}

/// Bytes of the solver's buffers that are not one entry per particle: the cell list's starts, scan workspace,
/// rebuild counter and grid block, the Verlet list (rows of n words), the parameter blocks, the boundary-velocity
/// table, the step scalars, and the thermal and contact blocks (the law's constants, the tool's shape) where modelled.
pub fn fixed_bytes<R: Real, D: TensorOps<R>>(s: &Setup<R, D>) -> usize {
    let n = s.particles.len();
    let buckets = crate::neighbour::buckets(&s.grid, s.blanking.is_some()) + 1;
    let cells = (buckets + scan_words(buckets) + 1) * 4 + size_of::<GridParams>() + 4 * s.grid.list_rows() * n;
    let table = s.bc_velocities.len().max(1) * size_of::<<D as Dim>::Vec<R>>();
    let run = size_of::<SphParams<R>>() + table + GRAPH_STEPS * size_of::<StepScalars>();
    let thermal =
        s.thermal.as_ref().map_or(0, |t| t.materials.len() * size_of::<ThermalMaterial>() + size_of::<GridParams>());
    // The contact law's constants and the tool's shape, one block each.
    let contact = s.contact.as_ref().map_or(0, |c| {
        let k = c.tools.len();
        let views = if c.tools[0].shape.parametric().is_some() {
            0
        } else {
            k * size_of::<crate::kernels::contact::MeshTool>()
        };
        let shapes: usize = c.tools.iter().map(|t| size_of::<ContactParams>() + t.shape.device_bytes()).sum();
        shapes + views + k * GRAPH_STEPS * size_of::<crate::kernels::contact::ToolState>()
    });
    // The damage's constants, one block.
    let damage = if s.damage.is_some() { size_of::<crate::kernels::damage::DamageParams>() } else { 0 };
    cells + run + thermal + contact + damage
}

/// Bytes the solver of setup `s` allocates: the registry's fields for every particle plus [`fixed_bytes`].
pub fn memory_bytes<R: Real, D: TensorOps<R>>(s: &Setup<R, D>) -> usize {
    s.particles.len() * per_particle_bytes(s) + fixed_bytes(s)
}

/// Most buffers one in-place reorder stages: every reordered field that can exist, and the snapshots of the
/// reference positions and (with blanking) velocities.
pub fn max_reorder_entries() -> usize {
    // The snapshots: pos_ref, and vel_ref with blanking.
    FIELDS.iter().filter(|f| f.reordered).count() + 2
}
