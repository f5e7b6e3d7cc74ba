//! The steady window of one observable (F_c, F_f or the chip thickness): MSER with batches matched to the signal's
//! correlation time, never starting before a minimum physical transient, with a drift test and the standard error
//! of the window's mean.
//!
//! Method (docs/validation.md, "Steady state"):
//! 1. Only samples at t ≥ t_min count, t_min being when the tool has travelled the minimum transient
//!    ([`MIN_TRANSIENT_UNCUT`] uncut chip thicknesses, see there).
//! 2. A pilot MSER-5 ([`super::steady::detect`]) on them gives a candidate steady part; its integrated
//!    autocorrelation time τ_int ([`super::autocorr::integrated_time`], in samples) sets the batch length
//!    b = max(5, ⌈[`BATCHES_PER_TAU`] · τ_int⌉).
//! 3. MSER on the batch means of b samples (White 1997, the statistic of host/cutting/steady.rs) over the same
//!    samples gives the window's first batch d*; the window is every sample from t_min + d*·b to the end.
//! 4. Over the window: mean, population standard deviation, the relative drift (least-squares slope × the window's
//!    duration / |mean|) and the standard error of the mean from the nb − d* batch means,
//!    SE = s_Y / √(nb − d*), s_Y their sample standard deviation.
//! 5. Steady when MSER's minimum lies strictly below ⌊nb/2⌋ (the transient ended within the series), the window
//!    holds at least 20 samples and 2 batches, and |drift| ≤ the stated tolerance.
//!
//! With fewer than 4 batches of b samples after t_min (the series is shorter than about 4 b: too short for its own
//! correlation time), the window is the pilot's and the verdict is "not steady".

use super::autocorr::integrated_time;
use super::steady::{BATCH, MIN_STEADY_SAMPLES, batch_means, mean_std, mser_minimum, relative_drift};

/// Batch length in units of τ_int. For an exponentially correlated signal (decay time τ_e, τ_int ≈ 2 τ_e), batches
/// of one τ_int leave neighbouring batch means correlated by about 0.33 (Ornstein–Uhlenbeck batch means: covariance
/// (τ_e/b)²(1 − e^{−b/τ_e})² against variance 2(τ_e/b)²(b/τ_e − 1 + e^{−b/τ_e})), so their spread underestimates the
/// standard error of the mean by about 1/√(1 + 2·0.33) ≈ 0.78; batches of 2 τ_int would leave 0.16 (≈ 0.88) but
/// halve the batches MSER sees. The cuts this serves are only a few correlation times long after their transient
/// (V0060: τ_int ≈ 10 µs against 110 µs), so the resolution of the truncation point is preferred.
pub const BATCHES_PER_TAU: f64 = 1.0;

/// The minimum transient, in uncut chip thicknesses t1 of tool travel. Derivation: the chip forms once the
/// primary shear zone spans the uncut layer, i.e. once the tool has pushed material across a shear plane of length
/// t1 / sin φ (φ the shear angle, ≈ 45° for the cuts of klippel-constitutive.md §5: ≈ 1.4 t1); the chip's head then
/// has to pass the chip station (2 t1 up the rake face by default) at the chip speed v_c t1/h, i.e. the tool
/// travels a further 2 h ≈ 2 t1 (compression ratio h/t1 ≈ 1 in the same tests). Until then neither the forces nor
/// the thickness at the station can be steady: 1.4 + 2 ≈ 3 t1, rounded to 3.
pub const MIN_TRANSIENT_UNCUT: f64 = 3.0;

/// Fewest batches MSER runs on.
const MIN_BATCHES: usize = 4;

/// The steady window of one observable.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Window {
    /// First sample index of the window (into the series given to [`find`]) and its time [s].
    pub start: usize,
    pub start_time: f64,
    /// Mean and population standard deviation of the samples in the window.
    pub mean: f64,
    pub std: f64,
    /// Relative drift over the window (see the module doc).
    pub drift: f64,
    /// Standard error of the mean from the batch means [the signal's unit]; NaN with fewer than 2 batches.
    pub sem: f64,
    /// τ_int of the candidate steady part, in samples and in seconds (× the mean sample interval).
    pub tau_samples: f64,
    pub tau_s: f64,
    /// Batch length b [samples] and the number of batches in the window.
    pub batch: usize,
    pub batches: usize,
    /// The verdict (module doc, step 5).
    pub steady: bool,
}

/// The steady window of `x` sampled at times `t` (ascending), with no sample before `t_min` in it, and the verdict
/// against the relative drift tolerance `max_drift`. None when the lengths differ, a value is not finite, or fewer
/// than 20 samples lie at t ≥ t_min.
pub fn find(t: &[f64], x: &[f64], t_min: f64, max_drift: f64) -> Option<Window> {
    if t.len() != x.len() || !t.iter().chain(x).all(|v| v.is_finite()) {
        return None;
    }
    let first = t.partition_point(|&ti| ti < t_min);
    let (ts, xs) = (&t[first..], &x[first..]);
    if xs.len() < MIN_STEADY_SAMPLES {
        return None;
    }
    let pilot = super::steady::detect(ts, xs, max_drift)?;
    let tau = integrated_time(&xs[pilot.start..]).unwrap_or(1.0);
    let batch = ((BATCHES_PER_TAU * tau).ceil() as usize).max(BATCH);
    let means = batch_means(xs, batch);
    let dt = (ts[ts.len() - 1] - ts[0]) / (ts.len() - 1) as f64;
    let (d, upper, enough) = if means.len() >= MIN_BATCHES {
        let (d, upper) = mser_minimum(&means);
        (d, upper, true)
    } else {
        // Too short for its correlation time: the pilot's window, not steady.
        (pilot.start / batch, usize::MAX, false)
    };
    let start = if enough { d * batch } else { pilot.start };
    let (mean, std) = mean_std(&xs[start..])?;
    let drift = relative_drift(&ts[start..], &xs[start..], mean);
    let window_means = means.get(d.min(means.len())..).unwrap_or(&[]);
    let sem = standard_error(window_means);
    let steady = enough
        && d < upper
        && xs.len() - start >= MIN_STEADY_SAMPLES
        && window_means.len() >= 2
        && drift.abs() <= max_drift;
    Some(Window {
        start: first + start,
        start_time: ts[start],
        mean,
        std,
        drift,
        sem,
        tau_samples: tau,
        tau_s: tau * dt,
        batch,
        batches: window_means.len(),
        steady,
    })
}

/// s_Y / √m of m batch means (s_Y with the m − 1 divisor); NaN for fewer than 2.
fn standard_error(y: &[f64]) -> f64 {
    let m = y.len();
    if m < 2 {
        return f64::NAN;
    }
    let mean = y.iter().sum::<f64>() / m as f64;
    let var = y.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (m - 1) as f64;
    (var / m as f64).sqrt()
}

/// The time at which a tool moving at `speed` [m/s] after a linear start-up ramp of `ramp` [s] has travelled
/// `distance` [m] (the inverse of [`crate::tool::motion::ToolMotion`]'s travel: s(t) = t²/(2 t_r) during the ramp,
/// t − t_r/2 after it). Infinite for a resting tool and a positive distance.
pub fn time_to_travel(distance: f64, speed: f64, ramp: f64) -> f64 {
    if distance <= 0.0 {
        return 0.0;
    }
    if speed <= 0.0 {
        return f64::INFINITY;
    }
    let s = distance / speed;
    if ramp > 0.0 && s < 0.5 * ramp { (2.0 * ramp * s).sqrt() } else { s + 0.5 * ramp.max(0.0) }
}
