//! The chip of one frame, followed from its root at the rake face to its free end: a chain of cross-sections normal
//! to the chip's local axis, each with its thickness and its particles. The saw-tooth of a segmented chip is the
//! thickness' rise and fall along the chain (klippel-constitutive.md §5.4: h_min, h_max, l_seg are read off the
//! chip's profile; [`super::chip_frame`] does the reading).
//!
//! Set-up and conventions as in [`super::chip`]: 2D, the tool cuts in +x, its rake face rises from `rake_point` at
//! the rake angle γ; d = (−sin γ, cos γ) runs up the face, n = (cos γ, sin γ) out of the face into the chip; the
//! chip is the workpiece above the uncut surface y = `surface_y`.
//!
//! Method (docs/validation.md, "Chip analysis of a frame"):
//! 1. **Root.** The face-normal slice of [`super::chip`] at u₀ = u_s + t1/2 up the face, u_s where the rake line
//!    crosses the uncut surface (half an uncut thickness above it, clear of the workpiece's surface), gives the
//!    first centre c₀; the first axis is d.
//! 2. **Cross-section** at a probe point p with axis a and normal m = (a_y, −a_x) (m = n for a = d: from the rake
//!    side to the free side): the chip particles with |(x − p)·a| ≤ Δx/2 (the sections, Δx apart, tile the chip), their w = (x − p)·m sorted; from the one
//!    nearest p (within 2 Δx, else the chip has ended) the walk goes both ways while consecutive gaps are ≤ 2 Δx.
//!    The thickness is h = w_last − w_first + Δx (each particle stands for a strip Δx wide); the section's centre is
//!    p + m (w_first + w_last)/2; each member's depth from the rake side is w − w_first.
//! 3. **March.** The next probe is c_k + Δx a_k; its axis a_{k+1} is the principal axis of the chip particles
//!    within 1.5 h_k of it that are connected to the one nearest it (links ≤ 2 Δx), as in [`super::chip_axis`],
//!    signed along a_k (re-estimated every h/(4 Δx) sections; the axis turns slowly). The distance along the chip is s_k = k Δx (the march advances Δx along the axis).
//! 4. **End.** The march stops where a probe finds no chip, or the thickness jumps above 2.5× the median of the
//!    last 20 sections (a curled chip touching its own earlier turn); the sections within one median thickness
//!    of the free end are dropped (the end cap thins to nothing).

use super::cells::{Cells, dist2};
use super::chip::{Station, rake_slice};
use super::chip_axis::{AXIS_WINDOW, principal_axis};

/// A thickness above this multiple of the median of the last [`JUMP_WINDOW`] sections ends the march.
pub const JUMP: f64 = 2.5;
/// Sections the jump test looks back over.
pub const JUMP_WINDOW: usize = 20;

/// A frame's tool and workpiece, as the chip analysis needs them (SI units, the tool where it is at the frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameSetup {
    /// Where the edge arc meets the rake face, in the world at the frame's time [m].
    pub rake_point: [f64; 2],
    /// Rake angle γ [rad].
    pub rake_angle: f64,
    /// Height of the uncut top surface [m].
    pub surface_y: f64,
    /// Particle spacing Δx [m].
    pub spacing: f64,
    /// Uncut chip thickness t1 [m].
    pub uncut: f64,
    /// Cutting speed v_c [m/s].
    pub speed: f64,
}

/// One cross-section of the chip (step 2 of the module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct Section {
    /// Distance along the chip from the first section [m].
    pub s: f64,
    /// Mid-point of the cross-section [m].
    pub centre: [f64; 2],
    /// Unit chip axis, towards the free end.
    pub axis: [f64; 2],
    /// Thickness h [m].
    pub thickness: f64,
    /// The cross-section's particles (indices into the chip's points) and their depth from the rake side [m].
    pub members: Vec<(usize, f64)>,
}

impl Section {
    /// The unit normal m from the rake side to the free side.
    pub fn normal(&self) -> [f64; 2] {
        [self.axis[1], -self.axis[0]]
    }
}

/// The chip's cross-sections from root to free end (module doc); empty where the root slice finds no chip.
/// `pts` are the chip's particles (the workpiece above the uncut surface).
pub fn sections(setup: &FrameSetup, pts: &[[f64; 2]]) -> Vec<Section> {
    let dx = setup.spacing;
    if !(dx > 0.0 && dx.is_finite()) {
        return Vec::new();
    }
    let cells = Cells::new(pts, 2.0 * dx);
    let Some(mut sec) = root_section(setup, pts, &cells) else { return Vec::new() };
    // The axis turns slowly along the chip: refreshing it every quarter thickness costs ~30 cell visits per chip
    // particle in all, every step would cost h/Δx times more.
    let every = ((0.25 * sec.thickness / dx).round() as usize).max(1);
    let mut out: Vec<Section> = Vec::new();
    while out.len() <= pts.len() {
        let next = next_section(pts, &cells, &sec, out.len().is_multiple_of(every), dx);
        out.push(sec);
        match next {
            Some(n) if !jumped(&out, n.thickness) => sec = n,
            _ => break,
        }
    }
    trim_end(out)
}

/// Step 1: the first section, at u₀ up the rake face, with the face's direction as its axis.
fn root_section(setup: &FrameSetup, pts: &[[f64; 2]], cells: &Cells) -> Option<Section> {
    let (sin, cos) = setup.rake_angle.sin_cos();
    let (d, n) = ([-sin, cos], [cos, sin]);
    let u_surface = if cos > 0.0 { (setup.surface_y - setup.rake_point[1]) / cos } else { 0.0 };
    let u0 = (u_surface + 0.5 * setup.uncut).max(0.0);
    let dx = setup.spacing;
    let station = Station {
        rake_point: setup.rake_point,
        rake_angle: setup.rake_angle,
        surface_y: setup.surface_y,
        station: u0,
        half_width: dx,
        spacing: dx,
    };
    let (first, last) = rake_slice(&station, pts.iter().copied())?;
    let w = 0.5 * (first + last);
    let p = [setup.rake_point[0] + u0 * d[0] + w * n[0], setup.rake_point[1] + u0 * d[1] + w * n[1]];
    cross_section(pts, cells, p, d, 3.0 * (last - first + dx), dx).map(|mut s| {
        s.s = 0.0;
        s
    })
}

/// Step 3: the section one spacing further along the chip (its axis re-estimated where `refresh`, else the
/// previous one); None where the chip has ended.
fn next_section(pts: &[[f64; 2]], cells: &Cells, prev: &Section, refresh: bool, dx: f64) -> Option<Section> {
    let p = [prev.centre[0] + dx * prev.axis[0], prev.centre[1] + dx * prev.axis[1]];
    let a = refresh
        .then(|| local_axis(pts, cells, p, AXIS_WINDOW * prev.thickness, dx))
        .flatten()
        .map(|a| if a[0] * prev.axis[0] + a[1] * prev.axis[1] < 0.0 { [-a[0], -a[1]] } else { a })
        .unwrap_or(prev.axis);
    let mut s = cross_section(pts, cells, p, a, 3.0 * prev.thickness, dx)?;
    s.s = prev.s + dx;
    Some(s)
}

/// The principal axis of the chip particles within `radius` of `p` connected to the one nearest it.
fn local_axis(pts: &[[f64; 2]], cells: &Cells, p: [f64; 2], radius: f64, dx: f64) -> Option<[f64; 2]> {
    let near = cells.within(pts, p, radius);
    let seed = near.iter().copied().min_by(|&i, &j| dist2(pts[i], p).total_cmp(&dist2(pts[j], p)))?;
    let piece: Vec<[f64; 2]> = cells.connected(pts, &near, seed, 2.0 * dx).into_iter().map(|i| pts[i]).collect();
    principal_axis(&piece).map(|(_, a)| a)
}

/// Step 2: the connected cross-section through `p` normal to the unit axis `a`, looking no further than `reach`
/// from `p`; `s` is left 0.
fn cross_section(pts: &[[f64; 2]], cells: &Cells, p: [f64; 2], a: [f64; 2], reach: f64, dx: f64) -> Option<Section> {
    let m = [a[1], -a[0]];
    let along = |x: [f64; 2], e: [f64; 2]| (x[0] - p[0]) * e[0] + (x[1] - p[1]) * e[1];
    let mut w: Vec<(f64, usize)> =
        cells.slab(pts, p, m, reach, 0.6 * dx).into_iter().map(|i| (along(pts[i], m), i)).collect();
    w.sort_by(|x, y| x.0.total_cmp(&y.0));
    let i0 = (0..w.len()).min_by(|&i, &j| w[i].0.abs().total_cmp(&w[j].0.abs()))?;
    if w[i0].0.abs() > 2.0 * dx {
        return None;
    }
    let (mut lo, mut hi) = (i0, i0);
    while lo > 0 && w[lo].0 - w[lo - 1].0 <= 2.0 * dx {
        lo -= 1;
    }
    while hi + 1 < w.len() && w[hi + 1].0 - w[hi].0 <= 2.0 * dx {
        hi += 1;
    }
    let (w_lo, w_hi) = (w[lo].0, w[hi].0);
    let mid = 0.5 * (w_lo + w_hi);
    Some(Section {
        s: 0.0,
        centre: [p[0] + mid * m[0], p[1] + mid * m[1]],
        axis: a,
        thickness: w_hi - w_lo + dx,
        members: w[lo..=hi].iter().map(|&(wi, i)| (i, wi - w_lo)).collect(),
    })
}

/// Median of `v` (non-empty, finite); NaN when empty.
pub fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let k = v.len() / 2;
    if v.len() % 2 == 1 { v[k] } else { 0.5 * (v[k - 1] + v[k]) }
}

/// Step 4's jump test: `h` above [`JUMP`] × the median thickness of the last [`JUMP_WINDOW`] sections.
fn jumped(done: &[Section], h: f64) -> bool {
    let mut last: Vec<f64> = done.iter().rev().take(JUMP_WINDOW).map(|s| s.thickness).collect();
    h > JUMP * median(&mut last)
}

/// Step 4's end: drops the sections within one median thickness of the last one.
fn trim_end(mut secs: Vec<Section>) -> Vec<Section> {
    let mut h: Vec<f64> = secs.iter().map(|s| s.thickness).collect();
    let cut = secs.last().map_or(0.0, |s| s.s) - median(&mut h);
    secs.retain(|s| s.s <= cut);
    secs
}
