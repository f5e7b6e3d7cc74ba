//! From the document tree to a validated [`Scene`]: every key is typed, range-checked and located; unknown keys
//! are refused table by table.

use super::doc::{Doc, Entry, Node, Val, show};
use super::error::SceneError;
use super::*;

mod cohesive;
mod damage;
mod mpm;
mod tool;
use damage::damage;
pub(super) use mpm::{method, mpm_scene};
use tool::tool;

type Result<T> = std::result::Result<T, SceneError>;

/// Most lattice points a scene may ask for (bounding-box lattices of all bodies together).
const MAX_POINTS: f64 = 2147483647.0;

const ROOT_KEYS: &[&str] = &[
    "name",
    "dim",
    "precision",
    "discretisation",
    "material",
    "body",
    "boundary",
    "stabilisation",
    "time",
    "output",
    "physics",
    "tool",
    "experiment",
    "analysis",
    "model",
    "damage",
    "blanking",
    "method",
    "cohesive",
];
/// The largest `stabilisation.xsph.pic`: the step's predictor takes the last step's rates, which keeps an explicit
/// relaxation of rate α = pic/Δt stable only while pic λ ≲ 1, λ ≤ 1.7 the largest decay rate of XSPH's sum (the
/// bonded blocks of V15 blew up at pic = 0.8 and ran at 0.7; docs/mpm.md "Smoothed-velocity damping").
const MAX_PIC: f64 = 0.5;
const PIC_EXPECTED: &str = "a PIC fraction 1 - beta in [0, 0.5] (the step's predictor keeps larger ones unstable)";
const BODY_KEYS: &[&str] = &["name", "shape", "velocity", "angular_velocity", "lattice", "material", "temperature"];
const SHAPES: &[(&str, &[&str])] = &[
    ("rectangle", &["min", "max"]),
    ("box", &["min", "max"]),
    ("disk", &["center", "radius"]),
    ("ring", &["center", "inner_radius", "outer_radius"]),
    ("spherical_shell", &["center", "inner_radius", "outer_radius"]),
    ("cylinder", &["center", "radius", "height", "inner_radius"]),
];

/// A table of the document under its dotted path.
#[derive(Clone, Copy)]
struct Tab<'a> {
    doc: &'a Doc,
    path: &'a str,
    node: &'a Node,
    entries: &'a [Entry],
}

impl<'a> Tab<'a> {
    fn key(&self, k: &str) -> String {
        if self.path.is_empty() { k.to_string() } else { format!("{}.{k}", self.path) }
    }

    fn get(&self, k: &str) -> Option<&'a Node> {
        self.entries.iter().find(|e| e.key == k).map(|e| &e.node)
    }

    /// An `Invalid` error for key `k`; `node` is its value (`None` when missing: located at the table).
    fn invalid(&self, k: &str, node: Option<&Node>, expected: impl Into<String>) -> SceneError {
        SceneError::Invalid {
            at: self.doc.loc(node.map_or(self.node.at, |n| n.at)),
            key: self.key(k),
            value: node.map(show),
            expected: expected.into(),
        }
    }

    /// Refuses keys not in `allowed`; a key listed in `elsewhere` gets `context` in the message.
    fn check_keys(&self, allowed: &[&str], elsewhere: &[&str], context: &str) -> Result<()> {
        for e in self.entries {
            if !allowed.contains(&e.key.as_str()) {
                return Err(SceneError::UnknownKey {
                    at: self.doc.loc(e.node.at),
                    key: self.key(&e.key),
                    context: if elsewhere.contains(&e.key.as_str()) { context.to_string() } else { String::new() },
                    expected: allowed.iter().map(|s| s.to_string()).collect(),
                });
            }
        }
        Ok(())
    }

    fn required<T>(&self, k: &str, expected: &str, value: Option<T>) -> Result<T> {
        value.ok_or_else(|| self.invalid(k, None, expected))
    }

    /// A finite number (TOML float or integer) satisfying `ok`; for a key with units, also a string of a number
    /// and a unit ([`super::units`]), converted to the key's unit.
    fn number(&self, k: &str, expected: &str, ok: impl Fn(f64) -> bool) -> Result<Option<f64>> {
        let Some(node) = self.get(k) else { return Ok(None) };
        let quantity = super::units::quantity(&self.key(k));
        match self.scalar(node, quantity) {
            Some(x) if x.is_finite() && ok(x) => Ok(Some(x)),
            _ => Err(self.invalid(k, Some(node), with_units(expected, quantity, node))),
        }
    }

    /// A node's number, or for a `quantity` its string with a unit converted.
    fn scalar(&self, node: &Node, quantity: Option<super::units::Quantity>) -> Option<f64> {
        match (&node.val, quantity) {
            (Val::Leaf(toml::Value::String(text)), Some(q)) => q.parse(text),
            _ => as_number(node),
        }
    }

    fn integer(&self, k: &str, expected: &str, ok: impl Fn(i64) -> bool) -> Result<Option<i64>> {
        let Some(node) = self.get(k) else { return Ok(None) };
        match &node.val {
            Val::Leaf(toml::Value::Integer(i)) if ok(*i) => Ok(Some(*i)),
            _ => Err(self.invalid(k, Some(node), expected)),
        }
    }

    fn string(&self, k: &str, expected: &str, ok: impl Fn(&str) -> bool) -> Result<Option<&'a str>> {
        let Some(node) = self.get(k) else { return Ok(None) };
        match &node.val {
            Val::Leaf(toml::Value::String(s)) if ok(s) => Ok(Some(s.as_str())),
            _ => Err(self.invalid(k, Some(node), expected)),
        }
    }

    /// A string that `parse` turns into a value (an enum's key names), or the key's error naming `expected`.
    fn named<T>(&self, k: &str, expected: &str, parse: impl Fn(&str) -> Option<T>) -> Result<Option<T>> {
        Ok(self.string(k, expected, |s| parse(s).is_some())?.and_then(parse))
    }

    fn boolean(&self, k: &str, expected: &str) -> Result<Option<bool>> {
        let Some(node) = self.get(k) else { return Ok(None) };
        match &node.val {
            Val::Leaf(toml::Value::Boolean(b)) => Ok(Some(*b)),
            _ => Err(self.invalid(k, Some(node), expected)),
        }
    }

    /// The required keys `min` and `max` of a box (points in m, `max` ≥ `min` on every axis).
    fn min_max(&self, dim: usize) -> Result<([f64; 3], [f64; 3])> {
        let e = point_text("a point", dim, "m");
        let min = self.required("min", &e, self.vector("min", dim, &e)?)?;
        let e_max = format!("{e} >= min on every axis");
        let max = self.required("max", &e_max, self.vector("max", dim, &e_max)?)?;
        if (0..dim).any(|k| max[k] < min[k]) {
            return Err(self.invalid("max", self.get("max"), e_max));
        }
        Ok((min, max))
    }

    /// An array of exactly `n` finite numbers (for a key with units, each also a string with a unit), padded
    /// with zeros to three.
    fn vector(&self, k: &str, n: usize, expected: &str) -> Result<Option<[f64; 3]>> {
        let Some(node) = self.get(k) else { return Ok(None) };
        let quantity = super::units::quantity(&self.key(k));
        let bad = || self.invalid(k, Some(node), with_units(expected, quantity, node));
        let Val::Array(items) = &node.val else { return Err(bad()) };
        if items.len() != n {
            return Err(bad());
        }
        let mut v = [0.0; 3];
        for (slot, item) in v.iter_mut().zip(items) {
            *slot = self.scalar(item, quantity).filter(|x| x.is_finite()).ok_or_else(bad)?;
        }
        Ok(Some(v))
    }

    /// A sub-table (a `[header]` or an inline table); `path` must be this table's key of `k`.
    fn table(&self, k: &str, path: &'a str, expected: &str) -> Result<Option<Tab<'a>>> {
        let Some(node) = self.get(k) else { return Ok(None) };
        match &node.val {
            Val::Table(entries) => Ok(Some(Tab { doc: self.doc, path, node, entries })),
            _ => Err(self.invalid(k, Some(node), expected)),
        }
    }

    /// The elements of an array of tables (`[[k]]`), empty when absent.
    fn tables(&self, k: &str, expected: &str) -> Result<Vec<(&'a Node, &'a [Entry])>> {
        let Some(node) = self.get(k) else { return Ok(Vec::new()) };
        let Val::Array(items) = &node.val else { return Err(self.invalid(k, Some(node), expected)) };
        items
            .iter()
            .map(|item| match &item.val {
                Val::Table(entries) => Ok((item, entries.as_slice())),
                _ => Err(self.invalid(k, Some(node), expected)),
            })
            .collect()
    }
}

/// `expected`, and where a key with units was given a string (`node` or one of its elements), what its strings
/// may say.
fn with_units(expected: &str, quantity: Option<super::units::Quantity>, node: &Node) -> String {
    let is_string = |n: &Node| matches!(n.val, Val::Leaf(toml::Value::String(_)));
    let strings = match &node.val {
        Val::Array(items) => items.iter().any(is_string),
        _ => is_string(node),
    };
    match quantity {
        Some(q) if strings => format!("{expected}, or {}", q.help()),
        _ => expected.to_string(),
    }
}

fn as_number(node: &Node) -> Option<f64> {
    match &node.val {
        Val::Leaf(toml::Value::Float(x)) => Some(*x),
        Val::Leaf(toml::Value::Integer(i)) => Some(*i as f64),
        _ => None,
    }
}

fn positive(x: f64) -> bool {
    x > 0.0
}

fn non_negative(x: f64) -> bool {
    x >= 0.0
}

fn any(_: f64) -> bool {
    true
}

/// `"a point [x, y] in m"` and the like.
fn point_text(what: &str, dim: usize, unit: &str) -> String {
    let names = ["x", "y", "z"];
    format!("{what} [{}] in {unit}", names[..dim].join(", "))
}

/// Whether `s` names one file in a folder: runs go to `runs/<name>`, so a name with a separator, `..` or an
/// absolute path would write outside it (issue 27).
fn plain_file_name(s: &str) -> bool {
    use std::path::Component;
    let mut parts = std::path::Path::new(s).components();
    !s.trim().is_empty()
        && !s.contains(['/', '\\', '\0'])
        && matches!(parts.next(), Some(Component::Normal(_)))
        && parts.next().is_none()
}

pub(super) fn scene(doc: &Doc) -> Result<Scene> {
    let Val::Table(entries) = &doc.root.val else { unreachable!("a TOML document is a table") };
    let root = Tab { doc, path: "", node: &doc.root, entries };
    // An SPH scene may say so; an MPM scene is read by `mpm_scene`, which `swarf run` and `swarf check` choose by
    // this key, and no other command reads.
    root.string(
        "method",
        "\"sph\": this command reads SPH scenes; `swarf run` and `swarf check` read MPM scenes (docs/mpm.md)",
        |s| s == "sph",
    )?;
    root.check_keys(ROOT_KEYS, &[], "")?;

    let name_expected =
        "a non-empty string naming the scene, a plain file name for its run folder (no '/' or '\\', not '.' or '..')";
    let name = root.required("name", name_expected, root.string("name", name_expected, plain_file_name)?)?;
    let dim_expected = "2 (plane strain) or 3";
    let dim = root.required("dim", dim_expected, root.integer("dim", dim_expected, |d| d == 2 || d == 3)?)? as usize;
    let precision_expected = "\"f32\", \"f64\" or \"mixed\"";
    let precision = root.named("precision", precision_expected, Precision::from_name)?.unwrap_or(Precision::F64);

    let model = model(&root, dim)?;
    let switches = model.switches();

    let (disc, discretisation) = discretisation(&root, dim)?;
    let (dx, h_over_dx) = (discretisation.dx, discretisation.h_over_dx);

    // [material]
    let material = material(&root, doc)?;

    // [physics]
    let physics = physics(&root, &material)?;

    // [[body]]
    let bodies = bodies(&root, &disc, (dim, dx), &material, &physics)?;

    // [[boundary]]
    let boundaries = boundaries(&root, dim, &bodies)?;

    // [stabilisation]
    let stabilisation = stabilisation(&root)?;

    let time = time(&root)?;
    let output = output(&root, time.end)?;

    // [tool] or [[tool]]
    let mut tools = tool::tools(&root, |t| tool(t, doc, dim, dx, 2.0 * h_over_dx * dx, &physics, &bodies, switches))?;
    let more_tools = if tools.len() > 1 { tools.split_off(1) } else { Vec::new() };
    let tool = tools.pop();

    // [experiment]
    let experiment = match root.table("experiment", "experiment", "a table [experiment] of measured observables")? {
        Some(t) => experiment(&t, &super::observe::catalogue(dim, tool.is_some(), &bodies))?,
        None => Vec::new(),
    };

    let analysis = analysis(&root, tool.is_some())?;

    // [damage]
    let damage = match root.table("damage", "damage", "a table [damage] (docs/damage.md)")? {
        Some(t) => damage(&t, dim, &material, &physics)?,
        None => None,
    };
    if damage.is_some()
        && stabilisation.cspm.is_some()
        && let Some(st) = root.table("stabilisation", "stabilisation", "")?
    {
        let e = "no CSPM with [damage] (the corrected gradient has no interaction mask): enabled = false";
        return Err(st.invalid("cspm", st.get("cspm"), e));
    }

    let blanking = blanking(&root, dim, tool.as_ref())?;
    let cohesive = cohesive::path(&root, &physics, damage.is_some(), blanking.is_some())?;
    if cohesive.is_none()
        && stabilisation.cspm.as_ref().is_some_and(|c| c.path_only)
        && let Some(st) = root.table("stabilisation", "stabilisation", "")?
        && let Some(c) = st.table("cspm", "stabilisation.cspm", "")?
    {
        let e = "\"all\": \"path\" corrects the faces of a cohesive path, and the scene has no [cohesive]";
        return Err(c.invalid("scope", c.get("scope"), e));
    }

    Ok(Scene {
        origin: doc.file.clone(),
        name: name.to_string(),
        dim,
        precision,
        discretisation,
        material,
        bodies,
        boundaries,
        stabilisation,
        time,
        output,
        physics,
        tool,
        more_tools,
        experiment,
        analysis,
        model,
        damage,
        blanking,
        cohesive,
    })
}

/// `[blanking]` (optional): `min`, `max` (the active box at t = 0, points in m), `velocity` (m/s; default the
/// first tool's translation velocity, else zero), `grow` (the rear faces stay put) and `rest_speed` (frozen outside
/// only when slower).
fn blanking(root: &Tab<'_>, dim: usize, tool: Option<&super::Tool>) -> Result<Option<super::Blanking>> {
    let Some(t) = root.table("blanking", "blanking", "a table [blanking] with min, max and velocity")? else {
        return Ok(None);
    };
    t.check_keys(&["min", "max", "velocity", "grow", "rest_speed"], &[], "")?;
    let (min, max) = t.min_max(dim)?;
    let e = point_text("a velocity", dim, "m/s");
    let velocity = match t.vector("velocity", dim, &e)? {
        Some(v) => v,
        None => tool.map_or([0.0; 3], |tl| tl.velocity),
    };
    let grow = t.boolean("grow", "true or false")?.unwrap_or(false);
    let mut b = super::Blanking { min, max, velocity, grow, rest_speed: None };
    b.rest_speed = match t.get("rest_speed") {
        // `inf`: every particle outside is frozen, whatever its speed.
        Some(node) if as_number(node) == Some(f64::INFINITY) => None,
        _ => t
            .number("rest_speed", "a speed >= 0 in m/s, or inf (every particle outside frozen)", |x| x >= 0.0)?
            .or(b.default_rest_speed()),
    };
    Ok(Some(b))
}

/// `[discretisation]` (required): its table (the bodies read their spacing from it) and its values.
fn discretisation<'a>(root: &Tab<'a>, dim: usize) -> Result<(Tab<'a>, Discretisation)> {
    let disc_expected = "a table [discretisation] with dx (and h_over_dx, skin_over_h, verlet_list, verlet_offsets)";
    let disc =
        root.required("discretisation", disc_expected, root.table("discretisation", "discretisation", disc_expected)?)?;
    disc.check_keys(&["dx", "h_over_dx", "skin_over_h", "verlet_list", "verlet_offsets", "period_z"], &[], "")?;
    let dx_expected = "a positive lattice spacing in m";
    let dx = disc.required("dx", dx_expected, disc.number("dx", dx_expected, positive)?)?;
    let h_over_dx = disc.number("h_over_dx", "a ratio h/dx in [1, 3]", |x| (1.0..=3.0).contains(&x))?.unwrap_or(1.7);
    let skin_over_h = disc
        .number("skin_over_h", "a cell-list skin in units of h, in [0, 1]", |x| (0.0..=1.0).contains(&x))?
        .unwrap_or(0.1);
    let verlet_list = disc.boolean("verlet_list", "true or false")?.unwrap_or(true);
    let verlet_offsets = disc
        .number("verlet_offsets", "16 or 32 (bits per Verlet-list offset)", |x| x == 16.0 || x == 32.0)?
        .map(|x| x as u32);
    let period_z = disc.number("period_z", "a positive period in m (3D only)", positive)?;
    if period_z.is_some() && dim != 3 {
        return Err(disc.invalid("period_z", disc.get("period_z"), "no period_z in 2D (a 3D scene's z period)"));
    }
    Ok((disc, Discretisation { dx, h_over_dx, skin_over_h, verlet_list, verlet_offsets, period_z }))
}

/// `[time]` (required): end, and the optional cfl, dt and max_steps.
fn time(root: &Tab<'_>) -> Result<Time> {
    let time_expected = "a table [time] with end (and cfl, dt)";
    let t = root.required("time", time_expected, root.table("time", "time", time_expected)?)?;
    t.check_keys(&["end", "cfl", "dt", "max_steps"], &[], "")?;
    let e = "a positive time in seconds";
    let end = t.required("end", e, t.number("end", e, positive)?)?;
    let cfl = t.number("cfl", "a CFL number in (0, 1]", |x| x > 0.0 && x <= 1.0)?.unwrap_or(0.5);
    let dt = t.number("dt", "a positive time step in seconds", positive)?;
    let max_steps = t.number("max_steps", "a step count >= 1", |x| x >= 1.0)?.unwrap_or(super::DEFAULT_MAX_STEPS);
    Ok(Time { end, cfl, dt, max_steps })
}

/// `[output]` (optional): every (default end/50) and vtu_encoding.
fn output(root: &Tab<'_>, end: f64) -> Result<Output> {
    let mut output = Output { every: end / 50.0, vtu_encoding: Default::default() };
    if let Some(o) = root.table("output", "output", "a table [output] with every, vtu_encoding")? {
        o.check_keys(&["every", "vtu_encoding"], &[], "")?;
        if let Some(every) = o.number("every", "a positive time in seconds", positive)? {
            output.every = every;
        }
        use crate::output::vtu::Encoding;
        let e = "\"raw\" or \"base64-zlib\"";
        if let Some(encoding) = o.named("vtu_encoding", e, Encoding::from_name)? {
            output.vtu_encoding = encoding;
        }
    }
    Ok(output)
}

/// `model` (optional, default `"swarf"`): `"swarf"`, `"mfree_iwf"` or a list of the original code's switches
/// (`super::model`); in 3D only `"swarf"` (the original code reproduced is the 2D one).
fn model(root: &Tab<'_>, dim: usize) -> Result<Model> {
    use super::model::{MODEL_NAMES, ModelSwitches, Switch};
    let Some(node) = root.get("model") else { return Ok(Model::Swarf) };
    let names = MODEL_NAMES.iter().map(|n| format!("\"{n}\"")).collect::<Vec<_>>().join(" or ");
    let switches = Switch::ALL.iter().map(|s| format!("\"{}\"", s.name())).collect::<Vec<_>>().join(", ");
    let expected = format!("{names}, or a list of the original code's switches ({switches})");
    let bad = || root.invalid("model", Some(node), expected.clone());
    let model = match &node.val {
        Val::Leaf(toml::Value::String(s)) => Model::from_name(s).ok_or_else(bad)?,
        Val::Array(items) => {
            let mut list = Vec::with_capacity(items.len());
            for item in items {
                match &item.val {
                    Val::Leaf(toml::Value::String(s)) => list.push(Switch::from_name(s).ok_or_else(bad)?),
                    _ => return Err(bad()),
                }
            }
            Model::Switches(ModelSwitches::of(&list))
        }
        _ => return Err(bad()),
    };
    if dim != 2 && !model.is_swarf() {
        return Err(root.invalid(
            "model",
            Some(node),
            "\"swarf\" in 3D (the original code reproduced, mfree_iwf, is Röthlin's 2D code)",
        ));
    }
    Ok(model)
}

/// `[analysis]` (optional): `early_stop = { tolerance = ε }`, ε in (0, 1], only with a `[tool]`.
fn analysis(root: &Tab<'_>, has_tool: bool) -> Result<Analysis> {
    let Some(t) = root.table("analysis", "analysis", "a table [analysis] with early_stop")? else {
        return Ok(Analysis::default());
    };
    t.check_keys(&["early_stop"], &[], "")?;
    let e = "a table { tolerance = ε }, ε in (0, 1] (relative)";
    let Some(es) = t.table("early_stop", "analysis.early_stop", e)? else { return Ok(Analysis::default()) };
    if !has_tool {
        return Err(t.invalid("early_stop", t.get("early_stop"), "no early_stop: it needs a [tool] (a cutting run)"));
    }
    es.check_keys(&["tolerance"], &[], "")?;
    let te = "a relative tolerance in (0, 1], e.g. 0.02";
    let tolerance = es.required("tolerance", te, es.number("tolerance", te, |x| x > 0.0 && x <= 1.0)?)?;
    Ok(Analysis { early_stop: Some(EarlyStopRule { tolerance }) })
}

/// `[material]`: a library material and/or the elastic constants (the library's where not given).
fn material(root: &Tab<'_>, doc: &Doc) -> Result<Material> {
    let mat_expected = "a table [material] with a library name and/or density, youngs_modulus and poisson_ratio";
    let mat = root.required("material", mat_expected, root.table("material", "material", mat_expected)?)?;
    mat.check_keys(&["name", "density", "youngs_modulus", "poisson_ratio"], &[], "")?;
    let library = match mat.string("name", "the name of a material of the library", |s| !s.trim().is_empty())? {
        Some(name) => Some(named_material(&mat, doc, "name", name)?),
        None => None,
    };
    let lib_elastic = library.as_ref().and_then(|m| m.elastic);
    let e = "a positive density in kg/m^3";
    let density = match mat.number("density", e, positive)? {
        Some(v) => v,
        None => match lib_elastic.map(|el| el.density) {
            Some(v) => v,
            None => mat.required("density", e, None)?,
        },
    };
    let e = "a positive Young's modulus in Pa";
    let youngs_modulus = match mat.number("youngs_modulus", e, positive)? {
        Some(v) => v,
        None => match lib_elastic.map(|el| el.youngs_modulus) {
            Some(v) => v,
            None => mat.required("youngs_modulus", e, None)?,
        },
    };
    let e = "a value in (-1, 0.5)";
    let poisson_ratio = match mat.number("poisson_ratio", e, |x| x > -1.0 && x < 0.5)? {
        Some(v) => v,
        None => match lib_elastic.map(|el| el.poisson_ratio) {
            Some(v) => v,
            None => mat.required("poisson_ratio", e, None)?,
        },
    };
    Ok(Material { library, density, youngs_modulus, poisson_ratio })
}

/// `[physics]`, with the defaults the material gives (plasticity where it has a flow-stress model, heating where
/// it also has a specific heat).
fn physics(root: &Tab<'_>, material: &Material) -> Result<Physics> {
    let lib = material.library.as_ref();
    let thermal = lib.and_then(|m| m.thermal);
    let has_flow = lib.is_some_and(|m| m.flow_stress.is_some());
    let mut physics = Physics {
        plasticity: has_flow,
        conduction: Conduction::Off,
        plastic_heating: has_flow && thermal.is_some_and(|t| t.specific_heat.is_some()),
        taylor_quinney: thermal.and_then(|t| t.taylor_quinney).unwrap_or(0.9),
        initial_temperature: thermal.and_then(|t| t.reference_temperature).unwrap_or(300.0),
        thermal_expansion: 0.0,
        expansion_reference: thermal.and_then(|t| t.reference_temperature).unwrap_or(300.0),
    };
    let phys_expected =
        "a table [physics] with plasticity, conduction, plastic_heating, taylor_quinney, initial_temperature";
    if let Some(ph) = root.table("physics", "physics", phys_expected)? {
        ph.check_keys(
            &[
                "plasticity",
                "conduction",
                "plastic_heating",
                "taylor_quinney",
                "initial_temperature",
                "thermal_expansion",
            ],
            &[],
            "",
        )?;
        if let Some(a) =
            ph.number("thermal_expansion", "a non-negative linear expansion coefficient in 1/K (e.g. 8.6e-6)", |x| {
                (0.0..1e-3).contains(&x)
            })?
        {
            physics.thermal_expansion = a;
        }
        if let Some(p) = ph.boolean("plasticity", "true or false")? {
            if p && !has_flow {
                return Err(ph.invalid(
                    "plasticity",
                    ph.get("plasticity"),
                    "false: the material has no flow-stress model (name a library material with [flow_stress])",
                ));
            }
            physics.plasticity = p;
        }
        let e = "\"off\", \"brookshaw\" or \"pse\"";
        if let Some(c) = ph.string("conduction", e, |s| matches!(s, "off" | "brookshaw" | "pse"))? {
            physics.conduction = match c {
                "brookshaw" => Conduction::Brookshaw,
                "pse" => Conduction::Pse,
                _ => Conduction::Off,
            };
            // The conductivity and specific heat of every body are checked with the bodies.
        }
        if let Some(h) = ph.boolean("plastic_heating", "true or false")? {
            if h && !(physics.plasticity && thermal.is_some_and(|t| t.specific_heat.is_some())) {
                return Err(ph.invalid(
                    "plastic_heating",
                    ph.get("plastic_heating"),
                    "false: heating needs plasticity and the material's specific heat",
                ));
            }
            physics.plastic_heating = h;
        }
        if let Some(t) = ph.number("taylor_quinney", "a coefficient in [0, 1]", |x| (0.0..=1.0).contains(&x))? {
            physics.taylor_quinney = t;
        }
        if let Some(t) = ph.number("initial_temperature", "a positive temperature in K", positive)? {
            physics.initial_temperature = t;
        }
    }
    if !physics.plasticity {
        physics.plastic_heating = false;
    }
    Ok(physics)
}

/// `[[body]]`: one or more bodies, each checked against the scene material and the conduction, and their lattice
/// points against the limit (an error at the largest body, or at dx where only dx was just overridden).
fn bodies(
    root: &Tab<'_>,
    disc: &Tab<'_>,
    dims: (usize, f64),
    material: &Material,
    physics: &Physics,
) -> Result<Vec<Body>> {
    let (dim, dx) = dims;
    let doc = root.doc;
    let body_expected = "one or more [[body]] tables";
    let body_tables = root.tables("body", body_expected)?;
    if body_tables.is_empty() {
        return Err(root.invalid("body", root.get("body"), body_expected));
    }
    let body_paths: Vec<String> = (0..body_tables.len()).map(|i| format!("body.{i}")).collect();
    let mut bodies: Vec<Body> = Vec::new();
    let mut lattice_points = 0.0;
    // The body with the most lattice points (index, points): the one to name when there are too many.
    let mut largest = (0, 0.0f64);
    for (i, &(node, entries)) in body_tables.iter().enumerate() {
        let t = Tab { doc, path: &body_paths[i], node, entries };
        let (body, points) = body(&t, i, dim, dx, &bodies)?;
        if let Some(m) = &body.material
            && let Some(e) = m.elastic
            && (e.density, e.youngs_modulus, e.poisson_ratio)
                != (material.density, material.youngs_modulus, material.poisson_ratio)
        {
            return Err(t.invalid(
                "material",
                t.get("material"),
                format!(
                    "a material with the scene material's elastic constants (density {}, E {:e}, ν {}): per-body \
                         mechanical materials are not supported yet, only per-body thermal data",
                    material.density, material.youngs_modulus, material.poisson_ratio
                ),
            ));
        }
        let th = body.material.as_ref().and_then(|m| m.thermal).or(material.library.as_ref().and_then(|m| m.thermal));
        let ok = th.is_some_and(|t| t.conductivity.is_some() && t.specific_heat.is_some());
        if physics.conduction != Conduction::Off && !ok {
            return Err(t.invalid(
                "material",
                t.get("material"),
                "a library material with [thermal] conductivity and specific_heat, for this body or the scene \
                 (the scene conducts heat)",
            ));
        }
        lattice_points += points;
        if points > largest.1 {
            largest = (i, points);
        }
        bodies.push(body);
    }
    if lattice_points > MAX_POINTS {
        let (i, points) = largest;
        let set = |n: &Node| matches!(n.at, super::doc::At::Set(_));
        if disc.get("dx").is_some_and(set) && !body_tables[i].1.iter().any(|e| set(&e.node)) {
            return Err(disc.invalid(
                "dx",
                disc.get("dx"),
                format!(
                    "a lattice spacing giving at most 2^31 - 1 lattice points (this one gives {lattice_points:.3e}; \
                     dx is too small for these bodies)"
                ),
            ));
        }
        // Else named by its body, the largest (a too-large body was blamed on `discretisation.dx`).
        return Err(SceneError::Invalid {
            at: doc.loc(body_tables[i].0.at),
            key: body_paths[i].clone(),
            value: Some(format!("'{}', {points:.3e} lattice points at dx = {dx:e} m", bodies[i].name)),
            expected: format!(
                "bodies of at most 2^31 - 1 lattice points in all (these give {lattice_points:.3e}): a smaller body \
                 or a larger discretisation.dx"
            ),
        });
    }
    Ok(bodies)
}

/// `[[boundary]]`: the boundary conditions, on the bodies they name.
fn boundaries(root: &Tab<'_>, dim: usize, bodies: &[Body]) -> Result<Vec<Boundary>> {
    let doc = root.doc;
    let boundary_tables = root.tables("boundary", "[[boundary]] tables")?;
    let boundary_paths: Vec<String> = (0..boundary_tables.len()).map(|i| format!("boundary.{i}")).collect();
    let mut boundaries = Vec::new();
    for (i, &(node, entries)) in boundary_tables.iter().enumerate() {
        let t = Tab { doc, path: &boundary_paths[i], node, entries };
        boundaries.push(boundary(&t, dim, bodies)?);
    }
    Ok(boundaries)
}

/// `[stabilisation]`: artificial viscosity, artificial stress, XSPH and the CSPM correction, each with its defaults.
fn stabilisation(root: &Tab<'_>) -> Result<Stabilisation> {
    let mut stabilisation = Stabilisation::default();
    let stab_expected = "a table [stabilisation] with artificial_viscosity, artificial_stress, xsph and/or cspm";
    if let Some(st) = root.table("stabilisation", "stabilisation", stab_expected)? {
        st.check_keys(&["artificial_viscosity", "artificial_stress", "xsph", "cspm"], &[], "")?;
        let e = "a table { alpha, beta, eta, switch, enabled }";
        if let Some(t) = st.table("artificial_viscosity", "stabilisation.artificial_viscosity", e)? {
            stabilisation.artificial_viscosity = artificial_viscosity(&t)?;
        }
        let e = "a table { epsilon, exponent, enabled }";
        if let Some(t) = st.table("artificial_stress", "stabilisation.artificial_stress", e)? {
            t.check_keys(&["epsilon", "exponent", "enabled"], &[], "")?;
            let exponent = t.integer("exponent", "an integer >= 1 (at most 64)", |n| (1..=64).contains(&n))?;
            let a = ArtificialStress {
                epsilon: t.number("epsilon", "a non-negative coefficient", non_negative)?.unwrap_or(0.3),
                exponent: exponent.unwrap_or(4) as u32,
            };
            if t.boolean("enabled", "true or false")?.unwrap_or(true) {
                stabilisation.artificial_stress = Some(a);
            }
        }
        if let Some(t) = st.table("xsph", "stabilisation.xsph", "a table { epsilon, pic, enabled }")? {
            t.check_keys(&["epsilon", "pic", "enabled"], &[], "")?;
            let x = Xsph {
                epsilon: t.number("epsilon", "a value in [0, 1]", |x| (0.0..=1.0).contains(&x))?.unwrap_or(0.5),
                pic: t.number("pic", PIC_EXPECTED, |x| (0.0..=MAX_PIC).contains(&x))?.unwrap_or(0.0),
            };
            if t.boolean("enabled", "true or false")?.unwrap_or(true) {
                stabilisation.xsph = Some(x);
            }
        }
        if let Some(t) = st.table("cspm", "stabilisation.cspm", "a table { min_determinant, scope, enabled }")? {
            t.check_keys(&["min_determinant", "scope", "enabled"], &[], "")?;
            let scope_expected = "\"all\" (every particle) or \"path\" (the cohesive path's faces only)";
            let c = Cspm {
                min_determinant: t
                    .number("min_determinant", "a value in [0, 1)", |x| (0.0..1.0).contains(&x))?
                    .unwrap_or(1e-8),
                path_only: t
                    .named("scope", scope_expected, |s| match s {
                        "all" => Some(false),
                        "path" => Some(true),
                        _ => None,
                    })?
                    .unwrap_or(false),
            };
            if t.boolean("enabled", "true or false")?.unwrap_or(true) {
                stabilisation.cspm = Some(c);
            }
        }
    }
    Ok(stabilisation)
}

/// `[stabilisation.artificial_viscosity]` (None: `enabled = false`). The Balsara switch scales the viscosity, so
/// it is refused where the viscosity is off rather than ignored.
fn artificial_viscosity(t: &Tab<'_>) -> Result<Option<ArtificialViscosity>> {
    t.check_keys(&["alpha", "beta", "eta", "switch", "enabled"], &[], "")?;
    let switch_expected = "\"none\" or \"balsara\" (Balsara's switch on the linear term, docs/solver.md)";
    let av = ArtificialViscosity {
        alpha: t.number("alpha", "a non-negative coefficient", non_negative)?.unwrap_or(1.0),
        beta: t.number("beta", "a non-negative coefficient", non_negative)?.unwrap_or(1.0),
        eta: t.number("eta", "a positive coefficient", positive)?.unwrap_or(0.1),
        switch: t.named("switch", switch_expected, ViscositySwitch::from_name)?.unwrap_or_default(),
    };
    if t.boolean("enabled", "true or false")?.unwrap_or(true) {
        return Ok(Some(av));
    }
    if av.switch != ViscositySwitch::None {
        let e = "\"none\" with enabled = false (the switch scales the artificial viscosity, which is off)";
        return Err(t.invalid("switch", t.get("switch"), e));
    }
    Ok(None)
}

/// The `[experiment]` table: each key names an observable of the scene (`catalogue`), each value is
/// `{ value, uncertainty }` or a bare number.
fn experiment(t: &Tab<'_>, catalogue: &[super::observe::Observable]) -> Result<Vec<Measurement>> {
    let names: Vec<&str> = catalogue.iter().map(|o| o.name.as_str()).collect();
    t.check_keys(&names, &[], "")?;
    let value_expected = "a finite, non-zero measured value (errors are relative to it)";
    let entry_expected = "a measured value: { value = v, uncertainty = u } or a number";
    let paths: Vec<String> = t.entries.iter().map(|e| t.key(&e.key)).collect();
    let mut out = Vec::new();
    for (e, path) in t.entries.iter().zip(&paths) {
        let (value, uncertainty) = match &e.node.val {
            Val::Table(entries) => {
                let m = Tab { doc: t.doc, path, node: &e.node, entries };
                m.check_keys(&["value", "uncertainty"], &[], "")?;
                let value = m.required("value", value_expected, m.number("value", value_expected, |x| x != 0.0)?)?;
                let uncertainty =
                    m.number("uncertainty", "a non-negative standard uncertainty in the value's unit", non_negative)?;
                (value, uncertainty)
            }
            _ => match as_number(&e.node) {
                Some(v) if v.is_finite() && v != 0.0 => (v, None),
                _ => return Err(t.invalid(&e.key, Some(&e.node), entry_expected)),
            },
        };
        out.push(Measurement { name: e.key.clone(), value, uncertainty });
    }
    // The catalogue's order (the parser's is not the file's).
    out.sort_by_key(|m| names.iter().position(|n| *n == m.name));
    Ok(out)
}

/// A library material by `name` for the key `k` of table `t`.
fn library_material(t: &Tab<'_>, doc: &Doc, k: &str) -> Result<crate::material::Material> {
    let e = "the name of a material of the library";
    let name = t.required(k, e, t.string(k, e, |s| !s.trim().is_empty())?)?;
    named_material(t, doc, k, name)
}

/// The material `name` of the key `k` of table `t`, from the scene's material search path
/// ([`crate::material::search`]); the error names the places searched and the names found there.
fn named_material(t: &Tab<'_>, doc: &Doc, k: &str, name: &str) -> Result<crate::material::Material> {
    let search = &doc.materials;
    let lib = search
        .library()
        .map_err(|err| t.invalid(k, t.get(k), format!("a material of the library ({search}): {err}")))?;
    lib.get(name).cloned().map_err(|_| {
        let names = lib.names().collect::<Vec<_>>().join(", ");
        // An empty list said "one of " and nothing (issue 27 #9): say where nothing was found instead.
        let choices = if names.is_empty() {
            format!("a material of the library, but no material files were found in {search}")
        } else {
            format!("a material of the library ({search}): one of {names}")
        };
        t.invalid(k, t.get(k), choices)
    })
}

/// Number of lattice points on an axis of length `extent`.
pub(super) fn points_on_axis(extent: f64, dx: f64, lattice: Lattice) -> usize {
    let n = (extent / dx + 1e-9).floor();
    let n = if n.is_finite() && n > 0.0 { n as usize } else { 0 };
    match lattice {
        Lattice::Nodes => n + 1,
        Lattice::Cells => n,
    }
}

/// One `[[body]]`; also returns the number of points of its bounding-box lattice.
fn body(t: &Tab<'_>, index: usize, dim: usize, dx: f64, earlier: &[Body]) -> Result<(Body, f64)> {
    let names: Vec<&str> = SHAPES.iter().map(|s| s.0).collect();
    let shape_expected = format!(
        "one of {}",
        names.iter().filter(|n| dim_of(n) == dim).map(|n| format!("\"{n}\"")).collect::<Vec<_>>().join(", ")
    );
    // Unknown keys first, against every shape's parameters when the shape itself is unknown.
    let all: Vec<&str> = SHAPES.iter().flat_map(|s| s.1.iter().copied()).collect();
    let kind = match t.get("shape") {
        Some(Node { val: Val::Leaf(toml::Value::String(s)), .. }) if names.contains(&s.as_str()) => Some(s.as_str()),
        _ => None,
    };
    match kind {
        Some(kind) => {
            let own = SHAPES.iter().find(|s| s.0 == kind).map_or(&[][..], |s| s.1);
            let allowed: Vec<&str> = BODY_KEYS.iter().chain(own).copied().collect();
            t.check_keys(&allowed, &all, &format!(" for shape '{kind}'"))?;
        }
        None => {
            let mut allowed: Vec<&str> = BODY_KEYS.to_vec();
            for k in &all {
                if !allowed.contains(k) {
                    allowed.push(k);
                }
            }
            t.check_keys(&allowed, &[], "")?;
        }
    }
    let name_expected = "a non-empty string, unique among the bodies";
    let name = match t.string("name", name_expected, |s| !s.trim().is_empty())? {
        Some(n) => n.to_string(),
        None => format!("body{index}"),
    };
    if earlier.iter().any(|b| b.name == name) {
        return Err(t.invalid("name", t.get("name"), format!("{name_expected} ('{name}' is taken)")));
    }
    let kind = t.required("shape", &shape_expected, t.string("shape", &shape_expected, |s| names.contains(&s))?)?;
    if dim_of(kind) != dim {
        return Err(t.invalid("shape", t.get("shape"), format!("{shape_expected} (dim = {dim})")));
    }

    let (shape, extents) = shape(t, kind, dim)?;

    let e = point_text("a velocity", dim, "m/s");
    let velocity = t.vector("velocity", dim, &e)?.unwrap_or([0.0; 3]);
    let angular_velocity = t.number("angular_velocity", "an angular velocity in rad/s", any)?.unwrap_or(0.0);
    let lattice = t.named("lattice", "\"nodes\" or \"cells\"", Lattice::parse)?.unwrap_or(shape.default_lattice());
    let points = (0..dim).map(|k| points_on_axis(extents[k], dx, lattice) as f64).product();
    // A body's own library material supplies its thermal data (per-material conductivity and heat capacity);
    // mechanics uses the scene's material, so a body material must not disagree with it elastically.
    let material = match t.string("material", "the name of a material of the library", |s| !s.trim().is_empty())? {
        Some(mname) => Some(named_material(t, t.doc, "material", mname)?),
        None => None,
    };
    let temperature = t.number("temperature", "a positive temperature in K", positive)?;
    Ok((Body { name, shape, velocity, angular_velocity, lattice, material, temperature }, points))
}

/// A body's shape (`kind`, already checked against the dimension) and its extents along each axis [m].
fn shape(t: &Tab<'_>, kind: &str, dim: usize) -> Result<(Shape, [f64; 3])> {
    let radius_text = "a positive radius in m";
    let inner_text = |outer: &str| format!("a radius in m, >= 0 and < {outer}");
    let center = |t: &Tab<'_>| {
        let e = point_text("a point", dim, "m");
        t.required("center", &e, t.vector("center", dim, &e)?)
    };
    Ok(match kind {
        "rectangle" | "box" => {
            let e = point_text("a point", dim, "m");
            let min = t.required("min", &e, t.vector("min", dim, &e)?)?;
            let e_max = format!("{} greater than min on every axis", point_text("a point", dim, "m"));
            let max = t.required("max", &e_max, t.vector("max", dim, &e_max)?)?;
            if (0..dim).any(|k| max[k] <= min[k]) {
                return Err(t.invalid("max", t.get("max"), e_max));
            }
            let extents = std::array::from_fn(|k| if k < dim { max[k] - min[k] } else { 0.0 });
            let shape = if dim == 2 {
                Shape::Rectangle { min: [min[0], min[1]], max: [max[0], max[1]] }
            } else {
                Shape::Box { min, max }
            };
            (shape, extents)
        }
        "disk" => {
            let c = center(t)?;
            let radius = t.required("radius", radius_text, t.number("radius", radius_text, positive)?)?;
            (Shape::Disk { center: [c[0], c[1]], radius }, [2.0 * radius, 2.0 * radius, 0.0])
        }
        "ring" | "spherical_shell" => {
            let c = center(t)?;
            let outer = t.required("outer_radius", radius_text, t.number("outer_radius", radius_text, positive)?)?;
            let e = inner_text("outer_radius");
            let inner = t.required("inner_radius", &e, t.number("inner_radius", &e, non_negative)?)?;
            if inner >= outer {
                return Err(t.invalid("inner_radius", t.get("inner_radius"), e));
            }
            let d = 2.0 * outer;
            if dim == 2 {
                (Shape::Ring { center: [c[0], c[1]], inner_radius: inner, outer_radius: outer }, [d, d, 0.0])
            } else {
                (Shape::SphericalShell { center: c, inner_radius: inner, outer_radius: outer }, [d, d, d])
            }
        }
        "cylinder" => {
            let c = center(t)?;
            let radius = t.required("radius", radius_text, t.number("radius", radius_text, positive)?)?;
            let e = "a positive height in m";
            let height = t.required("height", e, t.number("height", e, positive)?)?;
            let e = inner_text("radius");
            let inner = t.number("inner_radius", &e, non_negative)?.unwrap_or(0.0);
            if inner >= radius {
                return Err(t.invalid("inner_radius", t.get("inner_radius"), e));
            }
            (Shape::Cylinder { center: c, radius, height, inner_radius: inner }, [2.0 * radius, 2.0 * radius, height])
        }
        _ => unreachable!("shape checked above"),
    })
}

fn dim_of(shape: &str) -> usize {
    match shape {
        "rectangle" | "disk" | "ring" => 2,
        _ => 3,
    }
}

fn boundary(t: &Tab<'_>, dim: usize, bodies: &[Body]) -> Result<Boundary> {
    t.check_keys(&["kind", "min", "max", "velocity", "body", "temperature", "reverse_at"], &[], "")?;
    let kind_expected = "\"fixed\", \"velocity\", \"temperature\" or (3D) \"plane_strain\"";
    let kinds: &[&str] = if dim == 3 {
        &["fixed", "velocity", "temperature", "plane_strain"]
    } else {
        &["fixed", "velocity", "temperature"]
    };
    let kind = t.required("kind", kind_expected, t.string("kind", kind_expected, |s| kinds.contains(&s))?)?;
    if kind != "temperature"
        && let Some(v) = t.get("temperature")
    {
        return Err(t.invalid("temperature", Some(v), "no temperature unless kind = \"temperature\""));
    }
    let (min, max) = t.min_max(dim)?;
    let kind = if kind == "fixed" || kind == "plane_strain" {
        if let Some(v) = t.get("velocity") {
            return Err(t.invalid(
                "velocity",
                Some(v),
                format!("no velocity for kind = \"{kind}\" (remove it, or use kind = \"velocity\")"),
            ));
        }
        if kind == "fixed" { BoundaryKind::Fixed } else { BoundaryKind::PlaneStrain }
    } else if kind == "temperature" {
        if let Some(v) = t.get("velocity") {
            return Err(t.invalid("velocity", Some(v), "no velocity for kind = \"temperature\""));
        }
        BoundaryKind::Temperature { temperature: t.number("temperature", "a positive temperature in K", positive)? }
    } else {
        let e = format!("{} for kind = \"velocity\"", point_text("a velocity", dim, "m/s"));
        BoundaryKind::Velocity { velocity: t.required("velocity", &e, t.vector("velocity", dim, &e)?)? }
    };
    let names = bodies.iter().map(|b| format!("'{}'", b.name)).collect::<Vec<_>>().join(", ");
    let body_expected = format!("the name of a body (one of: {names})");
    let body = match t.string("body", &body_expected, |_| true)? {
        Some(name) => match bodies.iter().position(|b| b.name == name) {
            Some(i) => Some(i),
            None => return Err(t.invalid("body", t.get("body"), body_expected)),
        },
        None => None,
    };
    let reverse_at = reverse_at(t, &kind)?;
    Ok(Boundary { kind, min, max, body, reverse_at })
}

/// `reverse_at` (velocity boundaries only): increasing positive times [s] at which the prescribed velocity
/// changes sign (a load reversal).
fn reverse_at(t: &Tab<'_>, kind: &BoundaryKind) -> Result<Vec<f64>> {
    let Some(node) = t.get("reverse_at") else { return Ok(Vec::new()) };
    let expected = "an array of increasing positive times in s (kind = \"velocity\" only)";
    let bad = || t.invalid("reverse_at", Some(node), expected);
    let Val::Array(items) = &node.val else { return Err(bad()) };
    if !matches!(kind, BoundaryKind::Velocity { .. }) || items.is_empty() {
        return Err(bad());
    }
    let times: Vec<f64> = items.iter().map(as_number).collect::<Option<_>>().ok_or_else(bad)?;
    let increasing = times.windows(2).all(|w| w[0] < w[1]);
    if !increasing || times.iter().any(|x| !x.is_finite() || *x <= 0.0) {
        return Err(bad());
    }
    Ok(times)
}
