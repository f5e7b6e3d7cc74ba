//! The cutting record of a run: the tool force, the contact and the chip thickness sampled during the run
//! (`forces.csv`), and at the end the steady-state means, the chip geometry and the segmentation indicator that
//! go into `summary.json`.
//!
//! Forces: F = Σ (f_c + f_t), the tool's force on the workpiece summed over the particles
//! (roethlin-solver.md §5.4, "Reported tool force"), per unit depth in 2D; ×1e-3 gives N per mm of width, as the
//! experiments report (klippel-constitutive.md §5.2). With u the cutting direction and e the direction rotated
//! +90° from it (out of the workpiece for a tool cutting in +x), the cutting force is F_c = F·u and the feed
//! (thrust) force F_f = −F·e; both are positive in a normal cut.

use super::chip::{ChipGeometry, Station, chip_geometry};
use super::chip_axis::chip_thickness_normal;
use super::early_stop::{EarlyStop, MIN_WINDOW_UNCUT};
use super::energy_audit::EnergyAudit;
use super::segments::{Segments, crests_valleys};
use super::steady::{Steady, mean_from};
use super::tool_wear::ToolWear;
use super::window::{MIN_TRANSIENT_UNCUT, Window, find, time_to_travel};
use crate::kernels::contact::Tool2d;
use crate::output::TimeSeries;
use crate::scene::Scene;
use crate::tool::ContactPower;
use crate::{Error, Result};
use std::path::Path;

/// Columns of `forces.csv` (3D runs add [`FORCE_COLUMNS_3D`]). The powers are every tool's together
/// ([`crate::tool::ContactPower`]; W, per m of depth in 2D).
pub const FORCE_COLUMNS: &[&str] = &[
    "time",
    "step",
    "fc_n_per_mm",
    "ff_n_per_mm",
    "contacts",
    "chip_thickness_um",
    "wear_rate_m_per_s",
    "tool_x",
    "friction_ratio",
    "tool_power_w",
    "friction_power_w",
    "normal_power_w",
];

/// The columns a 3D run adds to `forces.csv`: the tool's total force on the workpiece [N] and its moment [N·m]
/// about the tool's reference point (the rotation axis' point o + c of a rotating tool, else the frame origin o).
pub const FORCE_COLUMNS_3D: &[&str] = &["fx_n", "fy_n", "fz_n", "mx_n_m", "my_n_m", "mz_n_m"];

/// The columns a scene with several tools adds for each tool k ≥ 2 (`_t2`, `_t3`, … appended): its force on the
/// workpiece [N; per m of depth in 2D], its moment about its reference point, the particles it touches and their
/// mean Usui wear rate (NaN without `usui` or contact).
pub const TOOL_COLUMNS: &[&str] =
    &["fx_n", "fy_n", "fz_n", "mx_n_m", "my_n_m", "mz_n_m", "contacts", "wear_rate_m_per_s"];

/// The columns of `forces.csv` in dimension `dim` with `tools` tools.
pub fn force_columns(dim: usize, tools: usize) -> Vec<String> {
    let extra = if dim == 3 { FORCE_COLUMNS_3D } else { &[] };
    let more = (2..=tools).flat_map(|k| TOOL_COLUMNS.iter().map(move |c| format!("{c}_t{k}")));
    FORCE_COLUMNS.iter().chain(extra).map(|c| c.to_string()).chain(more).collect()
}

/// The scalar results a cutting run adds to summary.json (the keys of [`CutAnalysis::json`]): the observables
/// `swarf study` compares and `[experiment]` may give measured values for; declared with the scene's observables.
pub use crate::scene::observe::SUMMARY_OBSERVABLES;

/// Largest relative drift of an observable over its steady window for it to count as steady.
pub const MAX_DRIFT: f64 = 0.1;

/// Hysteresis of the crest and valley detection of the chip thickness, in particle spacings: the thickness moves
/// in steps of one spacing, and a crest must stand out of that quantisation noise (host/cutting/segments.rs).
pub const SEGMENT_PROMINENCE_DX: f64 = 2.0;

/// Samples per output interval.
pub const SAMPLES_PER_OUTPUT: f64 = 10.0;

/// The tool's state at one instant (declared with the tool, below the solver and the methods that produce it).
pub use crate::tool::ToolSample;

pub struct CutRecorder {
    pub series: TimeSeries,
    every: f64,
    next: f64,
    dir: [f64; 3],
    up: [f64; 3],
    /// Width of the cut [m]: 1 in 2D (forces per unit depth), the workpiece's extent in z plus dx in 3D.
    width: f64,
    /// 3D: the total force and moment columns too.
    three_d: bool,
    /// Where the chip thickness is measured; None for a mesh tool (no rake face: no thickness).
    station: Option<Station>,
    /// The chip thickness' quantisation step, dx.
    spacing: f64,
    /// The uncut surface's height [m].
    surface_y: f64,
    /// Uncut chip thickness t1 [m] and cutting speed v_c [m/s].
    uncut: f64,
    speed: f64,
    /// End of the minimum transient: when the tool has travelled [`MIN_TRANSIENT_UNCUT`]·t1 [s].
    pub min_time: f64,
    /// The scene's early stop, if any.
    pub early_stop: Option<EarlyStop>,
    /// Samples kept for the analysis.
    pub time: Vec<f64>,
    pub fc: Vec<f64>,
    pub ff: Vec<f64>,
    pub thickness: Vec<Option<f64>>,
    /// Each tool's contact time and accumulated wear, and where each tool's contact count and wear rate lie in a
    /// row of forces.csv.
    wear: ToolWear,
    wear_columns: Vec<(usize, usize)>,
    /// Where the contact's powers lie in a row, and their works so far.
    power_columns: [usize; 3],
    pub energy: EnergyAudit,
}

impl CutRecorder {
    /// The recorder of a scene with a tool (None without one); `tool` is the parametric tool (None: a mesh tool,
    /// whose chip thickness is not measured). `pos` are the initial particle positions of the workpiece bodies
    /// (the uncut surface is their highest point plus dx/2; in 3D their z extent plus dx is the cut's width).
    ///
    /// F_c = F·u/w and F_f = −F·e/w (×1e-3: N/mm), u the unit cutting velocity, e = (−u_y, u_x, 0)/|…| the
    /// direction +90° from it in the x–y plane (out of the workpiece for a tool cutting in +x), w the width.
    pub fn new(scene: &Scene, tool: Option<Tool2d>, pos: &[[f64; 3]], out_dir: &Path) -> Option<CutRecorder> {
        let t = scene.tool.as_ref()?;
        let v = t.velocity;
        let speed = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        // A resting tool reports its forces along x and y.
        let dir = if speed > 0.0 { v.map(|c| c / speed) } else { [1.0, 0.0, 0.0] };
        let planar = dir[0].hypot(dir[1]);
        let up = if planar > 0.0 { [-dir[1] / planar, dir[0] / planar, 0.0] } else { [0.0, 1.0, 0.0] };
        let dx = scene.discretisation.dx;
        let three_d = scene.dim == 3;
        let width = if three_d {
            let (lo, hi) = pos.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| (l.min(p[2]), h.max(p[2])));
            if hi >= lo { hi - lo + dx } else { dx }
        } else {
            1.0
        };
        let (surface_y, uncut) = super::chip_run::surface_and_uncut(scene, t.position[1], pos);
        let tools = scene.tools().count();
        let columns = force_columns(scene.dim, tools);
        let at = |name: String| columns.iter().position(|c| *c == name).unwrap_or(usize::MAX);
        let suffix = |k: usize| if k == 1 { String::new() } else { format!("_t{k}") };
        let wear_columns =
            (1..=tools).map(|k| (at(format!("contacts{}", suffix(k))), at(format!("wear_rate_m_per_s{}", suffix(k)))));
        Some(CutRecorder {
            series: TimeSeries::new(
                out_dir.join("forces.csv"),
                &columns.iter().map(String::as_str).collect::<Vec<_>>(),
            ),
            every: scene.output.every / SAMPLES_PER_OUTPUT,
            next: 0.0,
            dir,
            up,
            width,
            three_d,
            station: tool.map(|tool| Station {
                rake_point: tool.rake_tangent(),
                rake_angle: tool.rake_angle,
                surface_y,
                station: t.chip_station.unwrap_or(2.0 * uncut),
                half_width: dx,
                spacing: dx,
            }),
            spacing: dx,
            surface_y,
            uncut,
            speed,
            min_time: time_to_travel(MIN_TRANSIENT_UNCUT * uncut, speed, t.ramp),
            early_stop: scene
                .analysis
                .early_stop
                .map(|e| EarlyStop::new(e.tolerance, time_to_travel(MIN_WINDOW_UNCUT * uncut, speed, 0.0))),
            time: Vec::new(),
            fc: Vec::new(),
            ff: Vec::new(),
            thickness: Vec::new(),
            wear: ToolWear::new(tools),
            wear_columns: wear_columns.collect(),
            power_columns: ["tool_power_w", "friction_power_w", "normal_power_w"].map(|c| at(c.to_string())),
            energy: EnergyAudit::default(),
        })
    }

    /// The frame chip analysis' set-up at `time` ([`super::chip_frame`]): this record's uncut surface, and the
    /// scene's tool where its motion puts it then. Err as [`super::chip_run::frame_setup`].
    pub fn frame_setup(&self, scene: &Scene, time: f64) -> Result<super::chip_profile::FrameSetup> {
        super::chip_run::frame_setup(scene, self.surface_y, time)
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
        let h = self.station.and_then(|mut st| {
            st.rake_point = [st.rake_point[0] + offset[0], st.rake_point[1] + offset[1]];
            chip_thickness_normal(&st, c.workpiece.iter().copied())
        });
        let along = |d: &[f64; 3]| c.force[0] * d[0] + c.force[1] * d[1] + c.force[2] * d[2];
        let fc = 1e-3 * along(&self.dir) / self.width;
        let ff = 0.0 - 1e-3 * along(&self.up) / self.width;
        let mut row = vec![
            c.time,
            c.steps as f64,
            fc,
            ff,
            c.contacts as f64,
            h.map_or(f64::NAN, |h| h * 1e6),
            c.wear_rate,
            offset[0],
            c.friction_ratio,
            c.power.tool,
            c.power.friction,
            c.power.normal,
        ];
        if self.three_d {
            row.extend(c.force);
            row.extend(c.moment);
        }
        for t in &c.more {
            row.extend(t.force);
            row.extend(t.moment);
            row.push(t.contacts as f64);
            row.push(t.wear_rate);
        }
        self.push(&row)?;
        Ok(())
    }

    fn push(&mut self, row: &[f64]) -> Result<()> {
        self.series.push(row).map_err(|e| Error::Output(format!("{}: {e}", self.series.path().display())))?;
        self.time.push(row[0]);
        self.fc.push(row[2]);
        self.ff.push(row[3]);
        self.thickness.push(row[5].is_finite().then_some(row[5] * 1e-6));
        let cell = |k: usize| row.get(k).copied().unwrap_or(f64::NAN);
        self.wear.push(row[0], self.wear_columns.iter().map(|&(n, w)| (cell(n), cell(w))));
        let [tool, friction, normal] = self.power_columns.map(cell);
        self.energy.push(row[0], ContactPower { tool, friction, normal });
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

    /// The early stop's check at an output step (`time`, `step`): true when the scene has an early stop and F_c
    /// and F_f are steady to its tolerance (host/cutting/early_stop.rs). Never before the minimum transient:
    /// the windows hold no earlier sample.
    pub fn early_stop_due(&mut self, time: f64, step: u64) -> bool {
        let Some(tol) = self.early_stop.as_ref().map(|e| e.tolerance) else { return false };
        if time < self.min_time {
            return false;
        }
        let fc = find(&self.time, &self.fc, self.min_time, tol);
        let ff = find(&self.time, &self.ff, self.min_time, tol);
        self.early_stop.as_mut().is_some_and(|e| e.check(fc.as_ref(), ff.as_ref(), time, step))
    }

    /// The end-of-run analysis (host/cutting/window.rs): each of F_c, F_f and the chip thickness gets its own
    /// steady window after the minimum transient, with batches matched to its correlation time, a drift test and a
    /// verdict; the means over those windows are the keys `fc_n_per_mm`, `ff_n_per_mm`, `chip_thickness_um` of
    /// summary.json (a force without a window: the mean of its second half), the chip geometry and the crests and
    /// valleys are taken over the thickness' window (null where there is nothing to report).
    pub fn analysis(&self) -> CutAnalysis {
        let fc_w = find(&self.time, &self.fc, self.min_time, MAX_DRIFT);
        let ff_w = find(&self.time, &self.ff, self.min_time, MAX_DRIFT);
        let half = self.time.len() / 2;
        let measured: Vec<(f64, f64)> =
            self.time.iter().zip(&self.thickness).filter_map(|(t, h)| h.map(|h| (*t, h))).collect();
        let (ht, hv): (Vec<f64>, Vec<f64>) = measured.iter().copied().unzip();
        let chip_w = find(&ht, &hv, self.min_time, MAX_DRIFT);
        let chip_part = chip_w.map_or(&[][..], |w| &hv[w.start..]);
        let chip = chip_geometry(&chip_part.iter().map(|&h| Some(h)).collect::<Vec<_>>());
        let segments =
            chip_w.and_then(|w| crests_valleys(&ht[w.start..], &hv[w.start..], SEGMENT_PROMINENCE_DX * self.spacing));
        CutAnalysis {
            steady: fc_w.map(|w| Steady {
                start: w.start,
                start_time: w.start_time,
                mean: w.mean,
                std: w.std,
                drift: w.drift,
                steady: w.steady,
            }),
            fc: fc_w.map_or_else(|| mean_from(&self.fc, half), |w| Some(w.mean)),
            ff: ff_w.map_or_else(|| mean_from(&self.ff, half), |w| Some(w.mean)),
            chip,
            samples: self.time.len(),
            windows: [fc_w, ff_w, chip_w],
            segments,
            pitch: segments.zip(chip).map(|(s, c)| s.pitch(self.speed, self.uncut, c.h_avg)),
            min_time: self.min_time,
            early_stop: self.early_stop.clone(),
            tools: self.wear.clone(),
        }
    }
}

/// What a cutting run reports at its end.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CutAnalysis {
    /// F_c's steady window as the MSER-5-era summary (start, mean, std, drift, verdict).
    pub steady: Option<Steady>,
    /// Mean forces over their own steady windows (the second half where none was found) [N/mm].
    pub fc: Option<f64>,
    pub ff: Option<f64>,
    pub chip: Option<ChipGeometry>,
    pub samples: usize,
    /// The steady windows of F_c, F_f [N/mm] and the chip thickness [m], in that order.
    pub windows: [Option<Window>; 3],
    /// Crests and valleys of the thickness over its window [m], and the pitch l_seg [m].
    pub segments: Option<Segments>,
    pub pitch: Option<f64>,
    /// End of the minimum transient [s].
    pub min_time: f64,
    /// The early stop's report (None: the scene has none).
    pub early_stop: Option<EarlyStop>,
    /// Each tool's contact time and accumulated wear ([`ToolWear`]).
    pub tools: ToolWear,
}

impl CutAnalysis {
    /// The summary.json entries.
    pub fn json(&self) -> serde_json::Value {
        let num = |x: Option<f64>| x.filter(|v| v.is_finite());
        let [fc_w, ff_w, chip_w] = &self.windows;
        let seg = self.segments;
        serde_json::json!({
            "fc_n_per_mm": num(self.fc),
            "ff_n_per_mm": num(self.ff),
            "chip_thickness_um": num(self.chip.map(|c| c.h_avg * 1e6)),
            "segmentation": num(self.chip.map(|c| c.segmentation)),
            "early_stop": EarlyStop::json(self.early_stop.as_ref()),
            "tools": self.tools.json(),
            "cutting": {
                "steady": self.steady.is_some_and(|s| s.steady),
                "steady_from_s": self.steady.map(|s| s.start_time),
                "fc_std_n_per_mm": self.steady.map(|s| s.std),
                "fc_drift": self.steady.map(|s| s.drift),
                "chip_h_min_um": num(self.chip.map(|c| c.h_min * 1e6)),
                "chip_h_max_um": num(self.chip.map(|c| c.h_max * 1e6)),
                "chip_samples": self.chip.map(|c| c.samples),
                "force_samples": self.samples,
                "min_transient_s": num(Some(self.min_time)),
                "observables": {
                    "fc_n_per_mm": window_json(fc_w.as_ref(), 1.0),
                    "ff_n_per_mm": window_json(ff_w.as_ref(), 1.0),
                    "chip_thickness_um": window_json(chip_w.as_ref(), 1e6),
                },
                "segments": seg.map(|s| serde_json::json!({
                    "crests": s.crests,
                    "valleys": s.valleys,
                    "h_crest_um": num(Some(s.h_crest * 1e6)),
                    "h_valley_um": num(Some(s.h_valley * 1e6)),
                    "degree": num(Some(s.degree)),
                    "period_s": num(Some(s.period)),
                    "pitch_um": num(self.pitch.map(|p| p * 1e6)),
                })),
                "method": "each observable (F_c, F_f, chip thickness) is averaged over its own steady window: MSER \
                           on batch means of one integrated autocorrelation time (at least 5 samples), after the \
                           tool has travelled 3 uncut chip thicknesses (the second half where no window is found); \
                           chip: thickness normal to the chip's local axis at tool.chip_station up the rake face, \
                           h_min/h_max 10th/90th percentiles, segments from crests and valleys \
                           (docs/validation.md)",
            }
        })
    }
}

/// One observable's window in summary.json, its values × `scale` (1e6: m → µm).
fn window_json(w: Option<&Window>, scale: f64) -> serde_json::Value {
    let num = |x: f64| Some(x).filter(|v| v.is_finite());
    match w {
        None => serde_json::Value::Null,
        Some(w) => serde_json::json!({
            "steady": w.steady,
            "window_from_s": w.start_time,
            "mean": num(w.mean * scale),
            "std": num(w.std * scale),
            "drift": num(w.drift),
            "standard_error": num(w.sem * scale),
            "correlation_time_s": num(w.tau_s),
            "correlation_time_samples": num(w.tau_samples),
            "batch_samples": w.batch,
            "batches": w.batches,
        }),
    }
}
