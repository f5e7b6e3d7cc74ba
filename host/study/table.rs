//! The errors of a study's runs, and its tables: `study.csv` (every number, for scripts) and `study.md` (a
//! Markdown table for docs/measurements/notebook.md).
//!
//! Error of a value a against a reference r: |a − r|/|r|, relative and unsigned (0 when both are 0, infinite when
//! only r is). Against the study's reference run (the finest-level f64 run), per observable; against the
//! experiment, per observable that `[experiment]` measures. A run's largest error is the largest over the
//! observables both it and the reference report: one number per run for the plot.

use std::fmt::Write as _;

use super::{Outcome, RunStats, Study};

/// |a − r|/|r| (see the module docs); `None` when either is missing.
pub fn relative(a: Option<f64>, r: Option<f64>) -> Option<f64> {
    let (a, r) = (a?, r?);
    Some(if r == 0.0 { if a == 0.0 { 0.0 } else { f64::INFINITY } } else { (a - r).abs() / r.abs() })
}

/// Milliseconds of wall time per step.
pub fn ms_per_step(s: &RunStats) -> f64 {
    1e3 * s.wall_s / s.steps.max(1) as f64
}

/// The errors of one run, per observable, and the largest of each kind.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Errors {
    /// Against the reference run (`None`: the run, the reference or the value is missing).
    pub reference: Vec<Option<f64>>,
    /// Against the experiment (`None`: not measured, or the value is missing).
    pub experiment: Vec<Option<f64>>,
    pub max_reference: Option<f64>,
    pub max_experiment: Option<f64>,
}

/// The errors of run `k` of `study`.
pub fn errors(study: &Study, k: usize) -> Errors {
    let n = study.observables.len();
    let values = |k: usize| match &study.runs[k].outcome {
        Outcome::Done(s) => s.values.clone(),
        _ => vec![None; n],
    };
    let own = values(k);
    let reference = values(study.reference);
    let reference: Vec<Option<f64>> = (0..n).map(|i| relative(own[i], reference[i])).collect();
    let experiment: Vec<Option<f64>> = (0..n).map(|i| relative(own[i], study.measured(i).map(|m| m.value))).collect();
    let max = |v: &[Option<f64>]| v.iter().flatten().copied().reduce(f64::max);
    Errors { max_reference: max(&reference), max_experiment: max(&experiment), reference, experiment }
}

/// A CSV field: numbers in Rust's shortest round-trip form, missing as empty, text quoted where RFC 4180 needs it.
pub fn num(x: Option<f64>) -> String {
    x.map_or(String::new(), |v| format!("{v}"))
}

pub fn text(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) { format!("\"{}\"", s.replace('"', "\"\"")) } else { s.to_string() }
}

/// `study.csv`: one row per run that has run (pending runs are left out). Columns: `level` (the factor as given),
/// `factor`, `dx_m`, `precision`, `backend`, `device`, `status` (`ok` or `failed`), `particles`, `steps`,
/// `wall_s`, `ms_per_step`; per observable its value, `<name>_err_ref` and, where `[experiment]` measures it,
/// `<name>_err_exp`; `max_err_ref`, `max_err_exp` (with an experiment) and `message` (a failed run's error).
pub fn csv(study: &Study) -> String {
    let with_exp = !study.experiment.is_empty();
    let mut head: Vec<String> = [
        "level",
        "factor",
        "dx_m",
        "precision",
        "backend",
        "device",
        "status",
        "particles",
        "steps",
        "wall_s",
        "ms_per_step",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    for (i, o) in study.observables.iter().enumerate() {
        head.push(o.name.clone());
        head.push(format!("{}_err_ref", o.name));
        if study.measured(i).is_some() {
            head.push(format!("{}_err_exp", o.name));
        }
    }
    head.push("max_err_ref".into());
    if with_exp {
        head.push("max_err_exp".into());
    }
    head.push("message".into());
    let mut out = head.iter().map(|h| text(h)).collect::<Vec<_>>().join(",");
    out.push('\n');
    for (k, run) in study.runs.iter().enumerate() {
        let (status, stats, message) = match &run.outcome {
            Outcome::Pending => continue,
            Outcome::Done(s) => ("ok", Some(s), ""),
            Outcome::Failed(m) => ("failed", None, m.as_str()),
        };
        let e = errors(study, k);
        let mut row = vec![
            text(&run.level.to_string()),
            format!("{}", run.level.factor()),
            format!("{}", run.dx),
            run.precision.as_str().to_string(),
            text(&run.backend),
            text(&run.device),
            status.to_string(),
            stats.map_or(String::new(), |s| s.particles.to_string()),
            stats.map_or(String::new(), |s| s.steps.to_string()),
            num(stats.map(|s| s.wall_s)),
            num(stats.map(ms_per_step)),
        ];
        for i in 0..study.observables.len() {
            row.push(num(stats.and_then(|s| s.values[i])));
            row.push(num(e.reference[i]));
            if study.measured(i).is_some() {
                row.push(num(e.experiment[i]));
            }
        }
        row.push(num(e.max_reference));
        if with_exp {
            row.push(num(e.max_experiment));
        }
        row.push(text(message));
        out.push_str(&row.join(","));
        out.push('\n');
    }
    out
}

/// `x` to `digits` significant digits: plain decimals for magnitudes in [10⁻³, 10⁵), exponent form otherwise.
pub fn sig(x: f64, digits: usize) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    if x == 0.0 {
        return "0".into();
    }
    let mag = x.abs().log10().floor() as i32;
    if (-3..5).contains(&mag) {
        let decimals = (digits as i32 - 1 - mag).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        format!("{x:.*e}", digits.saturating_sub(1))
    }
}

/// A relative error in per cent, two significant digits.
fn pct(e: f64) -> String {
    format!("{} %", sig(100.0 * e, 2))
}

/// `study.md`: a caption naming the scene, the reference and the devices, the table (one row per run that has run,
/// then the experiment's row) and the notes (failed runs, warnings). A cell holds the observable's value, its error
/// against the reference run and, where measured, against the experiment; the reference run's cells say "ref".
pub fn markdown(study: &Study) -> String {
    let mut s = String::new();
    let r = &study.runs[study.reference];
    let mut devices: Vec<String> = Vec::new();
    for run in &study.runs {
        let d = format!("{} ({})", run.device, run.backend);
        if !devices.contains(&d) {
            devices.push(d);
        }
    }
    let _ = write!(
        s,
        "Study of `{}` (`{}`) on {}. Errors are relative, |a − r|/|r|: \"ref\" against the finest {} run \
         (Δx = {} m, {}){}. Wall time is the time loop's.\n\n",
        study.scene,
        study.file,
        devices.join(", "),
        r.precision.as_str(),
        sig(r.dx, 4),
        r.backend,
        if study.experiment.is_empty() { "" } else { ", \"exp\" against the experiment (`[experiment]`)" }
    );
    let mut head = vec!["Δx [m]", "precision", "backend", "particles", "steps", "wall [s]", "ms/step"]
        .into_iter()
        .map(String::from)
        .collect::<Vec<_>>();
    for o in &study.observables {
        head.push(format!("{} [{}]", o.name, o.unit));
    }
    let _ = writeln!(s, "| {} |", head.join(" | "));
    let _ = writeln!(s, "|{}", "---|".repeat(head.len()));
    let mut failed = Vec::new();
    for (k, run) in study.runs.iter().enumerate() {
        let lead = [sig(run.dx, 4), run.precision.as_str().into(), run.backend.clone()];
        let mut cells: Vec<String> = lead.to_vec();
        match &run.outcome {
            Outcome::Pending => continue,
            Outcome::Failed(m) => {
                failed.push(format!("Δx = {} m, {}, {}: {m}", sig(run.dx, 4), run.precision.as_str(), run.backend));
                cells.push("failed".into());
                cells.extend(std::iter::repeat_n("–".to_string(), 3 + study.observables.len()));
            }
            Outcome::Done(st) => {
                let e = errors(study, k);
                cells.extend([
                    st.particles.to_string(),
                    st.steps.to_string(),
                    sig(st.wall_s, 3),
                    sig(ms_per_step(st), 3),
                ]);
                for i in 0..study.observables.len() {
                    let Some(v) = st.values[i] else {
                        cells.push("n/a".into());
                        continue;
                    };
                    let mut notes = Vec::new();
                    if k == study.reference {
                        notes.push("ref".to_string());
                    } else if let Some(err) = e.reference[i] {
                        notes.push(format!("ref {}", pct(err)));
                    }
                    if let Some(err) = e.experiment[i] {
                        notes.push(format!("exp {}", pct(err)));
                    }
                    let note = if notes.is_empty() { String::new() } else { format!(" ({})", notes.join(", ")) };
                    cells.push(format!("{}{note}", sig(v, 4)));
                }
            }
        }
        let _ = writeln!(s, "| {} |", cells.join(" | "));
    }
    if !study.experiment.is_empty() {
        let mut cells = vec!["experiment".to_string()];
        cells.extend(std::iter::repeat_n(String::new(), 6));
        for i in 0..study.observables.len() {
            cells.push(study.measured(i).map_or(String::new(), |m| match m.uncertainty {
                Some(u) => format!("{} ± {}", sig(m.value, 4), sig(u, 2)),
                None => sig(m.value, 4),
            }));
        }
        let _ = writeln!(s, "| {} |", cells.join(" | "));
    }
    if !failed.is_empty() || !study.warnings.is_empty() {
        s.push('\n');
    }
    for f in failed {
        let _ = writeln!(s, "- failed: {f}");
    }
    for w in &study.warnings {
        let _ = writeln!(s, "- warning: {w}");
    }
    s
}
