//! The material library (cases/materials/): loading, listing and evaluating named parameter sets.
//!
//! One parameter set per file, `cases/materials/<name>.toml`, built into the binary; [`search`] says where else
//! a name is looked up (`SWARF_MATERIALS`, a `materials/` folder beside the scene). Every number carries its
//! unit and source in a comment. The formulas live once in `swarf_kernels::material`: [`Material::sigma_y`] and [`FlowModel`] dispatch
//! to the kernel functions and never re-implement them.
//!
//! # Schema
//!
//! ```toml
//! name = "Ti6Al4V-Roethlin"          # required; must equal the file name without .toml
//! description = "..."                # required
//! source = "roethlin-solver.md §5.7 Tab 7.5"   # required: where the numbers come from
//!
//! [elastic]                          # optional (thermal-only materials have none)
//! density = 4430.0                   # kg/m^3, > 0
//! youngs_modulus = 110e9             # Pa, > 0
//! poisson_ratio = 0.35               # (-1, 0.5)
//!
//! [thermal]                          # optional; every key optional
//! density = 15250.0                  # kg/m^3, only where [elastic] is absent (thermal-only materials)
//! specific_heat = 562.0              # J/(kg K), > 0
//! conductivity = 6.8                 # W/(m K), >= 0
//! taylor_quinney = 0.9               # [0, 1]: fraction of plastic work turned into heat
//! reference_temperature = 300.0      # K: the flow-stress model's reference (JC T0; SCG shear modulus T_ref)
//! melt_temperature = 1836.0          # K: JC Tm; SCGL T_m0 (melt at ρ = ρ0); bilinear: reported only
//!
//! [flow_stress]                      # optional (elastic-only materials have none)
//! model = "johnson_cook"             # see below
//! # model parameters in SI (Pa, 1/s, K), except SCGL's U_k in eV
//! ```
//!
//! `[flow_stress]` keys per `model` (the JC family reads T0 and Tm from `[thermal]`, which must give both):
//!
//! | model | keys |
//! |---|---|
//! | `johnson_cook` | `A`, `B` [Pa], `C`, `n`, `m`, `reference_strain_rate` [1/s], `rate_form` (`"clamp"` default, or `"uintah"`) |
//! | `calamaz_2008` | the JC keys + `a`, `b`, `c`, `d` |
//! | `calamaz_2010` | the JC keys + `eps0`, `p`, `T_rec` [K], `q` |
//! | `calamaz_2011` | the JC keys + `a` |
//! | `sima_ozel_1` | the JC keys + `M`, `p`, `r`, `S` |
//! | `sima_ozel_2` | the JC keys + `b`, `d`, `r`, `S` |
//! | `sima_ozel_3` | the JC keys + `a`, `b`, `d`, `r`, `S` |
//! | `scgl` | `sigma_a`, `sigma_max` [Pa], `beta`, `eps_i`, `n`, `C1` [1/s], `U_k` [eV], `sigma_p` [Pa], `C2` [Pa s], `mu0` [Pa], `dmu_dp`, `dmu_dT` [Pa/K], `gamma0`, `melt_a`; T_ref and T_m0 from `[thermal]` |
//! | `bilinear` | `yield_stress` [Pa], `plastic_modulus` [Pa] (H = dσ_y/dε̄, not the tangent modulus) |
//!
//! `[damage]` (optional; docs/damage.md): the fracture strain of ductile damage and the fracture energy of its
//! evolution (`swarf_kernels::damage`):
//!
//! | model | keys |
//! |---|---|
//! | `jc` | `D1`..`D5`, `reference_strain_rate` [1/s], `reference_temperature`, `melt_temperature` [K] (default: `[thermal]`'s) |
//! | `jc_gg` | the JC keys + `D6`, `D7`, `D8` (Gerstgrasser's T_term, capped at 2.5) |
//! | `rice_tracey` | `D1` (D_RT1), `D2` (D_RT2) |
//!
//! plus, for any model, either `fracture_energy` G_f [J/m²] or `fracture_toughness` K_1C [Pa √m] (then
//! G_f = K_1C² (1 − ν²)/E with `[elastic]`'s E and ν), or neither (no softening: full damage at initiation). D3 is
//! used as exp(−|D3| σ*), so either sign of the printed value gives the same strain (klippel §2.6 [NOTE]).
//!
//! The equations behind each key are documented on the kernel parameter structs (`swarf_kernels::material`).
//! Unknown keys are refused; every error names the file, the line where known, the dotted key and what was
//! expected.

pub mod report;
pub mod search;

use crate::error::line_of;
use std::collections::{BTreeMap, HashMap};
use std::fmt;
use std::path::{Path, PathBuf};

use swarf_kernels::material::{
    Bilinear, Calamaz2008, Calamaz2010, Calamaz2011, Flow, FlowStress, JohnsonCook, RATE_FORM_CLAMP, RATE_FORM_UINTAH,
    ReturnOptions, ReturnResult, Scgl, SimaOzel1, SimaOzel2, SimaOzel3, plastic_heating, radial_return,
};

/// Boltzmann's constant [eV/K] (CODATA 2018, exact in SI), to store SCGL's U_k as U_k/k_B.
pub const BOLTZMANN_EV: f64 = 8.617333262e-5;

/// Linear elasticity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Elastic {
    /// ρ0 [kg/m³].
    pub density: f64,
    /// E [Pa].
    pub youngs_modulus: f64,
    /// ν [-].
    pub poisson_ratio: f64,
}

impl Elastic {
    /// G = E/(2(1 + ν)) [Pa].
    pub fn shear_modulus(&self) -> f64 {
        self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))
    }

    /// K = E/(3(1 − 2ν)) [Pa].
    pub fn bulk_modulus(&self) -> f64 {
        self.youngs_modulus / (3.0 * (1.0 - 2.0 * self.poisson_ratio))
    }

    /// Bulk sound speed c0 = √(K/ρ0) [m/s] (roethlin-solver.md §2.3; AT-21).
    pub fn sound_speed(&self) -> f64 {
        (self.bulk_modulus() / self.density).sqrt()
    }
}

/// Thermal properties; every entry optional.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Thermal {
    /// ρ [kg/m³] of a thermal-only material (otherwise in [`Elastic`]).
    pub density: Option<f64>,
    /// c_p [J/(kg K)].
    pub specific_heat: Option<f64>,
    /// k [W/(m K)].
    pub conductivity: Option<f64>,
    /// Taylor–Quinney coefficient t_q [-].
    pub taylor_quinney: Option<f64>,
    /// Reference temperature of the flow-stress model [K].
    pub reference_temperature: Option<f64>,
    /// Melt temperature [K].
    pub melt_temperature: Option<f64>,
}

/// A flow-stress model with its kernel parameter block.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FlowModel {
    JohnsonCook(JohnsonCook),
    Calamaz2008(Calamaz2008),
    Calamaz2010(Calamaz2010),
    Calamaz2011(Calamaz2011),
    SimaOzel1(SimaOzel1),
    SimaOzel2(SimaOzel2),
    SimaOzel3(SimaOzel3),
    Scgl(Scgl),
    Bilinear(Bilinear),
}

/// The `model` names of `[flow_stress]`.
pub const MODEL_NAMES: &[&str] = &[
    "johnson_cook",
    "calamaz_2008",
    "calamaz_2010",
    "calamaz_2011",
    "sima_ozel_1",
    "sima_ozel_2",
    "sima_ozel_3",
    "scgl",
    "bilinear",
];

macro_rules! dispatch {
    ($self:expr, $m:ident => $e:expr) => {
        match $self {
            FlowModel::JohnsonCook($m) => $e,
            FlowModel::Calamaz2008($m) => $e,
            FlowModel::Calamaz2010($m) => $e,
            FlowModel::Calamaz2011($m) => $e,
            FlowModel::SimaOzel1($m) => $e,
            FlowModel::SimaOzel2($m) => $e,
            FlowModel::SimaOzel3($m) => $e,
            FlowModel::Scgl($m) => $e,
            FlowModel::Bilinear($m) => $e,
        }
    };
}

impl FlowModel {
    /// The `model` key of this model.
    pub fn name(&self) -> &'static str {
        match self {
            FlowModel::JohnsonCook(_) => "johnson_cook",
            FlowModel::Calamaz2008(_) => "calamaz_2008",
            FlowModel::Calamaz2010(_) => "calamaz_2010",
            FlowModel::Calamaz2011(_) => "calamaz_2011",
            FlowModel::SimaOzel1(_) => "sima_ozel_1",
            FlowModel::SimaOzel2(_) => "sima_ozel_2",
            FlowModel::SimaOzel3(_) => "sima_ozel_3",
            FlowModel::Scgl(_) => "scgl",
            FlowModel::Bilinear(_) => "bilinear",
        }
    }

    /// σ_y(ε̄, ε̄̇, T) [Pa] (the kernel's `FlowStress::sigma_y`).
    pub fn sigma_y(&self, eps: f64, rate: f64, temp: f64) -> f64 {
        dispatch!(self, m => m.sigma_y(eps, rate, temp))
    }

    /// σ_y and its partials (the kernel's `FlowStress::flow`).
    pub fn flow(&self, eps: f64, rate: f64, temp: f64) -> Flow {
        dispatch!(self, m => m.flow(eps, rate, temp))
    }

    /// The model's melt temperature [K].
    pub fn melt_temperature(&self) -> f64 {
        dispatch!(self, m => m.melt_temperature())
    }

    /// The kernel's radial return with this model (see `swarf_kernels::material::radial_return`).
    #[allow(clippy::too_many_arguments)]
    pub fn radial_return(
        &self,
        s_trial: &[f64; 6],
        eps: f64,
        rate: f64,
        temp: f64,
        shear: f64,
        dt: f64,
        opts: &ReturnOptions,
    ) -> ReturnResult {
        dispatch!(self, m => radial_return(m, s_trial, eps, rate, temp, shear, dt, opts))
    }

    /// The Johnson–Cook block shared by the JC family (None for SCGL and bilinear).
    pub fn johnson_cook(&self) -> Option<&JohnsonCook> {
        match self {
            FlowModel::JohnsonCook(m) => Some(m),
            FlowModel::Calamaz2008(m) => Some(&m.jc),
            FlowModel::Calamaz2010(m) => Some(&m.jc),
            FlowModel::Calamaz2011(m) => Some(&m.jc),
            FlowModel::SimaOzel1(m) => Some(&m.jc),
            FlowModel::SimaOzel2(m) => Some(&m.jc),
            FlowModel::SimaOzel3(m) => Some(&m.jc),
            FlowModel::Scgl(_) | FlowModel::Bilinear(_) => None,
        }
    }

    /// This model with the Johnson–Cook block's low-rate form set to Uintah's (1 + ε̇*)^C, the only form of the
    /// original 2D code (`model = "mfree_iwf"`, roethlin-solver.md §11 erratum 9); SCGL and bilinear unchanged.
    pub fn with_uintah_rate(mut self) -> FlowModel {
        let jc = match &mut self {
            FlowModel::JohnsonCook(m) => Some(m),
            FlowModel::Calamaz2008(m) => Some(&mut m.jc),
            FlowModel::Calamaz2010(m) => Some(&mut m.jc),
            FlowModel::Calamaz2011(m) => Some(&mut m.jc),
            FlowModel::SimaOzel1(m) => Some(&mut m.jc),
            FlowModel::SimaOzel2(m) => Some(&mut m.jc),
            FlowModel::SimaOzel3(m) => Some(&mut m.jc),
            FlowModel::Scgl(_) | FlowModel::Bilinear(_) => None,
        };
        if let Some(jc) = jc {
            jc.rate_form = RATE_FORM_UINTAH;
        }
        self
    }
}

/// One named parameter set.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
    pub description: String,
    pub source: String,
    /// The file it was read from (for a built-in material, `built-in:<name>.toml`).
    pub file: PathBuf,
    /// The file's text: a run folder records it (`materials/<name>.toml`), so that it holds the values it ran.
    pub text: String,
    pub elastic: Option<Elastic>,
    pub thermal: Option<Thermal>,
    pub flow_stress: Option<FlowModel>,
    /// Ductile damage constants (`[damage]`), if given.
    pub damage: Option<DamageConstants>,
}

/// A material's damage constants (`[damage]`): the fracture-strain model and its constants, and G_f.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DamageConstants {
    /// `swarf_kernels::damage::model`.
    pub model: u32,
    /// D1..D8 (JC, JC-GG; zero where the model has fewer), D_RT1 and D_RT2 in d[0], d[1] (Rice–Tracey).
    pub d: [f64; 8],
    pub reference_strain_rate: f64,
    pub reference_temperature: f64,
    pub melt_temperature: f64,
    /// G_f [J/m²] (given, or from K_1C); None: no softening.
    pub fracture_energy: Option<f64>,
}

/// The damage models' names in `[damage]` and scenes, by `swarf_kernels::damage::model` index.
pub const DAMAGE_MODEL_NAMES: &[&str] = &["jc", "jc_gg", "rice_tracey"];

impl DamageConstants {
    /// The model's name ([`DAMAGE_MODEL_NAMES`]).
    pub fn model_name(&self) -> &'static str {
        DAMAGE_MODEL_NAMES.get(self.model as usize).copied().unwrap_or("jc")
    }
}

impl Material {
    /// Reads and validates one material file.
    pub fn load(path: &Path) -> Result<Material, MaterialError> {
        let file = path.display().to_string();
        let text =
            std::fs::read_to_string(path).map_err(|source| MaterialError::Read { file: file.clone(), source })?;
        let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned());
        let mut m = Material::parse(&text, &file, stem.as_deref())?;
        m.file = path.to_path_buf();
        Ok(m)
    }

    /// Parses a material from TOML text; `file` names it in errors; `stem`, when given, must equal `name`.
    pub fn parse(text: &str, file: &str, stem: Option<&str>) -> Result<Material, MaterialError> {
        let ctx = Ctx::new(text, file)?;
        let root: toml::Table = toml::from_str(text).map_err(|e| ctx.syntax(e))?;
        ctx.check_keys(&root, "", &["name", "description", "source", "elastic", "thermal", "flow_stress", "damage"])?;
        let name =
            ctx.required(&root, "", "name", "a string: the file name without .toml", ctx.string(&root, "", "name")?)?;
        if let Some(stem) = stem
            && name != stem
        {
            return Err(ctx.invalid("", "name", Some(format!("\"{name}\"")), format!("\"{stem}\" (the file name)")));
        }
        let description = ctx.required(&root, "", "description", "a string", ctx.string(&root, "", "description")?)?;
        let source =
            ctx.required(&root, "", "source", "a string naming the source", ctx.string(&root, "", "source")?)?;

        let elastic = match ctx.table(&root, "", "elastic")? {
            None => None,
            Some(t) => Some(parse_elastic(&ctx, t)?),
        };
        let thermal = match ctx.table(&root, "", "thermal")? {
            None => None,
            Some(t) => Some(parse_thermal(&ctx, t, elastic.is_some())?),
        };
        let flow_stress = match ctx.table(&root, "", "flow_stress")? {
            None => None,
            Some(t) => Some(parse_flow(&ctx, t, thermal.as_ref())?),
        };
        let damage = match ctx.table(&root, "", "damage")? {
            None => None,
            Some(t) => Some(parse_damage(&ctx, t, elastic.as_ref(), thermal.as_ref())?),
        };
        Ok(Material {
            damage,
            name: name.to_string(),
            description: description.to_string(),
            source: source.to_string(),
            file: PathBuf::from(file),
            text: text.to_string(),
            elastic,
            thermal,
            flow_stress,
        })
    }

    /// σ_y(ε̄, ε̄̇, T) [Pa] through the kernel function; +∞ for a material without `[flow_stress]` (it never
    /// yields).
    pub fn sigma_y(&self, eps: f64, rate: f64, temp: f64) -> f64 {
        self.flow_stress.as_ref().map_or(f64::INFINITY, |m| m.sigma_y(eps, rate, temp))
    }

    /// ρ [kg/m³] from `[elastic]`, or `[thermal]` for thermal-only materials.
    pub fn density(&self) -> Option<f64> {
        self.elastic.map(|e| e.density).or(self.thermal.and_then(|t| t.density))
    }

    /// G [Pa], when elastic.
    pub fn shear_modulus(&self) -> Option<f64> {
        self.elastic.map(|e| e.shear_modulus())
    }

    /// Plastic heating ΔT = t_q σ_y Δε̄/(ρ c_p) [K] (the kernel's `plastic_heating`); None without ρ, c_p or t_q.
    pub fn plastic_heating(&self, sigma_y: f64, d_eps: f64) -> Option<f64> {
        let t = self.thermal?;
        Some(plastic_heating(t.taylor_quinney?, sigma_y, d_eps, self.density()?, t.specific_heat?))
    }
}

/// All materials of a directory, by name.
#[derive(Clone, Debug, Default)]
pub struct Library {
    materials: BTreeMap<String, Material>,
}

impl Library {
    /// Loads every `*.toml` of `dir` (not recursive); the first invalid file is the error.
    pub fn load_dir(dir: impl AsRef<Path>) -> Result<Library, MaterialError> {
        let dir = dir.as_ref();
        let read_err = |source| MaterialError::Read { file: dir.display().to_string(), source };
        let mut paths = Vec::new();
        for entry in std::fs::read_dir(dir).map_err(read_err)? {
            let path = entry.map_err(read_err)?.path();
            if path.is_file() && path.extension().is_some_and(|e| e == "toml") {
                paths.push(path);
            }
        }
        paths.sort();
        let mut materials: BTreeMap<String, Material> = BTreeMap::new();
        for path in paths {
            let m = Material::load(&path)?;
            if let Some(first) = materials.get(&m.name) {
                return Err(MaterialError::Duplicate {
                    name: m.name.clone(),
                    first: first.file.display().to_string(),
                    second: path.display().to_string(),
                });
            }
            materials.insert(m.name.clone(), m);
        }
        Ok(Library { materials })
    }

    /// Adds the materials of `other` whose names this library lacks (an earlier folder of a search path shadows a
    /// later one).
    pub fn add_missing(&mut self, other: Library) {
        for (name, m) in other.materials {
            self.materials.entry(name).or_insert(m);
        }
    }

    /// The material `name`; the error lists the available names.
    pub fn get(&self, name: &str) -> Result<&Material, MaterialError> {
        self.materials.get(name).ok_or_else(|| MaterialError::NotFound {
            name: name.to_string(),
            available: self.names().map(String::from).collect(),
        })
    }

    /// Names in sorted order.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.materials.keys().map(String::as_str)
    }

    /// Materials in name order.
    pub fn iter(&self) -> impl Iterator<Item = &Material> {
        self.materials.values()
    }

    pub fn len(&self) -> usize {
        self.materials.len()
    }

    pub fn is_empty(&self) -> bool {
        self.materials.is_empty()
    }
}

/// Everything that can go wrong loading a material. Each names the file (and line where known), the dotted key and
/// what was expected.
#[derive(Debug, thiserror::Error)]
pub enum MaterialError {
    /// The file or directory could not be read.
    #[error("{file}: {source}")]
    Read {
        file: String,
        #[source]
        source: std::io::Error,
    },
    /// Not valid TOML.
    #[error("{}: {message}", at(file, *line))]
    Syntax { file: String, line: Option<usize>, message: String },
    /// A key the schema does not know.
    #[error("{}: unknown key {key}{context}; expected one of: {}", at(file, *line), expected.join(", "))]
    UnknownKey {
        file: String,
        line: Option<usize>,
        /// Dotted path, e.g. `flow_stress.AA`.
        key: String,
        /// e.g. ` for model 'johnson_cook'`; empty when none.
        context: String,
        expected: Vec<String>,
    },
    /// A missing key, or a value of the wrong type or out of range.
    #[error("{}: {key}{}: expected {expected}", at(file, *line), value.as_ref().map_or(" missing".to_string(), |v| format!(" = {v}")))]
    Invalid {
        file: String,
        line: Option<usize>,
        key: String,
        /// The offending value as TOML text; None when missing.
        value: Option<String>,
        expected: String,
    },
    /// Two files define the same name.
    #[error("material '{name}' is defined twice: {first} and {second}")]
    Duplicate { name: String, first: String, second: String },
    /// `Library::get` of an unknown name.
    #[error("unknown material '{name}'; available: {}", available.join(", "))]
    NotFound { name: String, available: Vec<String> },
}

fn at(file: &str, line: Option<usize>) -> String {
    match line {
        Some(l) => format!("{file}:{l}"),
        None => file.to_string(),
    }
}

/// Parse context: the file name and the line of every dotted key.
struct Ctx<'a> {
    file: &'a str,
    lines: HashMap<String, usize>,
    text: &'a str,
}

fn collect_lines(table: &toml::de::DeTable<'_>, prefix: &str, text: &str, out: &mut HashMap<String, usize>) {
    for (k, v) in table.iter() {
        let key: &str = k.get_ref();
        let path = if prefix.is_empty() { key.to_string() } else { format!("{prefix}.{key}") };
        out.insert(path.clone(), line_of(text, k.span().start));
        if let toml::de::DeValue::Table(t) = v.get_ref() {
            collect_lines(t, &path, text, out);
        }
    }
}

fn dotted(path: &str, key: &str) -> String {
    if path.is_empty() { key.to_string() } else { format!("{path}.{key}") }
}

impl<'a> Ctx<'a> {
    fn new(text: &'a str, file: &'a str) -> Result<Ctx<'a>, MaterialError> {
        let mut ctx = Ctx { file, lines: HashMap::new(), text };
        let de = toml::de::DeTable::parse(text).map_err(|e| ctx.syntax(e))?;
        collect_lines(de.get_ref(), "", text, &mut ctx.lines);
        Ok(ctx)
    }

    fn syntax(&self, e: toml::de::Error) -> MaterialError {
        MaterialError::Syntax {
            file: self.file.to_string(),
            line: e.span().map(|s| line_of(self.text, s.start)),
            message: e.message().trim().to_string(),
        }
    }

    fn line(&self, path: &str, key: &str) -> Option<usize> {
        self.lines.get(&dotted(path, key)).or_else(|| self.lines.get(path)).copied()
    }

    fn invalid(&self, path: &str, key: &str, value: Option<String>, expected: impl Into<String>) -> MaterialError {
        MaterialError::Invalid {
            file: self.file.to_string(),
            line: self.line(path, key),
            key: dotted(path, key),
            value,
            expected: expected.into(),
        }
    }

    fn check_keys(&self, t: &toml::Table, path: &str, allowed: &[&str]) -> Result<(), MaterialError> {
        self.check_keys_for(t, path, allowed, "")
    }

    fn check_keys_for(
        &self,
        t: &toml::Table,
        path: &str,
        allowed: &[&str],
        context: &str,
    ) -> Result<(), MaterialError> {
        for k in t.keys() {
            if !allowed.contains(&k.as_str()) {
                return Err(MaterialError::UnknownKey {
                    file: self.file.to_string(),
                    line: self.line(path, k),
                    key: dotted(path, k),
                    context: context.to_string(),
                    expected: allowed.iter().map(|s| s.to_string()).collect(),
                });
            }
        }
        Ok(())
    }

    fn required<T>(
        &self,
        _t: &toml::Table,
        path: &str,
        key: &str,
        expected: &str,
        v: Option<T>,
    ) -> Result<T, MaterialError> {
        v.ok_or_else(|| self.invalid(path, key, None, expected))
    }

    fn string<'t>(&self, t: &'t toml::Table, path: &str, key: &str) -> Result<Option<&'t str>, MaterialError> {
        match t.get(key) {
            None => Ok(None),
            Some(toml::Value::String(s)) => Ok(Some(s.as_str())),
            Some(v) => Err(self.invalid(path, key, Some(v.to_string()), "a string")),
        }
    }

    fn table<'t>(
        &self,
        t: &'t toml::Table,
        path: &str,
        key: &str,
    ) -> Result<Option<(&'t toml::Table, String)>, MaterialError> {
        match t.get(key) {
            None => Ok(None),
            Some(toml::Value::Table(s)) => Ok(Some((s, dotted(path, key)))),
            Some(v) => Err(self.invalid(path, key, Some(v.to_string()), "a table")),
        }
    }

    /// An optional finite number satisfying `ok`.
    fn number(
        &self,
        t: &toml::Table,
        path: &str,
        key: &str,
        expected: &str,
        ok: impl Fn(f64) -> bool,
    ) -> Result<Option<f64>, MaterialError> {
        let x = match t.get(key) {
            None => return Ok(None),
            Some(toml::Value::Float(x)) => *x,
            Some(toml::Value::Integer(i)) => *i as f64,
            Some(v) => return Err(self.invalid(path, key, Some(v.to_string()), expected)),
        };
        if x.is_finite() && ok(x) { Ok(Some(x)) } else { Err(self.invalid(path, key, Some(x.to_string()), expected)) }
    }

    /// A required finite number satisfying `ok`.
    fn req(
        &self,
        t: &toml::Table,
        path: &str,
        key: &str,
        expected: &str,
        ok: impl Fn(f64) -> bool,
    ) -> Result<f64, MaterialError> {
        let v = self.number(t, path, key, expected, ok)?;
        self.required(t, path, key, expected, v)
    }
}

type Sub<'t> = (&'t toml::Table, String);

fn parse_elastic(ctx: &Ctx, (t, path): Sub) -> Result<Elastic, MaterialError> {
    ctx.check_keys(t, &path, &["density", "youngs_modulus", "poisson_ratio"])?;
    Ok(Elastic {
        density: ctx.req(t, &path, "density", "a density in kg/m^3 > 0", |x| x > 0.0)?,
        youngs_modulus: ctx.req(t, &path, "youngs_modulus", "a modulus in Pa > 0", |x| x > 0.0)?,
        poisson_ratio: ctx.req(t, &path, "poisson_ratio", "a value in (-1, 0.5)", |x| x > -1.0 && x < 0.5)?,
    })
}

fn parse_thermal(ctx: &Ctx, (t, path): Sub, has_elastic: bool) -> Result<Thermal, MaterialError> {
    ctx.check_keys(
        t,
        &path,
        &["density", "specific_heat", "conductivity", "taylor_quinney", "reference_temperature", "melt_temperature"],
    )?;
    let density = ctx.number(t, &path, "density", "a density in kg/m^3 > 0", |x| x > 0.0)?;
    if has_elastic && density.is_some() {
        return Err(ctx.invalid(
            &path,
            "density",
            density.map(|d| d.to_string()),
            "no thermal.density when [elastic] gives elastic.density (give it once)",
        ));
    }
    let th = Thermal {
        density,
        specific_heat: ctx.number(t, &path, "specific_heat", "a specific heat in J/(kg K) > 0", |x| x > 0.0)?,
        conductivity: ctx.number(t, &path, "conductivity", "a conductivity in W/(m K) >= 0", |x| x >= 0.0)?,
        taylor_quinney: ctx.number(t, &path, "taylor_quinney", "a value in [0, 1]", |x| (0.0..=1.0).contains(&x))?,
        reference_temperature: ctx
            .number(t, &path, "reference_temperature", "a temperature in K >= 0", |x| x >= 0.0)?,
        melt_temperature: ctx.number(t, &path, "melt_temperature", "a temperature in K > 1", |x| x > 1.0)?,
    };
    if let (Some(t0), Some(tm)) = (th.reference_temperature, th.melt_temperature)
        && tm <= t0 + 1.0
    {
        return Err(ctx.invalid(
            &path,
            "melt_temperature",
            Some(tm.to_string()),
            format!("a melt temperature above reference_temperature + 1 K = {} K", t0 + 1.0),
        ));
    }
    Ok(th)
}

/// `[damage]` (module doc).
fn parse_damage(
    ctx: &Ctx,
    (t, path): Sub,
    elastic: Option<&Elastic>,
    thermal: Option<&Thermal>,
) -> Result<DamageConstants, MaterialError> {
    use swarf_kernels::damage::model;
    let names = format!("one of: {}", DAMAGE_MODEL_NAMES.join(", "));
    let name = ctx.required(t, &path, "model", &names, ctx.string(t, &path, "model")?)?;
    let (index, d_keys): (u32, &[&str]) = match name {
        "jc" => (model::JC, &["D1", "D2", "D3", "D4", "D5"]),
        "jc_gg" => (model::JC_GG, &["D1", "D2", "D3", "D4", "D5", "D6", "D7", "D8"]),
        "rice_tracey" => (model::RICE_TRACEY, &["D1", "D2"]),
        other => return Err(ctx.invalid(&path, "model", Some(format!("\"{other}\"")), names)),
    };
    let jc = index != model::RICE_TRACEY;
    let mut allowed = vec!["model", "fracture_energy", "fracture_toughness"];
    allowed.extend_from_slice(d_keys);
    if jc {
        allowed.extend_from_slice(&["reference_strain_rate", "reference_temperature", "melt_temperature"]);
    }
    ctx.check_keys_for(t, &path, &allowed, &format!(" for damage model '{name}'"))?;
    let mut d = [0.0; 8];
    for (k, key) in d_keys.iter().enumerate() {
        d[k] = ctx.req(t, &path, key, "a finite number", |_| true)?;
    }
    let (mut rate, mut t_ref, mut t_melt) = (1.0, 0.0, 1.0);
    if jc {
        rate = ctx.req(t, &path, "reference_strain_rate", "a strain rate in 1/s > 0", positive)?;
        let th_ref = thermal.and_then(|th| th.reference_temperature);
        let th_melt = thermal.and_then(|th| th.melt_temperature);
        t_ref = match ctx.number(t, &path, "reference_temperature", "a temperature in K >= 0", non_negative)? {
            Some(x) => x,
            None => ctx.required(t, &path, "reference_temperature", "a temperature in K (or [thermal]'s)", th_ref)?,
        };
        t_melt = match ctx.number(t, &path, "melt_temperature", "a temperature in K > 1", |x| x > 1.0)? {
            Some(x) => x,
            None => ctx.required(t, &path, "melt_temperature", "a temperature in K (or [thermal]'s)", th_melt)?,
        };
        if t_melt <= t_ref {
            return Err(ctx.invalid(
                &path,
                "melt_temperature",
                Some(t_melt.to_string()),
                format!("a melt temperature above the reference temperature {t_ref} K"),
            ));
        }
    }
    let gf = ctx.number(t, &path, "fracture_energy", "a fracture energy G_f in J/m^2 > 0", positive)?;
    let k1c = ctx.number(t, &path, "fracture_toughness", "a fracture toughness K_1C in Pa m^0.5 > 0", positive)?;
    let fracture_energy = match (gf, k1c) {
        (Some(_), Some(k)) => {
            return Err(ctx.invalid(
                &path,
                "fracture_toughness",
                Some(k.to_string()),
                "either fracture_energy or fracture_toughness, not both",
            ));
        }
        (Some(g), None) => Some(g),
        (None, Some(k)) => {
            let el =
                ctx.required(t, &path, "fracture_toughness", "fracture_energy (no [elastic] for E, ν)", elastic)?;
            Some(swarf_kernels::damage::fracture_energy_from_toughness(k, el.youngs_modulus, el.poisson_ratio))
        }
        (None, None) => None,
    };
    Ok(DamageConstants {
        model: index,
        d,
        reference_strain_rate: rate,
        reference_temperature: t_ref,
        melt_temperature: t_melt,
        fracture_energy,
    })
}

const JC_KEYS: &[&str] = &["model", "A", "B", "C", "n", "m", "reference_strain_rate", "rate_form"];

fn positive(x: f64) -> bool {
    x > 0.0
}

fn non_negative(x: f64) -> bool {
    x >= 0.0
}

fn parse_flow(ctx: &Ctx, (t, path): Sub, thermal: Option<&Thermal>) -> Result<FlowModel, MaterialError> {
    let model = ctx.required(
        t,
        &path,
        "model",
        &format!("one of: {}", MODEL_NAMES.join(", ")),
        ctx.string(t, &path, "model")?,
    )?;
    let extra: &[&str] = match model {
        "johnson_cook" => &[],
        "calamaz_2008" => &["a", "b", "c", "d"],
        "calamaz_2010" => &["eps0", "p", "T_rec", "q"],
        "calamaz_2011" => &["a"],
        "sima_ozel_1" => &["M", "p", "r", "S"],
        "sima_ozel_2" => &["b", "d", "r", "S"],
        "sima_ozel_3" => &["a", "b", "d", "r", "S"],
        "scgl" => {
            return parse_scgl(ctx, t, &path, thermal);
        }
        "bilinear" => {
            ctx.check_keys_for(t, &path, &["model", "yield_stress", "plastic_modulus"], " for model 'bilinear'")?;
            return Ok(FlowModel::Bilinear(Bilinear {
                yield_stress: ctx.req(t, &path, "yield_stress", "a stress in Pa >= 0", non_negative)?,
                plastic_modulus: ctx.req(t, &path, "plastic_modulus", "a modulus in Pa (dσ_y/dε̄, finite)", |_| true)?,
                melt_temp: thermal.and_then(|th| th.melt_temperature).unwrap_or(f64::INFINITY),
            }));
        }
        other => {
            return Err(ctx.invalid(
                &path,
                "model",
                Some(format!("\"{other}\"")),
                format!("one of: {}", MODEL_NAMES.join(", ")),
            ));
        }
    };
    let allowed: Vec<&str> = JC_KEYS.iter().chain(extra).copied().collect();
    ctx.check_keys_for(t, &path, &allowed, &format!(" for model '{model}'"))?;
    let jc = parse_jc(ctx, t, &path, thermal, model)?;
    let num = |k: &str, expected: &str, ok: fn(f64) -> bool| ctx.req(t, &path, k, expected, ok);
    let fraction = |x: f64| (0.0..=1.0).contains(&x);
    Ok(match model {
        "johnson_cook" => FlowModel::JohnsonCook(jc),
        "calamaz_2008" => FlowModel::Calamaz2008(Calamaz2008 {
            jc,
            a: num("a", "a value > 0", positive)?,
            b: num("b", "a value >= 0", non_negative)?,
            c: num("c", "a value > 0", positive)?,
            d: num("d", "a value > 0", positive)?,
        }),
        "calamaz_2010" => {
            let t_rec = num("T_rec", "a temperature in K", positive)?;
            if t_rec <= jc.ref_temp {
                return Err(ctx.invalid(
                    &path,
                    "T_rec",
                    Some(t_rec.to_string()),
                    format!("a temperature above thermal.reference_temperature = {} K", jc.ref_temp),
                ));
            }
            FlowModel::Calamaz2010(Calamaz2010 {
                jc,
                eps0: num("eps0", "a strain > 0", positive)?,
                p: num("p", "a value >= 0", non_negative)?,
                t_rec,
                q: num("q", "a value > 0", positive)?,
            })
        }
        "calamaz_2011" => FlowModel::Calamaz2011(Calamaz2011 { jc, a: num("a", "a value >= 0", non_negative)? }),
        "sima_ozel_1" => FlowModel::SimaOzel1(SimaOzel1 {
            jc,
            big_m: num("M", "a value in [0, 1]", fraction)?,
            p: num("p", "a value >= 0", non_negative)?,
            r: num("r", "a value > 0", positive)?,
            s: num("S", "a value > 0", positive)?,
        }),
        "sima_ozel_2" => FlowModel::SimaOzel2(SimaOzel2 {
            jc,
            b: num("b", "a value >= 0", non_negative)?,
            d: num("d", "a value > 0", positive)?,
            r: num("r", "a value > 0", positive)?,
            s: num("S", "a value > 0", positive)?,
        }),
        _ => FlowModel::SimaOzel3(SimaOzel3 {
            jc,
            a: num("a", "a value > 0", positive)?,
            b: num("b", "a value >= 0", non_negative)?,
            d: num("d", "a value > 0", positive)?,
            r: num("r", "a value > 0", positive)?,
            s: num("S", "a value > 0", positive)?,
        }),
    })
}

/// T0 and Tm of the JC family, from `[thermal]`.
fn jc_temperatures(ctx: &Ctx, thermal: Option<&Thermal>, model: &str) -> Result<(f64, f64), MaterialError> {
    let need = |key: &str| {
        ctx.invalid("thermal", key, None, format!("a temperature in K (required by flow_stress.model = '{model}')"))
    };
    let th = thermal.ok_or_else(|| need("reference_temperature"))?;
    Ok((
        th.reference_temperature.ok_or_else(|| need("reference_temperature"))?,
        th.melt_temperature.ok_or_else(|| need("melt_temperature"))?,
    ))
}

fn parse_jc(
    ctx: &Ctx,
    t: &toml::Table,
    path: &str,
    thermal: Option<&Thermal>,
    model: &str,
) -> Result<JohnsonCook, MaterialError> {
    let (ref_temp, melt_temp) = jc_temperatures(ctx, thermal, model)?;
    let rate_form = match ctx.string(t, path, "rate_form")? {
        None | Some("clamp") => RATE_FORM_CLAMP,
        Some("uintah") => RATE_FORM_UINTAH,
        Some(other) => {
            return Err(ctx.invalid(path, "rate_form", Some(format!("\"{other}\"")), "\"clamp\" or \"uintah\""));
        }
    };
    Ok(JohnsonCook {
        a: ctx.req(t, path, "A", "a stress in Pa >= 0", non_negative)?,
        b: ctx.req(t, path, "B", "a stress in Pa >= 0", non_negative)?,
        c: ctx.req(t, path, "C", "a value >= 0", non_negative)?,
        n: ctx.req(t, path, "n", "a value >= 0", non_negative)?,
        m: ctx.req(t, path, "m", "a value > 0", positive)?,
        ref_rate: ctx.req(t, path, "reference_strain_rate", "a strain rate in 1/s > 0", positive)?,
        ref_temp,
        melt_temp,
        rate_form,
        _pad: 0,
    })
}

fn parse_scgl(ctx: &Ctx, t: &toml::Table, path: &str, thermal: Option<&Thermal>) -> Result<FlowModel, MaterialError> {
    const KEYS: &[&str] = &[
        "model",
        "sigma_a",
        "sigma_max",
        "beta",
        "eps_i",
        "n",
        "C1",
        "U_k",
        "sigma_p",
        "C2",
        "mu0",
        "dmu_dp",
        "dmu_dT",
        "gamma0",
        "melt_a",
    ];
    ctx.check_keys_for(t, path, KEYS, " for model 'scgl'")?;
    let (ref_temp, melt_temp0) = jc_temperatures(ctx, thermal, "scgl")?;
    let num = |k: &str, expected: &str, ok: fn(f64) -> bool| ctx.req(t, path, k, expected, ok);
    let dmu_dt = num("dmu_dT", "a value in Pa/K <= 0 (the shear modulus falls with temperature)", |x| x <= 0.0)?;
    Ok(FlowModel::Scgl(Scgl {
        sigma_a: num("sigma_a", "a stress in Pa >= 0", non_negative)?,
        sigma_max: num("sigma_max", "a stress in Pa >= 0", non_negative)?,
        beta: num("beta", "a value >= 0", non_negative)?,
        eps_i: num("eps_i", "a strain >= 0", non_negative)?,
        n: num("n", "a value >= 0", non_negative)?,
        c1: num("C1", "a rate in 1/s > 0", positive)?,
        uk_over_kb: num("U_k", "an energy in eV > 0", positive)? / BOLTZMANN_EV,
        sigma_p: num("sigma_p", "a stress in Pa > 0", positive)?,
        c2: num("C2", "a drag coefficient in Pa s > 0", positive)?,
        mu0: num("mu0", "a modulus in Pa > 0", positive)?,
        dmu_dp: num("dmu_dp", "a value >= 0", non_negative)?,
        dmu_dt,
        ref_temp,
        melt_temp0,
        gamma0: num("gamma0", "a value > 0", positive)?,
        melt_a: num("melt_a", "a value >= 0", non_negative)?,
        pressure: 0.0,
        eta: 1.0,
    }))
}

impl fmt::Display for Material {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} ({})", self.name, self.flow_stress.as_ref().map_or("no flow stress", |m| m.name()))
    }
}
