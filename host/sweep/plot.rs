//! `sweep-<key>.png`: every summary value against one swept key, a panel per value (drawn with
//! [`crate::plot::draw_panels`]), one line per combination of the other keys' values. A key whose values are
//! not all numbers (a material name) is drawn against the values' positions 0, 1, ..., named in the x label. A
//! value that is the same in every finished run (the particle count of a sweep over time steps) has no panel.

use std::path::Path;

use super::{Outcome, Sweep};
use crate::plot::{Chart, Series, draw_panels};

/// Width and the height of one panel, in pixels.
const SIZE: (u32, u32) = (1000, 320);

/// The plot file of swept key `key`: its name made a plain file name.
pub fn file_name(key: &str) -> String {
    let plain: String =
        key.chars().map(|c| if c.is_ascii_alphanumeric() || matches!(c, '.' | '-') { c } else { '_' }).collect();
    format!("sweep-{plain}.png")
}

/// Draws the plot of every key into `dir`; returns a warning per plot not drawn (no finished run yet, or
/// nothing finite to draw).
pub fn draw_all(sweep: &Sweep, dir: &Path) -> Vec<String> {
    (0..sweep.keys.len())
        .filter_map(|k| {
            let path = dir.join(file_name(&sweep.keys[k]));
            draw_key(sweep, k, &path).err().map(|why| format!("{} not drawn: {why}", path.display()))
        })
        .collect()
}

/// One series: its label and points (x, one y per column).
struct Line {
    label: String,
    x: Vec<f64>,
    y: Vec<Vec<f64>>,
}

fn draw_key(sweep: &Sweep, k: usize, path: &Path) -> Result<(), String> {
    let key = &sweep.keys[k];
    let values: Vec<&String> = {
        let mut v: Vec<&String> = Vec::new();
        for p in &sweep.points {
            if !v.contains(&&p.values[k]) {
                v.push(&p.values[k]);
            }
        }
        v
    };
    let numeric: Option<Vec<f64>> =
        values.iter().map(|v| v.trim().parse::<f64>().ok().filter(|x| x.is_finite())).collect();
    let x_of = |v: &String| match &numeric {
        Some(xs) => xs[values.iter().position(|w| *w == v).unwrap_or(0)],
        None => values.iter().position(|w| *w == v).unwrap_or(0) as f64,
    };
    let mut lines: Vec<Line> = Vec::new();
    for p in &sweep.points {
        let Outcome::Done(v) = &p.outcome else { continue };
        let others: Vec<String> = sweep
            .keys
            .iter()
            .zip(&p.values)
            .enumerate()
            .filter(|(j, _)| *j != k)
            .map(|(_, (key, value))| format!("{key}={value}"))
            .collect();
        let label = if others.is_empty() { "runs".to_string() } else { others.join(", ") };
        let at = match lines.iter().position(|l| l.label == label) {
            Some(i) => i,
            None => {
                lines.push(Line { label, x: Vec::new(), y: vec![Vec::new(); sweep.columns.len()] });
                lines.len() - 1
            }
        };
        lines[at].x.push(x_of(&p.values[k]));
        for (c, y) in lines[at].y.iter_mut().enumerate() {
            y.push(v[c].unwrap_or(f64::NAN));
        }
    }
    if lines.is_empty() {
        return Err("no finished run yet".into());
    }
    for l in &mut lines {
        let mut order: Vec<usize> = (0..l.x.len()).collect();
        order.sort_by(|&a, &b| l.x[a].total_cmp(&l.x[b]));
        l.x = order.iter().map(|&i| l.x[i]).collect();
        l.y = l.y.iter().map(|y| order.iter().map(|&i| y[i]).collect()).collect();
    }
    let x_label = match &numeric {
        Some(_) => key.clone(),
        None => {
            let named: Vec<String> = values.iter().enumerate().map(|(i, v)| format!("{i}: {v}")).collect();
            format!("{key} ({})", named.join(", "))
        }
    };
    let titles: Vec<String> = sweep.columns.iter().map(|c| format!("{} against {key}", c.name)).collect();
    let y_labels: Vec<String> = sweep.columns.iter().map(|c| format!("{} ({})", c.name, c.unit)).collect();
    // A value the same in every run (or in none) says nothing against the key: it is in the table only.
    let varies = |c: usize| {
        let mut finite = lines.iter().flat_map(|l| l.y[c].iter().copied()).filter(|y| y.is_finite());
        finite.next().is_some_and(|first| finite.any(|y| y != first))
    };
    let charts: Vec<Chart> = (0..sweep.columns.len())
        .filter(|&c| varies(c))
        .map(|c| Chart {
            title: &titles[c],
            x_label: &x_label,
            y_label: &y_labels[c],
            series: lines.iter().map(|l| Series { label: &l.label, x: &l.x, y: &l.y[c] }).collect(),
        })
        .collect();
    if charts.is_empty() {
        return Err("no value differs between the finished runs".into());
    }
    let size = (SIZE.0, SIZE.1 * charts.len() as u32);
    draw_panels(path, &charts, size).map(|_| ()).map_err(|e| e.to_string())
}
