//! The chip analysis of one frame (host/cutting/chip_frame.rs and the modules it calls) on synthetic chips whose
//! geometry is known by construction: particles on a square lattice of spacing Δx filling a strip along the rake
//! face whose back surface is a saw-tooth (known h_min, h_max, pitch), with the plastic strain raised in bands of
//! known width crossing the chip at each notch and in a layer of known thickness along the rake side; a continuous
//! strip; a strip that curls on a circle of known radius. Tolerances are tied to Δx: a lattice resolves a length
//! to within one spacing.

use crate::common;

use swarf::backend::{AnyBackend, BackendChoice};
use swarf::cutting::chip_frame::{FrameChip, analyse};
use swarf::cutting::chip_profile::FrameSetup;
use swarf::cutting::curl::fit_circle;

/// Particle spacing [m].
const DX: f64 = 1e-6;
/// The uncut surface's height and the uncut chip thickness t1 [m]. t1 places the first section (t1/2 above the
/// surface) and the chip's head left out (3 t1²/h from the free end: 7.5 Δx for the saw-tooth).
const SURFACE: f64 = 100.0 * DX;
const T1: f64 = 10.0 * DX;
/// Saw-tooth: valley and crest thickness, pitch along the chip [m].
const H_MIN: f64 = 30.0 * DX;
const H_MAX: f64 = 50.0 * DX;
const PITCH: f64 = 40.0 * DX;
/// Chip length above the surface [m].
const LENGTH: f64 = 600.0 * DX;
/// Strains: the chip's bulk, the secondary layer, the bands.
const BULK: f64 = 1.0;
const LAYER: f64 = 3.0;
const BAND: f64 = 4.0;
/// Secondary layer thickness and band width [m].
const T_SL: f64 = 3.0 * DX;
const T_SEG: f64 = 4.0 * DX;
/// Bands run from each notch of the back surface down to the rake side at this angle to the chip axis [rad].
const BAND_ANGLE: f64 = std::f64::consts::FRAC_PI_4;

/// The tool's rake face is the line x = 0 (γ = 0) through the rake point 30 Δx below the surface; the tool cuts
/// in +x at 5 m/s.
fn setup() -> FrameSetup {
    FrameSetup {
        rake_point: [0.0, SURFACE - 30.0 * DX],
        rake_angle: 0.0,
        surface_y: SURFACE,
        spacing: DX,
        uncut: T1,
        speed: 5.0,
    }
}

/// Lattice points (i + ½, j + ½)Δx with i in 0..nx and y from `y0`, rows up to `y1`.
fn lattice(nx: usize, y0: f64, y1: f64) -> impl Iterator<Item = [f64; 2]> {
    let ny = ((y1 - y0) / DX).round() as usize;
    (0..ny).flat_map(move |j| (0..nx).map(move |i| [(i as f64 + 0.5) * DX, y0 + (j as f64 + 0.5) * DX]))
}

/// The uncut workpiece below the surface (left out by the analysis: the chip is what lies above it).
fn workpiece() -> Vec<[f64; 2]> {
    lattice(200, SURFACE - 60.0 * DX, SURFACE).collect()
}

/// The back surface of the saw-tooth chip at height y: rising from H_MIN at each notch y_k = SURFACE + k PITCH to
/// H_MAX just below the next one.
fn saw_tooth(y: f64) -> f64 {
    let phase = ((y - SURFACE) / PITCH).fract();
    H_MIN + (H_MAX - H_MIN) * phase
}

/// Distance of p from the band through the notch at y_k, running down to the rake side at BAND_ANGLE.
fn band_distance(p: [f64; 2], y_k: f64) -> f64 {
    let b = [BAND_ANGLE.sin(), BAND_ANGLE.cos()];
    let r = [p[0] - H_MIN, p[1] - y_k];
    (r[0] * b[1] - r[1] * b[0]).abs()
}

/// The strain of the segmented chip at p: a band within T_SEG/2 of a band line, else the layer within T_SL of the
/// rake face, else the bulk.
fn strain(p: [f64; 2]) -> f64 {
    let k = ((p[1] - SURFACE) / PITCH).round();
    let near_band = [k - 1.0, k, k + 1.0].iter().any(|k| band_distance(p, SURFACE + k * PITCH) <= 0.5 * T_SEG);
    if near_band && p[1] > SURFACE {
        BAND
    } else if p[0] < T_SL {
        LAYER
    } else {
        BULK
    }
}

/// The segmented chip with the workpiece below it: positions and strains.
fn segmented() -> (Vec<[f64; 2]>, Vec<f64>) {
    let chip = lattice(60, SURFACE, SURFACE + LENGTH).filter(|p| p[0] < saw_tooth(p[1]));
    let pos: Vec<[f64; 2]> = workpiece().into_iter().chain(chip).collect();
    let eps = pos.iter().map(|&p| if p[1] < SURFACE { 0.0 } else { strain(p) }).collect();
    (pos, eps)
}

fn run(pos: &[[f64; 2]], eps: &[f64], s: &FrameSetup) -> FrameChip {
    analyse(s, pos, Some(eps)).expect("a chip")
}

fn assert_within(what: &str, got: Option<f64>, want: f64, tol: f64) {
    let got = got.unwrap_or_else(|| panic!("{what}: none"));
    assert!((got - want).abs() <= tol, "{what}: {:.2} Δx, expected {:.2} ± {:.2} Δx", got / DX, want / DX, tol / DX);
}

#[test]
fn segmented_straight_chip_gives_its_teeth_bands_and_layer() {
    let (pos, eps) = segmented();
    let c = run(&pos, &eps, &setup());
    let s = c.segments.expect("segments");
    // The saw-tooth's crest and valley (construction), each within the lattice's resolution.
    assert_within("h_max", Some(s.h_max), H_MAX, DX);
    assert_within("h_min", Some(s.h_min), H_MIN, DX);
    assert_within("l_seg", Some(s.l_seg), PITCH, DX);
    // The analysed chip (from t1/2 above the surface to one thickness and the head before the end, ≈ 545 Δx) holds
    // ≈ 13 teeth.
    assert!((11..=15).contains(&s.crests), "{} crests", s.crests);
    assert!((s.degree - (H_MAX - H_MIN) / H_MAX).abs() <= 2.0 * DX / H_MAX, "degree {}", s.degree);
    // f = v_c t1/h_avg / l_seg with the mean of the saw-tooth, (H_MIN + H_MAX)/2, for h_avg (within 1 Δx).
    let f = setup().speed * T1 / (0.5 * (H_MIN + H_MAX)) / PITCH;
    assert!((s.frequency - f).abs() <= 0.05 * f, "f {} Hz, expected {f}", s.frequency);
    assert_within("h_avg", Some(c.h_avg), 0.5 * (H_MIN + H_MAX), DX);
    // The band width normal to the band and the layer's thickness (construction).
    assert_within("t_seg", c.t_seg, T_SEG, DX);
    assert!(c.bands + 2 >= s.crests, "{} bands for {} crests", c.bands, s.crests);
    assert_within("t_sl", c.t_sl, T_SL, DX);
    // Straight along the face: no curl.
    assert_eq!(c.r_chip, None);
}

#[test]
fn rotated_segmented_chip_on_a_raked_face_gives_the_same_geometry() {
    // The whole chip turned by γ = 10° about the rake point, with the face: the lattice is no longer aligned with
    // the chip, so each length is resolved within 1.5 Δx.
    let gamma = 10f64.to_radians();
    let mut s = setup();
    s.rake_angle = gamma;
    let (sin, cos) = gamma.sin_cos();
    let r = s.rake_point;
    let (pos, eps) = segmented();
    let (pos, eps): (Vec<[f64; 2]>, Vec<f64>) = pos
        .iter()
        .zip(&eps)
        .filter(|(p, _)| p[1] > SURFACE)
        .map(|(p, e)| {
            let q = [p[0] - r[0], p[1] - r[1]];
            ([r[0] + cos * q[0] - sin * q[1], r[1] + sin * q[0] + cos * q[1]], *e)
        })
        .unzip();
    let c = run(&pos, &eps, &s);
    let seg = c.segments.expect("segments");
    assert_within("h_max", Some(seg.h_max), H_MAX, 1.5 * DX);
    assert_within("h_min", Some(seg.h_min), H_MIN, 1.5 * DX);
    assert_within("l_seg", Some(seg.l_seg), PITCH, 1.5 * DX);
    assert_within("t_seg", c.t_seg, T_SEG, 1.5 * DX);
    assert_within("t_sl", c.t_sl, T_SL, 1.5 * DX);
}

#[test]
fn continuous_chip_has_no_segments() {
    // A strip of constant thickness 40 Δx with the rake layer and no bands.
    let h = 40.0 * DX;
    let chip = lattice(60, SURFACE, SURFACE + LENGTH).filter(|p| p[0] < h);
    let pos: Vec<[f64; 2]> = workpiece().into_iter().chain(chip).collect();
    let eps: Vec<f64> = pos.iter().map(|p| if p[1] > SURFACE && p[0] < T_SL { LAYER } else { BULK }).collect();
    let c = run(&pos, &eps, &setup());
    assert_eq!(c.segments, None);
    assert!(c.segmentation <= 0.03, "segmentation {}", c.segmentation);
    assert_within("h_avg", Some(c.h_avg), h, 0.5 * DX);
    assert_eq!((c.t_seg, c.bands), (None, 0));
    assert_within("t_sl", c.t_sl, T_SL, DX);
}

#[test]
fn uniform_strain_has_no_shear_layers() {
    // Without contrast there is no band and no layer to measure, whatever the geometry.
    let (pos, _) = segmented();
    let eps = vec![1.0; pos.len()];
    let c = run(&pos, &eps, &setup());
    assert!(c.segments.is_some());
    assert_eq!((c.t_seg, c.t_sl, c.bands), (None, None, 0));
}

/// A strip of thickness h up the face to 60 Δx above the surface, then curling away from the face (towards +x)
/// on a circle of centreline radius `radius` through half a turn.
fn curled(h: f64, radius: f64) -> Vec<[f64; 2]> {
    let top = SURFACE + 60.0 * DX;
    let centre = [0.5 * h + radius, top];
    let n = ((2.0 * (radius + h)) / DX).ceil() as usize + 100;
    let grid = (0..n).flat_map(|j| (0..n).map(move |i| [(i as f64 + 0.5) * DX, SURFACE + (j as f64 + 0.5) * DX]));
    let on_arc = move |p: [f64; 2]| {
        let r = (p[0] - centre[0]).hypot(p[1] - centre[1]);
        p[1] >= top && (r - radius).abs() < 0.5 * h
    };
    grid.filter(|p| (p[1] < top && p[0] < h) || on_arc(*p)).collect()
}

#[test]
fn curled_chip_gives_its_radius() {
    for (h, radius) in [(30.0 * DX, 150.0 * DX), (20.0 * DX, 300.0 * DX)] {
        let pos = curled(h, radius);
        let c = analyse(&setup(), &pos, None).expect("a chip");
        // The centreline's radius (construction) within 3 %; the thickness within 1 Δx along the curl.
        let r = c.r_chip.expect("a curl radius");
        assert!((r - radius).abs() <= 0.03 * radius, "r_chip {:.1} Δx, expected {:.1} Δx", r / DX, radius / DX);
        assert_within("h_avg", Some(c.h_avg), h, DX);
        assert_eq!(c.segments, None, "a constant thickness has no segments");
        // The march follows the curl over most of the half turn (π R), less the trimmed free end.
        assert!(c.length >= 0.8 * std::f64::consts::PI * radius, "length {:.0} Δx", c.length / DX);
        assert_eq!((c.t_seg, c.t_sl), (None, None), "no strain field given");
    }
}

#[test]
fn circle_fit_is_exact_on_a_circle() {
    // Kåsa's fit through points of an arc of 60° (construction: centre (3, −2) mm, radius 0.7 mm).
    let pts: Vec<[f64; 2]> = (0..20)
        .map(|k| (k as f64 / 19.0) * std::f64::consts::FRAC_PI_3)
        .map(|a| [3e-3 + 7e-4 * a.cos(), -2e-3 + 7e-4 * a.sin()])
        .collect();
    let (c, r) = fit_circle(&pts).expect("a circle");
    assert!((r - 7e-4).abs() <= 1e-12 && (c[0] - 3e-3).abs() <= 1e-12 && (c[1] + 2e-3).abs() <= 1e-12, "{c:?} {r}");
    assert_eq!(fit_circle(&[[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]), None, "collinear points have no circle");
}

#[test]
fn no_chip_above_the_surface_is_none() {
    assert_eq!(analyse(&setup(), &workpiece(), None), None);
    assert_eq!(analyse(&setup(), &[], None), None);
}

// ---------------------------------------------------------------------------------------------------------------
// A run: summary.json, `swarf chip`, and the errors on bad input

/// The coarse V0060 cut of tests/common (`coarse_overrides`, Δx = 20 µm) over 60 µs: the tool travels 0.38 mm, past the 3 t1 =
/// 0.27 mm whose chip is the head the analysis leaves out; with frames; the overrides are recorded as `swarf run --set` records them, so that the run
/// folder's scene is the one that ran.
fn coarse_run(tag: &str) -> std::path::PathBuf {
    let over = common::scenes::coarse_overrides(&["time.end=6.0e-5", "output.every=1.5e-5"]);
    let scene = swarf::scene::Scene::load("cases/cutting/v0060.toml", &over).expect("scene");
    let dir = std::env::temp_dir().join(format!("swarf-test-chip-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let mut o = swarf::run::RunOptions::quiet(dir.clone());
    (o.frames, o.overrides) = (true, over);
    let cpu = AnyBackend::select(BackendChoice::Cpu).expect("cpu").0;
    swarf::run::run(&cpu, &scene, &o).expect("the coarse cut runs");
    dir
}

#[test]
fn a_cut_reports_its_last_frame_chip_in_the_summary_and_through_swarf_chip() {
    let dir = coarse_run("summary");
    let text = std::fs::read_to_string(dir.join("summary.json")).expect("summary.json");
    let v: serde_json::Value = serde_json::from_str(&text).expect("json");
    // The station-based keys stay; the frame's chip is beside them.
    for key in ["chip_thickness_um", "segmentation"] {
        assert!(v.get(key).is_some(), "summary.json lacks {key}");
    }
    let frame = &v["cutting"]["chip_frame"];
    let h = frame["h_avg_um"].as_f64().unwrap_or_else(|| panic!("no chip in the summary: {frame}"));
    // A chip of the order of t1 = 90 µm (h/t1 ≈ 1 in Klippel's V0060, 1.16 simulated; a coarse cut: within 2×).
    assert!(h > 45.0 && h < 180.0, "h_avg {h} µm");
    // The last frame is the final state: `swarf chip` on the run folder reads the same chip.
    let r = swarf::cutting::chip_run::analyse_path(&dir, None).expect("swarf chip on the run folder");
    let c = r.chip.expect("a chip in the last frame");
    assert!((c.h_avg * 1e6 - h).abs() <= 1e-6 * h, "frame {} µm, summary {h} µm", c.h_avg * 1e6);
    assert_eq!(swarf::cutting::chip_report::json(Some(&c), r.time)["sections"], frame["sections"]);
    // The binary prints the table.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_swarf")).arg("chip").arg(&dir).output().expect("swarf");
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    for row in ["h_avg", "h_min", "h_max", "l_seg", "f_seg", "t_seg", "t_sl", "r_chip", "Tab. 9.56"] {
        assert!(table.contains(row), "no {row} in\n{table}");
    }
    // A frame index beyond the run's frames is refused, naming the folder's particles.pvd.
    let e = swarf::cutting::chip_run::analyse_path(&dir, Some(99)).expect_err("frame 99");
    assert!(e.to_string().contains("particles.pvd"), "{e}");
    // A damaged frame file is refused, naming it.
    let bad = dir.join("damaged.vtu");
    std::fs::write(&bad, b"<VTKFile>not a frame</VTKFile>").expect("write");
    let e = swarf::cutting::chip_run::analyse_path(&bad, None).expect_err("a damaged frame");
    assert!(e.to_string().contains("damaged.vtu"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_missing_path_is_refused_by_name() {
    let e = swarf::cutting::chip_run::analyse_path(std::path::Path::new("no/such/run"), None).expect_err("missing");
    assert!(e.to_string().contains("no/such/run"), "{e}");
    let out =
        std::process::Command::new(env!("CARGO_BIN_EXE_swarf")).args(["chip", "no/such/run"]).output().expect("swarf");
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("no/such/run"));
}
