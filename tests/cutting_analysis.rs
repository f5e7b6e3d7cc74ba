//! End-of-run cutting analysis on synthetic data whose answer is known by construction: MSER-5 steady-state
//! detection of a force series (host/cutting/steady.rs) and the chip thickness and geometry (host/cutting/chip.rs).

use swarf::cutting::chip::{Station, chip_geometry, chip_thickness};
use swarf::cutting::steady::{detect, mean_from, quantile_from};
use swarf::rng::SplitMix64;

// ---------------------------------------------------------------------------------------------------------------
// Steady state

/// Samples of the series, and the sample interval [s] (a typical output interval of a cutting run).
const N: usize = 2000;
const DT: f64 = 1e-6;
const MAX_DRIFT: f64 = 0.05;

fn times() -> Vec<f64> {
    (0..N).map(|i| i as f64 * DT).collect()
}

/// f(i) plus Gaussian noise of standard deviation `sigma`.
fn series(seed: u64, sigma: f64, f: impl Fn(usize) -> f64) -> Vec<f64> {
    let mut rng = SplitMix64::new(seed);
    (0..N).map(|i| f(i) + sigma * rng.normal()).collect()
}

#[test]
fn stationary_noise_is_steady_from_the_start() {
    let x = series(1, 5.0, |_| 150.0);
    let s = detect(&times(), &x, MAX_DRIFT).expect("valid series");
    assert!(s.steady, "{s:?}");
    assert!(s.start <= N / 10, "start {} beyond 10 % of {N}", s.start);
    assert_eq!(s.start_time, s.start as f64 * DT);
    // 0.5 ≈ 4σ/√n with σ = 5, n ≥ 1800.
    assert!((s.mean - 150.0).abs() <= 0.5, "mean {}", s.mean);
    // The population std of the noise itself: σ = 5 within 10 % (its sampling error is σ/√(2n) ≈ 1.7 %).
    assert!((s.std - 5.0).abs() <= 0.5, "std {}", s.std);
}

#[test]
fn exponential_rise_transient_is_cut_off() {
    // τ = 5 % of the duration, i.e. 100 samples.
    let tau = 0.05 * N as f64;
    let x = series(2, 3.0, |i| 150.0 * (1.0 - (-(i as f64) / tau).exp()));
    let s = detect(&times(), &x, MAX_DRIFT).expect("valid series");
    assert!(s.steady, "{s:?}");
    assert!((s.mean - 150.0).abs() <= 0.01 * 150.0, "mean {}", s.mean);
    // At 2τ the rise still lacks 150 e⁻² ≈ 20, far above the batch-mean noise 3/√5 ≈ 1.3: not steady yet.
    assert!(s.start as f64 > 2.0 * tau, "start {} not after 2τ = {}", s.start, 2.0 * tau);
    assert!(s.start < N / 2, "start {} not before half the series", s.start);
}

#[test]
fn linear_ramp_is_not_steady() {
    // 50 → 250: MSER of a ramp falls monotonically with truncation, so its minimum sits at the upper end ⌊nb/2⌋
    // = 200 batches (sample 1000); over that second half the fitted rise is 100 against a mean of 200.
    let x = series(3, 1.0, |i| 50.0 + 200.0 * i as f64 / (N - 1) as f64);
    let s = detect(&times(), &x, MAX_DRIFT).expect("valid series");
    assert!(!s.steady, "{s:?}");
    assert_eq!(s.start, N / 2);
    assert!((s.drift - 0.5).abs() <= 0.01, "drift {}", s.drift);
}

#[test]
fn step_is_found() {
    let step = 2 * N / 5;
    let x = series(4, 3.0, |i| if i < step { 100.0 } else { 160.0 });
    let s = detect(&times(), &x, MAX_DRIFT).expect("valid series");
    assert!(s.steady, "{s:?}");
    assert!(s.start.abs_diff(step) <= N / 50, "start {} vs step at {step}", s.start);
    assert!((s.mean - 160.0).abs() <= 0.01 * 160.0, "mean {}", s.mean);
}

#[test]
fn invalid_series_are_rejected() {
    let t = times();
    let x = series(5, 1.0, |_| 10.0);
    assert_eq!(detect(&t[..N - 1], &x, MAX_DRIFT), None, "lengths differ");
    let mut bad = x.clone();
    bad[7] = f64::NAN;
    assert_eq!(detect(&t, &bad, MAX_DRIFT), None, "NaN sample");
    let mut bad_t = t.clone();
    bad_t[3] = f64::INFINITY;
    assert_eq!(detect(&bad_t, &x, MAX_DRIFT), None, "infinite time");
    // 19 samples = 3 complete batches of 5.
    assert_eq!(detect(&t[..19], &x[..19], MAX_DRIFT), None, "fewer than 4 batches");
    assert!(detect(&t[..20], &x[..20], MAX_DRIFT).is_some(), "4 batches suffice");
}

#[test]
fn window_mean_and_quantiles() {
    let x = [9.0, 9.0, 1.0, 2.0, 3.0, 4.0, 5.0];
    // Hand values of numpy's linear method on [1, 2, 3, 4, 5]: h = q (n − 1), v[⌊h⌋] + frac·(v[⌊h⌋+1] − v[⌊h⌋]).
    let close = |a: Option<f64>, b: f64| a.is_some_and(|a| (a - b).abs() <= 1e-12);
    assert!(close(mean_from(&x, 2), 3.0));
    assert!(close(quantile_from(&x, 2, 0.1), 1.4)); // h = 0.4
    assert!(close(quantile_from(&x, 2, 0.5), 3.0)); // h = 2
    assert!(close(quantile_from(&x, 2, 0.9), 4.6)); // h = 3.6
    assert!(close(quantile_from(&x, 2, 0.0), 1.0));
    assert!(close(quantile_from(&x, 2, 1.0), 5.0));
    // Unsorted input: [3, 1, 2] sorts to [1, 2, 3]; q = 0.25 → h = 0.5 → 1.5.
    assert!(close(quantile_from(&[3.0, 1.0, 2.0], 0, 0.25), 1.5));
    assert_eq!(mean_from(&x, 7), None);
    assert_eq!(mean_from(&x, 8), None);
    assert_eq!(quantile_from(&x, 7, 0.5), None);
    assert_eq!(quantile_from(&x, 2, 1.5), None);
    assert_eq!(quantile_from(&x, 2, f64::NAN), None);
    assert_eq!(quantile_from(&[1.0, f64::NAN], 0, 0.5), None);
}

// ---------------------------------------------------------------------------------------------------------------
// Chip thickness

use crate::common::station::{DX, STATION, at, station};

/// A lattice strip on the face: u = iΔx up to station + 10Δx, w = (j + ½)Δx for j in `layers`, kept above the
/// surface. Its extent along n is (layers − 1)Δx between centres, i.e. `layers`·Δx of material.
fn strip(s: &Station, layers: std::ops::Range<usize>) -> Vec<[f64; 2]> {
    let top = ((STATION + 10.0 * DX) / DX).round() as usize;
    let mut p = Vec::new();
    for i in 0..=top {
        for j in layers.clone() {
            let q = at(s, i as f64 * DX, (j as f64 + 0.5) * DX);
            if q[1] > s.surface_y {
                p.push(q);
            }
        }
    }
    p
}

/// Uncut workpiece ahead of the tool: a square lattice below the surface, 300Δx long, 20Δx deep.
fn workpiece(s: &Station) -> Vec<[f64; 2]> {
    let mut p = Vec::new();
    for i in 0..300 {
        for j in 0..20 {
            p.push([s.rake_point[0] + (i as f64 + 0.5) * DX, s.surface_y - (j as f64 + 0.5) * DX]);
        }
    }
    p
}

fn assert_thickness(got: Option<f64>, expected: f64, what: &str) {
    let h = got.unwrap_or_else(|| panic!("{what}: no thickness"));
    assert!(((h - expected) / expected).abs() <= 1e-9, "{what}: {h} m, expected {expected} m");
}

#[test]
fn straight_chip_thickness_is_exact() {
    for rake in [10.0, 0.0, -5.0] {
        let s = station(rake);
        let mut p = strip(&s, 0..12);
        p.extend(workpiece(&s));
        // 12 layers: centres from 0.5Δx to 11.5Δx, plus one spacing → 12Δx.
        assert_thickness(chip_thickness(&s, p.iter().copied()), 12.0 * DX, &format!("γ = {rake}°"));
    }
}

#[test]
fn curled_strip_further_out_is_ignored() {
    for rake in [10.0, 0.0, -5.0] {
        let s = station(rake);
        let mut p = strip(&s, 0..12);
        p.extend(workpiece(&s));
        // A second strip at w ≥ 20Δx: 8.5Δx gap above the chip's last layer at 11.5Δx, more than 2Δx.
        p.extend(strip(&s, 20..26));
        assert_thickness(chip_thickness(&s, p), 12.0 * DX, &format!("curled, γ = {rake}°"));
    }
}

#[test]
fn empty_slice_or_no_chip_gives_none() {
    let s = station(10.0);
    let p = strip(&s, 0..12);
    // The strip ends 10Δx above the station; a slice 20Δx above it is empty.
    let beyond = Station { station: STATION + 20.0 * DX, ..s };
    assert_eq!(chip_thickness(&beyond, p.iter().copied()), None);
    // Every particle below the surface: no chip, although the slice holds the strip.
    let high = Station { surface_y: 1.0, ..s };
    assert_eq!(chip_thickness(&high, p.iter().copied()), None);
    // A single particle in the slice.
    assert_eq!(chip_thickness(&s, [at(&s, STATION, 0.5 * DX)]), None);
    assert_eq!(chip_thickness(&s, std::iter::empty()), None);
    // Invalid station.
    assert_eq!(chip_thickness(&Station { spacing: 0.0, ..s }, p.iter().copied()), None);
    assert_eq!(chip_thickness(&Station { rake_angle: f64::NAN, ..s }, p), None);
}

// ---------------------------------------------------------------------------------------------------------------
// Chip geometry

#[test]
fn saw_tooth_geometry() {
    // One period of 14 samples: up 80, 90, …, 150 µm, then down 140, …, 90 µm. Per period 80 and 150 occur once,
    // 90..140 twice; the period's sum is 80 + 150 + 2·(90 + … + 140) = 1610, so the mean is 1610/14 = 115 µm.
    // 50 periods, 700 samples, sorted: 80 at indices 0..49, 90 at 50..149, …, 140 at 550..649, 150 at 650..699.
    // 10th percentile: h = 0.1·699 = 69.9, between indices 69 and 70, both 90 → 90 µm.
    // 90th percentile: h = 0.9·699 = 629.1, between indices 629 and 630, both 140 → 140 µm.
    // Segmentation (140 − 90)/140 = 5/14. A None after every period is skipped.
    let period: Vec<f64> = (0..8).chain((1..7).rev()).map(|k| (80.0 + 10.0 * k as f64) * 1e-6).collect();
    assert_eq!(period.len(), 14);
    let mut h = Vec::new();
    for _ in 0..50 {
        h.extend(period.iter().map(|&v| Some(v)));
        h.push(None);
    }
    let g = chip_geometry(&h).expect("700 samples");
    let rel = |a: f64, b: f64| ((a - b) / b).abs();
    assert_eq!(g.samples, 700);
    assert!(rel(g.h_avg, 115e-6) <= 0.01, "h_avg {}", g.h_avg);
    assert!(rel(g.h_min, 90e-6) <= 1e-12, "h_min {}", g.h_min);
    assert!(rel(g.h_max, 140e-6) <= 1e-12, "h_max {}", g.h_max);
    assert!((g.segmentation - 5.0 / 14.0).abs() <= 1e-12, "segmentation {}", g.segmentation);
    assert!((g.segmentation - (g.h_max - g.h_min) / g.h_max).abs() <= 1e-12);
}

#[test]
fn constant_chip_has_no_segmentation() {
    let h = vec![Some(100e-6); 20];
    let g = chip_geometry(&h).expect("20 samples");
    assert_eq!(g.segmentation, 0.0);
    assert_eq!((g.h_min, g.h_max), (100e-6, 100e-6));
    assert!((g.h_avg - 100e-6).abs() <= 1e-18);
}

#[test]
fn too_few_or_invalid_thickness_samples() {
    // Four values and any number of Nones: fewer than 5 samples.
    let h = [Some(1e-4), None, Some(1e-4), None, Some(1e-4), Some(1e-4), None];
    assert_eq!(chip_geometry(&h), None);
    let h = [Some(1e-4), Some(1e-4), Some(f64::NAN), Some(1e-4), Some(1e-4), Some(1e-4)];
    assert_eq!(chip_geometry(&h), None);
}

// The wear tallies of summary.json (host/cutting/tool_wear.rs).
use swarf::cutting::tool_wear::{ToolTally, ToolWear};

/// Two tools over four samples 1 µs apart: the first touches at the last three with rates 1, 100, 1 m/s (a
/// spike), the second never; a NaN rate with contact counts as contact time but no wear. Sums by hand.
#[test]
fn tallies_sum_the_rectangles_and_the_median_ignores_a_spike() {
    let mut w = ToolWear::new(2);
    let samples = [(1e-6, [0.0, 0.0], [f64::NAN, f64::NAN]), (2e-6, [3.0, 0.0], [1.0, f64::NAN])];
    let more = [(3e-6, [5.0, 0.0], [100.0, f64::NAN]), (4e-6, [2.0, 0.0], [1.0, f64::NAN])];
    for (t, n, r) in samples.iter().chain(&more) {
        w.push(*t, n.iter().copied().zip(r.iter().copied()));
    }
    let a = &w.tools[0];
    assert!((a.contact_time - 3e-6).abs() < 1e-18 && a.first == Some(2e-6) && a.last == Some(4e-6));
    assert!((a.wear - 102e-6).abs() < 1e-15, "{}", a.wear);
    assert!((a.wear_median() - 3e-6).abs() < 1e-18, "{}", a.wear_median());
    assert_eq!(w.tools[1], ToolTally::default());
    let j = w.json();
    assert!(j[1]["wear_m"].is_null() && j[1]["contact_time_s"] == 0.0);
    w.push(5e-6, [(1.0, f64::NAN), (0.0, f64::NAN)].into_iter());
    assert!((w.tools[0].contact_time - 4e-6).abs() < 1e-18 && (w.tools[0].wear - 102e-6).abs() < 1e-15);
}
