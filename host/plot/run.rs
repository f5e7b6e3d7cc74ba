//! The standard plots of a run folder, from its CSV time series.
//!
//! | CSV (required columns)                                | PNG               | content                                    |
//! |-------------------------------------------------------|-------------------|--------------------------------------------|
//! | `energy.csv` (time, kinetic, elastic, total, momentum_x, momentum_y, momentum_z, angular_z) | `energy.png` | kinetic, elastic and total energy vs time |
//! |                                                       | `momentum.png`    | two panels: linear momentum x, y, z; angular momentum z |
//! | `forces.csv`, if present (time, fc_n_per_mm, ff_n_per_mm) | `forces.png`  | cutting and feed force per mm of width     |
//! | `temperature.csv`, if present (time, then any columns) | `temperature.png` | every column but time and step             |
//!
//! `energy.csv` is required; the others are plotted when they exist, and a present but malformed one (a missing
//! column, no rows, unparseable) is an error rather than silently skipped. Columns are found by name, so extra
//! columns and any order are fine. Quantities are SI as written by the run (per unit depth in 2D).

use std::path::{Path, PathBuf};

use super::{Chart, Drawn, PlotError, Series, draw, draw_panels};
use crate::output::csv;

/// Image size of single-chart plots, (width, height) in pixels.
pub const DEFAULT_SIZE: (u32, u32) = (1200, 800);

/// Draws every standard plot of `run_dir` (see the module docs) at [`DEFAULT_SIZE`] (the two-panel
/// `momentum.png` is 1.5 times as high) and returns what was written, in the order energy, momentum, forces,
/// temperature. Points skipped as non-finite are counted in each [`Drawn`], not treated as errors.
pub fn plot_run(run_dir: &Path) -> Result<Vec<Drawn>, PlotError> {
    plot_run_sized(run_dir, DEFAULT_SIZE)
}

/// [`plot_run`] with single-chart images of `size` pixels (`momentum.png` gets 1.5 times the height).
pub fn plot_run_sized(run_dir: &Path, size: (u32, u32)) -> Result<Vec<Drawn>, PlotError> {
    let tall = (size.0, size.1.saturating_mul(3) / 2);
    let mut out = Vec::new();

    let energy = Table::read(&run_dir.join("energy.csv"))?;
    let time = energy.column("time")?;
    let energies = [("kinetic", "kinetic"), ("elastic", "elastic"), ("total", "total")];
    let chart = Chart {
        title: "Energy",
        x_label: "time (s)",
        y_label: "energy (J; J/m in 2D)",
        series: energy.series(time, &energies)?,
    };
    out.push(draw(&run_dir.join("energy.png"), &chart, size)?);

    let linear = [("momentum_x", "p_x"), ("momentum_y", "p_y"), ("momentum_z", "p_z")];
    let angular = [("angular_z", "L_z")];
    let charts = [
        Chart {
            title: "Linear momentum",
            x_label: "time (s)",
            y_label: "momentum (kg·m/s; per m in 2D)",
            series: energy.series(time, &linear)?,
        },
        Chart {
            title: "Angular momentum about the origin",
            x_label: "time (s)",
            y_label: "angular momentum (kg·m²/s; per m in 2D)",
            series: energy.series(time, &angular)?,
        },
    ];
    out.push(draw_panels(&run_dir.join("momentum.png"), &charts, tall)?);

    let path = run_dir.join("forces.csv");
    if path.exists() {
        let forces = Table::read(&path)?;
        let time = forces.column("time")?;
        let columns = [("fc_n_per_mm", "F_c (cutting)"), ("ff_n_per_mm", "F_f (feed)")];
        let chart = Chart {
            title: "Tool force",
            x_label: "time (s)",
            y_label: "force per width (N/mm)",
            series: forces.series(time, &columns)?,
        };
        out.push(draw(&run_dir.join("forces.png"), &chart, size)?);
    }

    let path = run_dir.join("temperature.csv");
    if path.exists() {
        let temperature = Table::read(&path)?;
        let time = temperature.column("time")?;
        let names: Vec<&str> =
            temperature.header.iter().map(String::as_str).filter(|&h| h != "time" && h != "step").collect();
        if names.is_empty() {
            return Err(PlotError::MissingColumn {
                path: temperature.path.clone(),
                column: "t_max".into(),
                columns: temperature.header.clone(),
            });
        }
        let columns: Vec<(&str, &str)> = names.iter().map(|&n| (n, n)).collect();
        let chart = Chart {
            title: "Temperature",
            x_label: "time (s)",
            y_label: "temperature (K)",
            series: temperature.series(time, &columns)?,
        };
        out.push(draw(&run_dir.join("temperature.png"), &chart, size)?);
    }
    Ok(out)
}

/// A CSV read whole, stored by column.
struct Table {
    path: PathBuf,
    header: Vec<String>,
    columns: Vec<Vec<f64>>,
}

impl Table {
    fn read(path: &Path) -> Result<Self, PlotError> {
        let (header, rows) = csv::read(path).map_err(|error| PlotError::Read { path: path.to_path_buf(), error })?;
        if rows.is_empty() {
            return Err(PlotError::NoRows { path: path.to_path_buf() });
        }
        // `csv::read` guarantees every row has the header's length.
        let columns =
            (0..header.len()).map(|j| rows.iter().map(|r| r.get(j).copied().unwrap_or(f64::NAN)).collect()).collect();
        Ok(Self { path: path.to_path_buf(), header, columns })
    }

    fn column(&self, name: &str) -> Result<&[f64], PlotError> {
        match self.header.iter().position(|h| h == name) {
            Some(j) => Ok(&self.columns[j]),
            None => Err(PlotError::MissingColumn {
                path: self.path.clone(),
                column: name.to_string(),
                columns: self.header.clone(),
            }),
        }
    }

    /// Series of the named columns `(column, legend label)` against `x`.
    fn series<'a>(&'a self, x: &'a [f64], columns: &[(&str, &'a str)]) -> Result<Vec<Series<'a>>, PlotError> {
        columns.iter().map(|&(name, label)| Ok(Series { label, x, y: self.column(name)? })).collect()
    }
}
