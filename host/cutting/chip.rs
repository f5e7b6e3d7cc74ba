//! Chip thickness from particle positions, and the chip geometry (mean, crest, valley, segmentation) over a run.
//!
//! Set-up (2D plane strain, SI units): the tool moves in +x; its rake face is a straight line facing +x that rises
//! from the cutting edge up and back, at the rake angle γ from the vertical. Along the face the unit direction up
//! the face is d = (−sin γ, cos γ), and the unit normal out of the tool into the chip is n = (cos γ, sin γ). The
//! uncut top surface of the workpiece is the line y = `surface_y`; the chip flows up the rake face above it.
//!
//! Method (the reference for docs/validation.md). The thickness at one instant is measured on a slice across the
//! chip, normal to the rake face, at the distance `station` up the face from a point `rake_point` on it:
//!
//! 1. every particle p gets face coordinates u = (p − rake_point)·d (along the face) and
//!    w = (p − rake_point)·n (out of the face);
//! 2. the slice holds the particles with |u − station| ≤ half_width, w ≥ −spacing (a particle may sit slightly
//!    inside the tool, by the contact's penetration) and p.y > surface_y (material above the uncut surface, i.e.
//!    chip, not workpiece);
//! 3. their w are sorted, and from the smallest one the walk goes outwards while consecutive gaps are ≤ 2·spacing:
//!    this keeps the connected cross-section lying on the rake face and drops a curled chip that crosses the slice
//!    again further out, or loose particles;
//! 4. the thickness is (w_last − w_first) + spacing, since each particle stands for a strip one spacing wide.
//!
//! Fewer than 2 particles in the slice give no value. The slice is normal to the face, so it cuts the chip square
//! only while the chip runs along the face; where the chip has curled away from the face by an angle θ at the
//! station, the slice crosses it obliquely and the value overestimates the thickness by the factor 1/cos θ.
//!
//! Over the steady part of a run the thickness samples give the chip geometry: h_avg is their mean, h_max and h_min
//! the 90th and 10th percentiles (robust against single-particle noise; the experiments' h_max/h_min are the
//! crest and valley of the saw-tooth chip, klippel-constitutive.md §5.4), and the segmentation degree is
//! (h_max − h_min)/h_max (klippel-constitutive.md §4.9 [NOTE], H9).

use super::steady::quantile_sorted;

/// Fewest thickness samples `chip_geometry` accepts.
const MIN_SAMPLES: usize = 5;

/// Where the chip is measured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Station {
    /// A point on the rake-face line (e.g. where the edge arc meets the rake face) [m].
    pub rake_point: [f64; 2],
    /// Rake angle γ [rad] from the vertical; positive leans the face back, away from the chip.
    pub rake_angle: f64,
    /// Height of the uncut top surface [m].
    pub surface_y: f64,
    /// Distance up the rake face from `rake_point` to the slice [m].
    pub station: f64,
    /// Half width of the slice along the face [m].
    pub half_width: f64,
    /// Particle spacing Δx [m].
    pub spacing: f64,
}

/// Chip thickness [m] at one instant from the particle positions (see the module doc). Positions are (x, y).
/// None when fewer than 2 particles lie in the slice, or the station has a non-finite field, a spacing ≤ 0 or a
/// negative half width. Particles with non-finite positions fall outside the slice.
pub fn chip_thickness(s: &Station, pos: impl IntoIterator<Item = [f64; 2]>) -> Option<f64> {
    rake_slice(s, pos).map(|(first, last)| last - first + s.spacing)
}

/// Steps 1–3 of the module doc: the face-normal coordinates w of the first and the last particle centre of the
/// connected cross-section in the slice (the thickness is their difference plus one spacing). None as for
/// [`chip_thickness`].
pub(crate) fn rake_slice(s: &Station, pos: impl IntoIterator<Item = [f64; 2]>) -> Option<(f64, f64)> {
    let fields = [s.rake_point[0], s.rake_point[1], s.rake_angle, s.surface_y, s.station, s.half_width, s.spacing];
    if !fields.iter().all(|v| v.is_finite()) || s.spacing <= 0.0 || s.half_width < 0.0 {
        return None;
    }
    let (sin, cos) = s.rake_angle.sin_cos();
    let (d, n) = ([-sin, cos], [cos, sin]);
    let mut w: Vec<f64> = pos
        .into_iter()
        .filter(|p| p[1] > s.surface_y)
        .filter_map(|p| {
            let r = [p[0] - s.rake_point[0], p[1] - s.rake_point[1]];
            let (u, w) = (r[0] * d[0] + r[1] * d[1], r[0] * n[0] + r[1] * n[1]);
            // Written so that NaN coordinates fail both tests.
            ((u - s.station).abs() <= s.half_width && w >= -s.spacing).then_some(w)
        })
        .collect();
    if w.len() < 2 {
        return None;
    }
    w.sort_by(f64::total_cmp);
    Some((w[0], connected_end(&w, 2.0 * s.spacing)))
}

/// The last value of the run starting at `w[0]` whose consecutive gaps are ≤ `max_gap` (`w` ascending, non-empty).
fn connected_end(w: &[f64], max_gap: f64) -> f64 {
    let mut last = w[0];
    for &v in &w[1..] {
        if v - last > max_gap {
            break;
        }
        last = v;
    }
    last
}

/// Chip geometry over the steady part of a run: from the thickness samples h (None samples skipped):
/// h_avg = mean, h_max = 90th and h_min = 10th percentile (robust against single-particle noise; the experiments'
/// h_max/h_min are the crest and valley of the saw-tooth, klippel-constitutive.md §5.4), segmentation
/// (h_max − h_min)/h_max (klippel-constitutive.md §4.9 [NOTE], H9). None when fewer than 5 samples remain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChipGeometry {
    /// Mean thickness [m].
    pub h_avg: f64,
    /// 10th percentile (valley of the saw-tooth) [m].
    pub h_min: f64,
    /// 90th percentile (crest of the saw-tooth) [m].
    pub h_max: f64,
    /// Segmentation degree (h_max − h_min)/h_max [–].
    pub segmentation: f64,
    /// Number of thickness samples used.
    pub samples: usize,
}

/// See [`ChipGeometry`]. Percentiles are numpy's default (linear interpolation between order statistics). None also
/// when a sample is not finite or h_max ≤ 0 (the segmentation would be undefined).
pub fn chip_geometry(h: &[Option<f64>]) -> Option<ChipGeometry> {
    let mut v: Vec<f64> = h.iter().flatten().copied().collect();
    if v.len() < MIN_SAMPLES || !v.iter().all(|x| x.is_finite()) {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let h_avg = v.iter().sum::<f64>() / v.len() as f64;
    let h_min = quantile_sorted(&v, 0.1)?;
    let h_max = quantile_sorted(&v, 0.9)?;
    if h_max <= 0.0 {
        return None;
    }
    Some(ChipGeometry { h_avg, h_min, h_max, segmentation: (h_max - h_min) / h_max, samples: v.len() })
}
