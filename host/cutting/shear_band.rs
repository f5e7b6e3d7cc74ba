//! The shear layers of a frame's chip, from the equivalent plastic strain ε_p of its particles: t_seg, the
//! thickness of the primary shear bands between segments, and t_sl, the thickness of the secondary shear layer along
//! the rake side (klippel-constitutive.md §5.4 "shear-layer thickness in the primary (t_seg) and secondary (t_sl)
//! zones"; Tab. 9.56 gives 4–6 and 3 µm measured on V0060's etched chips, 6–11 and 5–6 µm simulated).
//!
//! Both are full widths at half maximum above the chip's bulk, read on the cross-sections of
//! [`super::chip_profile`] (docs/validation.md, "Chip analysis of a frame"):
//!
//! - **Bulk** ε_b: the median ε_p over the sections' particles (bands and layer are a small part of the chip).
//! - **Secondary layer.** ε_L is the median over the sections of the mean ε_p of each section's rake-side row
//!   (depth < Δx). Without contrast (ε_L − ε_b ≤ ½ ε_b, or ε_L ≤ 0) there is no layer. Otherwise, with the half
//!   level θ = (ε_b + ε_L)/2, each section's layer reaches the depth of its first particle below θ (the particles
//!   above it, Δx apart from depth 0, span that depth); t_sl is the median over the sections.
//! - **Primary bands.** Between two consecutive crests of the thickness lies one valley and the band that made
//!   it: the particles of the sections from crest to crest, less those within 2 t_sl of the rake side (the
//!   secondary layer), hold its peak ε_pk. With contrast (ε_pk − ε_b > ½ ε_b, ε_pk > 0), the largest connected piece
//!   (links ≤ 2 Δx) of the particles at or above (ε_b + ε_pk)/2 is the band (a window may also hold the end of
//!   the neighbouring band). A band of width t and length L
//!   has position variances t²/12 across and L²/12 along it, so t = √(12 λ_min + Δx²) with λ_min the smaller
//!   eigenvalue of their position covariance (the Δx² restores the width of n rows Δx apart: (n² − 1)Δx²/12 is
//!   their variance); a piece not at least twice as long as wide is no band. t_seg is the median over the bands.

use super::cells::Cells;
use super::chip_axis::covariance;
use super::chip_profile::{Section, median};

/// Least relative excess of a layer or band over the bulk: (ε − ε_b) > MIN_CONTRAST · ε_b.
pub const MIN_CONTRAST: f64 = 0.5;

/// The bulk strain ε_b: the median ε_p over the sections' particles; None without one.
pub fn bulk_strain(sections: &[Section], eps: &[f64]) -> Option<f64> {
    let mut idx: Vec<usize> = sections.iter().flat_map(|s| s.members.iter().map(|m| m.0)).collect();
    idx.sort_unstable();
    idx.dedup();
    let mut v: Vec<f64> = idx.iter().map(|&i| eps[i]).filter(|e| e.is_finite()).collect();
    (!v.is_empty()).then(|| median(&mut v))
}

/// Whether `peak` stands out of the bulk `bulk` (module doc).
fn contrasts(peak: f64, bulk: f64) -> bool {
    peak > 0.0 && peak - bulk > MIN_CONTRAST * bulk.max(0.0)
}

/// t_sl [m], the secondary shear layer's thickness (module doc); None without a layer.
pub fn rake_layer(sections: &[Section], eps: &[f64], bulk: f64, dx: f64) -> Option<f64> {
    let mut rows: Vec<f64> = sections
        .iter()
        .filter_map(|s| {
            let row: Vec<f64> = s.members.iter().filter(|m| m.1 < dx).map(|m| eps[m.0]).collect();
            (!row.is_empty()).then(|| row.iter().sum::<f64>() / row.len() as f64)
        })
        .collect();
    let level = median(&mut rows);
    if !contrasts(level, bulk) {
        return None;
    }
    let half = 0.5 * (bulk + level);
    let mut depth: Vec<f64> = sections
        .iter()
        .map(|s| {
            s.members.iter().filter(|m| eps[m.0] < half || eps[m.0].is_nan()).map(|m| m.1).fold(s.thickness, f64::min)
        })
        .collect();
    Some(median(&mut depth))
}

/// The thicknesses [m] of the primary shear bands between the consecutive crests `crests` (indices into
/// `sections`), one per band found (module doc). `t_sl` is the secondary layer's thickness (None: no layer).
pub fn band_widths(
    sections: &[Section],
    crests: &[usize],
    pts: &[[f64; 2]],
    eps: &[f64],
    bulk: f64,
    t_sl: Option<f64>,
    dx: f64,
) -> Vec<f64> {
    let cells = Cells::new(pts, 2.0 * dx);
    let skip = 2.0 * t_sl.unwrap_or(0.0);
    crests
        .windows(2)
        .filter_map(|c| {
            let mut idx: Vec<usize> = sections[c[0]..=c[1]]
                .iter()
                .flat_map(|s| s.members.iter().filter(|m| m.1 >= skip).map(|m| m.0))
                .collect();
            idx.sort_unstable();
            idx.dedup();
            band_width(&cells, pts, eps, &idx, bulk, dx)
        })
        .collect()
}

/// One band's width from the particles `idx` around it (module doc); None without contrast or elongation.
fn band_width(cells: &Cells, pts: &[[f64; 2]], eps: &[f64], idx: &[usize], bulk: f64, dx: f64) -> Option<f64> {
    let peak = idx.iter().map(|&i| eps[i]).filter(|e| e.is_finite()).fold(f64::NEG_INFINITY, f64::max);
    if !contrasts(peak, bulk) {
        return None;
    }
    let half = 0.5 * (bulk + peak);
    let above: Vec<usize> = idx.iter().copied().filter(|&i| eps[i] >= half).collect();
    let piece = cells.components(pts, &above, 2.0 * dx).into_iter().next()?;
    let band: Vec<[f64; 2]> = piece.into_iter().map(|i| pts[i]).collect();
    let (_, [cxx, cyy, cxy]) = covariance(&band)?;
    let gap = (0.5 * (cxx - cyy)).hypot(cxy);
    let (lo, hi) = (0.5 * (cxx + cyy) - gap, 0.5 * (cxx + cyy) + gap);
    (hi >= 4.0 * lo.max(0.0)).then(|| (12.0 * lo.max(0.0) + dx * dx).sqrt())
}
