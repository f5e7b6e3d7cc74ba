//! The sweep's tables: `sweep.csv` (every number, for scripts) and `sweep.md` (a Markdown table). The cell
//! formats are the study's ([`crate::study::table`]).

use std::fmt::Write as _;

pub use crate::study::table::sig;
use crate::study::table::{num, text};

use super::{Outcome, Sweep};
use crate::scene::observe::Source;

/// `sweep.csv`: one row per run that has run (pending runs are left out). Columns: `run` (the run folder's
/// name), one per swept key (the value as given), `status` (`ok` or `failed`), one per summary value
/// ([`Sweep::columns`]: empty where not measured), `message` (a failed run's error).
pub fn csv(sweep: &Sweep) -> String {
    let mut head = vec!["run".to_string()];
    head.extend(sweep.keys.iter().cloned());
    head.push("status".into());
    head.extend(sweep.columns.iter().map(|c| c.name.clone()));
    head.push("message".into());
    let mut out = head.iter().map(|h| text(h)).collect::<Vec<_>>().join(",");
    out.push('\n');
    for p in &sweep.points {
        let (status, values, message) = match &p.outcome {
            Outcome::Pending => continue,
            Outcome::Done(v) => ("ok", Some(v), ""),
            Outcome::Failed(m) => ("failed", None, m.as_str()),
        };
        let mut row = vec![text(&folder_name(&p.dir))];
        row.extend(p.values.iter().map(|v| text(v)));
        row.push(status.into());
        for i in 0..sweep.columns.len() {
            row.push(num(values.and_then(|v| v[i])));
        }
        row.push(text(message));
        out.push_str(&row.join(","));
        out.push('\n');
    }
    out
}

/// `sweep.md`: a caption naming the scene, the table (one row per run that has run: the swept values, then the
/// summary values, whole numbers as they are and others to 4 significant digits) and the notes (failed runs, warnings).
pub fn markdown(sweep: &Sweep) -> String {
    let mut s = String::new();
    let _ = write!(
        s,
        "Sweep of `{}` (`{}`) over {}. Values are read from each run folder's summary.json{}.\n\n",
        sweep.scene,
        sweep.file,
        sweep.keys.iter().map(|k| format!("`{k}`")).collect::<Vec<_>>().join(" × "),
        if sweep.columns.iter().any(|c| matches!(c.source, Source::Energy(_))) { " and energy.csv" } else { "" }
    );
    let mut head: Vec<String> = sweep.keys.clone();
    head.extend(sweep.columns.iter().map(|c| format!("{} [{}]", c.name, c.unit)));
    let _ = writeln!(s, "| {} |", head.join(" | "));
    let _ = writeln!(s, "|{}", "---|".repeat(head.len()));
    let mut failed = Vec::new();
    for p in &sweep.points {
        let mut cells = p.values.clone();
        match &p.outcome {
            Outcome::Pending => continue,
            Outcome::Failed(m) => {
                failed.push(format!("{}: {m}", folder_name(&p.dir)));
                cells.push("failed".into());
                cells.extend(std::iter::repeat_n("–".to_string(), sweep.columns.len() - 1));
            }
            Outcome::Done(v) => cells.extend(v.iter().map(|x| x.map_or("n/a".into(), cell))),
        }
        let _ = writeln!(s, "| {} |", cells.join(" | "));
    }
    if !failed.is_empty() || !sweep.warnings.is_empty() {
        s.push('\n');
    }
    for f in failed {
        let _ = writeln!(s, "- failed: {f}");
    }
    for w in &sweep.warnings {
        let _ = writeln!(s, "- warning: {w}");
    }
    s
}

/// A Markdown cell: whole numbers (particles, steps) as they are, others to 4 significant digits.
pub fn cell(x: f64) -> String {
    if x.fract() == 0.0 && x.abs() < 1e15 { format!("{x}") } else { sig(x, 4) }
}

fn folder_name(dir: &std::path::Path) -> String {
    dir.file_name().map_or_else(|| dir.display().to_string(), |n| n.to_string_lossy().into_owned())
}
