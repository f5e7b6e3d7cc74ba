//! The early stop of a cutting run (`[analysis] early_stop = { tolerance = ε }`): the run ends once F_c and F_f
//! are both steady to ε, checked at output steps on the force samples so far.
//!
//! Criterion, for each of F_c and F_f (their windows from [`super::window::find`], which never start before the
//! minimum transient): the MSER window is found inside the admissible range with at least 20 samples and 2
//! batches, its relative drift is at most ε, and the standard error of its mean (batch means of the
//! correlation-time batches) is at most ε·|mean|.

use super::window::Window;

/// The early stop's state and, at the end, its report (`early_stop` in summary.json).
#[derive(Clone, Debug, PartialEq)]
pub struct EarlyStop {
    /// The tolerance ε (relative).
    pub tolerance: f64,
    /// Where the run stopped early (time [s], step); None while it has not.
    pub at: Option<(f64, u64)>,
    /// Why it stopped, or at the last check why it did not yet.
    pub reason: String,
}

impl EarlyStop {
    pub fn new(tolerance: f64) -> Self {
        EarlyStop { tolerance, at: None, reason: "not checked: no force samples after the minimum transient".into() }
    }

    /// One check with the windows of F_c and F_f at `time`, `step`; true when the run should stop here.
    pub fn check(&mut self, fc: Option<&Window>, ff: Option<&Window>, time: f64, step: u64) -> bool {
        let eps = self.tolerance;
        match (judge("F_c", fc, eps), judge("F_f", ff, eps)) {
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
                "stopped": e.at.is_some(),
                "at_time_s": e.at.map(|a| a.0),
                "at_step": e.at.map(|a| a.1),
                "reason": e.reason,
            }),
        }
    }
}

/// Ok(a description) when `w` is steady to `eps`, else Err(why not).
fn judge(name: &str, w: Option<&Window>, eps: f64) -> Result<String, String> {
    let w = w.ok_or_else(|| format!("{name}: fewer than 20 samples after the minimum transient"))?;
    let rel_se = w.sem / w.mean.abs();
    if !w.steady {
        return Err(format!(
            "{name}: not steady (MSER window at the edge of its range, too few batches of {} samples, or drift {:.3} \
             above {eps})",
            w.batch, w.drift
        ));
    }
    // Written so that a NaN standard error (fewer than 2 batches) fails.
    if !(rel_se <= eps) {
        return Err(format!("{name}: standard error of the mean {rel_se:.4} of it, above {eps}"));
    }
    Ok(format!(
        "{name} from {:.3e} s, drift {:.4}, standard error {rel_se:.4} of the mean ({} batches of {})",
        w.start_time, w.drift, w.batches, w.batch
    ))
}
