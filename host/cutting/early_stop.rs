//! The early stop of a cutting run (`[analysis] early_stop = { tolerance = ε }`): the run ends once F_c and F_f
//! are both steady to ε, checked at output steps on the force samples so far.
//!
//! Criterion, for each of F_c and F_f (their windows from [`super::window::find`], which never start before the
//! minimum transient): the MSER window is found inside the admissible range with at least 20 samples and 2
//! batches, its relative drift is at most ε, and the standard error of its mean (batch means of the
//! correlation-time batches) is at most ε·|mean|; and, because τ_int estimated on a short record is biased low
//! (n samples cannot show correlations much longer than n/10, so a young window's batches are too short and its
//! standard error too small), the window holds at least [`MIN_BATCHES`] batches and spans at least
//! [`MIN_WINDOW_UNCUT`] uncut chip thicknesses of tool travel.

use super::window::Window;

/// Fewest batches of the window (the standard error from m batch means has m − 1 degrees of freedom: with 8, its
/// own relative uncertainty is about 1/√14 ≈ 27 %).
pub const MIN_BATCHES: usize = 8;

/// Shortest window, in uncut chip thicknesses t1 of tool travel. The forces' τ_int measured on coarse V0060 cuts
/// is 0.5–0.65 t1/v_c (10 µs at 6.355 m/s, 1 µs at 50 m/s; docs/validation.md), so 4 t1 is 6–8 correlation
/// times: the least over which a correlation time and a standard error can be told apart from a slow swing.
pub const MIN_WINDOW_UNCUT: f64 = 4.0;

/// The early stop's state and, at the end, its report (`early_stop` in summary.json).
#[derive(Clone, Debug, PartialEq)]
pub struct EarlyStop {
    /// The tolerance ε (relative).
    pub tolerance: f64,
    /// Shortest window [s] (the time for [`MIN_WINDOW_UNCUT`] t1 of travel at the cutting speed).
    pub min_span: f64,
    /// Where the run stopped early (time [s], step); None while it has not.
    pub at: Option<(f64, u64)>,
    /// Why it stopped, or at the last check why it did not yet.
    pub reason: String,
}

impl EarlyStop {
    /// The state for tolerance ε = `tolerance` with windows no shorter than `min_span` [s].
    pub fn new(tolerance: f64, min_span: f64) -> Self {
        EarlyStop {
            tolerance,
            min_span,
            at: None,
            reason: "not checked: no force samples after the minimum transient".into(),
        }
    }

    /// One check with the windows of F_c and F_f at `time`, `step`; true when the run should stop here.
    pub fn check(&mut self, fc: Option<&Window>, ff: Option<&Window>, time: f64, step: u64) -> bool {
        let eps = self.tolerance;
        let (end, span) = (time, self.min_span);
        match (judge("F_c", fc, eps, end, span), judge("F_f", ff, eps, end, span)) {
            (Ok(a), Ok(b)) => {
                self.reason = format!("F_c and F_f steady to {eps}: {a}; {b}");
                self.at = Some((time, step));
                true
            }
            (Err(e), _) | (_, Err(e)) => {
                self.reason = e;
                false
            }
        }
    }

    /// The summary.json entry `early_stop` (`enabled` is false where the scene has no early stop: `json(None)`).
    pub fn json(e: Option<&EarlyStop>) -> serde_json::Value {
        match e {
            None => serde_json::json!({ "enabled": false }),
            Some(e) => serde_json::json!({
                "enabled": true,
                "tolerance": e.tolerance,
                "min_window_s": e.min_span,
                "stopped": e.at.is_some(),
                "at_time_s": e.at.map(|a| a.0),
                "at_step": e.at.map(|a| a.1),
                "reason": e.reason,
            }),
        }
    }
}

/// Ok(a description) when `w` is steady to `eps`, else Err(why not).
/// `end` is the time of the last sample, `min_span` the shortest window [s].
fn judge(name: &str, w: Option<&Window>, eps: f64, end: f64, min_span: f64) -> Result<String, String> {
    let w = w.ok_or_else(|| format!("{name}: fewer than 20 samples after the minimum transient"))?;
    let rel_se = w.sem / w.mean.abs();
    if !w.steady {
        return Err(format!(
            "{name}: not steady (MSER window at the edge of its range, too few batches of {} samples, or drift {:.3} \
             above {eps})",
            w.batch, w.drift
        ));
    }
    if w.batches < MIN_BATCHES || end - w.start_time < min_span {
        return Err(format!(
            "{name}: window of {} batches over {:.3e} s, short of {MIN_BATCHES} batches and {min_span:.3e} s",
            w.batches,
            end - w.start_time
        ));
    }
    // A NaN standard error (fewer than 2 batches) fails too.
    if rel_se.is_nan() || rel_se > eps {
        return Err(format!("{name}: standard error of the mean {rel_se:.4} of it, above {eps}"));
    }
    Ok(format!(
        "{name} from {:.3e} s, drift {:.4}, standard error {rel_se:.4} of the mean ({} batches of {})",
        w.start_time, w.drift, w.batches, w.batch
    ))
}
