//! How the rigid tool moves: at a constant velocity, optionally reached through a linear start-up ramp
//! (the ramp softens the impact of the tool on the workpiece at t = 0).

/// The tool's kinematics: its frame origin starts at `start` and moves with `velocity`, reached linearly over
/// `ramp` seconds (0: no ramp).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ToolMotion {
    pub start: [f64; 2],
    pub velocity: [f64; 2],
    pub ramp: f64,
}

impl ToolMotion {
    /// v(t) = v · min(t/t_r, 1).
    pub fn velocity_at(&self, t: f64) -> [f64; 2] {
        let f = if self.ramp > 0.0 && t < self.ramp { t.max(0.0) / self.ramp } else { 1.0 };
        [self.velocity[0] * f, self.velocity[1] * f]
    }

    /// x(t) = x0 + v s(t), s = t²/(2 t_r) during the ramp and t − t_r/2 after it (the integral of v(t)).
    pub fn offset_at(&self, t: f64) -> [f64; 2] {
        let s = if self.ramp > 0.0 && t < self.ramp {
            0.5 * t.max(0.0) * t.max(0.0) / self.ramp
        } else if self.ramp > 0.0 {
            t - 0.5 * self.ramp
        } else {
            t
        };
        [self.start[0] + self.velocity[0] * s, self.start[1] + self.velocity[1] * s]
    }
}
