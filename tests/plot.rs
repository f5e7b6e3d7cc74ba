//! PNG plots: a chart is written as a valid PNG of the requested size with something drawn on it; the standard
//! plots of a run folder; refused input gives typed errors naming the file, never a panic; non-finite and
//! constant data still plot.

use std::fs;
use std::path::{Path, PathBuf};

use crate::common::files::entries;

use plotters::prelude::*;
use swarf::output::TimeSeries;
use swarf::plot::{self, Chart, PlotError, Series};

/// A fresh, empty directory for one test.
fn test_dir(name: &str) -> PathBuf {
    crate::common::files::fresh_dir("plot", name)
}

/// CRC-32 (ISO-HDLC, as PNG uses), bitwise.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 != 0 { (crc >> 1) ^ 0xEDB8_8320 } else { crc >> 1 };
        }
    }
    !crc
}

/// Checks that `path` is a well-formed PNG (signature, IHDR first, every chunk's CRC, IDAT present, IEND last)
/// and returns its (width, height) and file size.
fn png_info(path: &Path) -> ((u32, u32), usize) {
    let bytes = fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{}: not a PNG signature", path.display());
    let be32 = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap());
    let mut at = 8;
    let mut types = Vec::new();
    while at < bytes.len() {
        let len = be32(at) as usize;
        let end = at + 8 + len;
        assert!(end + 4 <= bytes.len(), "{}: chunk at {at} runs past the end", path.display());
        let kind = String::from_utf8_lossy(&bytes[at + 4..at + 8]).into_owned();
        assert_eq!(crc32(&bytes[at + 4..end]), be32(end), "{}: bad CRC in {kind}", path.display());
        types.push(kind);
        at = end + 4;
    }
    assert_eq!(types.first().map(String::as_str), Some("IHDR"), "{}: {types:?}", path.display());
    assert_eq!(types.last().map(String::as_str), Some("IEND"), "{}: {types:?}", path.display());
    assert!(types.iter().any(|t| t == "IDAT"), "{}: no IDAT in {types:?}", path.display());
    assert_eq!(be32(8), 13, "IHDR length");
    ((be32(16), be32(20)), bytes.len())
}

/// Size of a PNG of one white fill of `size` pixels, written by the same backend: a drawn chart must be larger.
fn blank_png_len(dir: &Path, size: (u32, u32)) -> usize {
    let path = dir.join(format!("blank-{}x{}.png", size.0, size.1));
    {
        let root = BitMapBackend::new(&path, size).into_drawing_area();
        root.fill(&WHITE).expect("fill");
        root.present().expect("present");
    }
    let len = png_info(&path).1;
    fs::remove_file(&path).expect("remove blank");
    len
}

/// Asserts `path` is a PNG of `size` pixels with far more content than a blank one.
fn assert_drawn(path: &Path, size: (u32, u32)) {
    let (dims, len) = png_info(path);
    assert_eq!(dims, size, "{}", path.display());
    let blank = blank_png_len(path.parent().unwrap(), size);
    assert!(len > 2 * blank, "{}: {len} bytes, a blank image is {blank}", path.display());
}

/// No scratch or temporary files left beside the outputs.
fn assert_no_leftovers(dir: &Path) {
    let hidden: Vec<String> = entries(dir).into_iter().filter(|n| n.starts_with('.')).collect();
    assert!(hidden.is_empty(), "{}: left over {hidden:?}", dir.display());
}

fn linspace(n: usize, end: f64) -> Vec<f64> {
    (0..n).map(|i| end * i as f64 / (n - 1) as f64).collect()
}

#[test]
fn two_series_make_a_png_of_the_requested_size() {
    let dir = test_dir("two_series");
    let t = linspace(200, 2e-4);
    let a: Vec<f64> = t.iter().map(|&t| (t * 3e4).sin()).collect();
    let b: Vec<f64> = t.iter().map(|&t| 0.5 * (t * 5e4).cos()).collect();
    let chart = Chart {
        title: "Two waves",
        x_label: "time (s)",
        y_label: "amplitude (m)",
        series: vec![Series { label: "sine", x: &t, y: &a }, Series { label: "cosine", x: &t, y: &b }],
    };
    let path = dir.join("waves.png");
    let drawn = plot::draw(&path, &chart, (800, 600)).expect("draw");
    assert_eq!(drawn.path, path);
    assert_eq!(drawn.skipped, 0);
    assert_eq!(drawn.warning(), None);
    assert_drawn(&path, (800, 600));
    // Redrawing replaces the file, at another size.
    plot::draw(&path, &chart, (640, 480)).expect("redraw");
    assert_drawn(&path, (640, 480));
    assert_eq!(entries(&dir), ["waves.png"]);
}

// The columns a run writes (`swarf::run::energy_header`), so the test reads the real format.
use swarf::run::energy_header;

/// energy.csv's header and every row come from one table (`solver::diagnostics::ENERGY_COLUMNS`): a row has one
/// value per column, in the header's order, and no column name repeats.
#[test]
fn energy_rows_follow_the_header() {
    use swarf::solver::diagnostics::Diagnostics;
    let header = energy_header();
    let mut names = header.clone();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), header.len(), "a repeated column in {header:?}");
    let d = Diagnostics {
        time: 1.5e-6,
        step: 7,
        kinetic: 2.0,
        elastic: 3.0,
        plastic_work: 0.25,
        damage_dissipation: 0.5,
        min_contact_ids: Some([4, 9]),
        ..Default::default()
    };
    let row = d.energy_row();
    assert_eq!(row.len(), header.len());
    let at = |name: &str| row[header.iter().position(|n| *n == name).expect(name)];
    assert_eq!(at("time"), 1.5e-6);
    assert_eq!(at("step"), 7.0);
    assert_eq!(at("total"), 5.0);
    assert_eq!(at("balance"), 5.75);
    assert_eq!(at("damage_dissipation"), 0.5);
    assert_eq!((at("min_contact_id_a"), at("min_contact_id_b")), (4.0, 9.0));
}

/// An energy.csv as a run writes it: energy sloshing between kinetic and elastic, momentum conserved to noise.
fn write_energy(dir: &Path, rows: usize) {
    let mut csv = TimeSeries::new(dir.join("energy.csv"), &energy_header());
    for i in 0..rows {
        let t = 1e-6 * i as f64;
        let kinetic = 2.0 * (t * 2e5).cos().powi(2);
        let elastic = 2.0 - kinetic;
        let noise = 1e-12 * ((i * 7919) % 13) as f64;
        let first = [
            t,
            (i * 10) as f64,
            kinetic,
            elastic,
            2.0 + noise,
            0.1 + noise,
            -noise,
            0.0,
            0.0,
            0.0,
            3e-3,
            100.0,
            300.0,
            0.0,
        ];
        // The energy-balance and pair-distance columns after these are not plotted: zeros.
        let mut row = vec![0.0; energy_header().len()];
        row[..first.len()].copy_from_slice(&first);
        csv.push(&row).expect("push");
    }
    csv.write().expect("write energy.csv");
}

fn write_forces(dir: &Path, rows: usize) {
    let mut csv = TimeSeries::new(dir.join("forces.csv"), &["time", "step", "fc_n_per_mm", "ff_n_per_mm"]);
    for i in 0..rows {
        let t = 1e-6 * i as f64;
        let ramp = (t / 2e-5).min(1.0);
        csv.push(&[t, i as f64, 250.0 * ramp + 5.0 * (t * 1e6).sin(), 90.0 * ramp]).expect("push");
    }
    csv.write().expect("write forces.csv");
}

fn names(drawn: &[plot::Drawn]) -> Vec<String> {
    drawn.iter().map(|d| d.path.file_name().unwrap().to_string_lossy().into_owned()).collect()
}

#[test]
fn plot_run_draws_energy_momentum_and_optional_forces_and_temperature() {
    let dir = test_dir("run");
    write_energy(&dir, 101);
    let drawn = plot::plot_run(&dir).expect("plot_run");
    assert_eq!(names(&drawn), ["energy.png", "momentum.png"]);
    assert!(drawn.iter().all(|d| d.skipped == 0 && d.path.parent() == Some(dir.as_path())));
    let (w, h) = plot::run::DEFAULT_SIZE;
    assert_drawn(&dir.join("energy.png"), (w, h));
    assert_drawn(&dir.join("momentum.png"), (w, h * 3 / 2));

    write_forces(&dir, 101);
    let drawn = plot::plot_run(&dir).expect("plot_run with forces");
    assert_eq!(names(&drawn), ["energy.png", "momentum.png", "forces.png"]);
    assert_drawn(&dir.join("forces.png"), (w, h));

    let mut csv = TimeSeries::new(dir.join("temperature.csv"), &["time", "t_max", "t_tool"]);
    for i in 0..50 {
        csv.push(&[1e-6 * i as f64, 293.15 + 10.0 * i as f64, 293.15 + 2.0 * i as f64]).expect("push");
    }
    csv.write().expect("write temperature.csv");
    let drawn = plot::plot_run_sized(&dir, (640, 400)).expect("plot_run with temperature");
    assert_eq!(names(&drawn), ["energy.png", "momentum.png", "forces.png", "temperature.png"]);
    assert_drawn(&dir.join("temperature.png"), (640, 400));
    assert_drawn(&dir.join("momentum.png"), (640, 600));
    assert_no_leftovers(&dir);
}

#[test]
fn missing_or_malformed_csv_is_an_error_naming_the_file() {
    let dir = test_dir("missing");
    let err = plot::plot_run(&dir).expect_err("no energy.csv");
    assert!(matches!(err, PlotError::Read { ref path, .. } if path.ends_with("energy.csv")), "{err:?}");
    assert!(err.to_string().contains("energy.csv"), "{err}");
    assert!(entries(&dir).is_empty(), "{:?}", entries(&dir));

    // A header and no rows.
    TimeSeries::new(dir.join("energy.csv"), &energy_header()).write().expect("write");
    let err = plot::plot_run(&dir).expect_err("no rows");
    assert!(matches!(err, PlotError::NoRows { .. }), "{err:?}");
    assert!(err.to_string().contains("energy.csv"), "{err}");

    // Not a number.
    fs::write(dir.join("energy.csv"), "time,kinetic\n0,zero\n").expect("write");
    let err = plot::plot_run(&dir).expect_err("bad number");
    assert!(err.to_string().contains("energy.csv") && err.to_string().contains("line 2"), "{err}");

    // A forces.csv without the feed force column.
    write_energy(&dir, 11);
    let mut csv = TimeSeries::new(dir.join("forces.csv"), &["time", "fc_n_per_mm"]);
    csv.push(&[0.0, 1.0]).expect("push");
    csv.write().expect("write");
    let err = plot::plot_run(&dir).expect_err("missing column");
    match &err {
        PlotError::MissingColumn { path, column, .. } => {
            assert!(path.ends_with("forces.csv"));
            assert_eq!(column, "ff_n_per_mm");
        }
        e => panic!("{e:?}"),
    }
    assert!(err.to_string().contains("forces.csv") && err.to_string().contains("ff_n_per_mm"), "{err}");
    assert_no_leftovers(&dir);
}

#[test]
fn constant_and_non_finite_series_draw() {
    let dir = test_dir("degenerate");
    let t = linspace(50, 1e-4);
    let constant = vec![2.5; 50];
    let zero = vec![0.0; 50];
    let mut gappy: Vec<f64> = t.iter().map(|&t| 1.0 + t * 1e4).collect();
    gappy[10] = f64::NAN;
    gappy[11] = f64::INFINITY;
    gappy[30] = f64::NEG_INFINITY;
    gappy[49] = 1e305; // beyond ±1e300: skipped too
    let all_nan = vec![f64::NAN; 50];

    let chart = |series| Chart { title: "Degenerate", x_label: "time (s)", y_label: "value (1)", series };
    let size = (640, 480);

    let path = dir.join("constant.png");
    let drawn =
        plot::draw(&path, &chart(vec![Series { label: "constant", x: &t, y: &constant }]), size).expect("constant");
    assert_eq!(drawn.skipped, 0);
    assert_drawn(&path, size);

    let path = dir.join("zero.png");
    plot::draw(&path, &chart(vec![Series { label: "zero", x: &t, y: &zero }]), size).expect("zero");
    assert_drawn(&path, size);

    let path = dir.join("nan.png");
    let series = vec![
        Series { label: "with gaps", x: &t, y: &gappy },
        Series { label: "all NaN", x: &t, y: &all_nan },
        Series { label: "constant", x: &t, y: &constant },
    ];
    let drawn = plot::draw(&path, &chart(series), size).expect("NaN");
    assert_eq!(drawn.skipped, 4 + 50);
    let warning = drawn.warning().expect("warning");
    assert!(warning.contains("nan.png") && warning.contains("54 non-finite points"), "{warning}");
    assert_drawn(&path, size);

    // A single point, and a single point with a NaN time.
    let path = dir.join("point.png");
    let drawn = plot::draw(
        &path,
        &chart(vec![
            Series { label: "one", x: &[1.0], y: &[3.0] },
            Series { label: "nan x", x: &[f64::NAN], y: &[1.0] },
        ]),
        size,
    )
    .expect("single point");
    assert_eq!(drawn.skipped, 1);
    assert_drawn(&path, size);

    // Tiny and huge magnitudes (exponent tick labels).
    let tiny: Vec<f64> = t.iter().map(|&t| 1e-9 * t).collect();
    let huge: Vec<f64> = t.iter().map(|&t| -1e20 * t).collect();
    plot::draw(&dir.join("tiny.png"), &chart(vec![Series { label: "tiny", x: &t, y: &tiny }]), size).expect("tiny");
    plot::draw(&dir.join("huge.png"), &chart(vec![Series { label: "huge", x: &t, y: &huge }]), size).expect("huge");

    // The smallest image, with the longest tick labels (a span of 1e-8 of the values) and a long legend label.
    let long: Vec<f64> = t.iter().map(|&t| -12345.0 * (1.0 + 1e4 * t * 1e-8)).collect();
    let label = "a rather long legend label that is wider than the image";
    let path = dir.join("small.png");
    plot::draw(&path, &chart(vec![Series { label, x: &t, y: &long }]), plot::MIN_SIZE).expect("small");
    assert_eq!(png_info(&path).0, plot::MIN_SIZE);
    assert_no_leftovers(&dir);
}

#[test]
fn refused_input_is_a_typed_error_and_writes_nothing() {
    let dir = test_dir("refused");
    let path = dir.join("bad.png");
    let t = [0.0, 1.0, 2.0];
    let y = [1.0, 2.0, 3.0];
    let chart = |series| Chart { title: "Bad", x_label: "x", y_label: "y", series };

    let err = plot::draw(&path, &chart(vec![Series { label: "empty", x: &[], y: &[] }]), (640, 480)).unwrap_err();
    assert!(matches!(err, PlotError::EmptySeries { ref label, .. } if label == "empty"), "{err:?}");
    assert!(err.to_string().contains("bad.png") && err.to_string().contains("empty"), "{err}");

    let err = plot::draw(&path, &chart(vec![Series { label: "short", x: &t, y: &y[..2] }]), (640, 480)).unwrap_err();
    assert!(matches!(err, PlotError::LengthMismatch { x: 3, y: 2, .. }), "{err:?}");

    let err = plot::draw(&path, &chart(vec![]), (640, 480)).unwrap_err();
    assert!(matches!(err, PlotError::NoSeries { .. }), "{err:?}");

    let nan = [f64::NAN; 3];
    let err = plot::draw(&path, &chart(vec![Series { label: "nan", x: &t, y: &nan }]), (640, 480)).unwrap_err();
    assert!(matches!(err, PlotError::NoFiniteData { skipped: 3, .. }), "{err:?}");

    for size in [(0, 480), (640, 0), (10, 10), (100_000, 480)] {
        let err = plot::draw(&path, &chart(vec![Series { label: "ok", x: &t, y: &y }]), size).unwrap_err();
        assert!(matches!(err, PlotError::Size { .. }), "{size:?}: {err:?}");
        assert!(err.to_string().contains("bad.png"), "{err}");
    }

    // A destination directory that does not exist.
    let missing = dir.join("no-such-dir").join("x.png");
    let err = plot::draw(&missing, &chart(vec![Series { label: "ok", x: &t, y: &y }]), (640, 480)).unwrap_err();
    assert!(err.to_string().contains("x.png"), "{err}");

    assert!(entries(&dir).is_empty(), "{:?}", entries(&dir));
}

/// Log–log panels (`plot::draw_log_log`, a study's wall time against error): a PNG of the requested size with
/// content, values ≤ 0 skipped and counted (they have no place on a log axis), a range within one decade drawn
/// too, and no scratch file left; a chart with nothing positive to draw is refused.
#[test]
fn log_log_panels_skip_non_positive_values() {
    let dir = test_dir("log_log");
    let (wall, err) = ([0.5, 2.0, 30.0, 400.0], [0.3, 0.0, 2e-3, 1e-5]);
    let (narrow_x, narrow_y) = ([0.818, 0.905], [1.97, 2.5e-5]);
    let charts = [
        Chart {
            title: "decades",
            x_label: "wall time (s)",
            y_label: "relative error",
            series: vec![Series { label: "f64", x: &wall, y: &err }],
        },
        Chart {
            title: "one decade of x",
            x_label: "wall time (s)",
            y_label: "relative error",
            series: vec![Series { label: "f32", x: &narrow_x, y: &narrow_y }],
        },
    ];
    let path = dir.join("study.png");
    let drawn = plot::draw_log_log(&path, &charts, (900, 1200)).expect("drawn");
    assert_eq!(drawn.skipped, 1, "the zero error is skipped");
    assert_drawn(&path, (900, 1200));
    assert_no_leftovers(&dir);
    let zeros = [0.0, -1.0];
    let nothing = [Chart {
        title: "nothing",
        x_label: "x",
        y_label: "y",
        series: vec![Series { label: "z", x: &wall[..2], y: &zeros }],
    }];
    let e = plot::draw_log_log(&dir.join("none.png"), &nothing, (900, 600)).expect_err("refused");
    assert!(matches!(e, PlotError::NoFiniteData { .. }), "{e}");
    assert!(!dir.join("none.png").exists());
}
