//! What an identification writes after every batch: `history.csv`, `report.md` (the best set, and per experiment
//! predicted against measured forces and chip with their errors), `convergence.png` (the best objective against
//! evaluations), `forces.png` (predicted and measured F_c and F_f of every experiment at the best set) and the best
//! set as a library material file, `materials/<material>-<identification>.toml`: the model's material with the
//! identified `material.flow_stress.*` values (load it with `swarf material NAME --library <out>/materials`, or
//! from scenes with `SWARF_MATERIALS=<out>/materials`).

use std::path::{Path, PathBuf};

use super::file::Spec;
use super::history::{self, Row};
use super::material_key;
use super::scenes;
use crate::plot::{Chart, Series, draw, draw_panels};
use crate::{Error, Result};

pub const REPORT: &str = "report.md";
pub const CONVERGENCE: &str = "convergence.png";
pub const FORCES: &str = "forces.png";

/// The evaluation of smallest finite objective (the first of equals).
pub fn best(rows: &[Row]) -> Option<&Row> {
    rows.iter().filter(|r| r.objective.is_finite()).fold(None, |b: Option<&Row>, r| match b {
        Some(b) if b.objective <= r.objective => Some(b),
        _ => Some(r),
    })
}

/// Writes every output; returns the material file and the warnings (plots or material not written).
pub fn write_all(spec: &Spec, header: &[String], rows: &[Row], dir: &Path) -> Result<(Option<PathBuf>, Vec<String>)> {
    let io = |p: &Path, e: std::io::Error| Error::Output(format!("{}: {e}", p.display()));
    let path = dir.join(history::FILE);
    crate::output::write_atomic(&path, history::csv(header, rows).as_bytes()).map_err(|e| io(&path, e))?;
    let path = dir.join(REPORT);
    crate::output::write_atomic(&path, markdown(spec, rows).as_bytes()).map_err(|e| io(&path, e))?;
    let mut warnings = Vec::new();
    if let Err(e) = convergence(rows, &dir.join(CONVERGENCE)) {
        warnings.push(format!("{} not drawn: {e}", dir.join(CONVERGENCE).display()));
    }
    if let Err(e) = forces(spec, rows, &dir.join(FORCES)) {
        warnings.push(format!("{} not drawn: {e}", dir.join(FORCES).display()));
    }
    let material = match material(spec, rows, dir) {
        Ok(m) => m,
        Err(e) => {
            warnings.push(format!("best material not written: {e}"));
            None
        }
    };
    Ok((material, warnings))
}

/// Relative error in percent, or "n/a".
fn err_pct(sim: Option<f64>, exp: Option<f64>) -> String {
    match (sim, exp) {
        (Some(s), Some(e)) if e != 0.0 => format!("{:+.1} %", 100.0 * (s - e) / e),
        _ => "n/a".into(),
    }
}

fn cell(x: Option<f64>) -> String {
    x.map_or("n/a".into(), |v| format!("{v:.4}"))
}

/// `report.md`.
pub fn markdown(spec: &Spec, rows: &[Row]) -> String {
    let o = &spec.optimizer;
    let mut s = format!(
        "# Identification {}\n\nFile `{}`; optimiser {} (seed {}), budget {} evaluations in batches of {}; {} experiments; \
         objective: {} over experiments of w_c ΔF_c² + w_f ΔF_f² (+ w_h Δh²) (klippel-constitutive.md §6.2, Eqs. 9.14–9.17; \
         w_c = {}, w_f = {}){}.\n\n{} evaluations done, {} failed.\n\n",
        spec.name,
        spec.file.display(),
        super::file::method_name(&o.method),
        o.seed,
        o.budget,
        o.batch,
        spec.experiments.len(),
        if spec.objective.mean { "the mean" } else { "the sum (Eq. 9.17)" },
        spec.objective.fc_weight,
        spec.objective.ff_weight,
        match spec.objective.replicas {
            1 => String::new(),
            k =>
                format!("; each experiment's forces and chip the mean of {k} runs at CFL numbers 1e-3 apart (replicas)"),
        },
        rows.len(),
        rows.iter().filter(|r| !r.objective.is_finite()).count(),
    );
    let Some(b) = best(rows) else {
        return s + "No finite objective yet.\n";
    };
    s += &format!(
        "Best: evaluation {} (batch {}), objective {:.6}.\n\n| parameter | lower | upper | best |\n|---|---|---|---|\n",
        b.evaluation, b.batch, b.objective
    );
    for (p, x) in spec.parameters.iter().zip(&b.params) {
        s += &format!("| `{}` | {} | {} | {x:.6e} |\n", p.key, p.lower, p.upper);
    }
    s += "\n| experiment | F_c measured | F_c predicted | error | F_f measured | F_f predicted | error | chip measured [µm] | chip predicted | error |\n|---|---|---|---|---|---|---|---|---|---|\n";
    for (e, sim) in spec.experiments.iter().zip(&b.sims) {
        let m = &e.measured;
        s += &format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            e.name,
            cell(m.fc),
            cell(sim.fc),
            err_pct(sim.fc, m.fc),
            cell(m.ff),
            cell(sim.ff),
            err_pct(sim.ff, m.ff),
            cell(m.chip),
            cell(sim.chip),
            err_pct(sim.chip, m.chip)
        );
    }
    s + "\nForces in N/mm of width; errors (predicted − measured)/measured.\n"
}

/// `convergence.png`: the best objective so far against evaluations.
fn convergence(rows: &[Row], path: &Path) -> std::result::Result<(), String> {
    let x: Vec<f64> = rows.iter().map(|r| (r.evaluation + 1) as f64).collect();
    let mut so_far = f64::INFINITY;
    let y: Vec<f64> = rows
        .iter()
        .map(|r| {
            if r.objective.is_finite() {
                so_far = so_far.min(r.objective);
            }
            if so_far.is_finite() { so_far } else { f64::NAN }
        })
        .collect();
    let chart = Chart {
        title: "convergence",
        x_label: "evaluations",
        y_label: "best objective ΔF² [N²/mm²]",
        series: vec![Series { label: "best so far", x: &x, y: &y }],
    };
    draw(path, &chart, (900, 500)).map(|_| ()).map_err(|e| e.to_string())
}

/// `forces.png`: per experiment (x: its number in the file), measured and predicted F_c and F_f at the best set.
fn forces(spec: &Spec, rows: &[Row], path: &Path) -> std::result::Result<(), String> {
    let b = best(rows).ok_or("no finite objective yet")?;
    let x: Vec<f64> = (1..=spec.experiments.len()).map(|i| i as f64).collect();
    let nan = f64::NAN;
    let col = |f: &dyn Fn(usize) -> Option<f64>| {
        (0..spec.experiments.len()).map(|i| f(i).unwrap_or(nan)).collect::<Vec<f64>>()
    };
    let (fc_m, fc_p) = (col(&|i| spec.experiments[i].measured.fc), col(&|i| b.sims[i].fc));
    let (ff_m, ff_p) = (col(&|i| spec.experiments[i].measured.ff), col(&|i| b.sims[i].ff));
    let names: Vec<&str> = spec.experiments.iter().map(|e| e.name.as_str()).collect();
    let x_label = format!("experiment ({})", names.join(", "));
    let panel = |title, m, p| Chart {
        title,
        x_label: &x_label,
        y_label: "force [N/mm]",
        series: vec![Series { label: "measured", x: &x, y: m }, Series { label: "predicted (best set)", x: &x, y: p }],
    };
    let charts = [panel("F_c", &fc_m, &fc_p), panel("F_f", &ff_m, &ff_p)];
    draw_panels(path, &charts, (900, 800)).map(|_| ()).map_err(|e| e.to_string())
}

/// The best set as a library material file: the first experiment's scene material with the identified
/// `material.flow_stress.*` values, named `<material>-<identification>`; None for a scene without a library
/// material.
fn material(spec: &Spec, rows: &[Row], dir: &Path) -> std::result::Result<Option<PathBuf>, String> {
    let Some(b) = best(rows) else { return Ok(None) };
    let (scene, _) = scenes::scene_for(spec, &spec.experiments[0], &b.params, None)?;
    let Some(m) = scene.material.library.as_ref() else { return Ok(None) };
    let name: String = format!("{}-{}", m.name, spec.name)
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-') { c } else { '_' })
        .collect();
    let values: Vec<String> =
        spec.parameters.iter().zip(&b.params).map(|(p, x)| format!("{} = {x:?}", p.key)).collect();
    let description = format!(
        "{} identified by swarf identify {} (evaluation {}, objective {:.6}): {}",
        m.name,
        spec.file.display(),
        b.evaluation,
        b.objective,
        values.join(", ")
    );
    let edits: Vec<(&str, f64)> = spec
        .parameters
        .iter()
        .zip(&b.params)
        .filter_map(|(p, x)| material_key::flow_key(&p.key).map(|k| (k, *x)))
        .collect();
    let out = material_key::with_values(m, &edits, Some((&name, &description)))?;
    let folder = dir.join(crate::material::search::FOLDER);
    std::fs::create_dir_all(&folder).map_err(|e| format!("{}: {e}", folder.display()))?;
    let path = folder.join(format!("{name}.toml"));
    crate::output::write_atomic(&path, out.text.as_bytes()).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(Some(path))
}
