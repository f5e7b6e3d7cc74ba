//! The tool's rigid motion at one instant, as the contact pass sees it: a translation, and optionally a rotation
//! about an axis through a centre (milling cutters, grinding wheels). A tool-frame point p is at the world point
//!   x = o + c + R (p − c),   so   p = c + Rᵀ (x − o − c),
//! with o the translation, c the rotation centre (tool frame) and R = R(θ) the rotation; the tool's material
//! velocity at a world point x is
//!   v_tool(x) = v + ω × (x − o − c),
//! with ω = θ̇ a the angular velocity about the unit axis a. Without rotation (R = I, ω = 0) the maps reduce to
//! p = x − o and v_tool = v, and that path does no other arithmetic, so a translating tool gives the bits it gave
//! before rotation existed.

use bytemuck::{Pod, Zeroable};

/// Where the tool is at the end of the step and how it moves (world frame; z = 0 in 2D).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ToolState {
    /// The translation o: the world position of the tool frame's origin when the rotation angle is zero.
    pub offset: [f64; 3],
    /// The translation velocity v.
    pub velocity: [f64; 3],
    /// The rotation centre c, in the tool frame (the axis passes through o + c).
    pub centre: [f64; 3],
    /// The angular velocity ω = θ̇ a [rad/s].
    pub omega: [f64; 3],
    /// R(θ), tool frame to world, row by row.
    pub rotation: [[f64; 3]; 3],
    /// The run's time step Δt, which scales the penalty and friction stiffness (κ m/Δt², κ m/Δt). A step cut short
    /// to land on an output time must not stiffen the contact by (Δt/step)², so this is the nominal step.
    pub dt: f64,
    /// The length of this step, for the friction heat.
    pub step: f64,
    /// Nonzero when the tool rotates: the maps then use `centre`, `omega` and `rotation`; zero ignores them.
    pub rotating: u32,
    pub _pad: u32,
}

impl ToolState {
    /// The tool-frame point of world point `x`: x − o, or c + Rᵀ (x − o − c) when rotating.
    #[inline(always)]
    pub fn to_tool(&self, x: [f64; 3]) -> [f64; 3] {
        let o = self.offset;
        let d = [x[0] - o[0], x[1] - o[1], x[2] - o[2]];
        if self.rotating == 0 {
            return d;
        }
        let (c, m) = (self.centre, &self.rotation);
        let r = [d[0] - c[0], d[1] - c[1], d[2] - c[2]];
        let mut p = [0.0; 3];
        let mut i = 0;
        while i < 3 {
            p[i] = c[i] + (m[0][i] * r[0] + m[1][i] * r[1] + m[2][i] * r[2]);
            i += 1;
        }
        p
    }

    /// A tool-frame direction in the world frame: n, or R n when rotating.
    #[inline(always)]
    pub fn direction_to_world(&self, n: [f64; 3]) -> [f64; 3] {
        if self.rotating == 0 {
            return n;
        }
        let m = &self.rotation;
        let mut w = [0.0; 3];
        let mut i = 0;
        while i < 3 {
            w[i] = m[i][0] * n[0] + m[i][1] * n[1] + m[i][2] * n[2];
            i += 1;
        }
        w
    }

    /// The tool-frame point `p` in the world frame: o + p, or o + c + R (p − c) when rotating.
    #[inline(always)]
    pub fn point_to_world(&self, p: [f64; 3]) -> [f64; 3] {
        let o = self.offset;
        if self.rotating == 0 {
            return [o[0] + p[0], o[1] + p[1], o[2] + p[2]];
        }
        let c = self.centre;
        let r = self.direction_to_world([p[0] - c[0], p[1] - c[1], p[2] - c[2]]);
        [o[0] + c[0] + r[0], o[1] + c[1] + r[1], o[2] + c[2] + r[2]]
    }

    /// The tool's material velocity at world point `x`: v, or v + ω × (x − o − c) when rotating.
    #[inline(always)]
    pub fn velocity_at(&self, x: [f64; 3]) -> [f64; 3] {
        let v = self.velocity;
        if self.rotating == 0 {
            return v;
        }
        let (o, c, w) = (self.offset, self.centre, self.omega);
        let r = [(x[0] - o[0]) - c[0], (x[1] - o[1]) - c[1], (x[2] - o[2]) - c[2]];
        [v[0] + (w[1] * r[2] - w[2] * r[1]), v[1] + (w[2] * r[0] - w[0] * r[2]), v[2] + (w[0] * r[1] - w[1] * r[0])]
    }
}
