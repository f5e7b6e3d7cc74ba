//! The rigid tool's host side, below the solver and the methods: its motion (translation and rotation), the
//! contact set-up from a scene's `[tool]` (the built shape, the contact constants, the thermal-only tool particles,
//! the engagement check) and the sample of its state that the cutting analyses record.

pub mod motion;
pub mod outline;
pub mod setup;
pub mod shape;

pub use motion::{Rotation, ToolMotion};
pub use shape::{Picture, Shape};

/// The tool's state at one instant, for the cutting record: the force of the tool on the workpiece, its contact
/// statistics, where the tool's frame origin is, and the workpiece's positions (2D, f64).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ToolSample {
    pub time: f64,
    pub steps: u64,
    /// Σ (f_c + f_t) over the particles [N per m of depth in 2D; z = 0 there].
    pub force: [f64; 3],
    /// Σ (x − p) × (f_c + f_t) about the tool's reference point p (`ContactSample::moment`) [N·m; per m in 2D].
    pub moment: [f64; 3],
    pub contacts: usize,
    /// Mean Usui wear rate over the contacting particles [m/s] (NaN when wear is off or nothing touches).
    pub wear_rate: f64,
    /// Σ|f_t| / Σ|f_c| over the contacting particles (NaN when nothing touches).
    pub friction_ratio: f64,
    /// The power of every tool's contact forces now, summed over the tools (the energy audit's integrand).
    pub power: ContactPower,
    /// The tool's translation (z = 0 in 2D).
    pub offset: [f64; 3],
    /// The second and later tools' loads (scenes with several tools).
    pub more: Vec<ToolLoad>,
    /// The mechanical (not thermal-only) particles' positions.
    pub workpiece: Vec<[f64; 2]>,
}

/// The power of a tool's contact forces at one instant [W; per m of depth in 2D], from the forces f_i = f_c,i +
/// f_t,i the last contact pass put on the workpiece particles, their velocities v_i and the tool's material velocity
/// v_T(x_i) at them (`ToolState::velocity_at`: v + ω × (x − o − c)):
///
/// - `tool` = Σ f_i·v_T(x_i) = F·v + M·ω: the work rate of the tool on the workpiece, all that drives a cut;
/// - `friction` = Σ f_t,i·(v_T(x_i) − v_i): what the friction takes out at the interface (dissipated by sliding,
///   stored while the friction's stick spring loads);
/// - `normal` = Σ f_c,i·(v_T(x_i) − v_i): what the penalty takes out (stored while a particle presses in, returned
///   as it leaves) and its dashpot dissipates.
///
/// The workpiece's particles receive `tool − friction − normal` = Σ f_i·v_i, which the solver must book as kinetic,
/// elastic, plastic and viscous energy (docs/validation.md, "Energy audit of the cut").
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactPower {
    pub tool: f64,
    pub friction: f64,
    pub normal: f64,
}

impl ContactPower {
    /// The sum of two tools' powers.
    pub fn plus(self, o: ContactPower) -> ContactPower {
        ContactPower { tool: self.tool + o.tool, friction: self.friction + o.friction, normal: self.normal + o.normal }
    }

    /// The power the workpiece's particles receive, Σ f_i·v_i.
    pub fn workpiece(&self) -> f64 {
        self.tool - self.friction - self.normal
    }
}

/// A further tool's force on the workpiece [N; per m of depth in 2D], its moment about the tool's reference point
/// [N·m], the particles it touches and their mean Usui wear rate [m/s] (NaN without wear or contact), at one sample.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ToolLoad {
    pub force: [f64; 3],
    pub moment: [f64; 3],
    pub contacts: usize,
    pub wear_rate: f64,
}
