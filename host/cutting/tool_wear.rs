//! Each tool's contact time and accumulated Usui wear over a run, from the samples of `forces.csv` (the grains of a
//! grinding wheel, docs/3d.md "Grinding wheel segment"; Röthlin reports the mean accumulated wear per grain,
//! roethlin-solver.md §7.10, Tab. 7.11).
//!
//! A sample holds each tool's contact count and the mean wear rate Ẇ = Ψ exp(−ξ/T) p |v_t| of the particles it
//! touches. Over the interval ending at a sample with contact the tool wears Ẇ Δt (the rectangle rule on the
//! samples; Δt from the previous sample, or from t = 0 for the first):
//!
//! - `wear_m` = Σ Ẇ Δt over the samples with contact;
//! - `wear_median_m` = the median of those Ẇ times the contact time: robust to a single sample's spike, when one
//!   particle pressed hard against the tool dominates the mean (a grain's 170 m/s against its median 0.73 m/s);
//! - `contact_time_s` = Σ Δt over the samples with contact, and the first and last such sample's time.

use serde_json::{Value, json};

/// One tool's tally.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ToolTally {
    pub contact_time: f64,
    pub wear: f64,
    /// Ẇ of every sample with contact (finite ones), for the median.
    pub rates: Vec<f64>,
    pub first: Option<f64>,
    pub last: Option<f64>,
}

impl ToolTally {
    /// The median rate times the contact time (0 without a rate).
    pub fn wear_median(&self) -> f64 {
        let mut r = self.rates.clone();
        r.sort_by(f64::total_cmp);
        r.get(r.len() / 2).map_or(0.0, |m| m * self.contact_time)
    }
}

/// Every tool's tally, fed sample by sample.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ToolWear {
    pub tools: Vec<ToolTally>,
    last_time: f64,
}

impl ToolWear {
    pub fn new(tools: usize) -> Self {
        ToolWear { tools: vec![ToolTally::default(); tools], last_time: 0.0 }
    }

    /// Adds the sample at `time`: each tool's (contact count, mean wear rate) (rate NaN: wear off or no contact).
    pub fn push(&mut self, time: f64, tools: impl Iterator<Item = (f64, f64)>) {
        let dt = time - self.last_time;
        self.last_time = time;
        for (tally, (n, w)) in self.tools.iter_mut().zip(tools) {
            if n > 0.0 {
                tally.contact_time += dt;
                tally.first.get_or_insert(time);
                tally.last = Some(time);
                if w.is_finite() {
                    tally.wear += w * dt;
                    tally.rates.push(w);
                }
            }
        }
    }

    /// summary.json's `tools`: one entry per tool in the scene's order (null wear where no rate was recorded).
    pub fn json(&self) -> Value {
        Value::Array(
            self.tools
                .iter()
                .map(|t| {
                    let worn = !t.rates.is_empty();
                    json!({
                        "contact_time_s": t.contact_time,
                        "first_contact_s": t.first,
                        "last_contact_s": t.last,
                        "wear_m": worn.then_some(t.wear),
                        "wear_median_m": worn.then(|| t.wear_median()),
                    })
                })
                .collect(),
        )
    }
}
