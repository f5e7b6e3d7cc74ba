//! `swarf material`: list the library, print a material, evaluate its flow stress, draw flow curves.

use super::{Library, Material};
use crate::plot::{Chart, Series, draw};
use std::fmt::Write;
use std::path::Path;

/// One line per material: name, flow-stress model, source.
pub fn list(lib: &Library) -> String {
    let mut s = String::new();
    for m in lib.iter() {
        let model = m.flow_stress.map_or("elastic/thermal only", |f| f.name());
        let _ = writeln!(s, "{:<34} {:<20} {}", m.name, model, m.source);
    }
    s
}

/// Every parameter of a material with units, and σ_y (MPa) at the requested (ε̄, ε̄̇ [1/s], T [K]) points.
pub fn describe(m: &Material, at: &[[f64; 3]]) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "{} — {}\nsource: {}\nfile: {}", m.name, m.description, m.source, m.file.display());
    if let Some(e) = m.elastic {
        let _ = writeln!(
            s,
            "elastic: density {} kg/m^3, Young's modulus {:.4e} Pa, Poisson's ratio {}",
            e.density, e.youngs_modulus, e.poisson_ratio
        );
    }
    if let Some(t) = m.thermal {
        let _ = writeln!(s, "thermal: {t:?}");
    }
    match m.flow_stress {
        Some(f) => {
            let _ = writeln!(s, "flow stress: {f:?}");
        }
        None => {
            let _ = writeln!(s, "flow stress: none (elastic or thermal-only material)");
        }
    }
    if !at.is_empty() {
        let _ = writeln!(s, "| strain | rate 1/s | T K | sigma_y MPa |\n|---|---|---|---|");
        for p in at {
            let _ = writeln!(s, "| {} | {} | {} | {:.2} |", p[0], p[1], p[2], m.sigma_y(p[0], p[1], p[2]) / 1e6);
        }
    }
    s
}

/// Flow curves σ_y(ε̄) for ε̄ ∈ [0, 2] at each (rate, temperature) of `at` (or 1/s, 1e3/s, 1e5/s at the
/// reference temperature when `at` is empty), drawn to a PNG.
pub fn plot(m: &Material, at: &[[f64; 3]], path: &Path) -> Result<(), String> {
    let t_ref = m.thermal.and_then(|t| t.reference_temperature).unwrap_or(300.0);
    let states: Vec<(f64, f64)> = if at.is_empty() {
        vec![(1.0, t_ref), (1e3, t_ref), (1e5, t_ref)]
    } else {
        at.iter().map(|p| (p[1], p[2])).collect()
    };
    let eps: Vec<f64> = (0..=200).map(|i| i as f64 * 0.01).collect();
    let curves: Vec<(String, Vec<f64>)> = states
        .iter()
        .map(|&(rate, temp)| {
            (format!("{rate:e}/s, {temp} K"), eps.iter().map(|&e| m.sigma_y(e, rate, temp) / 1e6).collect())
        })
        .collect();
    let title = format!("{} flow stress", m.name);
    let chart = Chart {
        title: &title,
        x_label: "equivalent plastic strain",
        y_label: "flow stress (MPa)",
        series: curves.iter().map(|(l, y)| Series { label: l, x: &eps, y }).collect(),
    };
    draw(path, &chart, (1000, 700)).map(|_| ()).map_err(|e| e.to_string())
}
