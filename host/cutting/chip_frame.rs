//! The chip geometry of one frame, from its particles along the whole chip: the quantities Klippel tabulates for
//! segmented chips (klippel-constitutive.md §5.4, Tab. 9.19 and, for V0060, Tab. 9.56: h_min, h_max, l_seg, t_seg,
//! t_sl, r_chip) and the segment frequency (§4.9 [NOTE]).
//!
//! Definitions (docs/validation.md, "Chip analysis of a frame"; the steps in [`super::chip_profile`],
//! [`super::shear_band`], [`super::curl`]):
//! - h(s): the thickness normal to the chip's axis at distance s along it, from the root to the chip's head (the
//!   part formed over the first 3 t1 of the tool's travel, the time series' minimum transient, is left out);
//!   h_avg its mean, h_10/h_90 its 10th/90th percentiles, segmentation (h_90 − h_10)/h_90 (the station's
//!   percentile indicator, [`super::chip::chip_geometry`], over space instead of time);
//! - crests and valleys of h(s), filtered by a running median over 5 sections, with a hysteresis of 2 Δx
//!   ([`super::segments::extrema`]): h_max and h_min are the means of the crest and valley thicknesses, the
//!   saw-tooth's tooth and root of Tab. 9.56 (each the unfiltered extreme within ±2 sections of where the filtered
//!   profile has it), the degree (h_max − h_min)/h_max (§4.9 [NOTE]), l_seg the mean distance along the chip
//!   between consecutive crests;
//! - the segment frequency f = v_chip/l_seg with v_chip = v_c t1/h_avg (plane-strain mass conservation, §4.9
//!   [NOTE]: ≈ 113–125 kHz measured on V0060);
//! - t_seg, t_sl: the primary band and secondary layer thicknesses ([`super::shear_band`]);
//! - r_chip: the curl radius of the centreline ([`super::curl`]).

use super::chip_profile::{FrameSetup, Section, median, sections};
use super::curl::curl_radius;
use super::segments::extrema;
use super::shear_band::{band_widths, bulk_strain, rake_layer};
use super::steady::quantile_sorted;
use super::window::MIN_TRANSIENT_UNCUT;

/// Hysteresis of the crest and valley detection along the chip, in particle spacings (as at the station:
/// [`super::record::SEGMENT_PROMINENCE_DX`]).
pub use super::record::SEGMENT_PROMINENCE_DX;

/// Half width of the running median h(s) is filtered with before its crests and valleys are sought, in sections
/// (5 sections, ±2 Δx): a lattice crossed obliquely by the section reads single sections one spacing thick or thin,
/// and a median removes such spikes while it keeps ramps and steps (the saw-tooth's flanks and notches).
pub const MEDIAN_HALF_WIDTH: usize = 2;

/// The segments of a frame's chip: crests and valleys of h(s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameSegments {
    pub crests: usize,
    pub valleys: usize,
    /// Mean valley and crest thickness [m].
    pub h_min: f64,
    pub h_max: f64,
    /// (h_max − h_min)/h_max.
    pub degree: f64,
    /// Mean distance between consecutive crests along the chip [m]; NaN with one crest.
    pub l_seg: f64,
    /// v_chip/l_seg [Hz]; NaN with one crest.
    pub frequency: f64,
}

/// The chip geometry of one frame (module doc); lengths in m.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameChip {
    /// Cross-sections analysed and the chip's length along its axis over them [m].
    pub sections: usize,
    pub length: f64,
    /// Chip particles in the sections.
    pub particles: usize,
    pub h_avg: f64,
    pub h_p10: f64,
    pub h_p90: f64,
    /// (h_90 − h_10)/h_90.
    pub segmentation: f64,
    /// v_c t1/h_avg [m/s].
    pub v_chip: f64,
    pub segments: Option<FrameSegments>,
    /// Median primary band thickness and the number of bands measured (0: none).
    pub t_seg: Option<f64>,
    pub bands: usize,
    pub t_sl: Option<f64>,
    pub r_chip: Option<f64>,
}

/// The chip of one frame: `pos` the workpiece particles (x, y), `eps` their equivalent plastic strain where the
/// frame has it (same length). None where no chip is found (fewer than 3 cross-sections; module doc of
/// [`super::chip_profile`]).
pub fn analyse(setup: &FrameSetup, pos: &[[f64; 2]], eps: Option<&[f64]>) -> Option<FrameChip> {
    let keep: Vec<usize> = (0..pos.len())
        .filter(|&i| pos[i][0].is_finite() && pos[i][1] > setup.surface_y && pos[i][1].is_finite())
        .collect();
    let pts: Vec<[f64; 2]> = keep.iter().map(|&i| pos[i]).collect();
    let secs = without_head(sections(setup, &pts), setup);
    if secs.len() < 3 {
        return None;
    }
    let mut chip = profile(setup, &secs)?;
    chip.particles = distinct_members(&secs);
    let h = running_median(&secs.iter().map(|s| s.thickness).collect::<Vec<_>>(), MEDIAN_HALF_WIDTH);
    let (crests, valleys) = extrema(&h, SEGMENT_PROMINENCE_DX * setup.spacing);
    chip.segments = segments(&secs, &crests, &valleys, chip.v_chip);
    chip.r_chip = curl_radius(setup, &secs);
    if let Some(e) = eps.filter(|e| e.len() == pos.len()) {
        let e: Vec<f64> = keep.iter().map(|&i| e[i]).collect();
        shear_layers(setup, &secs, &crests, &pts, &e, &mut chip);
    }
    Some(chip)
}

/// The sections less the chip's head: the chip the tool formed over its first [`MIN_TRANSIENT_UNCUT`] t1 of travel
/// (the minimum transient of the time series, [`super::window`]) is t1/h as long (plane-strain mass conservation),
/// so the sections within 3 t1²/h of the free end are dropped, h the median thickness.
fn without_head(mut secs: Vec<Section>, setup: &FrameSetup) -> Vec<Section> {
    let mut h: Vec<f64> = secs.iter().map(|s| s.thickness).collect();
    let head = MIN_TRANSIENT_UNCUT * setup.uncut * setup.uncut / median(&mut h);
    let end = secs.last().map_or(0.0, |s| s.s) - head;
    secs.retain(|s| s.s <= end);
    secs
}

/// h_avg, the percentiles, the segmentation and v_chip of the sections' thickness profile.
fn profile(setup: &FrameSetup, secs: &[Section]) -> Option<FrameChip> {
    let mut h: Vec<f64> = secs.iter().map(|s| s.thickness).collect();
    h.sort_by(f64::total_cmp);
    let h_avg = h.iter().sum::<f64>() / h.len() as f64;
    let (h_p10, h_p90) = (quantile_sorted(&h, 0.1)?, quantile_sorted(&h, 0.9)?);
    Some(FrameChip {
        sections: secs.len(),
        length: secs.last().map_or(0.0, |s| s.s),
        particles: 0,
        h_avg,
        h_p10,
        h_p90,
        segmentation: (h_p90 - h_p10) / h_p90,
        v_chip: setup.speed * setup.uncut / h_avg,
        segments: None,
        t_seg: None,
        bands: 0,
        t_sl: None,
        r_chip: None,
    })
}

fn distinct_members(secs: &[Section]) -> usize {
    let mut idx: Vec<usize> = secs.iter().flat_map(|s| s.members.iter().map(|m| m.0)).collect();
    idx.sort_unstable();
    idx.dedup();
    idx.len()
}

/// The running median of `h` over 2 `half` + 1 values (fewer at the ends).
fn running_median(h: &[f64], half: usize) -> Vec<f64> {
    (0..h.len())
        .map(|i| {
            let mut w = h[i.saturating_sub(half)..(i + half + 1).min(h.len())].to_vec();
            median(&mut w)
        })
        .collect()
}

/// The segments from the crests and valleys (indices) of the filtered thickness; None without both. Each crest
/// (valley) reads the largest (smallest) unfiltered thickness within the filter's half width of it: the median
/// cuts a sharp notch or peak by up to two flank steps.
fn segments(secs: &[Section], crests: &[usize], valleys: &[usize], v_chip: f64) -> Option<FrameSegments> {
    if crests.is_empty() || valleys.is_empty() {
        return None;
    }
    let near = |i: usize| &secs[i.saturating_sub(MEDIAN_HALF_WIDTH)..(i + MEDIAN_HALF_WIDTH + 1).min(secs.len())];
    let extreme = |i: usize, pick: fn(f64, f64) -> f64| near(i).iter().map(|s| s.thickness).reduce(pick);
    let h_max = crests.iter().filter_map(|&i| extreme(i, f64::max)).sum::<f64>() / crests.len() as f64;
    let h_min = valleys.iter().filter_map(|&i| extreme(i, f64::min)).sum::<f64>() / valleys.len() as f64;
    let l_seg = match (crests.first(), crests.last()) {
        (Some(&a), Some(&b)) if crests.len() >= 2 => (secs[b].s - secs[a].s) / (crests.len() - 1) as f64,
        _ => f64::NAN,
    };
    Some(FrameSegments {
        crests: crests.len(),
        valleys: valleys.len(),
        h_min,
        h_max,
        degree: (h_max - h_min) / h_max,
        l_seg,
        frequency: v_chip / l_seg,
    })
}

/// t_sl, then t_seg between the `crests` (needs the bulk strain).
fn shear_layers(
    setup: &FrameSetup,
    secs: &[Section],
    crests: &[usize],
    pts: &[[f64; 2]],
    eps: &[f64],
    chip: &mut FrameChip,
) {
    let dx = setup.spacing;
    let Some(bulk) = bulk_strain(secs, eps) else { return };
    chip.t_sl = rake_layer(secs, eps, bulk, dx);
    let mut widths = band_widths(secs, crests, pts, eps, bulk, chip.t_sl, dx);
    chip.bands = widths.len();
    chip.t_seg = (!widths.is_empty()).then(|| median(&mut widths));
}
