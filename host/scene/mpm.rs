//! An MPM scene (`method = "mpm"`; docs/mpm.md): Nairn's orthogonal cut as ductile fracture (nairn-mpm.md §3), or
//! a bonded block pulled apart across its cohesive plane (the cohesive law's energy test, V15). The scene names
//! the set-up's few parameters; `mpm::setup` builds the particles, the grid, the crack and the tool from them.

use super::{Precision, SceneError};
use serde::Serialize;
use std::path::Path;

/// `method = "mpm"` and its tables.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MpmScene {
    /// Where the scene came from (messages); not a key.
    #[serde(skip)]
    pub origin: String,
    /// `name` (required).
    pub name: String,
    /// `precision` (optional, default "f64"): "f32" or "f64".
    pub precision: Precision,
    /// `[material]` (required).
    pub material: MpmMaterial,
    /// `[cohesive]` (required).
    pub cohesive: CohesiveSpec,
    /// `[cut]` or `[bond]` (exactly one).
    pub setup: Setup,
    /// `[time]`.
    pub time: MpmTime,
    /// `[damping]` (optional).
    pub damping: Damping,
}

/// `[material]`: neo-Hookean J2 with linear hardening (nairn-mpm.md §1.4, §2).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MpmMaterial {
    /// `bulk_modulus` K, `shear_modulus` G [Pa].
    pub bulk_modulus: f64,
    pub shear_modulus: f64,
    /// `density` [kg/m³].
    pub density: f64,
    /// `yield_stress` σ_y0 [Pa].
    pub yield_stress: f64,
    /// `tangent_modulus` E_T [Pa] (default 0: elastic–perfectly plastic); E_p = E E_T/(E − E_T).
    pub tangent_modulus: f64,
}

/// `[cohesive]`: the traction law of each mode (nairn-mpm.md §1.5, Eq. 3).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CohesiveSpec {
    /// `law` (default "cubic"): the shape of both modes' laws, "cubic" (Eq. 3) or "triangular"
    /// (`kernels::cohesive::TRIANGULAR`; docs/mpm.md "Traction laws").
    pub law: LawShape,
    /// `toughness` G_c [J/m²] and `peak` σ_c [Pa] of mode I.
    pub toughness: f64,
    pub peak: f64,
    /// `toughness_shear`, `peak_shear` (default: mode I's).
    pub toughness_shear: f64,
    pub peak_shear: f64,
}

/// The variant of a (variant, key value) table that `name` names.
pub(crate) fn by_name<T: Copy>(all: &[(T, &str)], name: &str) -> Option<T> {
    all.iter().find(|(_, n)| *n == name).map(|(v, _)| *v)
}

/// The shape of a cohesive law; its discriminant is the kernels' constant (`kernels::cohesive::TractionLaw::shape`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
#[repr(u32)]
pub enum LawShape {
    Cubic = crate::kernels::cohesive::CUBIC,
    Triangular = crate::kernels::cohesive::TRIANGULAR,
}

impl LawShape {
    /// Each shape and its key value, once.
    pub const ALL: [(LawShape, &'static str); 2] = [(LawShape::Cubic, "cubic"), (LawShape::Triangular, "triangular")];

    /// The shape a key value names.
    pub fn from_name(name: &str) -> Option<LawShape> {
        by_name(&Self::ALL, name)
    }

    /// The kernels' constant for this shape.
    pub fn kernel(self) -> u32 {
        self as u32
    }
}

/// The set-up.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Setup {
    Cut(CutSetup),
    Bond(BondSetup),
}

/// `[cut]`: Nairn's set-up (nairn-mpm.md §3, Fig. 1), lengths in units of the depth h.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CutSetup {
    /// `depth` h [m] (required).
    pub depth: f64,
    /// `particles_across` (default 15, odd: the cut plane then lies mid-cell): particles through h; the cell is
    /// 2h/n (2 × 2 particles per cell).
    pub particles_across: u32,
    /// `width` w, `crack` a, `starter` (its traction-free first part), `base` d (defaults 30, 18, 2, 3) [h].
    pub width: f64,
    pub crack: f64,
    pub starter: f64,
    pub base: f64,
    /// `rake` α, `clearance` θ [deg] (defaults 30, 5).
    pub rake: f64,
    pub clearance: f64,
    /// `speed` [m/s] (default 2), `ramp` (default 0.3): the fraction of the run over which the speed ramps up.
    pub speed: f64,
    pub ramp: f64,
    /// `friction` μ (default 0).
    pub friction: f64,
    /// `cut_length` [h] (default 12): how far the tool travels; the run's end unless `[time] end` is given.
    pub cut_length: f64,
    /// `tool_height` [h] (default 6): the rake face's height above the cut plane.
    pub tool_height: f64,
    /// `room` [h] (default 10): the grid's height above the specimen, where the chip curls, and half of it behind
    /// the tool (a chip that curls over the tool's top comes down there).
    pub room: f64,
}

/// `[bond]`: two blocks joined along y = 0 by the cohesive law, the lower one's bottom held, the upper one's top
/// gripped and moved at `pull` (ramped), so that the plane opens in mode I (pull along y) or slides in mode II
/// (along x).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BondSetup {
    /// `width` and `height` (of each block) [m].
    pub width: f64,
    pub height: f64,
    /// `cell` Δx [m] (2 × 2 particles per cell).
    pub cell: f64,
    /// `pull` [m/s]: the grip's final velocity.
    pub pull: [f64; 2],
    /// `ramp` (default 0.1): the fraction of the run over which the grip's speed ramps up.
    pub ramp: f64,
}

/// `[time]`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MpmTime {
    /// `end` [s] (required for `[bond]`; for `[cut]` default: the cut length at the ramped speed).
    pub end: f64,
    /// `cfl` (default 0.5): Δt = cfl Δx / c_d, c_d = √((K + 4G/3)/ρ).
    pub cfl: f64,
    /// `samples` (default 400): force samples over the run, each the mean over its interval.
    pub samples: u32,
    /// `frames` (default 10): particle frames over the run.
    pub frames: u32,
}

/// Young's modulus E = 9KG/(3K + G) of bulk modulus K and shear modulus G.
pub fn young_modulus(bulk: f64, shear: f64) -> f64 {
    9.0 * bulk * shear / (3.0 * bulk + shear)
}

/// `[damping]`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Damping {
    /// `pic` (default 1): the PIC fraction 1 − β of Eq. 8 (1: full PIC, the paper's production runs; 0: FLIP).
    pub pic: f64,
    /// `feedback` (default 0: off): the gain g of the start-up kinetic-energy feedback damping during the ramp
    /// (nairn-mpm.md §1.3), dimensionless: 1/Q = g/(v² t_ramp²), v the ramp's full speed, so that the damping
    /// reaches about g K/(½ M v²)/t_ramp over the ramp whatever the scale (docs/mpm.md "Start-up damping").
    pub feedback: f64,
    /// `position_update` (default "second"): the particles' position update, "second" (Eq. 10, the paper's),
    /// "first" (Eq. 10 without its acceleration term) or "zeroth" (Eq. 9): the variants of Fig. 2 (V14).
    pub position_update: PositionUpdate,
}

/// The particles' position update of an MPM scene (`[damping] position_update`); its discriminant is the kernels'
/// constant (`kernels::mpm::grid::MpmParams::position_order`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
#[repr(u32)]
pub enum PositionUpdate {
    Zeroth = crate::kernels::mpm::grid::POSITION_ZEROTH,
    First = crate::kernels::mpm::grid::POSITION_FIRST,
    Second = crate::kernels::mpm::grid::POSITION_SECOND,
}

impl PositionUpdate {
    /// Each variant and its key value, once.
    pub const ALL: [(PositionUpdate, &'static str); 3] =
        [(PositionUpdate::Zeroth, "zeroth"), (PositionUpdate::First, "first"), (PositionUpdate::Second, "second")];

    /// The variant a key value names.
    pub fn from_name(name: &str) -> Option<PositionUpdate> {
        by_name(&Self::ALL, name)
    }

    /// The kernels' constant.
    pub fn kernel(self) -> u32 {
        self as u32
    }
}

impl MpmScene {
    /// Reads an MPM scene file, applies the `--set` overrides and validates it.
    pub fn load(path: impl AsRef<Path>, overrides: &[String]) -> Result<MpmScene, SceneError> {
        let path = path.as_ref();
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Read { file: file.clone(), source })?;
        MpmScene::from_str(&text, &file, overrides)
    }

    /// Parses an MPM scene from `text` (`origin` names it in messages).
    pub fn from_str(text: &str, origin: &str, overrides: &[String]) -> Result<MpmScene, SceneError> {
        let mut doc = super::doc::Doc::parse(text, origin)?;
        for arg in overrides {
            doc.apply(arg)?;
        }
        super::read::mpm_scene(&doc)
    }

    /// Young's modulus of the specimen ([`young_modulus`]).
    pub fn young(&self) -> f64 {
        young_modulus(self.material.bulk_modulus, self.material.shear_modulus)
    }

    /// The particle spacing [m]: half the cell (2 × 2 particles per cell): h/n for a cut, `cell`/2 for a bond.
    pub fn spacing(&self) -> f64 {
        match self.setup {
            Setup::Cut(c) => c.depth / f64::from(c.particles_across),
            Setup::Bond(b) => 0.5 * b.cell,
        }
    }

    /// The override that scales the particle spacing by `factor` (a `swarf study` level): a bond's `bond.cell`
    /// times the factor; a cut's `cut.particles_across`, the odd count nearest n/factor (at least 3: the cut plane
    /// lies mid-cell only for odd counts), so that a cut's levels 1, 1/2, 2 from 15 through h give 15, 31, 7. The
    /// spacing the override gives is [`Self::spacing`] of the scene loaded with it.
    pub fn level_override(&self, factor: f64) -> String {
        match self.setup {
            Setup::Cut(c) => {
                let odd = 2.0 * ((f64::from(c.particles_across) / factor - 1.0) / 2.0).round() + 1.0;
                format!("cut.particles_across={}", odd.max(3.0))
            }
            Setup::Bond(b) => format!("bond.cell={:e}", b.cell * factor),
        }
    }

    /// The dilatational wave speed c_d = √((K + 4G/3)/ρ).
    pub fn wave_speed(&self) -> f64 {
        let m = &self.material;
        ((m.bulk_modulus + 4.0 / 3.0 * m.shear_modulus) / m.density).sqrt()
    }
}

/// The method a scene file asks for: its top-level `method` key ("sph" when absent). Read before the scene is
/// validated, so that each method validates its own keys.
pub fn method_of(text: &str, origin: &str) -> Result<String, SceneError> {
    let doc = super::doc::Doc::parse(text, origin)?;
    super::read::method(&doc)
}

/// Whether the scene file at `path` asks for the MPM ([`method_of`] of its text): how `sweep` and `study` choose
/// their planner.
pub fn is_mpm_file(path: &Path) -> Result<bool, SceneError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|source| SceneError::Read { file: file.clone(), source })?;
    Ok(method_of(&text, &file)? == "mpm")
}
