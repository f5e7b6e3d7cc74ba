//! Klippel's orthogonal-cutting database (cases/data/cutting-experiments.csv, thesis App. 11.3; klippel-constitutive.md
//! §5.5) and the model scene scaled to one of its conditions.
//!
//! The scaling is Klippel's identification model (klippel-constitutive.md §4.9): the height is fixed to the feed,
//! always 10 particles per uncut chip thickness, so every length of the model scales with the feed f while the
//! particle counts stay (188 × 30 for V0060). [`scale_overrides`] gives the scene overrides, with s = f / f_model:
//!
//! - `discretisation.dx` = s Δx (Δx = f/10 for the V0060 and V0300 models);
//! - every body's box (`body.N.min`, `body.N.max`) and every boundary's region (`boundary.N.min`, `.max`) × s;
//! - the tool's `length`, `height` and `chip_station` × s, `depth_of_cut` = f, `edge_radius` = the measured
//!   r_n, `velocity` = v_c along the model's direction, and `position` such that the edge's front keeps the
//!   model's clearance × s: x = −(r_n + s·g), g = −(x_model + r_model) (3 µm for V0060);
//! - the cut length × s (10 f for the models): `time.end` = s · end_model · |v_model| / v_c, and `output.every`
//!   in proportion, so every run writes as many samples.
//!
//! Nothing else is scaled (stabilisation, contact stiffness, CFL are dimensionless; thermal tool widths are not
//! used by the models). Rake 0° and clearance 7° hold for every test of the file (§5.2), so they are the model's.

use std::path::Path;

use crate::scene::{Scene, Shape};
use crate::{Error, Result};

/// One row of the data file.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub test: String,
    pub material: String,
    pub vc_m_per_min: f64,
    pub feed_mm: f64,
    pub fc: f64,
    pub fc_sd: f64,
    pub ff: f64,
    pub ff_sd: f64,
    pub edge_radius_um: f64,
    pub status: String,
}

/// The statuses that may be fitted (data/README.md: `short` is usable where its deviations are small).
pub const FITTABLE: &[&str] = &["ok", "short"];

const HEADER: &str =
    "test,material,vc_m_per_min,feed_mm,fc_n_per_mm,fc_sd,ff_n_per_mm,ff_sd,edge_radius_um,edge_radius_sd,status";

/// Reads the data file (its header must be the one above).
pub fn read(path: &Path) -> Result<Vec<Row>> {
    let err = |m: String| Error::Scene(format!("{}: {m}", path.display()));
    let text = std::fs::read_to_string(path).map_err(|e| err(e.to_string()))?;
    let mut lines = text.lines();
    if lines.next().map(str::trim) != Some(HEADER) {
        return Err(err(format!("line 1: expected the header {HEADER}")));
    }
    let mut rows = Vec::new();
    for (i, line) in lines.enumerate().filter(|(_, l)| !l.trim().is_empty()) {
        let c: Vec<&str> = line.split(',').map(str::trim).collect();
        let num = |k: usize| c.get(k).and_then(|s| s.parse::<f64>().ok()).filter(|x| x.is_finite());
        let bad = || err(format!("line {}: expected 11 comma-separated fields as in the header", i + 2));
        if c.len() != 11 {
            return Err(bad());
        }
        rows.push(Row {
            test: c[0].to_string(),
            material: c[1].to_string(),
            vc_m_per_min: num(2).ok_or_else(bad)?,
            feed_mm: num(3).ok_or_else(bad)?,
            fc: num(4).ok_or_else(bad)?,
            fc_sd: num(5).ok_or_else(bad)?,
            ff: num(6).ok_or_else(bad)?,
            ff_sd: num(7).ok_or_else(bad)?,
            edge_radius_um: num(8).ok_or_else(bad)?,
            status: c[10].to_string(),
        });
    }
    Ok(rows)
}

/// The row of test `id` if it may be fitted; otherwise what is expected instead (unknown id, or its status).
pub fn usable<'a>(rows: &'a [Row], id: &str) -> std::result::Result<&'a Row, String> {
    let row = rows.iter().find(|r| r.test == id).ok_or_else(|| "a test id of the data file".to_string())?;
    if !FITTABLE.contains(&row.status.as_str()) {
        return Err(format!("a test of status ok or short (test {id} has status \"{}\", not for fitting)", row.status));
    }
    if !(row.vc_m_per_min > 0.0 && row.feed_mm > 0.0 && row.edge_radius_um > 0.0) {
        return Err(format!("a test with positive v_c, feed and edge radius (test {id} has not)"));
    }
    Ok(row)
}

/// A cutting condition: speed, feed (uncut chip thickness), measured edge radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Condition {
    pub vc_m_per_min: f64,
    pub feed_mm: f64,
    pub edge_radius_um: f64,
}

fn vec2(v: [f64; 2]) -> String {
    format!("[{:?}, {:?}]", v[0], v[1])
}

/// The scene overrides that turn the feed-scaled model `model` into `cond` (module docs). Refused (the reason,
/// as what is expected) for a model without a tool, a depth of cut or a moving tool, or with a body that is not a
/// rectangle.
pub fn scale_overrides(model: &Scene, cond: &Condition) -> std::result::Result<Vec<String>, String> {
    let tool = model.tool.as_ref().ok_or("a cutting model scene with a [tool]")?;
    let f0 = tool.depth_of_cut.ok_or("a model whose tool has depth_of_cut (the model's feed)")?;
    let v0 = tool.velocity[0].hypot(tool.velocity[1]);
    if model.dim != 2 || !(f0 > 0.0 && v0 > 0.0) {
        return Err("a 2D model with a positive depth_of_cut and a moving tool".into());
    }
    let f = cond.feed_mm * 1e-3;
    let v = cond.vc_m_per_min / 60.0;
    let r = cond.edge_radius_um * 1e-6;
    let s = f / f0;
    let sc = |p: [f64; 2]| [p[0] * s, p[1] * s];
    let mut out = vec![format!("discretisation.dx={:?}", model.discretisation.dx * s)];
    for (k, b) in model.bodies.iter().enumerate() {
        let Shape::Rectangle { min, max } = b.shape else {
            return Err(format!("a model of rectangle bodies (body {k} is a {})", b.shape.kind()));
        };
        out.push(format!("body.{k}.min={}", vec2(sc(min))));
        out.push(format!("body.{k}.max={}", vec2(sc(max))));
    }
    for (k, b) in model.boundaries.iter().enumerate() {
        out.push(format!("boundary.{k}.min={}", vec2(sc([b.min[0], b.min[1]]))));
        out.push(format!("boundary.{k}.max={}", vec2(sc([b.max[0], b.max[1]]))));
    }
    let gap = -(tool.position[0] + tool.edge_radius);
    out.push(format!("tool.length={:?}", tool.length * s));
    out.push(format!("tool.height={:?}", tool.height * s));
    if let Some(station) = tool.chip_station {
        out.push(format!("tool.chip_station={:?}", station * s));
    }
    out.push(format!("tool.depth_of_cut={f:?}"));
    out.push(format!("tool.edge_radius={r:?}"));
    out.push(format!("tool.position=[{:?}]", -(r + s * gap)));
    out.push(format!("tool.velocity={}", vec2([tool.velocity[0] / v0 * v, tool.velocity[1] / v0 * v])));
    let end = model.time.end * s * v0 / v;
    out.push(format!("time.end={end:?}"));
    out.push(format!("output.every={:?}", model.output.every * end / model.time.end));
    Ok(out)
}
