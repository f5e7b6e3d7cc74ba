//! The scene's `model`: swarf's own model (the default), or the original 2D code, MFREE_IWF (Röthlin's [C2D],
//! github.com/iwf-inspire/mfree_iwf-ul_cut_gpu), reproduced bugs included, for comparison with results published
//! with it (issue 22; docs/validation.md, "The original model"). A model is a set of [`Switch`]es; every kernel flag
//! and host choice that differs is taken from [`ModelSwitches`] in exactly one place, and [`Model::switches`] is the
//! one place those come from.

use serde::Serialize;

/// One difference of the original code that swarf can reproduce (each a documented bug or quirk of that code).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Switch {
    /// The code's radial-return procedure (`material::c2d_return`): the elastic check at the previous ε̄̇, its
    /// secant iteration with the absolute tolerance 1e-6, its f32 roundings.
    C2dReturn,
    /// The trial deviatoric norm without the factor 2 on S_xy² (**bug**, roethlin-solver.md §11 erratum 25a).
    C2dNorm,
    /// Johnson–Cook's Uintah low-rate form (1 + ε̇*)^C, the code's only form (erratum 9).
    UintahRate,
    /// W = 0.25 (2 − q)⁶ for 1 < q < 2 in XSPH and the artificial stress (**bug**, erratum 24).
    KernelW6,
    /// The friction's slip v_r − v_r∘n (GLM's componentwise product) with the history unprojected, and the friction
    /// heat's v_r − (v_r·n)(1, 1) (**bugs**, erratum 25).
    GlmSlip,
    /// `tool.depth_of_cut` measured from the centre of the top particle row (swarf: the row + Δx/2).
    RowDatum,
    /// Δt = CFL h/(c0 + √v) with v the tool's speed in the code's units (**bug**, erratum 13).
    SqrtVDt,
    /// Pairs closer than 1e-4 code length units (1 µm in the cut's cm; erratum 31) skipped, not 1e-6 h.
    AbsCutoff,
    /// Every mechanically fixed particle held at its initial temperature (the code's thermal boundary, which it
    /// applies where the tool has thermal constants: here with `[tool.thermal]`).
    FixedTemperature,
    /// The code's conduction: the receiving particle's own conductivity (no harmonic mean), its reference density,
    /// and the tool particles' volume from the workpiece's particle mass (roethlin-solver.md §5.6).
    C2dConduction,
    /// The theses' undamped contact, `tool.contact_law = "step"` with `contact_damping = 0`, as the defaults of
    /// those keys (swarf's: `"bulk"` with ξ = 1, whose forces converge in Δt and κ: docs/validation.md,
    /// "Contact law against Δt and κ"); a scene that sets either key keeps its own.
    StepContact,
}

impl Switch {
    /// Every switch, in the order `model = "mfree_iwf"` lists them.
    pub const ALL: [Switch; 11] = [
        Switch::C2dReturn,
        Switch::C2dNorm,
        Switch::UintahRate,
        Switch::KernelW6,
        Switch::GlmSlip,
        Switch::RowDatum,
        Switch::SqrtVDt,
        Switch::AbsCutoff,
        Switch::FixedTemperature,
        Switch::C2dConduction,
        Switch::StepContact,
    ];

    /// The switch's name in a scene's `model = [...]` list.
    pub fn name(self) -> &'static str {
        match self {
            Switch::C2dReturn => "c2d_return",
            Switch::C2dNorm => "c2d_norm",
            Switch::UintahRate => "uintah_rate",
            Switch::KernelW6 => "kernel_w6",
            Switch::GlmSlip => "glm_slip",
            Switch::RowDatum => "row_datum",
            Switch::SqrtVDt => "sqrt_v_dt",
            Switch::AbsCutoff => "abs_cutoff",
            Switch::FixedTemperature => "fixed_temperature",
            Switch::C2dConduction => "c2d_conduction",
            Switch::StepContact => "step_contact",
        }
    }

    /// The switch named `name`, if any.
    pub fn from_name(name: &str) -> Option<Switch> {
        Switch::ALL.into_iter().find(|s| s.name() == name)
    }

    fn bit(self) -> u32 {
        1 << Switch::ALL.iter().position(|s| *s == self).unwrap_or(0)
    }
}

/// A set of [`Switch`]es: what the run takes from the original code.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ModelSwitches(u32);

impl ModelSwitches {
    /// None: swarf's model.
    pub const NONE: ModelSwitches = ModelSwitches(0);

    /// The set of `switches`.
    pub fn of(switches: &[Switch]) -> ModelSwitches {
        ModelSwitches(switches.iter().fold(0, |b, s| b | s.bit()))
    }

    /// Whether `s` is in the set.
    pub fn has(self, s: Switch) -> bool {
        self.0 & s.bit() != 0
    }

    /// Whether the set is empty (swarf's model).
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// The switches in the set, in [`Switch::ALL`]'s order.
    pub fn list(self) -> Vec<Switch> {
        Switch::ALL.into_iter().filter(|s| self.has(*s)).collect()
    }
}

impl Serialize for ModelSwitches {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(self.list().into_iter().map(Switch::name))
    }
}

/// `model` (optional, default `"swarf"`): `"swarf"`, `"mfree_iwf"` (every [`Switch`]), or a list of switch names
/// (`["kernel_w6", "glm_slip"]`: the original code's in those respects only, to measure each one's effect).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum Model {
    #[default]
    Swarf,
    MfreeIwf,
    /// Some of the original code's switches.
    Switches(ModelSwitches),
}

/// The names `model` takes besides a list of switches.
pub const MODEL_NAMES: &[&str] = &["swarf", "mfree_iwf"];

impl Model {
    /// The model named `name` (`"swarf"`, `"mfree_iwf"`), if any.
    pub fn from_name(name: &str) -> Option<Model> {
        match name {
            "swarf" => Some(Model::Swarf),
            "mfree_iwf" => Some(Model::MfreeIwf),
            _ => None,
        }
    }

    /// What the run takes from the original code: the one place every switch is decided.
    pub fn switches(&self) -> ModelSwitches {
        match self {
            Model::Swarf => ModelSwitches::NONE,
            Model::MfreeIwf => ModelSwitches::of(&Switch::ALL),
            Model::Switches(s) => *s,
        }
    }

    /// Whether this is swarf's own model (nothing switched).
    pub fn is_swarf(&self) -> bool {
        self.switches().is_empty()
    }
}

impl Serialize for Model {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Model::Swarf => s.serialize_str("swarf"),
            Model::MfreeIwf => s.serialize_str("mfree_iwf"),
            Model::Switches(sw) => sw.serialize(s),
        }
    }
}

/// The original code's units where its set-up used non-SI ones: its orthogonal cut (`setup_ref_cut`) is in cm, g and
/// µs, its other set-ups (rings, impact) in SI. Lengths and speeds of the scene are converted to them where a
/// reproduced formula is not dimensionally consistent (the √v of [`Switch::SqrtVDt`], the absolute cutoff of
/// [`Switch::AbsCutoff`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CodeUnits {
    /// One code length unit in m (0.01 for the cut's cm, 1 otherwise).
    pub length: f64,
    /// One code speed unit in m/s (1e4 for the cut's cm/µs, 1 otherwise).
    pub speed: f64,
}

impl CodeUnits {
    /// The cut's units with a tool, SI without.
    pub fn of(has_tool: bool) -> CodeUnits {
        if has_tool { CodeUnits { length: 0.01, speed: 1e4 } } else { CodeUnits { length: 1.0, speed: 1.0 } }
    }

    /// The code's √v as a speed in m/s: √(v/u)·u = √(u v) for v [m/s] and the code speed unit u.
    pub fn sqrt_speed(self, v: f64) -> f64 {
        (self.speed * v).sqrt()
    }

    /// The code's near-zero cutoff, r² < 1e-8 code length units², as r² in m².
    pub fn cutoff_squared(self) -> f64 {
        1e-8 * self.length * self.length
    }
}
