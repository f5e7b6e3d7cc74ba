//! How a rigid tool moves: a translation at a constant velocity and optionally a rotation about an axis at a
//! constant angular velocity (milling cutters, grinding wheels), both reached through the same linear start-up
//! ramp (the ramp softens the impact of the tool on the workpiece at t = 0). Three components in every dimension
//! (z = 0 in 2D); the kernels see it at each step as a [`ToolState`].

use crate::kernels::contact::ToolState;

/// A rotation about the axis through `centre` (tool frame) along the unit vector `axis`, at `rate` rad/s once the
/// ramp is over (right-handed about `axis`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Rotation {
    pub axis: [f64; 3],
    pub centre: [f64; 3],
    pub rate: f64,
}

/// The tool's kinematics: its frame origin starts at `start` and moves with `velocity`, and it turns as
/// `rotation` says, both reached linearly over `ramp` seconds (0: no ramp).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ToolMotion {
    pub start: [f64; 3],
    pub velocity: [f64; 3],
    pub ramp: f64,
    /// None: a translating tool (its kernels' path has no rotation arithmetic).
    pub rotation: Option<Rotation>,
}

impl ToolMotion {
    /// A translating tool (z = 0 in 2D).
    pub fn translating(start: [f64; 3], velocity: [f64; 3], ramp: f64) -> ToolMotion {
        ToolMotion { start, velocity, ramp, rotation: None }
    }

    /// The ramp's factor f(t) = min(t/t_r, 1): v(t) = v f(t), ω(t) = ω f(t).
    fn factor(&self, t: f64) -> f64 {
        if self.ramp > 0.0 && t < self.ramp { t.max(0.0) / self.ramp } else { 1.0 }
    }

    /// The integral of the ramp's factor, s(t) = t²/(2 t_r) during the ramp and t − t_r/2 after it:
    /// x(t) = x0 + v s(t), θ(t) = ω s(t).
    fn travel(&self, t: f64) -> f64 {
        if self.ramp > 0.0 && t < self.ramp {
            0.5 * t.max(0.0) * t.max(0.0) / self.ramp
        } else if self.ramp > 0.0 {
            t - 0.5 * self.ramp
        } else {
            t
        }
    }

    /// v(t) = v · min(t/t_r, 1).
    pub fn velocity_at(&self, t: f64) -> [f64; 3] {
        let f = self.factor(t);
        self.velocity.map(|v| v * f)
    }

    /// x(t) = x0 + v s(t).
    pub fn offset_at(&self, t: f64) -> [f64; 3] {
        let s = self.travel(t);
        std::array::from_fn(|k| self.start[k] + self.velocity[k] * s)
    }

    /// The rotation angle θ(t) = ω s(t) [rad] (0 without a rotation).
    pub fn angle_at(&self, t: f64) -> f64 {
        self.rotation.map_or(0.0, |r| r.rate * self.travel(t))
    }

    /// The angular velocity θ̇(t) = ω min(t/t_r, 1) [rad/s] (0 without a rotation).
    pub fn angular_velocity_at(&self, t: f64) -> f64 {
        self.rotation.map_or(0.0, |r| r.rate * self.factor(t))
    }

    /// The tool as the kernels see it at time `t`, with the run's nominal step `dt` and this step's length `step`.
    pub fn state_at(&self, t: f64, dt: f64, step: f64) -> ToolState {
        let mut s =
            ToolState { offset: self.offset_at(t), velocity: self.velocity_at(t), dt, step, ..Default::default() };
        if let Some(r) = self.rotation {
            let w = self.angular_velocity_at(t);
            s.centre = r.centre;
            s.omega = r.axis.map(|a| a * w);
            s.rotation = rotation_matrix(r.axis, self.angle_at(t));
            s.rotating = 1;
        }
        s
    }
}

/// Rodrigues' rotation by `angle` about the unit vector `a`: R = cos θ I + sin θ [a]× + (1 − cos θ) a aᵀ.
pub fn rotation_matrix(a: [f64; 3], angle: f64) -> [[f64; 3]; 3] {
    let (s, c) = angle.sin_cos();
    let k = 1.0 - c;
    let cross = [[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]];
    std::array::from_fn(|i| std::array::from_fn(|j| (if i == j { c } else { 0.0 }) + s * cross[i][j] + k * a[i] * a[j]))
}
