//! Unit suffixes in scene files: where people think in other units, a length, speed, angle or temperature key
//! also takes a string of a number and a unit (`"381.3 m/min"`, `"33 um"`, `"10 deg"`, `"25 C"`), in a vector
//! element by element (`velocity = ["381.3 m/min", 0.0]`). A plain number keeps the key's documented unit (SI,
//! and degrees for the tool's angles); the scene holds, and the summary echoes, the converted value.

/// A kind of quantity, with the key's unit first among its units.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    /// m.
    Length,
    /// m/s.
    Speed,
    /// degree (the tool's angles are given in degrees).
    Angle,
    /// K.
    Temperature,
}

/// Each unit: its names and the conversion to the key's unit, x ↦ x·scale + offset.
type Unit = (&'static [&'static str], f64, f64);

impl Quantity {
    fn units(self) -> &'static [Unit] {
        match self {
            Quantity::Length => &[
                (&["m"], 1.0, 0.0),
                (&["cm"], 1e-2, 0.0),
                (&["mm"], 1e-3, 0.0),
                (&["um", "µm", "μm"], 1e-6, 0.0),
                (&["nm"], 1e-9, 0.0),
            ],
            Quantity::Speed => &[
                (&["m/s"], 1.0, 0.0),
                (&["m/min"], 1.0 / 60.0, 0.0),
                (&["mm/s"], 1e-3, 0.0),
                (&["mm/min"], 1e-3 / 60.0, 0.0),
                (&["km/h"], 1.0 / 3.6, 0.0),
            ],
            Quantity::Angle => &[(&["deg", "°"], 1.0, 0.0), (&["rad"], 180.0 / std::f64::consts::PI, 0.0)],
            Quantity::Temperature => &[(&["K"], 1.0, 0.0), (&["C", "°C", "degC"], 1.0, 273.15)],
        }
    }

    fn name(self) -> &'static str {
        match self {
            Quantity::Length => "length",
            Quantity::Speed => "speed",
            Quantity::Angle => "angle",
            Quantity::Temperature => "temperature",
        }
    }

    /// What a unit string may say, for messages: e.g. `a string "<number> <unit>" with a length unit: m, cm, …`.
    pub(super) fn help(self) -> String {
        let names: Vec<&str> = self.units().iter().flat_map(|(names, _, _)| names.iter().copied()).collect();
        format!("a string \"<number> <unit>\" with a {} unit: {}", self.name(), names.join(", "))
    }

    /// `text` ("381.3 m/min") in the key's unit; None if it is not a finite number and one of the units.
    pub fn parse(self, text: &str) -> Option<f64> {
        let text = text.trim();
        // The unit is a suffix whose rest is a number ("1e-3 m": not the "e").
        let units =
            self.units().iter().flat_map(|(names, scale, offset)| names.iter().map(move |n| (n, scale, offset)));
        let mut found = units.filter_map(|(name, scale, offset)| {
            let number = text.strip_suffix(name)?.trim();
            let x: f64 = number.parse().ok().filter(|x: &f64| x.is_finite())?;
            Some(x * scale + offset)
        });
        found.next().filter(|y| y.is_finite())
    }
}

/// The keys that take units, dotted, with array indices left out (`body.velocity` for `body.0.velocity`).
const KEYS: &[(&str, Quantity)] = &[
    ("discretisation.dx", Quantity::Length),
    ("body.center", Quantity::Length),
    ("body.min", Quantity::Length),
    ("body.max", Quantity::Length),
    ("body.radius", Quantity::Length),
    ("body.inner_radius", Quantity::Length),
    ("body.outer_radius", Quantity::Length),
    ("body.height", Quantity::Length),
    ("body.velocity", Quantity::Speed),
    ("body.temperature", Quantity::Temperature),
    ("boundary.min", Quantity::Length),
    ("blanking.min", Quantity::Length),
    ("blanking.max", Quantity::Length),
    ("blanking.velocity", Quantity::Speed),
    ("blanking.rest_speed", Quantity::Speed),
    ("boundary.max", Quantity::Length),
    ("boundary.velocity", Quantity::Speed),
    ("boundary.temperature", Quantity::Temperature),
    ("physics.initial_temperature", Quantity::Temperature),
    ("tool.rake_angle", Quantity::Angle),
    ("tool.clearance_angle", Quantity::Angle),
    ("tool.edge_radius", Quantity::Length),
    ("tool.length", Quantity::Length),
    ("tool.height", Quantity::Length),
    ("tool.position", Quantity::Length),
    ("discretisation.period_z", Quantity::Length),
    ("tool.mesh.cell", Quantity::Length),
    ("tool.mesh.cutoff", Quantity::Length),
    ("tool.mesh.angle", Quantity::Angle),
    ("tool.depth_of_cut", Quantity::Length),
    ("tool.velocity", Quantity::Speed),
    ("tool.chip_station", Quantity::Length),
    ("tool.rotation.centre", Quantity::Length),
    ("tool.thermal.temperature", Quantity::Temperature),
    ("tool.thermal.fixed_width", Quantity::Length),
];

/// The quantity of the dotted key `key` (`body.0.velocity`), if it takes units.
pub fn quantity(key: &str) -> Option<Quantity> {
    let plain: Vec<&str> = key.split('.').filter(|part| part.parse::<usize>().is_err()).collect();
    let plain = plain.join(".");
    KEYS.iter().find(|(k, _)| *k == plain).map(|(_, q)| *q)
}
