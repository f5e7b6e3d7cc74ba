//! Scene files (TOML): schema, loading, `--set` overrides, validation, and the particle sets they describe.
//!
//! A scene is a TOML file in SI units (m, s, kg, Pa). [`Scene::load`] reads it, applies `--set key=value`
//! overrides (a dotted path into the document, e.g. `time.end=1e-4` or `body.1.velocity=[-200.0, 0.0]`),
//! checks every key and value, and returns a [`Scene`]; nothing is generated before the whole scene is valid.
//! [`Scene::generate`] then fills the bodies with lattices of particles ([`ParticleSet`]).
//!
//! The fields of [`Scene`] and the types below document each key: its unit, its default and its allowed range.
//! Unknown keys anywhere are an error, and so is a parameter of a shape other than the body's. Errors
//! ([`SceneError`]) name the file and line (or the `--set` argument), the key and what was expected, e.g.
//!
//! ```text
//! cases/rings.toml:12: material.poisson_ratio = 0.5: expected a value in (-1, 0.5)
//! --set time.end=-1: time.end: expected a positive time in seconds
//! ```
//!
//! A minimal scene:
//!
//! ```toml
//! name = "disk"
//! dim = 2
//! [discretisation]
//! dx = 0.1
//! [material]
//! density = 1.0
//! youngs_modulus = 1.0e7
//! poisson_ratio = 0.4
//! [[body]]
//! shape = "disk"
//! center = [0.0, 0.0]
//! radius = 1.0
//! [time]
//! end = 1e-3
//! ```

mod doc;
mod error;
mod generate;
pub mod model;
pub mod mpm;
pub mod observe;
mod read;
pub mod units;

use std::fmt::Write as _;
use std::path::Path;

use serde::Serialize;

pub use error::{Location, SceneError};
pub use model::{Model, ModelSwitches, Switch};

/// The default of `time.max_steps`: the most steps a run takes unless its scene allows more.
pub const DEFAULT_MAX_STEPS: f64 = 1e9;

/// The folder of a run folder that holds copies of its scene's mesh files (`run::record_inputs`), so that the run
/// folder resumes from anywhere, as its `materials/` does for the library materials.
pub const RECORDED_MESHES: &str = "meshes";

/// The name under [`RECORDED_MESHES`] of the mesh file a scene names `file`: the name spelled flat (each path
/// separator `__`, each `..` `up`, a drive's `:` `_`), so that every relative or absolute name has one file there.
pub fn recorded_mesh_name(file: &str) -> String {
    file.replace("..", "up").replace(['/', '\\'], "__").replace(':', "_")
}

/// Where a scene file `scene_file` finds the mesh file it names `file`: relative to the scene file's folder (as
/// given, when the scene has no file or the name is absolute); where that file does not exist, the copy a run
/// folder recorded beside its `scene.toml` ([`RECORDED_MESHES`]), when there is one.
pub fn mesh_file_path(scene_file: &str, file: &str) -> std::path::PathBuf {
    let (scene, name) = (std::path::Path::new(scene_file), std::path::Path::new(file));
    let dir = scene.parent().filter(|_| scene.is_file());
    let given = match dir {
        Some(d) if name.is_relative() => d.join(name),
        _ => name.to_path_buf(),
    };
    if given.is_file() {
        return given;
    }
    dir.map(|d| d.join(RECORDED_MESHES).join(recorded_mesh_name(file))).filter(|r| r.is_file()).unwrap_or(given)
}
pub use generate::{Bc, ParticleSet};

/// A validated scene. Vectors and points are stored with three components; in 2D the third is 0.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Scene {
    /// Where the scene came from (the file path, or the origin given to [`Scene::from_str`]); used in messages.
    /// Not a key of the file.
    pub origin: String,
    /// `name` (required): the name of the scene, used in output names and reports.
    pub name: String,
    /// `dim` (required): 2 (plane strain, per unit depth) or 3.
    pub dim: usize,
    /// `precision` (optional, default `"f64"`): `"f32"` or `"f64"`, the floating-point type of the particle state,
    /// or `"mixed"`: f32 with compensated positions (`Precision::Mixed`).
    pub precision: Precision,
    /// `[discretisation]` (required).
    pub discretisation: Discretisation,
    /// `[material]` (required): an inline linear-elastic material.
    pub material: Material,
    /// `[[body]]` (one or more): the bodies, each a shape filled with a lattice of particles.
    pub bodies: Vec<Body>,
    /// `[[boundary]]` (zero or more): boundary conditions; where regions overlap, the last entry wins.
    pub boundaries: Vec<Boundary>,
    /// `[stabilisation]` (optional): each stabiliser is on when its table is present (and not `enabled = false`).
    pub stabilisation: Stabilisation,
    /// `[time]` (required).
    pub time: Time,
    /// `[output]` (optional).
    pub output: Output,
    /// `[physics]` (optional): plasticity, heat conduction and heating, initial temperature.
    pub physics: Physics,
    /// `[tool]` (optional): a rigid cutting tool with penalty contact and friction; or `[[tool]]`, several tools,
    /// this the first (the one whose forces are the cutting run's F_c and F_f and whose chip is analysed).
    pub tool: Option<Tool>,
    /// The second and later `[[tool]]` entries (empty with `[tool]`): all of one kind with the first (parametric
    /// outlines or meshes), each with its own motion and contact law. Absent from `summary.json` when empty.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub more_tools: Vec<Tool>,
    /// `[experiment]` (optional): measured values of the scene's observables ([`observe`]), the
    /// reference `swarf study` reports its error against; in the order of the scene's observables.
    pub experiment: Vec<Measurement>,
    /// `[analysis]` (optional): options of the end-of-run analysis of a cutting run.
    pub analysis: Analysis,
    /// `model` (optional, default `"swarf"`): `"swarf"`, `"mfree_iwf"` (the original 2D code, MFREE_IWF, with its
    /// bugs: docs/validation.md, "The original model") or a list of that model's switches ([`Switch`]); 2D only.
    /// Absent from `summary.json` when `"swarf"`, so those scenes record what they recorded before.
    #[serde(skip_serializing_if = "Model::is_swarf")]
    pub model: Model,
    /// `[damage]` (optional, needs plasticity): ductile damage (docs/damage.md). Absent from `summary.json` when
    /// off, so the scenes without it record what they recorded before.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub damage: Option<Damage>,
    /// `[blanking]` (optional): only the particles inside a box moving with the tool are integrated; the rest are
    /// frozen and skipped (docs/3d.md, "Blanking"). Absent from `summary.json` when off.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub blanking: Option<Blanking>,
    /// `[cohesive]` (optional): a predefined cohesive cut path (docs/mpm.md "The cohesive path in SPH"). Absent
    /// from `summary.json` when off.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cohesive: Option<CohesivePath>,
}

/// `[cohesive]`: a horizontal cut plane whose faces are joined by Nairn's cubic law over `extent`, and across
/// which the continuum does not interact (nairn-mpm.md §7.2).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CohesivePath {
    /// `toughness`, `peak` (required), `toughness_shear`, `peak_shear` (default mode I's): the laws, as an MPM
    /// scene's `[cohesive]`.
    pub law: mpm::CohesiveSpec,
    /// `plane` (required) [m]: y of the plane, strictly between two particle rows.
    pub plane: f64,
    /// `extent` (required) [m]: [x_min, x_max], the reference x over which the plane is cut.
    pub extent: [f64; 2],
    /// `traction_free` (optional) [m]: [x_min, x_max] within the extent, the starter crack whose faces carry no
    /// bond.
    pub traction_free: Option<[f64; 2]>,
    /// `coupling` (default "bonds"): what joins the faces before a bond fails.
    pub coupling: Coupling,
}

/// `cohesive.coupling`; its discriminant is the kernels' constant (`kernels::sph::bond::BondParams::coupling`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
#[repr(u32)]
pub enum Coupling {
    /// The bonds alone, from t = 0, with the law of `law` (Nairn's intrinsic law; no continuum pair across).
    Bonds = crate::kernels::sph::bond::BONDS,
    /// The continuum until the traction on the plane reaches the strength, then a bond softening linearly from it
    /// (an extrinsic law; docs/mpm.md "Continuum until onset").
    Continuum = crate::kernels::sph::bond::CONTINUUM,
}

impl Coupling {
    /// Each coupling and its key value, once.
    pub const ALL: [(Coupling, &'static str); 2] = [(Coupling::Bonds, "bonds"), (Coupling::Continuum, "continuum")];

    /// The coupling a key value names.
    pub fn from_name(name: &str) -> Option<Coupling> {
        mpm::by_name(&Self::ALL, name)
    }
}

/// `[blanking]`: the active box [min, max] at t = 0, moving at `velocity` (roethlin-solver.md §7.6.3; the original
/// code's `src/blanking.cpp`). Particles outside it at rest are frozen: not integrated, nobody's neighbour, their
/// state kept. The box advances in jumps of the cell list's skin, each of which rebuilds the cell list, so a particle
/// the box reaches is active within one skin of its travel (docs/3d.md, "Blanking").
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Blanking {
    /// `min`, `max` (required) [m]: the box's corners at t = 0.
    pub min: [f64; 3],
    pub max: [f64; 3],
    /// `velocity` (optional, default the first tool's translation velocity, else zero) [m/s].
    pub velocity: [f64; 3],
    /// `grow` (optional, default false): the rear faces stay put and only the front ones move (the original code's
    /// box with one face held), so the box never leaves behind material it has worked.
    pub grow: bool,
    /// `rest_speed` (optional, m/s, ≥ 0 or `inf`; default 1 % of |velocity|, `inf` for a box at rest): a particle
    /// outside the box is frozen only when it moves no faster than this, so that a chip thrown out of the box
    /// keeps moving instead of freezing in the path of the material behind it. None (`inf`): every particle
    /// outside, as in the original code.
    pub rest_speed: Option<f64>,
}

impl Blanking {
    /// The box's speed |velocity| [m/s].
    pub fn speed(&self) -> f64 {
        self.velocity.iter().map(|v| v * v).sum::<f64>().sqrt()
    }

    /// The default rest speed: 1 % of the box's speed (None, the pure box, for a box at rest).
    pub fn default_rest_speed(&self) -> Option<f64> {
        let speed = self.speed();
        (speed > 0.0).then_some(0.01 * speed)
    }
}

/// `[damage]`: ductile damage (`swarf_kernels::damage`, docs/damage.md), its constants from the library material's
/// `[damage]` unless the table gives them.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Damage {
    /// `model` (optional, default the material's): `"jc"`, `"jc_gg"` or `"rice_tracey"`.
    pub model: String,
    /// `D1`..`D8` (each optional, default the material's; the model's count required).
    pub constants: [f64; 8],
    /// `reference_strain_rate` [1/s], `reference_temperature`, `melt_temperature` [K] (JC, JC-GG; default the
    /// material's `[damage]`, else its `[thermal]`).
    pub reference_strain_rate: f64,
    pub reference_temperature: f64,
    pub melt_temperature: f64,
    /// G_f [J/m²] from `fracture_energy`, or `fracture_toughness` K_1C [Pa √m] with the scene's E and ν, else the
    /// material's; 0: none (full damage at initiation).
    pub fracture_energy: f64,
    /// `mask` (optional, default false): the interaction mask of fully damaged neighbours in tension.
    pub mask: bool,
    /// `mask_form` (optional, `"printed"` (default) or `"invariant"`): Klippel's mask as printed (v_j F_j − v_i: a
    /// masked neighbour at rest in the lab frame), or the Galilean-invariant pair cut (docs/damage.md).
    pub mask_printed: bool,
    /// `delete` (optional, default false): fully damaged particles leave the interactions.
    pub delete: bool,
    /// `[[damage.pre_crack]]`: regions of initial damage (`min`, `max` [m]; `damage` D, default full; `omega` ω,
    /// default 1).
    pub pre_cracks: Vec<PreCrack>,
}

/// A pre-crack: particles inside the box [min, max] start with damage D and initiation ω.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PreCrack {
    pub min: [f64; 3],
    pub max: [f64; 3],
    pub damage: f64,
    pub omega: f64,
}

/// `[analysis]`: `early_stop = { tolerance = ε }` (optional, needs a `[tool]`): the run ends once F_c and F_f are
/// both steady to ε (host/cutting/early_stop.rs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Analysis {
    pub early_stop: Option<EarlyStopRule>,
}

/// `analysis.early_stop`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct EarlyStopRule {
    /// `tolerance` (required), in (0, 1]: the relative drift and the relative standard error of the means
    /// F_c and F_f must both be within it.
    pub tolerance: f64,
}

/// One entry of `[experiment]`: `<observable> = { value = v, uncertainty = u }` (or `<observable> = v`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Measurement {
    /// The observable's name, as in summary.json and study.csv (e.g. `fc_n_per_mm`).
    pub name: String,
    /// `value` (required; the observable's unit), finite and non-zero: the measured value. Errors are relative
    /// to it, so it cannot be zero.
    pub value: f64,
    /// `uncertainty` (optional; the same unit), ≥ 0: the measurement's standard uncertainty, as published.
    pub uncertainty: Option<f64>,
}

/// `[tool]`: the rigid cutting tool (roethlin-solver.md §5.4, §5.5; klippel-constitutive.md §1.3). The parametric
/// tool's outline is the rake face, top, back and flank faces and the edge arc (kernels/src/contact/tool2d.rs),
/// in 3D extruded along z (a prism); the tool frame's origin is the lowest point of the cutting edge and the rake
/// face faces +x. In 3D the tool may instead be a triangle mesh (`mesh`), whose own coordinates (scaled and
/// oriented) are the tool frame; its outline keys are then absent (NaN here: null in summary.json).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Tool {
    /// `rake_angle` (required; unit degree), in (−90, 90): γ from the vertical, positive leaning back.
    pub rake_angle: f64,
    /// `clearance_angle` (required; unit degree), ≥ 0, with γ + α < 90: α of the flank from the horizontal.
    pub clearance_angle: f64,
    /// `edge_radius` (optional, default 0 = sharp; unit m), ≥ 0: r_c of the edge arc.
    pub edge_radius: f64,
    /// `length` (required; unit m), > 0: the tool's extent behind the edge's lowest point.
    pub length: f64,
    /// `height` (required; unit m), > 0: its extent above the edge's lowest point.
    pub height: f64,
    /// `mesh` (optional, 3D only): the tool is this triangle mesh (see [`ToolMesh`]) instead of the outline.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mesh: Option<ToolMesh>,
    /// `position` (required; unit m) `[x, y]` (a mesh tool: `[x, y, z]`, where its frame's origin is at t = 0;
    /// z = 0 otherwise, left out of summary.json): where the edge's lowest point is at t = 0. With `depth_of_cut` the
    /// file gives `[x]` only and y is resolved when the scene is read: y = y_top + dx/2 − depth_of_cut, y_top the
    /// highest particle row of the workpiece body (`body`, default the first `[[body]]`); under `model =
    /// "mfree_iwf"` y = y_top − depth_of_cut (the original code's datum). Always resolved here.
    #[serde(serialize_with = "planar")]
    pub position: [f64; 3],
    /// `depth_of_cut` (optional; unit m), > 0: the edge's lowest point lies this far below the workpiece's uncut
    /// surface (top particle row + dx/2). Keeps the cut's geometry when dx changes (`--set discretisation.dx`);
    /// excludes a y in `position`.
    pub depth_of_cut: Option<f64>,
    /// `body` (optional, only with `depth_of_cut`; default the first `[[body]]`): the workpiece body whose top
    /// surface `depth_of_cut` is measured from, as an index into [`Scene::bodies`].
    pub body: Option<usize>,
    /// `velocity` (required; unit m/s) `[vx, vy]` (a mesh tool: `[vx, vy, vz]`): the cutting velocity (zero: a
    /// resting tool, e.g. a contact test).
    #[serde(serialize_with = "planar")]
    pub velocity: [f64; 3],
    /// `ramp` (optional, default 0; unit s), ≥ 0: the velocity is reached linearly over this time.
    pub ramp: f64,
    /// `rotation = { axis, centre, rpm }` (optional, default none): the tool also turns (see [`ToolRotation`]).
    /// Absent from `summary.json` when absent here, so scenes without it record what they recorded before.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rotation: Option<ToolRotation>,
    /// `contact_law` (optional, default `"bulk"`; `"step"` under the original model's `step_contact`): how the
    /// penalty spring is set: `"step"`, k = κ m/Δt² (the theses' codes, (5.116)), or `"bulk"`, k = κ K A²/V with
    /// the workpiece's bulk modulus K (LS-DYNA, (5.117)), which does not change with the time step.
    pub contact_law: ContactLawKind,
    /// `contact_stiffness` (optional, default 0.1, the theses' codes), in (0, 1]: κ, with `"step"` the fraction of a
    /// penetration the penalty force removes per step, with `"bulk"` the fraction of K A²/V.
    pub contact_stiffness: f64,
    /// `contact_damping` (optional, default 1: critical; 0, undamped, under the original model's `step_contact`), in
    /// [0, 1]: ξ, the fraction of critical damping 2√(k m) of a dashpot beside the penalty spring (it never pulls a
    /// particle in).
    pub contact_damping: f64,
    /// `friction_stiffness` (optional, default `contact_stiffness`, as in Röthlin's code), in (0, 1]: κ_t of the
    /// LS-DYNA friction update, with `"step"` f* = f_old − κ_t m v_t/Δt (Klippel's (4.47) and Röthlin's (5.129)
    /// write m/Δt: 1), with `"bulk"` a stick stiffness of κ_t K A²/V per unit slip.
    pub friction_stiffness: Option<f64>,
    /// `friction` (optional, default 0), ≥ 0: the Coulomb coefficient μ.
    pub friction: f64,
    /// `friction_cap` (optional, default `"none"`): `"none"`, `"static"` (|f_t| ≤ κ_fric A σ_y0/√3 with the static
    /// yield stress σ_y(0, ε̇0, T0), (7.6)) or `"current"` (the particle's current σ_y, (7.7)/(9.21)).
    pub friction_cap: FrictionCap,
    /// `friction_cap_factor` (optional, default 1), > 0: κ_fric.
    pub friction_cap_factor: f64,
    /// `friction_heating` (optional, default 0 = off), in [0, 1]: the fraction η of the friction work that heats
    /// the workpiece (the theses: 0.9; Klippel's identification model: off).
    pub friction_heating: f64,
    /// `usui = { psi, xi }` (optional): record the Usui wear rate Ψ exp(−ξ/T) p v (Ψ [1/Pa], default 7.8e-9;
    /// ξ [K], default 2500; roethlin-solver.md §7.8).
    pub usui: Option<[f64; 2]>,
    /// `chip_station` (optional, default twice the uncut chip thickness; unit m), > 0: where up the rake face the
    /// chip thickness is measured (host/cutting/chip.rs).
    pub chip_station: Option<f64>,
    /// `[tool.thermal]` (optional): the tool as thermal-only particles (a heat sink, roethlin-solver.md §5.6).
    pub thermal: Option<ToolThermal>,
}

/// A tool's 3-vector as summary.json shows it: `[x, y]` when z = 0 (the parametric tool's, as before 3D tools),
/// else `[x, y, z]`.
fn planar<S: serde::Serializer>(v: &[f64; 3], s: S) -> std::result::Result<S::Ok, S::Error> {
    use serde::Serialize as _;
    if v[2] == 0.0 { v[..2].serialize(s) } else { v.serialize(s) }
}

/// `mesh = { file, scale, axis, angle, weld, cell, cutoff, safe }` in `[tool]` (3D): a rigid tool given as a closed
/// triangle surface (docs/3d.md). The file's coordinates times `scale`, turned by `angle` about `axis`, are the tool
/// frame; `position` places its origin. The mesh is read, checked and hashed into its grid when the scene is read.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ToolMesh {
    /// `file` (required): an STL (binary or ASCII), OBJ or LS-DYNA keyword file (`.stl`, `.obj`, `.k`/`.key`/`.dyn`),
    /// relative to the scene file's folder.
    pub file: String,
    /// `scale` (optional, default 1), > 0: the file's unit in m (1e-6 for a mesh in µm).
    pub scale: f64,
    /// `axis` (optional, default `[0, 0, 1]`), finite and non-zero, and `angle` (optional, default 0; unit degree):
    /// the rotation of the scaled mesh into the tool frame.
    pub axis: [f64; 3],
    pub angle: f64,
    /// `weld` (optional, default 1e-9), ≥ 0: vertices closer than this fraction of the bounding box's diagonal are
    /// merged before the checks (STL repeats every corner).
    pub weld: f64,
    /// `cell` (optional, default the mean edge length; unit m), > 0: the grid's cell size.
    pub cell: Option<f64>,
    /// `cutoff` (optional, default 2h = 2 h_over_dx dx; unit m), > 0: points farther than this from the surface are
    /// not resolved exactly (the contact needs only those inside or near it).
    pub cutoff: f64,
    /// `safe` (optional, default false): the inside test by ray parity (roethlin §5.5's safe mode) instead of the
    /// pseudo-normals.
    pub safe: bool,
    /// Triangles of the checked mesh (reported).
    pub triangles: usize,
    /// The checked, placed mesh's grid (the tool frame), built once when the scene is read.
    #[serde(skip)]
    pub grid: std::sync::Arc<crate::mesh::MeshGridData>,
}

/// `rotation` in `[tool]`: the tool turns about the axis through `centre` along `axis`, at `rpm` once the ramp is
/// over (the same `ramp` as the translation).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ToolRotation {
    /// `axis` (required) `[x, y, z]`: finite and non-zero (normalised when the motion is built); along z, `[0, 0,
    /// ±1]`, while the tool is the parametric 2D one, which can only turn in its plane.
    pub axis: [f64; 3],
    /// `centre` (required; unit m) `[x, y, z]`: a point on the axis in the tool frame (origin: the edge's lowest
    /// point; the axis passes through `position` + `centre` at t = 0).
    pub centre: [f64; 3],
    /// `rpm` (required; unit 1/min), finite: the rotational speed, positive turning right-handed about `axis`;
    /// ω = 2π rpm/60 rad/s.
    pub rpm: f64,
}

/// How the tool's penalty spring is set (`tool.contact_law`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ContactLawKind {
    /// κ m/Δt²: the fraction κ of a penetration removed per step (the theses' codes).
    Step,
    /// κ K A²/V: a spring of the workpiece's stiffness (LS-DYNA).
    Bulk,
}

/// Friction cap of the tool contact (`tool.friction_cap`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum FrictionCap {
    None,
    Static,
    Current,
}

/// `[tool.thermal]`: the tool sampled by particles on the workpiece's lattice spacing that conduct heat and move
/// with the tool.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ToolThermal {
    /// `material` (required): a library material with `[thermal]` density, specific_heat and conductivity.
    #[serde(skip)]
    pub material: Option<crate::material::Material>,
    /// `temperature` (optional, default `physics.initial_temperature`; unit K), > 0: the tool's initial
    /// temperature, and that of its held band.
    pub temperature: f64,
    /// `fixed_width` (optional, default 2·dx; unit m), ≥ 0: tool particles closer than this to the top or back
    /// face are held at `temperature` (the tool's far boundary).
    pub fixed_width: f64,
    /// `lattice` (optional, default "cells"): "cells" keeps the centres of the cells of spacing dx from the tool's
    /// back and edge that lie at least dx/2 inside the tool; "nodes" the original code's sampling
    /// (`tool::sample_tool`): the nodes of spacing dx from its bounding box's lower-left corner less 0.1 dx that lie
    /// inside it (parametric tools only).
    pub lattice: Lattice,
}

/// `[physics]`: what the run models beyond elasticity; everything off by default except what the material
/// implies (a material with a flow-stress model is plastic unless `plasticity = false`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Physics {
    /// `plasticity` (optional, default: true when the material has a flow-stress model): radial return with the
    /// material's flow-stress model after every step.
    pub plasticity: bool,
    /// `conduction` (optional, default `"off"`): `"off"`, `"brookshaw"` or `"pse"` (needs the material's thermal
    /// conductivity and specific heat).
    pub conduction: Conduction,
    /// `plastic_heating` (optional, default true with plasticity when the material has a specific heat): heats
    /// particles by t_q σ_y Δε̄/(ρ c_p).
    pub plastic_heating: bool,
    /// `taylor_quinney` (optional, default the material's, else 0.9) [-], in [0, 1].
    pub taylor_quinney: f64,
    /// `initial_temperature` (optional, default the material's reference temperature, else 300) [K], > 0.
    pub initial_temperature: f64,
    /// `thermal_expansion` (optional, default 0 = off) [1/K], ≥ 0: the linear expansion coefficient α; the EOS
    /// then uses ρ0(T) = ρ0/(1 + 3α (T − T_ref)), T_ref the material's reference temperature (else 300 K).
    pub thermal_expansion: f64,
    /// The reference temperature of the expansion [K] (the material's reference temperature, else 300).
    pub expansion_reference: f64,
}

impl Physics {
    /// The volumetric expansion 3α [1/K] of the EOS's ρ0(T) (0: off), for the SPH parameters and the damage's
    /// triaxiality alike.
    pub fn volumetric_expansion(&self) -> f64 {
        3.0 * self.thermal_expansion
    }
}

/// Heat conduction discretisation (`physics.conduction`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Conduction {
    Off,
    Brookshaw,
    Pse,
}

/// Floating-point precision of the particle state (`precision`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Precision {
    F32,
    F64,
    /// f32 state with compensated positions: each coordinate an f32 pair hi + lo, the corrector's position sum
    /// exact to the rounding of the step's displacement (docs/measurements/notebook.md, "Mixed precision").
    Mixed,
}

impl Precision {
    pub fn as_str(self) -> &'static str {
        match self {
            Precision::F32 => "f32",
            Precision::F64 => "f64",
            Precision::Mixed => "mixed",
        }
    }

    /// The precision named `name` as [`Precision::as_str`] writes it (scene files, checkpoints), if any.
    pub fn from_name(name: &str) -> Option<Precision> {
        [Precision::F32, Precision::F64, Precision::Mixed].into_iter().find(|p| p.as_str() == name)
    }
}

/// `[discretisation]`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Discretisation {
    /// `dx` (required; unit m), > 0: the lattice spacing of every body.
    pub dx: f64,
    /// `h_over_dx` (optional, default 1.7), in [1, 3]: the smoothing length h in units of dx.
    pub h_over_dx: f64,
    /// `skin_over_h` (optional, default 0.1), in [0, 1]: the neighbour lists' skin s in units of h. The lists are
    /// rebuilt (and the particles reordered) only when a particle has moved farther than s/2 (with the Verlet
    /// list; s without it) since the last build; the cells grow from h to h + s/2. 0 rebuilds every step in which
    /// anything moved. The results do not depend on it beyond round-off (the order of the neighbour sums).
    pub skin_over_h: f64,
    /// `verlet_list` (optional, default true): the pair loops read each particle's candidates within 2h + s from
    /// a list built with the cell list (docs/neighbour-search.md, "Verlet list") instead of walking the ±2
    /// stencil of cells. With one lane per particle the sums are bitwise the same either way.
    pub verlet_list: bool,
    /// `verlet_offsets` (optional, 16 or 32; default 32 for a 3D scene of more than 32 767 particles, else 16):
    /// the bits of each candidate's offset j − i in the Verlet list. 16 halves the list's memory and traffic but
    /// cannot reach a partner more than 32 767 sorted places away, whose particle then walks the stencil: in 3D
    /// two layers of cells apart, or across a z period (docs/neighbour-search.md, "Wide offsets"). The sums are
    /// the same either way.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub verlet_offsets: Option<u32>,
    /// `period_z` (optional, 3D only; unit m), > 0: the domain is periodic in z with this period: a particle near
    /// z = z_0 + P interacts with those near z_0 (nearest images), so an extruded 2D model has no z faces. Give
    /// the bodies' z extent plus dx (a `nodes` lattice from 0 to P − dx; `cells`: 0 to P). At least 5 neighbour
    /// cells of (2h + s)/2 (about 8 dx).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub period_z: Option<f64>,
}

/// `[material]`: linear elasticity (for now the only material; a library by name comes later).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Material {
    /// `name` (optional): a material of the library (`SWARF_MATERIALS`, `materials/` beside the scene file, the
    /// built-in cases/materials/: [`crate::material::search`]); it supplies the elastic constants (unless given
    /// here), the flow-stress model and the thermal data. Without `name` the material is inline and elastic.
    #[serde(skip)]
    pub library: Option<crate::material::Material>,
    /// `density` (required unless `name` gives it; unit kg/m^3), > 0: the reference density ρ0.
    pub density: f64,
    /// `youngs_modulus` (required; unit Pa), > 0: E.
    pub youngs_modulus: f64,
    /// `poisson_ratio` (required; dimensionless), in (-1, 0.5): ν.
    pub poisson_ratio: f64,
}

impl Material {
    /// The elastic constants (one place computes the moduli and the sound speed: `material::Elastic`).
    pub fn elastic(&self) -> crate::material::Elastic {
        crate::material::Elastic {
            density: self.density,
            youngs_modulus: self.youngs_modulus,
            poisson_ratio: self.poisson_ratio,
        }
    }

    /// Bulk modulus K = E / (3 (1 − 2ν)) (Pa).
    pub fn bulk_modulus(&self) -> f64 {
        self.elastic().bulk_modulus()
    }

    /// Shear modulus G = E / (2 (1 + ν)) (Pa).
    pub fn shear_modulus(&self) -> f64 {
        self.elastic().shear_modulus()
    }

    /// Bulk sound speed c0 = √(K/ρ0) (m/s), the speed of the equation of state p = c0² (ρ − ρ0).
    pub fn sound_speed(&self) -> f64 {
        self.elastic().sound_speed()
    }
}

/// How a body's lattice sits in its bounding box (`lattice`): the box is [min, max] for a rectangle or box,
/// [c − R, c + R] per axis for disk, ring and spherical shell (R the outer radius), and [c − R, c + R]² ×
/// [c_z, c_z + height] for a cylinder. On each axis of extent L there are floor(L/dx + 1e-9) intervals.
///
/// For the round shapes the points are placed relative to the centre and kept by their distance from it, computed
/// in f64 as √(Δx² + Δy² (+ Δz²)). When 2R/dx is an integer m (to 1e-9) the offsets from the centre are
/// (k − m/2)·dx (nodes) or (k + ½ − m/2)·dx (cells), i.e. the same lattice computed so that it is exactly
/// symmetric: every body of a given shape gets the same particles wherever its centre lies, and a point exactly
/// on a radius is kept or dropped alike on all sides. Otherwise the offsets are −R + k·dx or −R + (k + ½)·dx.
/// This reproduces the theses' counts: a ring r_i = 0.03, r_o = 0.04 m with dx = 0.08/79 has 2116 particles, the
/// unit disk with dx = 2/19 has 276.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Lattice {
    /// Points at corner + k·dx, k = 0 ..= floor(extent/dx + 1e-9) on each axis (the theses' lattices).
    Nodes,
    /// Cell centres corner + (k + ½)·dx, k = 0 .. floor(extent/dx + 1e-9) (exclusive).
    Cells,
}

impl Lattice {
    pub fn as_str(self) -> &'static str {
        match self {
            Lattice::Nodes => "nodes",
            Lattice::Cells => "cells",
        }
    }

    /// The lattice a scene's `lattice` key names ("nodes" or "cells").
    pub fn parse(s: &str) -> Option<Lattice> {
        [Lattice::Nodes, Lattice::Cells].into_iter().find(|l| l.as_str() == s)
    }
}

/// A `[[body]]` entry.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Body {
    /// `name` (optional, default `"body<index>"`, e.g. `body0`): unique among the bodies.
    pub name: String,
    /// `shape` (required) and its parameters, given as keys of the body table (see [`Shape`]).
    #[serde(flatten)]
    pub shape: Shape,
    /// `velocity` (optional, default zeros; unit m/s), `dim` components: the initial translation velocity.
    pub velocity: [f64; 3],
    /// `angular_velocity` (optional, default 0; unit rad/s): an initial rigid rotation about the z axis through the
    /// body's centre ([`Shape::centre`]): v += ω (−(y − cy), x − cx, 0).
    pub angular_velocity: f64,
    /// `lattice` (optional): `"nodes"` or `"cells"`; default `"cells"` for rectangle and box, `"nodes"` otherwise.
    pub lattice: Lattice,
    /// `material` (optional): a library material whose thermal data (conductivity, specific heat) this body uses
    /// instead of the scene material's; mechanics uses the scene material, so its elastic constants, if any, must
    /// equal the scene material's.
    #[serde(skip)]
    pub material: Option<crate::material::Material>,
    /// `temperature` (optional; unit K), > 0: the body's initial temperature (default `physics.initial_temperature`).
    pub temperature: Option<f64>,
}

/// The `shape` of a body and its parameters (keys of the body table; those of other shapes are an error).
/// Points are in metres. A lattice point ([`Lattice`]) is kept when it lies in the shape as stated per variant;
/// rectangles and boxes keep every point of their lattice.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "shape", rename_all = "snake_case")]
pub enum Shape {
    /// `shape = "rectangle"` (dim 2): `min = [x, y]`, `max = [x, y]` (max > min on both axes).
    Rectangle { min: [f64; 2], max: [f64; 2] },
    /// `shape = "box"` (dim 3): `min = [x, y, z]`, `max = [x, y, z]` (max > min on every axis).
    Box { min: [f64; 3], max: [f64; 3] },
    /// `shape = "disk"` (dim 2): `center = [x, y]`, `radius` > 0. Keeps r < radius.
    Disk { center: [f64; 2], radius: f64 },
    /// `shape = "ring"` (dim 2): `center = [x, y]`, `inner_radius` ≥ 0, `outer_radius` > inner_radius.
    /// Keeps inner_radius ≤ r < outer_radius.
    Ring { center: [f64; 2], inner_radius: f64, outer_radius: f64 },
    /// `shape = "spherical_shell"` (dim 3): `center = [x, y, z]`, `inner_radius` ≥ 0 (0: a solid sphere),
    /// `outer_radius` > inner_radius. Keeps inner_radius ≤ r < outer_radius.
    SphericalShell { center: [f64; 3], inner_radius: f64, outer_radius: f64 },
    /// `shape = "cylinder"` (dim 3), axis along z: `center = [x, y, z]` (the centre of the base), `radius` > 0,
    /// `height` > 0, `inner_radius` (optional, default 0: solid; > 0: a tube) < radius. Keeps
    /// inner_radius ≤ ρ < radius in the xy-plane and c_z ≤ z ≤ c_z + height.
    Cylinder { center: [f64; 3], radius: f64, height: f64, inner_radius: f64 },
}

impl Shape {
    /// The `shape` string.
    pub fn kind(&self) -> &'static str {
        match self {
            Shape::Rectangle { .. } => "rectangle",
            Shape::Box { .. } => "box",
            Shape::Disk { .. } => "disk",
            Shape::Ring { .. } => "ring",
            Shape::SphericalShell { .. } => "spherical_shell",
            Shape::Cylinder { .. } => "cylinder",
        }
    }

    /// The centre of rotation for `angular_velocity`: the centre of a rectangle or box, the `center` of the
    /// other shapes (for a cylinder, the centre of its base). z is 0 in 2D.
    pub fn centre(&self) -> [f64; 3] {
        match *self {
            Shape::Rectangle { min, max } => [0.5 * (min[0] + max[0]), 0.5 * (min[1] + max[1]), 0.0],
            Shape::Box { min, max } => std::array::from_fn(|k| 0.5 * (min[k] + max[k])),
            Shape::Disk { center, .. } | Shape::Ring { center, .. } => [center[0], center[1], 0.0],
            Shape::SphericalShell { center, .. } | Shape::Cylinder { center, .. } => center,
        }
    }

    /// The lattice used when the body gives none.
    pub fn default_lattice(&self) -> Lattice {
        match self {
            Shape::Rectangle { .. } | Shape::Box { .. } => Lattice::Cells,
            _ => Lattice::Nodes,
        }
    }
}

/// A `[[boundary]]` entry: a condition on every particle in an axis-aligned region.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Boundary {
    /// `kind` (required): `"fixed"` (v = 0 for ever) or `"velocity"` (v prescribed for ever, with `velocity`).
    #[serde(flatten)]
    pub kind: BoundaryKind,
    /// `min` (required; unit m), `dim` components: the region is min ≤ x ≤ max (inclusive) on every axis.
    pub min: [f64; 3],
    /// `max` (required; unit m), `dim` components, ≥ min on every axis.
    pub max: [f64; 3],
    /// `body` (optional): restrict to the particles of the body with this name. Stored as the index into
    /// [`Scene::bodies`].
    pub body: Option<usize>,
    /// `reverse_at` (optional, `kind = "velocity"` only; unit s): increasing times at which the prescribed
    /// velocity changes sign, a load reversal (the CT specimen's, docs/damage.md). Empty: constant.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub reverse_at: Vec<f64>,
}

impl Boundary {
    /// The sign of the prescribed velocity at time `t`: −1 after an odd number of the `reverse_at` times.
    pub fn sign_at(reverse_at: &[f64], t: f64) -> f64 {
        if reverse_at.iter().filter(|&&r| r <= t).count() % 2 == 1 { -1.0 } else { 1.0 }
    }
}

/// The kind of a boundary condition.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum BoundaryKind {
    /// `kind = "fixed"`: v = 0 for ever (`velocity` is not allowed).
    Fixed,
    /// `kind = "velocity"`: `velocity` (required; unit m/s), `dim` components, prescribed for ever and used as the
    /// initial velocity too.
    Velocity { velocity: [f64; 3] },
    /// `kind = "plane_strain"` (3D only): the particles keep v_z = 0 and move in their x–y planes, and their
    /// velocity gradient drops ∂/∂z of the in-plane velocity and the in-plane derivatives of v_z (S_xz = S_yz = 0);
    /// an extruded 2D model whose every particle is so held deforms in plane strain (ε_zz = 0).
    PlaneStrain,
    /// `kind = "temperature"`: the particles are held at `temperature` (optional, default the initial temperature)
    /// [K]; no conduction into them and no heating. Independent of the mechanical conditions.
    Temperature { temperature: Option<f64> },
}

impl BoundaryKind {
    pub fn as_str(&self) -> &'static str {
        match self {
            BoundaryKind::Fixed => "fixed",
            BoundaryKind::Velocity { .. } => "velocity",
            BoundaryKind::PlaneStrain => "plane_strain",
            BoundaryKind::Temperature { .. } => "temperature",
        }
    }
}

/// `[stabilisation]`: `None` = off. A table that is present is on unless it says `enabled = false`.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Stabilisation {
    /// `artificial_viscosity = { alpha, beta, eta, switch, enabled }`: Monaghan's artificial viscosity.
    pub artificial_viscosity: Option<ArtificialViscosity>,
    /// `artificial_stress = { epsilon, exponent, enabled }`: Monaghan–Gray artificial stress against the tensile
    /// instability.
    pub artificial_stress: Option<ArtificialStress>,
    /// `xsph = { epsilon, enabled }`: XSPH velocity smoothing of the particle motion.
    pub xsph: Option<Xsph>,
    /// `cspm = { min_determinant, scope, enabled }`: the Randles–Libersky (CSPM) kernel-gradient correction
    /// (`kernels::sph::correction`). Absent from `summary.json` when off.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cspm: Option<Cspm>,
}

/// `[stabilisation.cspm]`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Cspm {
    /// `min_determinant` (optional, default 1e-8, as the original 3D code; dimensionless), in [0, 1): where
    /// det B ≤ this, the particle's gradient is left uncorrected (B is the identity on an interior lattice).
    pub min_determinant: f64,
    /// `scope` (optional, default `"all"`): `"all"` corrects every particle; `"path"` only those with a neighbour
    /// across the cohesive path (`[cohesive]`, required), the faces' rows the path truncates (docs/mpm.md).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub path_only: bool,
}

/// `[stabilisation.artificial_viscosity]`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ArtificialViscosity {
    /// `alpha` (optional, default 1; dimensionless), ≥ 0: the linear (bulk) coefficient.
    pub alpha: f64,
    /// `beta` (optional, default 1; dimensionless), ≥ 0: the quadratic (von Neumann–Richtmyer) coefficient.
    pub beta: f64,
    /// `eta` (optional, default 0.1; dimensionless), > 0: the singularity guard, η² h² added to r² in μ_ij.
    pub eta: f64,
    /// `switch` (optional, default "none"): "balsara" scales the linear term's sound speeds by Balsara's
    /// compression share f = |∇·v| / (|∇·v| + |∇×v| + 1e-4 c/h) (`kernels::sph::interact::balsara`,
    /// docs/solver.md "The Balsara switch"); refused with `enabled = false`. Absent from `summary.json` when "none".
    #[serde(skip_serializing_if = "ViscositySwitch::is_none")]
    pub switch: ViscositySwitch,
}

/// `[stabilisation.artificial_viscosity] switch`: which particles' viscosity is turned down.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ViscositySwitch {
    /// Monaghan's viscosity everywhere (α and β as given).
    #[default]
    None,
    /// Balsara's switch (J. Comput. Phys. 121 (1995) 357) on the linear term.
    Balsara,
}

impl ViscositySwitch {
    /// The values the scene key takes, in its order.
    pub const ALL: [ViscositySwitch; 2] = [ViscositySwitch::None, ViscositySwitch::Balsara];

    pub fn as_str(self) -> &'static str {
        match self {
            ViscositySwitch::None => "none",
            ViscositySwitch::Balsara => "balsara",
        }
    }

    /// The switch named `name` as [`ViscositySwitch::as_str`] writes it, if any.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.as_str() == name)
    }

    fn is_none(&self) -> bool {
        *self == ViscositySwitch::None
    }
}

/// `[stabilisation.artificial_stress]`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ArtificialStress {
    /// `epsilon` (optional, default 0.3; dimensionless), ≥ 0: the fraction of positive principal stress opposed.
    pub epsilon: f64,
    /// `exponent` (optional, default 4), integer ≥ 1: n in f_ij^n = (W(r_ij)/W(Δx))^n.
    pub exponent: u32,
}

/// `[stabilisation.xsph]`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Xsph {
    /// `epsilon` (optional, default 0.5; dimensionless), in [0, 1]: the weight of the neighbour-averaged velocity.
    pub epsilon: f64,
    /// `pic` (optional, default 0 = off; dimensionless), in [0, 0.5]: the PIC-damping analogue's fraction 1 − β
    /// (nairn-mpm.md §7.2, Eq. 8): each step the velocity gives up that fraction of its difference from the
    /// kernel-smoothed velocity (docs/mpm.md "Smoothed-velocity damping"). Absent from `summary.json` when 0.
    #[serde(skip_serializing_if = "is_zero")]
    pub pic: f64,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

/// `[time]`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Time {
    /// `end` (required; unit s), > 0: the simulated time at which the run stops.
    pub end: f64,
    /// `cfl` (optional, default 0.5), in (0, 1]: dt = cfl · h / (c0 + |v|max) when no fixed `dt` is given.
    pub cfl: f64,
    /// `dt` (optional; unit s), > 0: a fixed time step (the solver refuses it if above the CFL limit).
    pub dt: Option<f64>,
    /// `max_steps` (optional, default 1e9), ≥ 1: the most steps the run may take; `check` and `run` refuse a
    /// scene that needs more (`check::steps`) before any work, instead of a run that never ends.
    pub max_steps: f64,
}

/// `[output]`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Output {
    /// `every` (optional, default `time.end / 50`; unit s), > 0: simulated time between frames.
    pub every: f64,
    /// `vtu_encoding` (optional, default `"raw"`): the frames' appended data, `"raw"` (fastest; ParaView, VTK) or
    /// `"base64-zlib"` (smaller; also meshio), [`crate::output::vtu::Encoding`].
    pub vtu_encoding: crate::output::vtu::Encoding,
}

impl Scene {
    /// Every tool of the scene, the first (`tool`) first.
    pub fn tools(&self) -> impl Iterator<Item = &Tool> {
        self.tool.iter().chain(&self.more_tools)
    }

    /// This scene with its precision replaced by `precision` where one is given (a command line's override):
    /// the set-up reads the scene's precision.
    pub fn with_precision(&self, precision: Option<Precision>) -> std::borrow::Cow<'_, Scene> {
        match precision {
            Some(p) if p != self.precision => std::borrow::Cow::Owned(Scene { precision: p, ..self.clone() }),
            _ => std::borrow::Cow::Borrowed(self),
        }
    }

    /// Reads the scene file at `path`, applies the `--set key=value` `overrides` in order, and validates it.
    pub fn load(path: impl AsRef<Path>, overrides: &[String]) -> Result<Scene, SceneError> {
        let path = path.as_ref();
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Read { file: file.clone(), source })?;
        Scene::from_str(&text, &file, overrides)
    }

    /// Parses a scene from `text`; `origin` stands for the file name in messages and places its material search
    /// path ([`crate::material::search::Search::for_scene`]).
    pub fn from_str(text: &str, origin: &str, overrides: &[String]) -> Result<Scene, SceneError> {
        Scene::from_str_in(text, origin, overrides, crate::material::search::Search::for_scene(origin))
    }

    /// [`Scene::from_str`] with the material names looked up in `materials`.
    pub fn from_str_in(
        text: &str,
        origin: &str,
        overrides: &[String],
        materials: crate::material::search::Search,
    ) -> Result<Scene, SceneError> {
        let mut doc = doc::Doc::parse(text, origin)?;
        doc.materials = materials;
        for arg in overrides {
            doc.apply(arg)?;
        }
        read::scene(&doc)
    }

    /// The library materials the scene names (scene, bodies, thermal tool), each once, in that order.
    pub fn library_materials(&self) -> Vec<&crate::material::Material> {
        let tool = self.tool.as_ref().and_then(|t| t.thermal.as_ref()).and_then(|t| t.material.as_ref());
        let bodies = self.bodies.iter().filter_map(|b| b.material.as_ref());
        let mut out: Vec<&crate::material::Material> = Vec::new();
        for m in self.material.library.iter().chain(bodies).chain(tool) {
            if !out.iter().any(|o| o.name == m.name) {
                out.push(m);
            }
        }
        out
    }

    /// The smoothing length h = h_over_dx · dx (m).
    pub fn h(&self) -> f64 {
        self.discretisation.h_over_dx * self.discretisation.dx
    }

    /// The mass of every particle, ρ0 · dx^dim (kg) (per unit depth in 2D).
    pub fn particle_mass(&self) -> f64 {
        self.material.density * self.particle_volume()
    }

    /// The volume of every particle, dx^dim (m^dim) (per unit depth in 2D).
    pub fn particle_volume(&self) -> f64 {
        self.discretisation.dx.powi(self.dim as i32)
    }

    /// The face a lattice particle presents to a plane, Δx^(dim − 1): a cohesive bond's tributary area (Δx per
    /// unit depth in 2D, Δx² in 3D).
    pub fn bond_area(&self) -> f64 {
        self.discretisation.dx.powi(self.dim as i32 - 1)
    }

    /// Fills the bodies with particles and applies the boundary conditions; see [`ParticleSet`].
    pub fn generate(&self) -> Result<ParticleSet, SceneError> {
        generate::generate(self)
    }

    /// A few lines describing the scene, for `swarf run` and `swarf check`.
    pub fn summary(&self) -> String {
        let d = self.dim;
        let m = &self.material;
        let dx = self.discretisation.dx;
        let mut s = String::new();
        let _ = writeln!(s, "scene          {} ({})", self.name, self.origin);
        let _ = writeln!(
            s,
            "dimension      {d}{}, precision {}",
            if d == 2 { " (plane strain)" } else { "" },
            self.precision.as_str()
        );
        let _ = writeln!(
            s,
            "lattice        dx = {} m, h = {}·dx = {} m, neighbour skin {}·h, {}",
            num(dx),
            num(self.discretisation.h_over_dx),
            num(self.h()),
            num(self.discretisation.skin_over_h),
            if self.discretisation.verlet_list { "Verlet list" } else { "cell stencil (no Verlet list)" }
        );
        let _ = writeln!(
            s,
            "material       elastic: rho = {} kg/m^3, E = {} Pa, nu = {}, c0 = sqrt(K/rho) = {} m/s",
            num(m.density),
            num(m.youngs_modulus),
            num(m.poisson_ratio),
            num(m.sound_speed())
        );
        for (i, b) in self.bodies.iter().enumerate() {
            let label = if i == 0 { "bodies" } else { "" };
            let shape = match &b.shape {
                Shape::Rectangle { min, max } => format!("rectangle {} .. {}", pt(min), pt(max)),
                Shape::Box { min, max } => format!("box {} .. {}", pt(min), pt(max)),
                Shape::Disk { center, radius } => format!("disk r = {} at {}", num(*radius), pt(center)),
                Shape::Ring { center, inner_radius, outer_radius } => {
                    format!("ring r = {} .. {} at {}", num(*inner_radius), num(*outer_radius), pt(center))
                }
                Shape::SphericalShell { center, inner_radius, outer_radius } => {
                    format!("spherical shell r = {} .. {} at {}", num(*inner_radius), num(*outer_radius), pt(center))
                }
                Shape::Cylinder { center, radius, height, inner_radius } => format!(
                    "cylinder r = {} .. {}, height {} on {}",
                    num(*inner_radius),
                    num(*radius),
                    num(*height),
                    pt(center)
                ),
            };
            let mut line = format!("{label:<15}{}: {shape} m, {}", b.name, b.lattice.as_str());
            if b.velocity.iter().any(|&v| v != 0.0) {
                let _ = write!(line, ", v = {} m/s", pt(&b.velocity[..d]));
            }
            if b.angular_velocity != 0.0 {
                let _ = write!(line, ", omega = {} rad/s", num(b.angular_velocity));
            }
            let _ = writeln!(s, "{line}");
        }
        for (i, bc) in self.boundaries.iter().enumerate() {
            let label = if i == 0 { "boundaries" } else { "" };
            let mut line = format!("{label:<15}{}: {} .. {} m", bc.kind.as_str(), pt(&bc.min[..d]), pt(&bc.max[..d]));
            if let BoundaryKind::Velocity { velocity } = &bc.kind {
                let _ = write!(line, ", v = {} m/s", pt(&velocity[..d]));
            }
            if let Some(body) = bc.body {
                let _ = write!(line, ", body {}", self.bodies[body].name);
            }
            let _ = writeln!(s, "{line}");
        }
        let st = &self.stabilisation;
        let mut on = Vec::new();
        if let Some(av) = &st.artificial_viscosity {
            let switch = match av.switch {
                ViscositySwitch::None => String::new(),
                s => format!(", {} switch", s.as_str()),
            };
            on.push(format!("AV (alpha {}, beta {}, eta {}{switch})", num(av.alpha), num(av.beta), num(av.eta)));
        }
        if let Some(a) = &st.artificial_stress {
            on.push(format!("AS (epsilon {}, n {})", num(a.epsilon), a.exponent));
        }
        if let Some(x) = &st.xsph {
            on.push(format!("XSPH (epsilon {})", num(x.epsilon)));
            if x.pic > 0.0 {
                on.push(format!("smoothed-velocity damping (pic {})", num(x.pic)));
            }
        }
        if let Some(c) = &st.cspm {
            let scope = if c.path_only { ", the path's faces only" } else { "" };
            on.push(format!("CSPM (min det {}{scope})", num(c.min_determinant)));
        }
        let _ = writeln!(s, "stabilisation  {}", if on.is_empty() { "none".to_string() } else { on.join(", ") });
        if let Some(b) = &self.blanking {
            let v = b.velocity;
            let _ =
                writeln!(s, "blanking       box {} .. {} at t = 0, moving at {} m/s", pt(&b.min), pt(&b.max), pt(&v));
        }
        let step = match self.time.dt {
            Some(dt) => format!("fixed dt = {} s", num(dt)),
            None => format!("cfl {}", num(self.time.cfl)),
        };
        let _ = writeln!(
            s,
            "time           end {} s, {step}, output every {} s",
            num(self.time.end),
            num(self.output.every)
        );
        s
    }
}

/// A number with at most 6 significant digits, for summaries.
fn num(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let a = x.abs();
    if (1e-3..1e6).contains(&a) {
        let digits = (5 - a.log10().floor() as i32).max(0) as usize;
        let s = format!("{x:.digits$}");
        if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s }
    } else {
        let s = format!("{x:.5e}");
        let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
        let mantissa =
            if mantissa.contains('.') { mantissa.trim_end_matches('0').trim_end_matches('.') } else { mantissa };
        format!("{mantissa}e{exponent}")
    }
}

fn pt(p: &[f64]) -> String {
    format!("({})", p.iter().map(|&x| num(x)).collect::<Vec<_>>().join(", "))
}

/// Warnings about input that runs but whose result is not meaningful (issue 8, degenerate input): a body one
/// particle thick (its stresses have no interior to rest on), particles with no neighbour within the kernel
/// support 2h (they move ballistically and carry no stress), and two bodies that start as one piece (equal
/// velocity, spin, material and temperature) whose closest particles lie more than 1.5 Δx but less than 2h apart
/// (a seam: a lattice that does not tile the bodies' extents leaves a weak plane where they meet; the SHTB at
/// Δx = 0.1414 mm parted there without damage, docs/damage.md). `set` is the scene's generated particle set.
pub fn degenerate_input_warnings(scene: &Scene, set: &ParticleSet) -> Vec<String> {
    let dx = scene.discretisation.dx;
    let support = 2.0 * scene.h();
    let mut out = Vec::new();
    let axes = ["x", "y", "z"];
    for (b, body) in scene.bodies.iter().enumerate() {
        let idx: Vec<usize> = (0..set.len()).filter(|&i| set.body[i] as usize == b).collect();
        if idx.len() < 2 {
            continue;
        }
        for (k, axis) in axes.iter().enumerate().take(scene.dim) {
            let (lo, hi) = idx.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &i| {
                (lo.min(set.pos[i][k]), hi.max(set.pos[i][k]))
            });
            if hi - lo < 0.5 * dx {
                out.push(format!(
                    "body '{}' is one particle thick along {axis}: its stresses have no interior neighbours and are \
                     not meaningful",
                    body.name
                ));
            }
        }
    }
    let grid = NeighbourGrid::new(set, support);
    for (b, &k) in grid.lonely(set).iter().enumerate() {
        if k > 0 {
            out.push(format!(
                "{k} particle(s) of body '{}' have no neighbour within 2h: they move ballistically and carry no stress",
                scene.bodies[b].name
            ));
        }
    }
    // Bodies that start as one piece (the same velocity, spin, material and temperature): a seam between them is
    // the lattice's, not the scene's (bodies meant to collide start apart, or in motion).
    // Only their particles are searched: a one-body scene or a collision costs no scan.
    let one_piece = |a: &Body, b: &Body| {
        (a.velocity, a.angular_velocity, &a.material, a.temperature)
            == (b.velocity, b.angular_velocity, &b.material, b.temperature)
    };
    let bodies = &scene.bodies;
    let paired: Vec<bool> =
        (0..bodies.len()).map(|a| (0..bodies.len()).any(|b| b != a && one_piece(&bodies[a], &bodies[b]))).collect();
    for ((a, b), d) in grid.closest_across_bodies(set, &paired) {
        if d > 1.5 * dx && one_piece(&bodies[a], &bodies[b]) {
            out.push(format!(
                "bodies '{}' and '{}' meet across a seam {:.2} Δx wide (their closest particles, {} m apart, interact \
                 but the seam holds less material than the lattice: a weak plane); make the bodies' extents whole \
                 multiples of discretisation.dx = {}",
                scene.bodies[a].name,
                scene.bodies[b].name,
                d / dx,
                num(d),
                num(dx)
            ));
        }
    }
    // The corrected gradient is steeper at free surfaces than the plain one (B⁻¹ > I): measured, a spinning disk
    // goes non-finite at CFL 0.5 and a thin 3D block landing on a tool at 0.4, both run at 0.3 (docs/solver.md).
    if scene.stabilisation.cspm.is_some() && scene.time.dt.is_none() && scene.time.cfl > 0.3 {
        out.push(format!(
            "CSPM with time.cfl = {}: the corrected gradients lower the stable time step; runs measured stable at \
             time.cfl = 0.3 (docs/solver.md, \"CSPM\")",
            scene.time.cfl
        ));
    }
    out
}

/// A hash grid of cell 2h over a particle set, for the set-up's checks of neighbours within 2h.
struct NeighbourGrid {
    support: f64,
    cells: std::collections::HashMap<[i64; 3], Vec<usize>>,
}

impl NeighbourGrid {
    fn new(set: &ParticleSet, support: f64) -> Self {
        let mut cells: std::collections::HashMap<[i64; 3], Vec<usize>> = std::collections::HashMap::new();
        for (i, p) in set.pos.iter().enumerate() {
            cells.entry(Self::cell(support, p)).or_default().push(i);
        }
        NeighbourGrid { support, cells }
    }

    fn cell(support: f64, p: &[f64; 3]) -> [i64; 3] {
        std::array::from_fn(|k| (p[k] / support).floor() as i64)
    }

    /// Calls `f(j, d)` for every other particle j within 2h of particle i, at distance d, until `f` returns false.
    fn for_neighbours(&self, set: &ParticleSet, i: usize, mut f: impl FnMut(usize, f64) -> bool) {
        let (p, r2) = (&set.pos[i], self.support * self.support);
        let c = Self::cell(self.support, p);
        for x in -1..=1 {
            for y in -1..=1 {
                for z in -1..=1 {
                    for &j in self.cells.get(&[c[0] + x, c[1] + y, c[2] + z]).map_or(&[][..], |v| v.as_slice()) {
                        let d2: f64 = (0..3).map(|k| (set.pos[j][k] - p[k]).powi(2)).sum();
                        if j != i && d2 < r2 && !f(j, d2.sqrt()) {
                            return;
                        }
                    }
                }
            }
        }
    }

    /// Per body, its particles with no neighbour within 2h.
    fn lonely(&self, set: &ParticleSet) -> Vec<usize> {
        let bodies = set.body.iter().map(|&b| b as usize + 1).max().unwrap_or(0);
        let mut lonely = vec![0usize; bodies];
        for i in 0..set.len() {
            let mut found = false;
            self.for_neighbours(set, i, |_, _| {
                found = true;
                false
            });
            if !found {
                lonely[set.body[i] as usize] += 1;
            }
        }
        lonely
    }

    /// For every pair of bodies (a < b), both marked in `searched`, with particles within 2h of each other, the
    /// closest such distance, in body order. Particles of unmarked bodies are not searched.
    fn closest_across_bodies(&self, set: &ParticleSet, searched: &[bool]) -> Vec<((usize, usize), f64)> {
        let bodies = searched.len();
        let mut closest = vec![f64::INFINITY; bodies * bodies];
        for i in (0..set.len()).filter(|&i| searched[set.body[i] as usize]) {
            let a = set.body[i] as usize;
            self.for_neighbours(set, i, |j, d| {
                let b = set.body[j] as usize;
                if a < b && searched[b] {
                    closest[a * bodies + b] = closest[a * bodies + b].min(d);
                }
                true
            });
        }
        (0..bodies * bodies)
            .filter(|&k| closest[k].is_finite())
            .map(|k| ((k / bodies, k % bodies), closest[k]))
            .collect()
    }
}
