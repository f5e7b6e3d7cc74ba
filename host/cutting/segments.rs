//! Chip segmentation from the crests and valleys of the chip-thickness signal at the chip station, and the segment
//! pitch l_seg.
//!
//! Method (docs/validation.md, "Segmentation"). A saw-tooth chip passing the station makes its thickness rise to a
//! crest (a segment) and fall to a valley (the shear band between two segments) once per segment. Extrema are
//! found with hysteresis (the peak-detection rule of Billauer's `peakdet`): a crest is the largest value since the
//! last valley, confirmed once the signal has fallen more than `prominence` below it, and a valley likewise the
//! smallest value since the last crest, confirmed once the signal has risen more than `prominence` above it. A
//! prominence of a few spacings keeps the thickness' own quantisation (it moves in steps of one particle spacing)
//! from counting as segments. Then
//!
//! - h_crest, h_valley: the means of the crest and valley values;
//! - degree = (h_crest − h_valley)/h_crest, the segmentation degree of klippel-constitutive.md §4.9 [NOTE] with the
//!   measured crests and valleys in place of the 90th/10th percentiles of [`super::chip::chip_geometry`] (the
//!   percentile indicator, kept as `segmentation` for continuity, equals it for a clean saw-tooth whose crests and
//!   valleys fill the top and bottom 10 % of the samples, and reads noise as segmentation where there are no
//!   crests);
//! - period T = (t_last crest − t_first crest)/(crests − 1), the time between segments passing the station;
//! - pitch l_seg = v_chip T with v_chip = v_c t1/h_avg (the chip carries the uncut layer's material: plane-strain
//!   mass conservation, klippel-constitutive.md §4.9 [NOTE], "segment frequency ≈ v_chip/l_seg").

/// Crests and valleys of one thickness signal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segments {
    pub crests: usize,
    pub valleys: usize,
    /// Mean crest and valley values [the signal's unit].
    pub h_crest: f64,
    pub h_valley: f64,
    /// (h_crest − h_valley)/h_crest.
    pub degree: f64,
    /// Mean time between consecutive crests [s]; NaN with fewer than 2 crests.
    pub period: f64,
}

impl Segments {
    /// The pitch l_seg = v_c t1/h_avg × T [m] for cutting speed `v_c` [m/s], uncut thickness `t1` and mean chip
    /// thickness `h_avg` (same unit); NaN where T is.
    pub fn pitch(&self, v_c: f64, t1: f64, h_avg: f64) -> f64 {
        v_c * t1 / h_avg * self.period
    }
}

/// Crests and valleys of `h` sampled at times `t` (equal lengths, finite) with hysteresis `prominence` > 0. None
/// when the input is invalid or no crest and valley were both found.
pub fn crests_valleys(t: &[f64], h: &[f64], prominence: f64) -> Option<Segments> {
    let valid = t.len() == h.len() && prominence > 0.0 && t.iter().chain(h).all(|v| v.is_finite());
    if !valid || h.is_empty() {
        return None;
    }
    let (crests, valleys) = extrema(h, prominence);
    if crests.is_empty() || valleys.is_empty() {
        return None;
    }
    let mean = |idx: &[usize]| idx.iter().map(|&i| h[i]).sum::<f64>() / idx.len() as f64;
    let (h_crest, h_valley) = (mean(&crests), mean(&valleys));
    let period = match (crests.first(), crests.last()) {
        (Some(&a), Some(&b)) if crests.len() >= 2 => (t[b] - t[a]) / (crests.len() - 1) as f64,
        _ => f64::NAN,
    };
    Some(Segments {
        crests: crests.len(),
        valleys: valleys.len(),
        h_crest,
        h_valley,
        degree: (h_crest - h_valley) / h_crest,
        period,
    })
}

/// The indices of the crests and of the valleys of `h` (finite) found with hysteresis `prominence` (the module
/// doc's rule, in the order they occur; the first of equal extreme values counts).
pub fn extrema(h: &[f64], prominence: f64) -> (Vec<usize>, Vec<usize>) {
    let (mut crests, mut valleys) = (Vec::new(), Vec::new());
    if h.is_empty() {
        return (crests, valleys);
    }
    let (mut hi, mut lo) = (0, 0);
    let mut seeking_crest = true;
    for (i, &x) in h.iter().enumerate() {
        if x > h[hi] {
            hi = i;
        }
        if x < h[lo] {
            lo = i;
        }
        if seeking_crest && x < h[hi] - prominence {
            crests.push(hi);
            (lo, seeking_crest) = (i, false);
        } else if !seeking_crest && x > h[lo] + prominence {
            valleys.push(lo);
            (hi, seeking_crest) = (i, true);
        }
    }
    (crests, valleys)
}
