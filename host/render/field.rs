//! The field `swarf render` colours the particles by: a scalar array of the frame by its name, or a short name
//! people type (`T`, `eps`, `vmises`, ...), or a 3-component array (velocity) as its magnitude.

use std::path::Path;

use crate::output::vtu::{OwnedValues, ReadFrame};
use crate::{Error, Result};

/// Short names: (typed, the frame's array).
const ALIASES: &[(&str, &str)] = &[
    ("T", "temperature"),
    ("eps", "plastic_strain"),
    ("epsdot", "plastic_strain_rate"),
    ("vmises", "von_mises"),
    ("rho", "density"),
    ("p", "pressure"),
    ("vel", "velocity"),
];

/// Display unit and the factor from the frame's SI value to it (stresses in MPa: Pa ticks would be 1e9s).
fn unit(name: &str) -> (&'static str, f64) {
    match name {
        "temperature" => ("K", 1.0),
        "plastic_strain" => ("-", 1.0),
        "plastic_strain_rate" => ("1/s", 1.0),
        "von_mises" | "pressure" => ("MPa", 1e-6),
        "density" => ("kg/m³", 1.0),
        "velocity" => ("m/s", 1.0),
        _ => ("", 1.0),
    }
}

/// A resolved field.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    /// The frame's array name.
    pub name: String,
    /// "|velocity|" for a vector, else the name.
    pub label: String,
    pub unit: &'static str,
    scale: f64,
    components: usize,
}

impl Field {
    /// `requested` (a frame array or a short name) in `frame` (read from `file`); an error names the field and
    /// lists the ones available.
    pub fn resolve(requested: &str, frame: &ReadFrame, file: &Path) -> Result<Field> {
        let name = ALIASES.iter().find(|(a, _)| *a == requested).map_or(requested, |(_, n)| n);
        let found = frame.point_data.iter().find(|(n, c, _)| n == name && drawable(*c));
        let Some((_, components, _)) = found else {
            return Err(missing(requested, frame, file));
        };
        let (unit, scale) = unit(name);
        let label = if *components == 3 { format!("|{name}|") } else { name.to_string() };
        Ok(Field { name: name.to_string(), label, unit, scale, components: *components })
    }

    /// The field's values in display units, one per particle (a vector's magnitude); `None` if `frame` lacks it.
    pub fn values(&self, frame: &ReadFrame) -> Option<Vec<f64>> {
        let (_, c, v) = frame.point_data.iter().find(|(n, c, _)| *n == self.name && *c == self.components)?;
        let v: Vec<f64> = match v {
            OwnedValues::F64(v) => v.clone(),
            OwnedValues::F32(v) => v.iter().map(|&x| f64::from(x)).collect(),
            OwnedValues::U32(v) => v.iter().map(|&x| f64::from(x)).collect(),
            OwnedValues::I32(v) => v.iter().map(|&x| f64::from(x)).collect(),
        };
        let magnitude = |x: &[f64]| if x.len() == 1 { x[0] } else { x.iter().map(|y| y * y).sum::<f64>().sqrt() };
        Some(v.chunks(*c).map(|x| self.scale * magnitude(x)).collect())
    }
}

/// The error of a field that `frame` (read from `file`) lacks: it names the field and lists the available ones.
pub fn missing(requested: &str, frame: &ReadFrame, file: &Path) -> Error {
    Error::Scene(format!(
        "render: no field '{requested}' in {}; available: {}",
        file.display(),
        available(frame).join(", ")
    ))
}

/// Scalars and 3-vectors can be drawn; a 6-component tensor (stress) cannot (its von Mises value can).
fn drawable(components: usize) -> bool {
    components == 1 || components == 3
}

/// The frame's drawable arrays, each with its short name where it has one: `temperature (T)`.
pub fn available(frame: &ReadFrame) -> Vec<String> {
    frame
        .point_data
        .iter()
        .filter(|(_, c, _)| drawable(*c))
        .map(|(n, _, _)| match ALIASES.iter().find(|(_, a)| a == n) {
            Some((short, _)) => format!("{n} ({short})"),
            None => n.clone(),
        })
        .collect()
}
