//! The cutting record of a run: the tool force, the contact and the chip thickness sampled during the run
//! (`forces.csv`), and at the end the steady-state means, the chip geometry and the segmentation indicator that
//! go into `summary.json`.
//!
//! Forces: F = Σ (f_c + f_t), the tool's force on the workpiece summed over the particles
//! (roethlin-solver.md §5.4, "Reported tool force"), per unit depth in 2D; ×1e-3 gives N per mm of width, as the
//! experiments report (klippel-constitutive.md §5.2). With u the cutting direction and e the direction rotated
//! +90° from it (out of the workpiece for a tool cutting in +x), the cutting force is F_c = F·u and the feed
//! (thrust) force F_f = −F·e; both are positive in a normal cut.

use super::chip::{ChipGeometry, Station, chip_geometry, chip_thickness};
use super::steady::{Steady, detect, mean_from};
use crate::kernels::contact::Tool2d;
use crate::output::TimeSeries;
use crate::scene::Scene;
use crate::{Error, Result};
use std::path::Path;

/// Columns of `forces.csv`.
pub const FORCE_COLUMNS: &[&str] =
    &["time", "step", "fc_n_per_mm", "ff_n_per_mm", "contacts", "chip_thickness_um", "wear_rate_m_per_s", "tool_x"];

/// The scalar results a cutting run adds to summary.json (the keys of [`CutAnalysis::json`]): the observables
/// `swarf study` compares and `[experiment]` may give measured values for; declared with the scene's observables.
pub use crate::scene::observe::SUMMARY_OBSERVABLES;

/// Largest relative drift of F_c over the steady part for the run to count as steady.
pub const MAX_DRIFT: f64 = 0.1;

/// Samples per output interval.
pub const SAMPLES_PER_OUTPUT: f64 = 10.0;

/// The tool's state at one instant (declared with the tool, below the solver and the methods that produce it).
pub use crate::tool::ToolSample;

pub struct CutRecorder {
    pub series: TimeSeries,
    every: f64,
    next: f64,
    dir: [f64; 2],
    up: [f64; 2],
    station: Station,
    /// Samples kept for the analysis.
    pub time: Vec<f64>,
    pub fc: Vec<f64>,
    pub ff: Vec<f64>,
    pub thickness: Vec<Option<f64>>,
}

impl CutRecorder {
    /// The recorder of a scene with a tool (None without one). `pos` are the initial particle positions of the
    /// workpiece bodies (the uncut surface is their highest point plus dx/2).
    pub fn new(scene: &Scene, tool: Tool2d, pos: &[[f64; 3]], out_dir: &Path) -> Option<CutRecorder> {
        let t = scene.tool.as_ref()?;
        let speed = t.velocity[0].hypot(t.velocity[1]);
        // A resting tool reports its forces along x and y.
        let dir = if speed > 0.0 { [t.velocity[0] / speed, t.velocity[1] / speed] } else { [1.0, 0.0] };
        let dx = scene.discretisation.dx;
        let surface_y = pos.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max) + 0.5 * dx;
        let uncut = (surface_y - t.position[1]).max(dx);
        Some(CutRecorder {
            series: TimeSeries::new(out_dir.join("forces.csv"), FORCE_COLUMNS),
            every: scene.output.every / SAMPLES_PER_OUTPUT,
            next: 0.0,
            dir,
            up: [-dir[1], dir[0]],
            station: Station {
                rake_point: tool.rake_tangent(),
                rake_angle: tool.rake_angle,
                surface_y,
                station: t.chip_station.unwrap_or(2.0 * uncut),
                half_width: dx,
                spacing: dx,
            },
            time: Vec::new(),
            fc: Vec::new(),
            ff: Vec::new(),
            thickness: Vec::new(),
        })
    }

    /// Whether a sample is due at simulated time `t`.
    pub fn due(&self, t: f64) -> bool {
        t >= self.next
    }

    /// The time of the next sample.
    pub fn next(&self) -> f64 {
        self.next
    }

    /// Takes a sample of the tool's state (`method::Method::tool_sample`).
    pub fn sample(&mut self, c: &ToolSample) -> Result<()> {
        let offset = c.offset;
        let mut st = self.station;
        st.rake_point = [st.rake_point[0] + offset[0], st.rake_point[1] + offset[1]];
        let h = chip_thickness(&st, c.workpiece.iter().copied());
        let fc = 1e-3 * (c.force[0] * self.dir[0] + c.force[1] * self.dir[1]);
        let ff = 0.0 - 1e-3 * (c.force[0] * self.up[0] + c.force[1] * self.up[1]);
        self.push(&[
            c.time,
            c.steps as f64,
            fc,
            ff,
            c.contacts as f64,
            h.map_or(f64::NAN, |h| h * 1e6),
            c.wear_rate,
            offset[0],
        ])?;
        Ok(())
    }

    fn push(&mut self, row: &[f64]) -> Result<()> {
        self.series.push(row).map_err(|e| Error::Output(format!("{}: {e}", self.series.path().display())))?;
        self.time.push(row[0]);
        self.fc.push(row[2]);
        self.ff.push(row[3]);
        self.thickness.push(row[5].is_finite().then_some(row[5] * 1e-6));
        while self.next <= row[0] {
            self.next += self.every;
        }
        Ok(())
    }

    /// Restores the samples of `forces.csv` up to `time` (a resumed run).
    pub fn resume(&mut self, time: f64) -> Result<()> {
        if let Ok((_, rows)) = crate::output::csv::read(self.series.path()) {
            for r in rows.into_iter().filter(|r| r[0] <= time) {
                self.push(&r)?;
            }
        }
        Ok(())
    }

    /// Rewrites `forces.csv` (atomically).
    pub fn write(&self) -> Result<()> {
        self.series.write().map_err(|e| Error::Output(format!("{}: {e}", self.series.path().display())))
    }

    /// The end-of-run analysis: steady state of F_c (MSER-5, host/cutting/steady.rs), the mean forces over the
    /// steady part, the chip geometry over the part of it where the thickness itself is steady (MSER-5 again), and the keys `fc_n_per_mm`, `ff_n_per_mm`, `chip_thickness_um` and
    /// `segmentation` of summary.json (null where there is nothing to report).
    pub fn analysis(&self) -> CutAnalysis {
        let steady = detect(&self.time, &self.fc, MAX_DRIFT);
        let start = steady.map_or(self.time.len() / 2, |s| s.start);
        // The chip reaches the measuring station later than the force settles: its own transient (the chip's
        // head passing the station) is cut off by MSER-5 on the thickness samples themselves.
        let measured: Vec<(f64, f64)> =
            self.time.iter().zip(&self.thickness).skip(start).filter_map(|(t, h)| h.map(|h| (*t, h))).collect();
        let (ht, hv): (Vec<f64>, Vec<f64>) = measured.iter().copied().unzip();
        let chip_start = detect(&ht, &hv, f64::INFINITY).map_or(0, |s| s.start);
        let chip = chip_geometry(&hv[chip_start.min(hv.len())..].iter().map(|&h| Some(h)).collect::<Vec<_>>());
        CutAnalysis {
            steady,
            fc: mean_from(&self.fc, start),
            ff: mean_from(&self.ff, start),
            chip,
            samples: self.time.len(),
        }
    }
}

/// What a cutting run reports at its end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CutAnalysis {
    pub steady: Option<Steady>,
    /// Mean forces over the steady part (the second half if none was found) [N/mm].
    pub fc: Option<f64>,
    pub ff: Option<f64>,
    pub chip: Option<ChipGeometry>,
    pub samples: usize,
}

impl CutAnalysis {
    /// The summary.json entries.
    pub fn json(&self) -> serde_json::Value {
        let num = |x: Option<f64>| x.filter(|v| v.is_finite());
        serde_json::json!({
            "fc_n_per_mm": num(self.fc),
            "ff_n_per_mm": num(self.ff),
            "chip_thickness_um": num(self.chip.map(|c| c.h_avg * 1e6)),
            "segmentation": num(self.chip.map(|c| c.segmentation)),
            "cutting": {
                "steady": self.steady.is_some_and(|s| s.steady),
                "steady_from_s": self.steady.map(|s| s.start_time),
                "fc_std_n_per_mm": self.steady.map(|s| s.std),
                "fc_drift": self.steady.map(|s| s.drift),
                "chip_h_min_um": num(self.chip.map(|c| c.h_min * 1e6)),
                "chip_h_max_um": num(self.chip.map(|c| c.h_max * 1e6)),
                "chip_samples": self.chip.map(|c| c.samples),
                "force_samples": self.samples,
                "method": "forces: mean over the steady part found by MSER-5 on F_c (second half if none); chip: \
                           thickness across a slice at tool.chip_station up the rake face, h_avg mean, h_min/h_max \
                           10th/90th percentiles over the steady part (docs/validation.md)",
            }
        })
    }
}
