//! The rigid 2D cutting tool (roethlin-solver.md §5.4, "Tool geometry"): four line segments (rake face, top,
//! back, flank) and the edge arc of radius r_c tangent to the rake and flank faces, with the exact signed distance
//! and outward normal of any point (AT-40, AT-41).
//!
//! Tool frame: the origin is the lowest point of the cutting edge, the tool lies above it (y ≥ 0) and cuts in +x,
//! its rake face facing +x. The rake angle γ is measured from the vertical (positive leans the face back, away
//! from the chip), the clearance angle α from the horizontal (the flank rises behind the edge). The wedge angle
//! is β = 90° − γ − α. With the sharp corner T of the rake and flank lines, the rake direction up the face
//! d_r = (−sin γ, cos γ) and the flank direction back along the face d_f = (−cos α, sin α):
//!   arc centre  c = T + r/sin(β/2) · b,  b = (d_r + d_f)/|d_r + d_f| (the bisector),
//!   tangent points T_r = T + r/tan(β/2) · d_r and T_f = T + r/tan(β/2) · d_f,
//! so that c lies at distance r from both lines (AT-40). The lowest point of the rounded edge is c − (0, r)
//! (α ≥ 0 puts the downward normal inside the arc), which fixes T.
//!
//! The outline, counter-clockwise: flank F → T_f, arc T_f → T_r, rake T_r → R, top R → TL, back TL → F, with
//! R on the rake line at y = height, F on the flank line at x = −length and TL = (−length, height). The rounded
//! polygon is convex.

use crate::real::Real;
use bytemuck::{Pod, Zeroable};

/// Construction parameters of a 2D tool (radians, metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToolShape {
    pub rake_angle: f64,
    pub clearance_angle: f64,
    pub edge_radius: f64,
    /// Extent behind the edge's lowest point, along −x.
    pub length: f64,
    /// Extent above the edge's lowest point, along +y.
    pub height: f64,
}

/// Why a tool shape cannot be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShapeError {
    /// The wedge angle 90° − γ − α is not in (0°, 180°), or α < 0.
    Angles,
    /// A negative or non-finite edge radius, length or height.
    Size,
    /// The faces are too short for the edge arc, or the flank reaches above the top.
    TooSmall,
}

/// Segment indices in [`Tool2d::seg`].
pub const RAKE: usize = 0;
pub const TOP: usize = 1;
pub const BACK: usize = 2;
pub const FLANK: usize = 3;
/// The primitive index of the edge arc in [`Closest::primitive`].
pub const ARC: u32 = 4;

/// A built tool: plain data for the kernels (f64: the geometry is evaluated in double precision in every run).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Tool2d {
    /// Segments RAKE, TOP, BACK, FLANK, each (a.x, a.y, b.x, b.y, n.x, n.y): end points in counter-clockwise order
    /// and the outward unit normal.
    pub seg: [[f64; 6]; 4],
    /// Edge-arc centre and radius (radius 0: a sharp edge, the arc is the corner point).
    pub centre: [f64; 2],
    pub radius: f64,
    /// Outward normals at the arc's flank and rake ends; the arc covers the normals between them counter-clockwise.
    pub n_flank: [f64; 2],
    pub n_rake: [f64; 2],
    /// Unit normal of the chord T_f–T_r pointing to the edge (the corner region beyond it is outside the arc).
    pub n_chord: [f64; 2],
    pub rake_angle: f64,
    pub clearance_angle: f64,
}

/// The closest boundary point of a query point.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Closest {
    /// Signed distance: negative inside the tool.
    pub distance: f64,
    /// The closest point on the outline.
    pub point: [f64; 2],
    /// Outward unit normal of the outline at `point` (for an outside point, the direction from it to the query).
    pub normal: [f64; 2],
    /// 0..4: segment RAKE, TOP, BACK, FLANK; 4: the arc.
    pub primitive: u32,
}

#[inline(always)]
fn sqrt(x: f64) -> f64 {
    <f64 as Real>::sqrt(x)
}

#[inline(always)]
fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

#[inline(always)]
fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

#[inline(always)]
fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

#[inline(always)]
fn add_scaled(a: [f64; 2], s: f64, d: [f64; 2]) -> [f64; 2] {
    [a[0] + s * d[0], a[1] + s * d[1]]
}

impl Tool2d {
    /// Builds the tool of `s` in its frame (see the module doc).
    pub fn new(s: &ToolShape) -> Result<Tool2d, ShapeError> {
        let (g, a) = (s.rake_angle, s.clearance_angle);
        let half_pi = core::f64::consts::FRAC_PI_2;
        let wedge = half_pi - g - a;
        if !(g.is_finite() && a.is_finite()) || a < 0.0 || wedge <= 0.0 || wedge >= core::f64::consts::PI {
            return Err(ShapeError::Angles);
        }
        let r = s.edge_radius;
        let finite = r.is_finite() && s.length.is_finite() && s.height.is_finite();
        if !(finite && r >= 0.0 && s.length > 0.0 && s.height > 0.0) {
            return Err(ShapeError::Size);
        }
        let (sg, cg, sa, ca) = (libm::sin(g), libm::cos(g), libm::sin(a), libm::cos(a));
        let d_r = [-sg, cg];
        let d_f = [-ca, sa];
        let n_rake = [cg, sg];
        let n_flank = [-sa, -ca];
        let bs = [d_r[0] + d_f[0], d_r[1] + d_f[1]];
        let bl = sqrt(dot(bs, bs));
        let b = [bs[0] / bl, bs[1] / bl];
        let half = 0.5 * wedge;
        let to_centre = r / libm::sin(half);
        let tangent = r / libm::tan(half);
        // T chosen so that the lowest point c − (0, r) is the origin.
        let tip = [-to_centre * b[0], r - to_centre * b[1]];
        let centre = add_scaled(tip, to_centre, b);
        let t_r = add_scaled(tip, tangent, d_r);
        let t_f = add_scaled(tip, tangent, d_f);
        let s_rake = (s.height - tip[1]) / cg;
        let s_flank = (s.length + tip[0]) / ca;
        // Snapped to the exact top and back so that those faces are exactly horizontal and vertical.
        let top = [tip[0] + s_rake * d_r[0], s.height];
        let back = [-s.length, tip[1] + s_flank * d_f[1]];
        if s_rake <= tangent || s_flank <= tangent || back[1] >= s.height || top[0] <= -s.length {
            return Err(ShapeError::TooSmall);
        }
        let corner = [-s.length, s.height];
        let seg = |p: [f64; 2], q: [f64; 2], n: [f64; 2]| [p[0], p[1], q[0], q[1], n[0], n[1]];
        let nc = [n_flank[0] + n_rake[0], n_flank[1] + n_rake[1]];
        let ncl = sqrt(dot(nc, nc));
        Ok(Tool2d {
            seg: [
                seg(t_r, top, n_rake),
                seg(top, corner, [0.0, 1.0]),
                seg(corner, back, [-1.0, 0.0]),
                seg(back, t_f, n_flank),
            ],
            centre,
            radius: r,
            n_flank,
            n_rake,
            n_chord: [nc[0] / ncl, nc[1] / ncl],
            rake_angle: g,
            clearance_angle: a,
        })
    }

    /// Where the edge arc meets the rake face (a point of the rake line).
    #[inline(always)]
    pub fn rake_tangent(&self) -> [f64; 2] {
        [self.seg[RAKE][0], self.seg[RAKE][1]]
    }

    /// Whether `p` (tool frame) lies inside the tool or on its outline: inside the four half-planes and, in the
    /// corner region beyond the chord T_f–T_r, inside the arc's circle.
    #[inline(always)]
    pub fn contains(&self, p: [f64; 2]) -> bool {
        let mut k = 0;
        while k < 4 {
            let s = &self.seg[k];
            if dot(sub(p, [s[0], s[1]]), [s[4], s[5]]) > 0.0 {
                return false;
            }
            k += 1;
        }
        let t_r = self.rake_tangent();
        if dot(sub(p, t_r), self.n_chord) <= 0.0 {
            return true;
        }
        let v = sub(p, self.centre);
        dot(v, v) <= self.radius * self.radius
    }

    /// The exact signed distance, closest point and outward normal of `p` (tool frame): the nearest of the four
    /// segments and the arc, signed by [`Tool2d::contains`].
    #[inline(always)]
    pub fn closest(&self, p: [f64; 2]) -> Closest {
        let mut best = Closest { distance: f64::INFINITY, ..Default::default() };
        let mut best2 = f64::INFINITY;
        let mut k = 0;
        while k < 4 {
            let s = &self.seg[k];
            let a = [s[0], s[1]];
            let ab = sub([s[2], s[3]], a);
            let t = dot(sub(p, a), ab) / dot(ab, ab);
            // Not f64::clamp: its NaN assertion would pull float formatting into the PTX.
            #[allow(clippy::manual_clamp)]
            let t = if t < 0.0 {
                0.0
            } else if t > 1.0 {
                1.0
            } else {
                t
            };
            let q = add_scaled(a, t, ab);
            let pq = sub(p, q);
            let d2 = dot(pq, pq);
            if d2 < best2 {
                best2 = d2;
                best = Closest { distance: 0.0, point: q, normal: [s[4], s[5]], primitive: k as u32 };
            }
            k += 1;
        }
        // The arc: only within its angular range (its end points are the segments' ends, covered above).
        let v = sub(p, self.centre);
        let vl = sqrt(dot(v, v));
        if self.radius > 0.0 && vl > 0.0 && cross(self.n_flank, v) >= 0.0 && cross(v, self.n_rake) >= 0.0 {
            let d = vl - self.radius;
            if d * d < best2 {
                best2 = d * d;
                let u = [v[0] / vl, v[1] / vl];
                best = Closest {
                    distance: 0.0,
                    point: add_scaled(self.centre, self.radius, u),
                    normal: u,
                    primitive: ARC,
                };
            }
        }
        let d = sqrt(best2);
        if self.contains(p) {
            best.distance = -d;
        } else {
            best.distance = d;
            // On the arc the normal is already (p − c)/|p − c|; recomputing it from the rounded closest point
            // would lose its length when d is a few ulp (tests/contact.rs).
            if d > 0.0 && best.primitive != ARC {
                let pq = sub(p, best.point);
                best.normal = [pq[0] / d, pq[1] / d];
            }
        }
        best
    }
}
