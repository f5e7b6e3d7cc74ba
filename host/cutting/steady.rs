//! Steady-state detection of a cutting-force time series.
//!
//! Method: MSER-5, the Marginal Standard Error Rule applied to batch means of 5 samples (White 1997, "An effective
//! truncation heuristic for bias reduction in simulation output", Simulation 69(6) 323–334; Franklin & White 2008,
//! "Stationarity tests and MSER-5: exploring the intuition behind mean-squared-error-reduction in warm-up period
//! determination", Proc. Winter Simulation Conference). The samples are grouped into nb batches of b = 5 consecutive
//! samples (an incomplete last batch is dropped from the rule) with means Y_k. For each truncation d the statistic
//!
//! MSER(d) = Σ_{k=d}^{nb−1} (Y_k − Ȳ_d)² / (nb − d)²,  Ȳ_d = mean of Y_d..Y_{nb−1},
//!
//! is the squared standard error of the truncated mean; its minimiser d* (the first one on ties) balances the bias
//! the transient adds against the variance lost by discarding data. Admissible range: d = 0 ..= ⌊nb/2⌋, the usual
//! rule that at most half the run may be discarded; a minimum at d = ⌊nb/2⌋ means MSER still falls at the edge of
//! the range, i.e. the transient did not end within the run, and the series is reported as not steady. The steady
//! part starts at sample 5·d* and runs to the end of the series (the samples of the dropped batch included).

/// Batch size of MSER-5.
pub(crate) const BATCH: usize = 5;
/// Fewest samples the steady part must hold for its mean to be reported as steady.
pub(crate) const MIN_STEADY_SAMPLES: usize = 20;

/// Result of the steady-state analysis of one series.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Steady {
    /// First sample index of the steady part.
    pub start: usize,
    /// Its time.
    pub start_time: f64,
    /// Mean and (population) standard deviation of the raw samples over the steady part.
    pub mean: f64,
    pub std: f64,
    /// Relative drift: slope of a least-squares line through the steady part × its duration / |mean|.
    pub drift: f64,
    /// Whether the series reached a steady state: MSER's minimum lies strictly inside the admissible range
    /// (not at its upper end, which means the transient never ended), the steady part holds at least 20 samples,
    /// and |drift| ≤ `max_drift`.
    pub steady: bool,
}

/// MSER-5 steady-state detection. `t` and `x` have equal length (else None); fewer than 4 batches → None;
/// any non-finite value → None.
///
/// The drift is NaN (and the series not steady) when the steady part's times are all equal; it is 0 for a series
/// that is identically 0.
pub fn detect(t: &[f64], x: &[f64], max_drift: f64) -> Option<Steady> {
    if t.len() != x.len() || !t.iter().chain(x).all(|v| v.is_finite()) {
        return None;
    }
    let means = batch_means(x, BATCH);
    if means.len() < 4 {
        return None;
    }
    let (d, upper) = mser_minimum(&means);
    let start = d * BATCH;
    let (mean, std) = mean_std(&x[start..])?;
    let drift = relative_drift(&t[start..], &x[start..], mean);
    let steady = d < upper && x.len() - start >= MIN_STEADY_SAMPLES && drift.abs() <= max_drift;
    Some(Steady { start, start_time: t[start], mean, std, drift, steady })
}

/// Mean of `x[start..]` (helper for the other series over the window that `detect` found on F_c); None if empty
/// or if a value in the window is not finite.
pub fn mean_from(x: &[f64], start: usize) -> Option<f64> {
    let w = x.get(start..)?;
    if w.is_empty() || !w.iter().all(|v| v.is_finite()) {
        return None;
    }
    Some(w.iter().sum::<f64>() / w.len() as f64)
}

/// The q-quantile (0..=1, linear interpolation between order statistics, as numpy's default) of `x[start..]`.
/// None if the window is empty, a value in it is not finite, or q lies outside [0, 1].
pub fn quantile_from(x: &[f64], start: usize, q: f64) -> Option<f64> {
    let w = x.get(start..)?;
    if !w.iter().all(|v| v.is_finite()) {
        return None;
    }
    let mut v = w.to_vec();
    v.sort_by(f64::total_cmp);
    quantile_sorted(&v, q)
}

/// numpy's default ("linear", Hyndman & Fan 1996 type 7) quantile of an ascending slice: position h = q (n − 1),
/// value v[⌊h⌋] + (h − ⌊h⌋)(v[⌊h⌋+1] − v[⌊h⌋]). None if empty or q is outside [0, 1] (NaN included).
pub(crate) fn quantile_sorted(v: &[f64], q: f64) -> Option<f64> {
    if v.is_empty() || !(0.0..=1.0).contains(&q) {
        return None;
    }
    let h = q * (v.len() - 1) as f64;
    let lo = (h.floor() as usize).min(v.len() - 1);
    let frac = h - lo as f64;
    let hi = (lo + 1).min(v.len() - 1);
    Some(v[lo] + frac * (v[hi] - v[lo]))
}

/// Means of consecutive batches of `b` samples (b ≥ 1); the incomplete last batch is dropped.
pub(crate) fn batch_means(x: &[f64], b: usize) -> Vec<f64> {
    x.chunks_exact(b.max(1)).map(|c| c.iter().sum::<f64>() / c.len() as f64).collect()
}

/// The first minimiser d* of MSER(d) over d = 0 ..= ⌊nb/2⌋, and that upper end ⌊nb/2⌋.
pub(crate) fn mser_minimum(y: &[f64]) -> (usize, usize) {
    let nb = y.len();
    let upper = nb / 2;
    // Welford's update run backwards from the last batch gives Σ(Y − Ȳ_d)² for every d in one pass, without the
    // cancellation of Σy² − (Σy)²/m when the spread is small against the mean.
    let (mut mean, mut m2) = (0.0, 0.0);
    let (mut best_d, mut best) = (upper, f64::INFINITY);
    for d in (0..nb).rev() {
        let m = (nb - d) as f64;
        let delta = y[d] - mean;
        mean += delta / m;
        m2 += delta * (y[d] - mean);
        // Going downwards, `<=` leaves the smallest d among equal minima: the first minimum.
        if d <= upper {
            let mser = m2 / (m * m);
            if mser <= best {
                best = mser;
                best_d = d;
            }
        }
    }
    (best_d, upper)
}

/// Mean and population standard deviation; None if empty.
pub(crate) fn mean_std(x: &[f64]) -> Option<(f64, f64)> {
    if x.is_empty() {
        return None;
    }
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n;
    Some((mean, var.sqrt()))
}

/// Slope of the least-squares line x(t) × (t_last − t_first) / |mean|: the change of the fitted trend over the
/// window relative to the level.
pub(crate) fn relative_drift(t: &[f64], x: &[f64], mean: f64) -> f64 {
    let n = t.len() as f64;
    let t_mean = t.iter().sum::<f64>() / n;
    // Centred sums: times of a long run are large against their spread.
    let (sxy, sxx) = t
        .iter()
        .zip(x)
        .fold((0.0, 0.0), |(sxy, sxx), (&ti, &xi)| (sxy + (ti - t_mean) * (xi - mean), sxx + (ti - t_mean).powi(2)));
    let span = match (t.first(), t.last()) {
        (Some(a), Some(b)) => b - a,
        _ => return f64::NAN,
    };
    let rise = sxy / sxx * span;
    if rise == 0.0 && mean == 0.0 { 0.0 } else { rise / mean.abs() }
}
