//! Scene errors. Each names where the problem is (the file and line, or the `--set` argument it came from), the
//! key (a dotted path, the same one `--set` takes) and what was expected.

use std::fmt;

/// Where a key or value of a scene came from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Location {
    /// The scene file (or the origin given to [`super::Scene::from_str`]), with the 1-based line when known.
    File { file: String, line: Option<usize> },
    /// A `--set key=value` override; `arg` is the whole `key=value` text.
    Set { arg: String },
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::File { file, line: Some(line) } => write!(f, "{file}:{line}"),
            Location::File { file, line: None } => write!(f, "{file}"),
            Location::Set { arg } => write!(f, "--set {arg}"),
        }
    }
}

/// Everything that can go wrong between a scene file and its particles. Validation errors (`Syntax`,
/// `UnknownKey`, `Invalid`, `Override`) are all raised before any particle is generated; `EmptyBody`, `Overlap`
/// and `EmptyBoundary` come from [`super::Scene::generate`].
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scene file could not be read.
    Read {
        file: String,
        #[source]
        source: std::io::Error,
    },
    /// The text is not valid TOML.
    Syntax { at: Location, message: String },
    /// A key the schema does not know (a typo, or a parameter of another shape).
    UnknownKey {
        at: Location,
        /// Dotted path of the key, e.g. `materail` or `body.0.radius`.
        key: String,
        /// Extra context, e.g. ` for shape 'ring'`; empty when none.
        context: String,
        /// The keys allowed in that table.
        expected: Vec<String>,
    },
    /// A missing key, or a value of the wrong type or out of range.
    Invalid {
        at: Location,
        /// Dotted path of the key, e.g. `material.poisson_ratio`.
        key: String,
        /// The offending value as TOML text; `None` when the key is missing.
        value: Option<String>,
        /// What was expected, e.g. `a value in (-1, 0.5)`.
        expected: String,
    },
    /// A `--set` argument that cannot be applied (no `=`, empty key segment, index out of range, ...).
    Override { arg: String, message: String },
    /// A body whose shape contains no lattice point.
    EmptyBody { file: String, body: String, index: usize, dx: f64 },
    /// Two bodies whose particles come closer than half a lattice spacing.
    Overlap {
        file: String,
        first: String,
        second: String,
        /// The closest offending pair: a particle of `first`, then one of `second` (m).
        points: Box<[[f64; 3]; 2]>,
        /// The dimension of the scene (how many coordinates to print).
        dim: usize,
        distance: f64,
        limit: f64,
    },
    /// A boundary condition whose region (and body) contains no particle.
    EmptyBoundary { file: String, index: usize, kind: &'static str },
}

fn point(p: &[f64; 3], dim3: bool) -> String {
    if dim3 { format!("({}, {}, {})", p[0], p[1], p[2]) } else { format!("({}, {})", p[0], p[1]) }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneError::Read { file, source } => write!(f, "{file}: cannot read the scene file: {source}"),
            SceneError::Syntax { at, message } => write!(f, "{at}: invalid TOML: {message}"),
            SceneError::UnknownKey { at, key, context, expected } => {
                write!(f, "{at}: unknown key '{key}'{context} (expected one of: {})", expected.join(", "))
            }
            SceneError::Invalid { at, key, value, expected } => match (at, value) {
                (_, None) => write!(f, "{at}: {key}: missing; expected {expected}"),
                // The `--set key=value` text already shows the value.
                (Location::Set { .. }, Some(_)) => write!(f, "{at}: {key}: expected {expected}"),
                (_, Some(value)) => write!(f, "{at}: {key} = {value}: expected {expected}"),
            },
            SceneError::Override { arg, message } => write!(f, "--set {arg}: {message}"),
            SceneError::EmptyBody { file, body, index, dx } => write!(
                f,
                "{file}: body '{body}' (body.{index}) contains no lattice point: dx = {dx} m is too coarse for it"
            ),
            SceneError::Overlap { file, first, second, points, dim, distance, limit } => {
                let [a, b] = &**points;
                let dim3 = *dim == 3;
                write!(
                    f,
                    "{file}: bodies '{first}' and '{second}' overlap: particles at {} and {} are {distance:e} m \
                     apart, closer than 0.5·dx = {limit:e} m",
                    point(a, dim3),
                    point(b, dim3)
                )
            }
            SceneError::EmptyBoundary { file, index, kind } => write!(
                f,
                "{file}: boundary.{index} (kind = \"{kind}\") selects no particle: its region (and body) contains \
                 none"
            ),
        }
    }
}
