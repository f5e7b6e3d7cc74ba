//! The identification file (`swarf identify <file.toml>`, docs/identification.md "The identification file"): the
//! experiments with their measured values, the parameters with their bounds, the objective's weights and the
//! optimiser. Every refusal names the file, the key and the value expected, before anything runs.

use std::path::{Path, PathBuf};

use super::data::{self, Condition};
use super::{BayesSettings, DeSettings, NelderMeadSettings, Noise, Strategy};
use crate::scene::Scene;
use crate::{Error, Result};

/// One experiment: a model scene, the overrides that make it this experiment, and what was measured.
#[derive(Clone, Debug, PartialEq)]
pub struct Experiment {
    /// A plain name (run folders and history columns use it).
    pub name: String,
    /// The model scene, as a path usable from the working directory.
    pub scene: PathBuf,
    /// The scene overrides of this experiment: the condition's scaling (for a `test` of the data file), then the
    /// experiment's own `set`.
    pub set: Vec<String>,
    pub measured: Measured,
    /// The data file's test id, where it came from there.
    pub test: Option<String>,
}

/// Measured values (forces per mm of width, N/mm; chip thickness, µm) and the chip term's weight (N²/mm² per µm²).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measured {
    pub fc: Option<f64>,
    pub ff: Option<f64>,
    pub chip: Option<f64>,
    pub chip_weight: f64,
}

/// One identified parameter: a scene key (or `material.flow_stress.<key>`) and its bounds, in the key's units.
#[derive(Clone, Debug, PartialEq)]
pub struct Parameter {
    pub key: String,
    pub lower: f64,
    pub upper: f64,
}

/// `[objective]`: the weights of Eqs. 9.14–9.16 (w_c = w_f = 1 in the thesis) and how experiments combine.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Objective {
    pub fc_weight: f64,
    pub ff_weight: f64,
    /// `combine = "mean"`: the mean over experiments instead of Eq. 9.17's sum.
    pub mean: bool,
    /// `replicas` (default 1): runs per experiment and parameter set, at CFL numbers a few 1e-3 apart
    /// (`scenes::replica_cfl`), whose mean forces and chip enter the objective. A cut is chaotic: one run's forces
    /// scatter by several per cent (docs/identification.md "Ck45 V0300 by DE"), and an optimiser over single runs
    /// selects the lucky ones.
    pub replicas: usize,
}

/// The optimiser and its settings (the existing settings structs).
#[derive(Clone, Debug, PartialEq)]
pub enum Method {
    De(DeSettings),
    /// Start and step in unit coordinates (converted from the file's parameter units).
    NelderMead(NelderMeadSettings),
    Bayes(BayesSettings),
}

#[derive(Clone, Debug, PartialEq)]
pub struct OptimizerSpec {
    pub method: Method,
    /// Evaluations of a parameter set (each runs every experiment).
    pub budget: usize,
    /// Parameter sets per batch.
    pub batch: usize,
    pub seed: u64,
}

/// A whole identification file.
#[derive(Clone, Debug, PartialEq)]
pub struct Spec {
    pub file: PathBuf,
    /// The file's text: a resumed identification must have the same.
    pub text: String,
    pub name: String,
    pub experiments: Vec<Experiment>,
    pub parameters: Vec<Parameter>,
    pub objective: Objective,
    pub optimizer: OptimizerSpec,
    /// Scene overrides applied to every run (after the experiment's): e.g. an early stop.
    pub set: Vec<String>,
    /// `[[holdout]]`: experiments that are not fitted, run at the best set when the optimisation ends to measure
    /// the prediction error (host/identify/holdout.rs); same keys as `[[experiment]]`.
    pub holdout: Vec<Experiment>,
    /// `compare`: library material names run on the holdout experiments beside the best set (e.g. Klippel's
    /// identified sets), so that their errors stand beside the identification's, all run in swarf.
    pub compare: Vec<String>,
}

/// Reads and checks the identification file `path` (the data file's rows and the model scenes are read too), its
/// `extends` chain resolved (host/identify/extends.rs).
pub fn read(path: &Path) -> Result<Spec> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::Scene(format!("{}: {e}", path.display())))?;
    let (root, extended) = super::extends::resolve(path, &text)?;
    // A variant's folder copy is the resolved table, whole: the folder alone says what it fitted.
    let text = if extended { toml::to_string(&root).map_err(|e| Error::Scene(e.to_string()))? } else { text };
    let f = Ctx { file: path.display().to_string(), dir: path.parent().unwrap_or(Path::new("")).to_path_buf() };
    f.keys(
        &root,
        "",
        &["name", "data", "set", "experiment", "parameter", "objective", "optimizer", "holdout", "compare"],
    )?;
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let name = f.string(&root, "", "name")?.unwrap_or(stem);
    let data = f.string(&root, "", "data")?.map(|p| f.dir.join(p));
    let set = f.strings(&root, "", "set")?;
    let holdout = experiments(&f, &root, data.as_deref(), "holdout")?;
    let experiments = experiments(&f, &root, data.as_deref(), "experiment")?;
    if let Some(h) = holdout.iter().find(|h| experiments.iter().any(|e| e.name == h.name)) {
        return Err(f.bad(
            "holdout",
            format!("\"{}\"", h.name),
            "experiments that are not also fitted ([[experiment]])",
        ));
    }
    let compare = f.strings_plain(&root, "compare")?;
    if !compare.is_empty() && holdout.is_empty() {
        return Err(f.missing("holdout", "[[holdout]] experiments for the compare materials to run on"));
    }
    let parameters = parameters(&f, &root)?;
    let objective = objective(&f, &root)?;
    let optimizer = optimizer(&f, &root, &parameters)?;
    Ok(Spec {
        file: path.to_path_buf(),
        text,
        name,
        experiments,
        parameters,
        objective,
        optimizer,
        set,
        holdout,
        compare,
    })
}

/// The file and its folder, for messages and relative paths.
struct Ctx {
    file: String,
    dir: PathBuf,
}

fn join(table: &str, key: &str) -> String {
    if table.is_empty() { key.to_string() } else { format!("{table}.{key}") }
}

impl Ctx {
    fn bad(&self, key: &str, found: impl std::fmt::Display, expected: &str) -> Error {
        Error::Scene(format!("{}: {key} = {found}: expected {expected}", self.file))
    }

    fn missing(&self, key: &str, expected: &str) -> Error {
        Error::Scene(format!("{}: {key} is missing: expected {expected}", self.file))
    }

    fn keys(&self, t: &toml::Table, at: &str, allowed: &[&str]) -> Result<()> {
        match t.keys().find(|k| !allowed.contains(&k.as_str())) {
            Some(k) => Err(self.bad(&join(at, k), "(unknown key)", &format!("one of {}", allowed.join(", ")))),
            None => Ok(()),
        }
    }

    fn string(&self, t: &toml::Table, at: &str, k: &str) -> Result<Option<String>> {
        match t.get(k) {
            None => Ok(None),
            Some(toml::Value::String(s)) if !s.trim().is_empty() => Ok(Some(s.trim().to_string())),
            Some(v) => Err(self.bad(&join(at, k), v, "a non-empty string")),
        }
    }

    fn strings(&self, t: &toml::Table, at: &str, k: &str) -> Result<Vec<String>> {
        let e = "an array of \"key=value\" scene overrides";
        match t.get(k) {
            None => Ok(Vec::new()),
            Some(toml::Value::Array(a)) => a
                .iter()
                .map(|v| match v {
                    toml::Value::String(s) if s.contains('=') => Ok(s.clone()),
                    _ => Err(self.bad(&join(at, k), v, e)),
                })
                .collect(),
            Some(v) => Err(self.bad(&join(at, k), v, e)),
        }
    }

    /// An array of plain names (letters, digits, '.', '_', '-'), each given once.
    fn strings_plain(&self, t: &toml::Table, k: &str) -> Result<Vec<String>> {
        let e = "an array of library material names, each once";
        let mut out: Vec<String> = Vec::new();
        match t.get(k) {
            None => {}
            Some(toml::Value::Array(a)) => {
                for v in a {
                    match v {
                        toml::Value::String(s) if plain(s) && !out.contains(s) => out.push(s.clone()),
                        _ => return Err(self.bad(k, v, e)),
                    }
                }
            }
            Some(v) => return Err(self.bad(k, v, e)),
        }
        Ok(out)
    }

    fn number(&self, t: &toml::Table, at: &str, k: &str, expected: &str, ok: fn(f64) -> bool) -> Result<Option<f64>> {
        let x = match t.get(k) {
            None => return Ok(None),
            Some(toml::Value::Float(x)) => *x,
            Some(toml::Value::Integer(i)) => *i as f64,
            Some(v) => return Err(self.bad(&join(at, k), v, expected)),
        };
        if ok(x) { Ok(Some(x)) } else { Err(self.bad(&join(at, k), x, expected)) }
    }

    fn count(&self, t: &toml::Table, at: &str, k: &str, expected: &str, min: i64) -> Result<Option<usize>> {
        match t.get(k) {
            None => Ok(None),
            Some(toml::Value::Integer(i)) if *i >= min => Ok(Some(*i as usize)),
            Some(v) => Err(self.bad(&join(at, k), v, expected)),
        }
    }

    fn table<'a>(&self, t: &'a toml::Table, at: &str, k: &str) -> Result<Option<&'a toml::Table>> {
        match t.get(k) {
            None => Ok(None),
            Some(toml::Value::Table(t)) => Ok(Some(t)),
            Some(v) => Err(self.bad(&join(at, k), v, "a table")),
        }
    }

    fn tables<'a>(&self, t: &'a toml::Table, k: &str) -> Result<Vec<&'a toml::Table>> {
        match t.get(k) {
            None => Ok(Vec::new()),
            Some(toml::Value::Array(a)) => a
                .iter()
                .enumerate()
                .map(|(i, v)| v.as_table().ok_or_else(|| self.bad(&format!("{k}.{i}"), v, &format!("a [[{k}]] table"))))
                .collect(),
            Some(v) => Err(self.bad(k, v, &format!("[[{k}]] tables"))),
        }
    }
}

fn positive(x: f64) -> bool {
    x.is_finite() && x > 0.0
}

fn non_negative(x: f64) -> bool {
    x.is_finite() && x >= 0.0
}

fn finite(x: f64) -> bool {
    x.is_finite()
}

/// A name usable as a file name and a CSV column: letters, digits, `.`, `_`, `-`.
fn plain(s: &str) -> bool {
    !s.is_empty() && s.chars().all(|c| c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-'))
}

/// `[[experiment]]` (or `[[holdout]]`, `kind`): `name`, `scene`, `set`, and the measured `fc_n_per_mm`,
/// `ff_n_per_mm`, `chip_thickness_um`, `chip_weight`; or `test`, a row of the data file, whose forces are the
/// measured ones and whose condition scales the model scene ([`data::scale_overrides`]). At least one experiment;
/// holdouts are optional.
fn experiments(f: &Ctx, root: &toml::Table, data_file: Option<&Path>, kind: &str) -> Result<Vec<Experiment>> {
    let tables = f.tables(root, kind)?;
    if tables.is_empty() && kind == "experiment" {
        return Err(f.missing("experiment", "at least one [[experiment]] with a scene and measured forces"));
    }
    let rows = match data_file {
        Some(p) if tables.iter().any(|t| t.contains_key("test")) => Some(data::read(p)?),
        _ => None,
    };
    let mut out: Vec<Experiment> = Vec::new();
    for (i, t) in tables.into_iter().enumerate() {
        let at = format!("{kind}.{i}");
        f.keys(
            t,
            &at,
            &["name", "scene", "test", "set", "fc_n_per_mm", "ff_n_per_mm", "chip_thickness_um", "chip_weight"],
        )?;
        let scene_rel =
            f.string(t, &at, "scene")?.ok_or_else(|| f.missing(&join(&at, "scene"), "the model scene file"))?;
        let scene = f.dir.join(scene_rel);
        let test = f.string(t, &at, "test")?;
        let e = "a positive force per mm of width in N/mm";
        let mut fc = f.number(t, &at, "fc_n_per_mm", e, positive)?;
        let mut ff = f.number(t, &at, "ff_n_per_mm", e, positive)?;
        let chip = f.number(t, &at, "chip_thickness_um", "a positive chip thickness in µm", positive)?;
        let chip_weight =
            f.number(t, &at, "chip_weight", "a weight ≥ 0 in N²/mm² per µm²", non_negative)?.unwrap_or(0.0);
        let mut set = Vec::new();
        if let Some(id) = &test {
            if fc.is_some() || ff.is_some() {
                let k = join(&at, if fc.is_some() { "fc_n_per_mm" } else { "ff_n_per_mm" });
                return Err(f.bad(&k, "(given with test)", "no forces beside test: they come from the data file"));
            }
            let Some(rows) = &rows else {
                return Err(
                    f.missing("data", "the data file of the experiments' test ids (e.g. \"cutting-experiments.csv\")")
                );
            };
            let row = data::usable(rows, id).map_err(|why| f.bad(&join(&at, "test"), format!("\"{id}\""), &why))?;
            (fc, ff) = (Some(row.fc), Some(row.ff));
            let model = Scene::load(&scene, &[]).map_err(|e| Error::Scene(format!("{}: {at}.scene: {e}", f.file)))?;
            let material = model.material.library.as_ref().map_or("", |m| m.name.as_str());
            if !material.to_lowercase().contains(&row.material.to_lowercase()) {
                let why =
                    format!("a model scene of the test's material {} (its material is \"{material}\")", row.material);
                return Err(f.bad(&join(&at, "scene"), scene.display(), &why));
            }
            let cond =
                Condition { vc_m_per_min: row.vc_m_per_min, feed_mm: row.feed_mm, edge_radius_um: row.edge_radius_um };
            set = data::scale_overrides(&model, &cond)
                .map_err(|why| f.bad(&join(&at, "scene"), scene.display(), &why))?;
        }
        set.extend(f.strings(t, &at, "set")?);
        if fc.is_none() && ff.is_none() {
            return Err(f.missing(
                &join(&at, "fc_n_per_mm"),
                "a measured fc_n_per_mm or ff_n_per_mm (or a test of the data file)",
            ));
        }
        if chip_weight > 0.0 && chip.is_none() {
            return Err(
                f.missing(&join(&at, "chip_thickness_um"), "the measured chip thickness that chip_weight weighs")
            );
        }
        let name = match f.string(t, &at, "name")?.or(test.clone()) {
            Some(n) => n,
            None => return Err(f.missing(&join(&at, "name"), "a name (letters, digits, '.', '_', '-')")),
        };
        if !plain(&name) || out.iter().any(|x| x.name == name) {
            return Err(f.bad(
                &join(&at, "name"),
                format!("\"{name}\""),
                "a name of letters, digits, '.', '_', '-' that no other experiment has",
            ));
        }
        out.push(Experiment { name, scene, set, measured: Measured { fc, ff, chip, chip_weight }, test });
    }
    Ok(out)
}

/// `[[parameter]]`: `key`, `lower`, `upper` (lower < upper, finite).
fn parameters(f: &Ctx, root: &toml::Table) -> Result<Vec<Parameter>> {
    let tables = f.tables(root, "parameter")?;
    if tables.is_empty() {
        return Err(f.missing("parameter", "at least one [[parameter]] with key, lower and upper"));
    }
    let mut out: Vec<Parameter> = Vec::new();
    for (i, t) in tables.into_iter().enumerate() {
        let at = format!("parameter.{i}");
        f.keys(t, &at, &["key", "lower", "upper"])?;
        let key =
            f.string(t, &at, "key")?.ok_or_else(|| f.missing(&join(&at, "key"), "a scene key, e.g. tool.friction"))?;
        if out.iter().any(|p| p.key == key) {
            return Err(f.bad(&join(&at, "key"), format!("\"{key}\""), "a key no other parameter has"));
        }
        let e = "a finite number";
        let lower = f.number(t, &at, "lower", e, finite)?.ok_or_else(|| f.missing(&join(&at, "lower"), e))?;
        let upper = f.number(t, &at, "upper", e, finite)?.ok_or_else(|| f.missing(&join(&at, "upper"), e))?;
        if lower >= upper {
            return Err(f.bad(
                &join(&at, "upper"),
                upper,
                &format!("a bound above lower = {lower} (empty or inverted bounds)"),
            ));
        }
        out.push(Parameter { key, lower, upper });
    }
    Ok(out)
}

/// `[objective]`: `fc_weight`, `ff_weight` (default 1, Eq. 9.14), `combine` = "sum" (Eq. 9.17, default) or "mean",
/// `replicas` (default 1).
fn objective(f: &Ctx, root: &toml::Table) -> Result<Objective> {
    let empty = toml::Table::new();
    let t = f.table(root, "", "objective")?.unwrap_or(&empty);
    f.keys(t, "objective", &["fc_weight", "ff_weight", "combine", "replicas"])?;
    let replicas = f.count(t, "objective", "replicas", "a whole number of runs ≥ 1", 1)?.unwrap_or(1);
    let e = "a weight ≥ 0";
    let fc_weight = f.number(t, "objective", "fc_weight", e, non_negative)?.unwrap_or(1.0);
    let ff_weight = f.number(t, "objective", "ff_weight", e, non_negative)?.unwrap_or(1.0);
    let mean = match f.string(t, "objective", "combine")?.as_deref() {
        None | Some("sum") => false,
        Some("mean") => true,
        Some(s) => return Err(f.bad("objective.combine", format!("\"{s}\""), "\"sum\" or \"mean\"")),
    };
    Ok(Objective { fc_weight, ff_weight, mean, replicas })
}

/// `[optimizer]`: `method`, `budget`, `batch`, `seed`, and the method's settings in `[optimizer.de]`,
/// `[optimizer.nelder_mead]` or `[optimizer.bayes]`.
fn optimizer(f: &Ctx, root: &toml::Table, params: &[Parameter]) -> Result<OptimizerSpec> {
    let o = f
        .table(root, "", "optimizer")?
        .ok_or_else(|| f.missing("optimizer", "an [optimizer] table with method and budget"))?;
    let at = "optimizer";
    f.keys(o, at, &["method", "budget", "batch", "seed", "de", "nelder_mead", "bayes"])?;
    let budget = f.count(o, at, "budget", "a budget of at least 1 evaluation", 1)?;
    let budget = budget.ok_or_else(|| f.missing("optimizer.budget", "a budget of at least 1 evaluation"))?;
    let batch = f.count(o, at, "batch", "at least 1 parameter set per batch", 1)?.unwrap_or(1);
    let seed = match o.get("seed") {
        None => 1,
        Some(toml::Value::Integer(i)) if *i >= 0 => *i as u64,
        Some(v) => return Err(f.bad("optimizer.seed", v, "an integer ≥ 0")),
    };
    let methods = "\"de\", \"nelder-mead\" or \"bayes\"";
    let method = f.string(o, at, "method")?.ok_or_else(|| f.missing("optimizer.method", methods))?;
    let method = match method.as_str() {
        "de" => Method::De(de_settings(f, o, seed)?),
        "nelder-mead" => Method::NelderMead(nelder_mead_settings(f, o, params)?),
        "bayes" => Method::Bayes(bayes_settings(f, o, seed)?),
        other => return Err(f.bad("optimizer.method", format!("\"{other}\""), methods)),
    };
    for (k, m) in [("de", "de"), ("nelder_mead", "nelder-mead"), ("bayes", "bayes")] {
        if o.contains_key(k) && method_name(&method) != m {
            return Err(f.bad(
                &format!("optimizer.{k}"),
                "(a table)",
                &format!("settings of the chosen method only (method = \"{}\")", method_name(&method)),
            ));
        }
    }
    Ok(OptimizerSpec { method, budget, batch, seed })
}

/// The file's name of a method.
pub fn method_name(m: &Method) -> &'static str {
    match m {
        Method::De(_) => "de",
        Method::NelderMead(_) => "nelder-mead",
        Method::Bayes(_) => "bayes",
    }
}

fn de_settings(f: &Ctx, o: &toml::Table, seed: u64) -> Result<DeSettings> {
    let mut s = DeSettings { seed, ..DeSettings::default() };
    let Some(t) = f.table(o, "optimizer", "de")? else { return Ok(s) };
    let at = "optimizer.de";
    f.keys(t, at, &["popsize", "mutation", "recombination", "strategy", "tol", "atol"])?;
    s.popsize = f.count(t, at, "popsize", "an integer ≥ 1", 1)?.unwrap_or(s.popsize);
    if let Some(v) = t.get("mutation") {
        let pair = v.as_array().and_then(|a| match a.as_slice() {
            [lo, hi] => Some((
                lo.as_float().or(lo.as_integer().map(|i| i as f64))?,
                hi.as_float().or(hi.as_integer().map(|i| i as f64))?,
            )),
            _ => None,
        });
        s.mutation = pair
            .filter(|(lo, hi)| 0.0 <= *lo && lo <= hi && *hi <= 2.0)
            .ok_or_else(|| f.bad("optimizer.de.mutation", v, "[F_lo, F_hi] with 0 ≤ F_lo ≤ F_hi ≤ 2"))?;
    }
    let unit = |x: f64| (0.0..=1.0).contains(&x);
    s.recombination = f.number(t, at, "recombination", "a rate in [0, 1]", unit)?.unwrap_or(s.recombination);
    s.tol = f.number(t, at, "tol", "a tolerance ≥ 0", non_negative)?.unwrap_or(s.tol);
    s.atol = f.number(t, at, "atol", "a tolerance ≥ 0", non_negative)?.unwrap_or(s.atol);
    s.strategy = match f.string(t, at, "strategy")?.as_deref() {
        None | Some("best1bin") => Strategy::Best1Bin,
        Some("rand1bin") => Strategy::Rand1Bin,
        Some(x) => return Err(f.bad("optimizer.de.strategy", format!("\"{x}\""), "\"best1bin\" or \"rand1bin\"")),
    };
    Ok(s)
}

/// Nelder–Mead: `start` in the parameters' units (default: the box's centre), `step` as a fraction of each
/// parameter's range (default 0.1), `xatol` (unit coordinates) and `fatol`.
fn nelder_mead_settings(f: &Ctx, o: &toml::Table, params: &[Parameter]) -> Result<NelderMeadSettings> {
    let mut s = NelderMeadSettings::from_start(vec![0.5; params.len()]);
    let Some(t) = f.table(o, "optimizer", "nelder_mead")? else { return Ok(s) };
    let at = "optimizer.nelder_mead";
    f.keys(t, at, &["start", "step", "xatol", "fatol"])?;
    if let Some(v) = t.get("start") {
        let e = format!("{} numbers within the parameters' bounds, in their order", params.len());
        let a = v
            .as_array()
            .filter(|a| a.len() == params.len())
            .ok_or_else(|| f.bad("optimizer.nelder_mead.start", v, &e))?;
        s.start = a
            .iter()
            .zip(params)
            .map(|(x, p)| {
                let x = x.as_float().or(x.as_integer().map(|i| i as f64)).filter(|x| (p.lower..=p.upper).contains(x));
                x.map(|x| (x - p.lower) / (p.upper - p.lower))
                    .ok_or_else(|| f.bad("optimizer.nelder_mead.start", v, &e))
            })
            .collect::<Result<_>>()?;
    }
    s.step = f.number(t, at, "step", "a fraction of the range in (0, 1]", |x| x > 0.0 && x <= 1.0)?.unwrap_or(s.step);
    s.xatol = f.number(t, at, "xatol", "a tolerance ≥ 0", non_negative)?.unwrap_or(s.xatol);
    s.fatol = f.number(t, at, "fatol", "a tolerance ≥ 0", non_negative)?.unwrap_or(s.fatol);
    Ok(s)
}

fn bayes_settings(f: &Ctx, o: &toml::Table, seed: u64) -> Result<BayesSettings> {
    let mut s = BayesSettings { seed, ..BayesSettings::default() };
    let Some(t) = f.table(o, "optimizer", "bayes")? else { return Ok(s) };
    let at = "optimizer.bayes";
    f.keys(t, at, &["initial", "candidates", "xi", "noise"])?;
    s.initial = f.count(t, at, "initial", "an integer ≥ 0 (0: max(2d + 1, 10))", 0)?.unwrap_or(s.initial);
    s.candidates = f.count(t, at, "candidates", "an integer ≥ 1", 1)?.unwrap_or(s.candidates);
    s.xi = f.number(t, at, "xi", "a margin ≥ 0", non_negative)?.unwrap_or(s.xi);
    s.noise = match t.get("noise") {
        Some(toml::Value::String(v)) if v == "fit" => Noise::Fit,
        _ => f.number(t, at, "noise", "a variance > 0 or \"fit\"", positive)?.map_or(s.noise, Noise::Fixed),
    };
    Ok(s)
}
