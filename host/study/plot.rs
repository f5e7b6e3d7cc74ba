//! `study.png`: wall time (x, log) against error (y, log), one series per precision (and backend, when the study
//! has several), a point per finished run, joined in order of wall time. The top panel is each run's largest error
//! against the reference run; with an `[experiment]`, a second panel is its largest error against the experiment.
//! An error of 0 (the reference run against itself) has no place on a log axis and is not drawn.

use std::path::Path;

use super::{Outcome, Study, table};
use crate::plot::{Chart, Series};

/// Image size in pixels (width, height of one panel).
const SIZE: (u32, u32) = (1200, 800);

/// Draws `study.png` at `path`; an error says why nothing could be drawn (no finished run with a non-zero error
/// yet, or the plotting failed).
pub fn draw(study: &Study, path: &Path) -> Result<(), String> {
    let several = study.runs.iter().any(|r| r.backend != study.runs[0].backend);
    // Series keys in order of first appearance: (precision, backend).
    let mut keys: Vec<(&str, &str)> = Vec::new();
    for r in &study.runs {
        let key = (r.precision.as_str(), r.backend.as_str());
        if !keys.contains(&key) {
            keys.push(key);
        }
    }
    let errors: Vec<table::Errors> = (0..study.runs.len()).map(|k| table::errors(study, k)).collect();
    let points = |pick: &dyn Fn(&table::Errors) -> Option<f64>| -> Vec<(String, Vec<f64>, Vec<f64>)> {
        keys.iter()
            .filter_map(|&(p, b)| {
                let mut pts: Vec<(f64, f64)> = study
                    .runs
                    .iter()
                    .zip(&errors)
                    .filter(|(r, _)| r.precision.as_str() == p && r.backend == b)
                    .filter_map(|(r, e)| match &r.outcome {
                        Outcome::Done(s) => pick(e).filter(|v| *v > 0.0 && v.is_finite()).map(|v| (s.wall_s, v)),
                        _ => None,
                    })
                    .filter(|(w, _)| *w > 0.0)
                    .collect();
                pts.sort_by(|a, b| a.0.total_cmp(&b.0));
                let label = if several { format!("{p} {b}") } else { p.to_string() };
                (!pts.is_empty()).then(|| (label, pts.iter().map(|q| q.0).collect(), pts.iter().map(|q| q.1).collect()))
            })
            .collect()
    };
    let against_ref = points(&|e| e.max_reference);
    let against_exp = if study.experiment.is_empty() { Vec::new() } else { points(&|e| e.max_experiment) };
    let r = &study.runs[study.reference];
    // Titles short enough for the panel's width at the default size (about 60 characters).
    let ref_title = format!(
        "{}: error against the finest {} run (Δx = {} m)",
        study.scene,
        r.precision.as_str(),
        table::sig(r.dx, 3)
    );
    let exp_title = format!("{}: error against the experiment", study.scene);
    let mut charts = Vec::new();
    for (title, data) in [(&ref_title, &against_ref), (&exp_title, &against_exp)] {
        if data.is_empty() {
            continue;
        }
        charts.push(Chart {
            title,
            x_label: "wall time (s)",
            y_label: "largest relative error over the observables",
            series: data.iter().map(|(label, x, y)| Series { label, x, y }).collect(),
        });
    }
    if charts.is_empty() {
        return Err("no finished run with a non-zero error to draw yet".into());
    }
    let size = (SIZE.0, SIZE.1 * charts.len() as u32);
    crate::plot::draw_log_log(path, &charts, size).map(|_| ()).map_err(|e| e.to_string())
}
