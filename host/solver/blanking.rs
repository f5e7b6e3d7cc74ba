//! The blanking's active box over time (roethlin-solver.md §7.6.3; the original code's `src/blanking.cpp`): the
//! scene's box [min, max] moving at a constant velocity, outside which particles are frozen
//! (`kernels::neighbour::BlankBox`, docs/3d.md "Blanking"). The box advances in jumps of one `step` of travel, and
//! the step at which it jumps rebuilds the cell list, so that a frozen particle it reaches (frozen particles do not
//! move, so only a jump can change their state) is active within one step of its travel, on every backend alike.

use crate::kernels::neighbour::BlankBox;

/// The blanking of a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Blanking {
    /// The scene's box at t = 0, its velocity and whether it grows (`[blanking]`).
    pub scene: crate::scene::Blanking,
    /// The travel between two jumps [m] (the cell list's skin).
    pub step: f64,
}

impl Blanking {
    fn speed(&self) -> f64 {
        self.scene.speed()
    }

    /// How many jumps the box has made by time t: ⌊t |v| / step⌋ (0 for a box at rest).
    pub fn jumps(&self, t: f64) -> i64 {
        let speed = self.speed();
        if speed > 0.0 && self.step > 0.0 { (t * speed / self.step).floor() as i64 } else { 0 }
    }

    /// The box at time t: moved by v · (jumps · step / |v|), the time of its last jump; growing, only its front
    /// faces move (on each axis the face the box moves towards).
    pub fn box_at(&self, t: f64) -> BlankBox {
        let (speed, b) = (self.speed(), &self.scene);
        let moved = if speed > 0.0 { self.jumps(t) as f64 * self.step / speed } else { 0.0 };
        let shift = |k: usize, front: bool| if b.grow && !front { 0.0 } else { b.velocity[k] * moved };
        BlankBox {
            lo: std::array::from_fn(|k| b.min[k] + shift(k, b.velocity[k] < 0.0)),
            hi: std::array::from_fn(|k| b.max[k] + shift(k, b.velocity[k] > 0.0)),
            rest_speed2: b.rest_speed.map_or(f64::INFINITY, |s| s * s),
            on: 1,
            _pad: 0,
        }
    }
}
