//! The background grid of MPM and what a node knows of the scene: its place, which of its two specimen fields a
//! particle joins across the crack (CRAMP, simplified to the straight cut plane: nairn-mpm.md §1.5, §7.1), its
//! boundary conditions and the tool's prescribed contact normal (§1.6, §1.8).

use super::hyperelastic::NeoHookeanJ2;
use crate::cohesive::Cohesive;
use bytemuck::{Pod, Zeroable};

/// A specimen particle below the cut plane.
pub const BELOW: u32 = 0;
/// A specimen particle above the cut plane (the chip's side).
pub const ABOVE: u32 = 1;
/// A particle of the rigid tool.
pub const TOOL: u32 = 2;

/// How far across the cut plane, in cells, a specimen particle may stray and still join its own side's fields
/// (`MpmParams::field_of`).
pub const STRAY_CELLS: f64 = 2.0;

/// [`MpmParams::position_order`]: x += v_g→p⁽ⁿ⁺¹⁾ Δt (Eq. 9, standard FLIP).
pub const POSITION_ZEROTH: u32 = 0;
/// [`MpmParams::position_order`]: Eq. 10 with its damping term only, x += v_g→p⁽ⁿ⁺¹⁾ Δt − ½ α (v_p − v_g→p) Δt².
pub const POSITION_FIRST: u32 = 1;
/// [`MpmParams::position_order`]: the whole of Eq. 10, x += v_g→p⁽ⁿ⁺¹⁾ Δt − ½ (a_g→p + α (v_p − v_g→p)) Δt².
pub const POSITION_SECOND: u32 = 2;

/// The run's constants, by value in every MPM pass. Lengths in metres, f64 whatever the run's precision, so that
/// a particle's field and a node's place are the same on every backend and in both precisions.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct MpmParams {
    /// The position of node (0, 0).
    pub origin: [f64; 2],
    /// The cell size Δx (square cells).
    pub dx: f64,
    /// The particles' half-width l_p (Δx/4 at 2 × 2 particles per cell).
    pub lp: f64,
    /// Nodes along x and y; the cells, (nx − 1)(ny − 1), are the cell list's.
    pub nodes: [u32; 2],
    /// Crack points on the plane (0: no crack; the starter's points are failed from the start).
    pub crack_points: u32,
    /// The particles' position update: [`POSITION_SECOND`] (Eq. 10, the paper's with PIC damping),
    /// [`POSITION_FIRST`] or [`POSITION_ZEROTH`] (Eq. 9), the variants of its Fig. 2 (nairn-mpm.md §1.2, V14).
    pub position_order: u32,
    /// The cut plane y = crack_y and the crack's extent crack_lo ≤ x ≤ crack_hi, across which the specimen's
    /// fields separate (it reaches past the specimen's edges, so that no node joins the sides around an edge).
    pub crack_y: f64,
    pub crack_lo: f64,
    pub crack_hi: f64,
    /// The crack points cover the material's part of the crack, from points_lo on, at spacing ds: point k sits at
    /// points_lo + (k + ½) ds and stands for ds of crack.
    pub points_lo: f64,
    pub crack_ds: f64,
    /// Nodes at y ≤ fix_below hold still (the specimen's fixed bottom edge; −∞: none).
    pub fix_below: f64,
    /// Nodes at y ≥ pull_above move at the step's pull velocity (a loading grip; +∞: none).
    pub pull_above: f64,
    /// A field lighter than this has no velocity (the small-mass nodes at a body's edge) [kg/m].
    pub mass_floor: f64,
    /// Coulomb friction μ between the specimen and the tool.
    pub friction: f64,
    /// The contact's volume check: a field touches the tool at a node where their volumes there (Σ S V) fill at
    /// least this fraction of a cell (1: they meet; below 1, contact acts across a gap).
    pub contact_fill: f64,
    /// The contact normals from the specimen into the tool, prescribed (nairn-mpm.md §1.6): the rake face's
    /// (−cos α, −sin α) for a tool cutting towards +x, and the flank's (0, 1).
    pub rake_normal: [f64; 2],
    pub flank_normal: [f64; 2],
    /// The direction of the tool wedge's bisector from the cutting edge, at (90° + α + 180° − θ)/2: the line
    /// through the edge along it parts the nodes that take the rake's normal from those that take the flank's.
    pub face_split: [f64; 2],
    pub cohesive: Cohesive,
    pub material: NeoHookeanJ2,
}

/// What changes from step to step, by value in the passes that need it.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct MpmStep {
    /// Δt [s].
    pub dt: f64,
    /// The PIC damping α_PIC = (1 − β)/Δt (nairn-mpm.md §1.2, Eq. 8) [1/s].
    pub alpha_pic: f64,
    /// The tool's velocity over the step and its displacement from its place at t = 0 at the step's end.
    pub tool_vel: [f64; 2],
    pub tool_disp: [f64; 2],
    /// The tool's cutting edge at the step's start (which face's normal a node takes).
    pub tool_tip: [f64; 2],
    /// The grip's velocity over the step (`MpmParams::pull_above`).
    pub pull_vel: [f64; 2],
    /// The start-up damping's gain 1/(Q M) of the kinetic-energy feedback (nairn-mpm.md §1.3; `step::feedback`)
    /// [1/(m² kg/m)]; 0: off (after the ramp), and the damping is reset to 0.
    pub feedback: f64,
}

impl MpmParams {
    /// Node (a, b)'s position.
    #[inline(always)]
    pub fn node_pos(&self, a: u32, b: u32) -> [f64; 2] {
        [self.origin[0] + a as f64 * self.dx, self.origin[1] + b as f64 * self.dx]
    }

    /// Node i's column and row (x fastest); (0, 0) on a grid without nodes.
    #[inline(always)]
    pub fn node_ab(&self, i: usize) -> (u32, u32) {
        let nx = self.nodes[0];
        if nx == 0 { (0, 0) } else { ((i as u32) % nx, (i as u32) / nx) }
    }

    /// The cell list's cells along x and y.
    #[inline(always)]
    pub fn cells(&self) -> [u32; 2] {
        [self.nodes[0] - 1, self.nodes[1] - 1]
    }

    /// The field (0: the node's own side, 1: the other side of the crack) that a specimen particle of side
    /// `kind` at (x, y) joins at the node at `node` (CRAMP's test, nairn-mpm.md §1.5): the other side when the
    /// segment from the particle to the node crosses the crack. The particle's y is first clamped to its side of
    /// the plane, so that a particle that strays a little across the plane stays on its side. A particle more
    /// than [`STRAY_CELLS`] cells across has left the crack's faces (a workpiece particle lifted over the cutting
    /// edge into the chip): it joins the side it is in, so that it moves with the material around it instead of
    /// alone in the other field (docs/mpm.md "Stray particles"). Without a crack, 0.
    #[inline(always)]
    pub fn field_of(&self, kind: u32, x: f64, y: f64, node: [f64; 2]) -> usize {
        if self.crack_points == 0 {
            return 0;
        }
        let yc = self.crack_y;
        let band = STRAY_CELLS * self.dx;
        let p_above = if kind == ABOVE { y > yc - band } else { y > yc + band };
        if (node[1] > yc) == p_above {
            return 0;
        }
        let yp = if p_above {
            if y > yc { y } else { yc }
        } else if y < yc {
            y
        } else {
            yc
        };
        // The node is strictly on the other side (no node lies on the plane: `MpmParams` places it mid-cell),
        // so node[1] ≠ yp.
        let xs = x + (yc - yp) / (node[1] - yp) * (node[0] - x);
        if xs >= self.crack_lo && xs <= self.crack_hi { 1 } else { 0 }
    }

    /// Crack point k's x.
    #[inline(always)]
    pub fn crack_x(&self, k: u32) -> f64 {
        self.points_lo + (k as f64 + 0.5) * self.crack_ds
    }

    /// The contact normal of field `field` (0: the node's own side, 1: the other side) at a node. Along the crack,
    /// by the side of the field's material: the chip's (above the plane) touches the rake face, the workpiece's
    /// (below it) the flank, as the crack parts them at the cutting edge (docs/mpm.md "Which face's normal").
    /// Elsewhere, by the node's place: the rake's on the rake's side of the wedge's bisector through the cutting
    /// edge (ahead of and above the edge), the flank's on the other side (behind and below it).
    #[inline(always)]
    pub fn tool_normal(&self, node: [f64; 2], tip: [f64; 2], field: usize) -> [f64; 2] {
        if self.crack_points > 0 && node[0] >= self.crack_lo && node[0] <= self.crack_hi {
            let above = (node[1] > self.crack_y) == (field == 0);
            return if above { self.rake_normal } else { self.flank_normal };
        }
        let (x, y) = (node[0] - tip[0], node[1] - tip[1]);
        let side = self.face_split[0] * y - self.face_split[1] * x;
        if side < 0.0 { self.rake_normal } else { self.flank_normal }
    }
}
