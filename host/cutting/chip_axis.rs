//! Chip thickness measured normal to the chip's own local axis, so that a chip that has curled away from the rake
//! face (or runs tilted to it) is cut square rather than obliquely.
//!
//! Method (docs/validation.md, "Chip thickness"):
//! 1. The face-normal slice of [`super::chip`] at the station gives a first cross-section: its centre c and its
//!    thickness h₀ (which overestimates the true h by 1/cos θ where the chip runs at θ to the face).
//! 2. The chip particles within [`AXIS_WINDOW`]·h₀ of c that are connected to the particle nearest c through
//!    neighbours at most 2 spacings apart (the slice's own gap rule) form the local piece of the chip; a curled
//!    chip crossing the window again further out, or loose particles, are not connected within it.
//! 3. The local axis a is the principal axis of that piece: the eigenvector of the larger eigenvalue of its
//!    position covariance C, at the angle ½ atan2(2 C_xy, C_xx − C_yy) (a strip is longer along its axis than
//!    across it within a window wider than it is thick); m ⟂ a is the local normal.
//! 4. A slice through the piece's centroid g along m (half width as the face-normal slice) holds the chip
//!    particles with |(p − g)·a| ≤ half_width; from the one nearest g the walk goes both ways while consecutive
//!    gaps in (p − g)·m are ≤ 2 spacings; the thickness is the walk's extent plus one spacing.
//!
//! Where the piece has fewer than 3 particles or no distinct principal axis (C ∝ identity), the face-normal value
//! h₀ is returned. For a straight strip along the face the two methods agree exactly (tests/cutting_analysis.rs);
//! for a strip tilted by θ the face-normal slice gives h/cos θ and this one h (tests/steady_state.rs).

use super::chip::{Station, rake_slice};
use std::collections::HashMap;

/// Radius of the window of step 2, in units of h₀: wide enough that the piece is clearly longer than thick
/// (a strip of thickness h in a disc of radius 1.5 h: axial variance ≈ 6× the normal one).
pub const AXIS_WINDOW: f64 = 1.5;

/// Chip thickness [m] normal to the chip's local axis (module doc). None as for [`super::chip::chip_thickness`].
pub fn chip_thickness_normal(s: &Station, pos: impl IntoIterator<Item = [f64; 2]>) -> Option<f64> {
    let chip: Vec<[f64; 2]> =
        pos.into_iter().filter(|p| p[0].is_finite() && p[1].is_finite() && p[1] > s.surface_y).collect();
    let (first, last) = rake_slice(s, chip.iter().copied())?;
    let h0 = last - first + s.spacing;
    let (sin, cos) = s.rake_angle.sin_cos();
    let w_mid = 0.5 * (first + last);
    let c = [s.rake_point[0] - s.station * sin + w_mid * cos, s.rake_point[1] + s.station * cos + w_mid * sin];
    let radius = AXIS_WINDOW * h0;
    let local: Vec<[f64; 2]> = chip.iter().copied().filter(|p| dist2(*p, c) <= radius * radius).collect();
    let piece = connected_piece(&local, c, 2.0 * s.spacing);
    let Some((g, a)) = principal_axis(&piece) else { return Some(h0) };
    let m = [-a[1], a[0]];
    let mut w: Vec<f64> = chip
        .iter()
        .filter(|p| ((p[0] - g[0]) * a[0] + (p[1] - g[1]) * a[1]).abs() <= s.half_width)
        .map(|p| (p[0] - g[0]) * m[0] + (p[1] - g[1]) * m[1])
        .collect();
    if w.len() < 2 {
        return Some(h0);
    }
    w.sort_by(f64::total_cmp);
    Some(extent_around_zero(&w, 2.0 * s.spacing) + s.spacing)
}

fn dist2(p: [f64; 2], q: [f64; 2]) -> f64 {
    (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)
}

/// The particles of `pts` connected to the one nearest `c` through links no longer than `link` (a flood fill over
/// a grid of cells `link` wide).
fn connected_piece(pts: &[[f64; 2]], c: [f64; 2], link: f64) -> Vec<[f64; 2]> {
    let Some(seed) = (0..pts.len()).min_by(|&i, &j| dist2(pts[i], c).total_cmp(&dist2(pts[j], c))) else {
        return Vec::new();
    };
    let cell = |p: [f64; 2]| ((p[0] / link).floor() as i64, (p[1] / link).floor() as i64);
    let mut grid: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    for (i, p) in pts.iter().enumerate() {
        grid.entry(cell(*p)).or_default().push(i);
    }
    let mut seen = vec![false; pts.len()];
    let (mut stack, mut out) = (vec![seed], Vec::new());
    seen[seed] = true;
    while let Some(i) = stack.pop() {
        out.push(pts[i]);
        let (cx, cy) = cell(pts[i]);
        for (dx, dy) in (-1..=1).flat_map(|a| (-1..=1).map(move |b| (a, b))) {
            for &j in grid.get(&(cx + dx, cy + dy)).map_or(&[][..], |v| v.as_slice()) {
                if !seen[j] && dist2(pts[i], pts[j]) <= link * link {
                    seen[j] = true;
                    stack.push(j);
                }
            }
        }
    }
    out
}

/// Centroid g and covariance (C_xx, C_yy, C_xy) of `pts` (sums over the points divided by their count); None for
/// fewer than 3 points.
pub(crate) fn covariance(pts: &[[f64; 2]]) -> Option<([f64; 2], [f64; 3])> {
    if pts.len() < 3 {
        return None;
    }
    let n = pts.len() as f64;
    let g = [pts.iter().map(|p| p[0]).sum::<f64>() / n, pts.iter().map(|p| p[1]).sum::<f64>() / n];
    let (mut cxx, mut cyy, mut cxy) = (0.0, 0.0, 0.0);
    for p in pts {
        let (x, y) = (p[0] - g[0], p[1] - g[1]);
        cxx += x * x;
        cyy += y * y;
        cxy += x * y;
    }
    Some((g, [cxx / n, cyy / n, cxy / n]))
}

/// Centroid and unit principal axis (larger eigenvalue of the covariance) of `pts`; None for fewer than 3 points
/// or an isotropic covariance.
pub(crate) fn principal_axis(pts: &[[f64; 2]]) -> Option<([f64; 2], [f64; 2])> {
    let (g, [cxx, cyy, cxy]) = covariance(pts)?;
    // Isotropic: no axis (the eigenvalue gap √((C_xx − C_yy)² + 4C_xy²) vanishes against the trace).
    if (cxx - cyy).hypot(2.0 * cxy) <= 1e-9 * (cxx + cyy) {
        return None;
    }
    let angle = 0.5 * (2.0 * cxy).atan2(cxx - cyy);
    Some((g, [angle.cos(), angle.sin()]))
}

/// Extent of the run through the value nearest 0 of ascending `w` whose consecutive gaps are ≤ `max_gap`.
fn extent_around_zero(w: &[f64], max_gap: f64) -> f64 {
    let i0 = (0..w.len()).min_by(|&i, &j| w[i].abs().total_cmp(&w[j].abs())).unwrap_or(0);
    let mut lo = i0;
    while lo > 0 && w[lo] - w[lo - 1] <= max_gap {
        lo -= 1;
    }
    let mut hi = i0;
    while hi + 1 < w.len() && w[hi + 1] - w[hi] <= max_gap {
        hi += 1;
    }
    w[hi] - w[lo]
}
