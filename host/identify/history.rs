//! `history.csv`: one row per evaluated parameter set, in order: `evaluation`, `batch`, the parameters, per
//! experiment `<name>:fc_n_per_mm`, `<name>:ff_n_per_mm`, `<name>:chip_thickness_um` (NaN where not measured),
//! `objective` (NaN for a failed evaluation) and `status` (`ok`, or the first failure). Numbers are written in
//! Rust's shortest round-trip form, so a resumed identification reads back exactly the values it told the
//! optimiser (docs/identification.md "Determinism and resume").

use std::path::Path;

use super::objective::Simulated;
use crate::{Error, Result};

pub const FILE: &str = "history.csv";

/// One evaluation.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub evaluation: usize,
    pub batch: usize,
    pub params: Vec<f64>,
    /// One per experiment, in the file's order.
    pub sims: Vec<Simulated>,
    pub objective: f64,
    pub status: String,
}

const QUANTITIES: [&str; 3] = ["fc_n_per_mm", "ff_n_per_mm", "chip_thickness_um"];

/// The header for `keys` (parameters) and `experiments` (names).
pub fn header(keys: &[String], experiments: &[String]) -> Vec<String> {
    let mut h = vec!["evaluation".to_string(), "batch".to_string()];
    h.extend(keys.iter().cloned());
    for e in experiments {
        h.extend(QUANTITIES.iter().map(|q| format!("{e}:{q}")));
    }
    h.extend(["objective".to_string(), "status".to_string()]);
    h
}

/// A status made one CSV field: no commas, quotes or line breaks.
pub fn field(s: &str) -> String {
    s.chars().map(|c| if matches!(c, ',' | '"' | '\n' | '\r') { ' ' } else { c }).collect()
}

/// The whole file.
pub fn csv(header: &[String], rows: &[Row]) -> String {
    let mut out = header.join(",") + "\n";
    let num = |x: Option<f64>| format!("{:?}", x.unwrap_or(f64::NAN));
    for r in rows {
        let mut cells = vec![r.evaluation.to_string(), r.batch.to_string()];
        cells.extend(r.params.iter().map(|p| format!("{p:?}")));
        for s in &r.sims {
            cells.extend([num(s.fc), num(s.ff), num(s.chip)]);
        }
        cells.push(format!("{:?}", r.objective));
        cells.push(field(&r.status));
        out += &(cells.join(",") + "\n");
    }
    out
}

/// Reads a history written with `header` for `np` parameters (refused, naming the file and line, when it differs).
pub fn read(path: &Path, header: &[String], np: usize) -> Result<Vec<Row>> {
    let err = |line: usize, m: &str| Error::Scene(format!("{}: line {line}: {m}", path.display()));
    let text = std::fs::read_to_string(path).map_err(|e| Error::Scene(format!("{}: {e}", path.display())))?;
    let mut lines = text.lines();
    if lines.next() != Some(header.join(",").as_str()) {
        return Err(err(1, &format!("expected the header {}", header.join(","))));
    }
    let n_exp = (header.len() - 4 - np) / 3;
    let mut rows = Vec::new();
    for (i, line) in lines.enumerate() {
        let c: Vec<&str> = line.split(',').collect();
        let bad = || err(i + 2, &format!("expected {} fields of numbers as the header names", header.len()));
        if c.len() != header.len() {
            return Err(bad());
        }
        let f = |k: usize| c[k].parse::<f64>().map_err(|_| bad());
        let opt = |k: usize| f(k).map(|x| Some(x).filter(|x| !x.is_nan()));
        let sims = (0..n_exp)
            .map(|e| {
                let at = 2 + np + 3 * e;
                Ok(Simulated { fc: opt(at)?, ff: opt(at + 1)?, chip: opt(at + 2)? })
            })
            .collect::<Result<Vec<_>>>()?;
        rows.push(Row {
            evaluation: c[0].parse().map_err(|_| bad())?,
            batch: c[1].parse().map_err(|_| bad())?,
            params: (0..np).map(|k| f(2 + k)).collect::<Result<_>>()?,
            sims,
            objective: f(c.len() - 2)?,
            status: c[c.len() - 1].to_string(),
        });
    }
    Ok(rows)
}
