//! The chip's curl radius r_chip (klippel-constitutive.md §5.4: "curl radius r_chip", tabulated in mm): the radius
//! of the circle fitted to the centreline of the part of the chip that has left the rake face.
//!
//! Method (docs/validation.md, "Chip analysis of a frame"): the centres of the cross-sections of
//! [`super::chip_profile`] whose rake-side edge lies more than 2 Δx off the rake-face line (the chip has left the
//! tool there) are fitted by the algebraic least-squares circle of Kåsa (1976): minimise
//! Σ (x² + y² + D x + E y + F)², linear in (D, E, F); centre (−D/2, −E/2), r = √(D²/4 + E²/4 − F). The points are
//! centred and scaled first (positions of 1e-4 m squared would lose digits). Exact for points on a circle; on an
//! arc of a few tens of degrees or more its bias is small against the wobble of a segmented chip's centreline.
//! No radius where fewer than 5 sections have left the face or their axis turns by less than [`MIN_TURN`] (a
//! straight chip).

use super::chip_profile::{FrameSetup, Section};

/// Least turn of the chip's axis over the fitted part for a curl radius to be reported [rad] (about 11°).
pub const MIN_TURN: f64 = 0.2;

/// r_chip [m] (module doc).
pub fn curl_radius(setup: &FrameSetup, sections: &[Section]) -> Option<f64> {
    let (sin, cos) = setup.rake_angle.sin_cos();
    let n = [cos, sin];
    let off = |s: &Section| {
        let m = s.normal();
        let h = 0.5 * (s.thickness - setup.spacing);
        let edge = [s.centre[0] - h * m[0], s.centre[1] - h * m[1]];
        (edge[0] - setup.rake_point[0]) * n[0] + (edge[1] - setup.rake_point[1]) * n[1] > 2.0 * setup.spacing
    };
    let free: Vec<&Section> = sections.iter().skip_while(|s| !off(s)).collect();
    if free.len() < 5 || turn(&free).abs() < MIN_TURN {
        return None;
    }
    let pts: Vec<[f64; 2]> = free.iter().map(|s| s.centre).collect();
    fit_circle(&pts).map(|(_, r)| r)
}

/// The signed angle the axis turns through from the first section to the last [rad].
fn turn(secs: &[&Section]) -> f64 {
    secs.windows(2)
        .map(|w| {
            let (a, b) = (w[0].axis, w[1].axis);
            (a[0] * b[1] - a[1] * b[0]).atan2(a[0] * b[0] + a[1] * b[1])
        })
        .sum()
}

/// Kåsa's circle through `pts` (≥ 3, not collinear): (centre, radius); None where the fit is singular.
pub fn fit_circle(pts: &[[f64; 2]]) -> Option<([f64; 2], f64)> {
    if pts.len() < 3 {
        return None;
    }
    let n = pts.len() as f64;
    let g = [pts.iter().map(|p| p[0]).sum::<f64>() / n, pts.iter().map(|p| p[1]).sum::<f64>() / n];
    let scale = (pts.iter().map(|p| (p[0] - g[0]).powi(2) + (p[1] - g[1]).powi(2)).sum::<f64>() / n).sqrt();
    if !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    // Normal equations of Σ (D x + E y + F + x² + y²)² in the scaled coordinates.
    let (mut a, mut b) = ([[0.0; 3]; 3], [0.0; 3]);
    for p in pts {
        let (x, y) = ((p[0] - g[0]) / scale, (p[1] - g[1]) / scale);
        let (row, z) = ([x, y, 1.0], -(x * x + y * y));
        for i in 0..3 {
            for j in 0..3 {
                a[i][j] += row[i] * row[j];
            }
            b[i] += row[i] * z;
        }
    }
    let [d, e, f] = solve3(a, b)?;
    let r2 = 0.25 * (d * d + e * e) - f;
    (r2 > 0.0).then(|| ([g[0] - 0.5 * d * scale, g[1] - 0.5 * e * scale], r2.sqrt() * scale))
}

/// The solution of a x = b (Cramer's rule); None where a is singular.
fn solve3(a: [[f64; 3]; 3], b: [f64; 3]) -> Option<[f64; 3]> {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(a);
    if d.abs() < 1e-12 * a[0][0].abs().max(1.0).powi(3) {
        return None;
    }
    Some(std::array::from_fn(|k| {
        let mut m = a;
        (0..3).for_each(|i| m[i][k] = b[i]);
        det(m) / d
    }))
}
