//! The per-observable steady-state analysis (host/cutting/window.rs, autocorr.rs), the chip thickness normal to the
//! chip's own axis (host/cutting/chip_axis.rs), the crests and valleys of a segmented chip (host/cutting/segments.rs)
//! and the early stop's verdict (host/cutting/early_stop.rs), on synthetic signals and geometries whose answer is
//! known by construction.

use swarf::cutting::autocorr::integrated_time;
use swarf::cutting::chip::{Station, chip_thickness};
use swarf::cutting::chip_axis::chip_thickness_normal;
use swarf::cutting::early_stop::EarlyStop;
use swarf::cutting::segments::crests_valleys;
use swarf::cutting::window::{BATCHES_PER_TAU, find, time_to_travel};
use swarf::rng::SplitMix64;

/// Sample interval [s] (V0060's: output every end/50, 10 samples per output).
const DT: f64 = 3.1e-7;

fn times(n: usize) -> Vec<f64> {
    (0..n).map(|i| i as f64 * DT).collect()
}

/// f(i) plus stationary AR(1) noise x_{i+1} = φ x_i + √(1 − φ²) σ ε (standard deviation σ, exact integrated
/// autocorrelation time τ_int = (1 + φ)/(1 − φ) samples).
fn ar1(seed: u64, n: usize, phi: f64, sigma: f64, f: impl Fn(usize) -> f64) -> Vec<f64> {
    let mut rng = SplitMix64::new(seed);
    let mut e = sigma * rng.normal();
    let k = (1.0 - phi * phi).sqrt() * sigma;
    (0..n)
        .map(|i| {
            let v = f(i) + e;
            e = phi * e + k * rng.normal();
            v
        })
        .collect()
}

fn tau_exact(phi: f64) -> f64 {
    (1.0 + phi) / (1.0 - phi)
}

// ---------------------------------------------------------------------------------------------------------------
// Correlation time

#[test]
fn ar1_correlation_time_is_estimated() {
    // Sokal's estimator with window M ≈ 5 τ has a relative standard deviation √(2(2M + 1)/n) (Sokal 1997, Eq. 3.19):
    // 8 % for φ = 0.9 (τ = 19, M ≈ 95) at n = 60 000; the tolerance 25 % is 3 of them. The first-zero-crossing
    // cut-off adds a bias below 1 % here (ρ_k = φ^k reaches the noise 1/√n ≈ 0.004 at k ≈ 52 ≫ τ).
    for (seed, phi) in [(11, 0.9), (12, 0.5), (13, 0.0)] {
        let x = ar1(seed, 60_000, phi, 4.0, |_| 100.0);
        let tau = integrated_time(&x).expect("a valid series");
        let exact = tau_exact(phi);
        assert!((tau - exact).abs() <= 0.25 * exact, "φ = {phi}: τ_int {tau} vs exact {exact}");
    }
    assert_eq!(integrated_time(&[1.0; 100]), None, "a constant series has no correlation time");
    assert_eq!(integrated_time(&[1.0, 2.0, f64::NAN, 3.0, 4.0]), None);
}

// ---------------------------------------------------------------------------------------------------------------
// Steady windows

#[test]
fn exponential_rise_in_correlated_noise() {
    // 150 (1 − e^{−i/T}) with T = 100 samples, AR(1) noise σ = 3, φ = 0.9 (τ_int = 19): the bias 150 e^{−i/T}
    // falls to the noise of a batch mean (σ √(τ_int/b) ≈ 2 for b = 2 τ_int) near i = T ln 75 ≈ 430.
    let n = 4000;
    let rise = 100.0;
    let x = ar1(21, n, 0.9, 3.0, |i| 150.0 * (1.0 - (-(i as f64) / rise).exp()));
    let w = find(&times(n), &x, 0.0, 0.05).expect("a window");
    assert!(w.steady, "{w:?}");
    // Tolerance: not before 2T (bias still 20 = 7σ), and within 10 T (bias 0.007) plus one batch.
    assert!(w.start as f64 >= 2.0 * rise, "window from sample {} before 2T", w.start);
    assert!((w.start as f64) <= 10.0 * rise + w.batch as f64, "window from sample {} after 10T + b", w.start);
    assert!((w.mean - 150.0).abs() <= 0.01 * 150.0, "mean {}", w.mean);
    // The batches are matched to the noise's correlation time: τ within 30 % (a shorter candidate than above).
    assert!((w.tau_samples - tau_exact(0.9)).abs() <= 0.3 * tau_exact(0.9), "τ {}", w.tau_samples);
    assert_eq!(w.batch, (BATCHES_PER_TAU * w.tau_samples).ceil() as usize);
    assert!((w.tau_s - w.tau_samples * DT).abs() <= 1e-12 * w.tau_s);
    // Standard error against σ √(τ_int/n_window): within 40 % (few dozen batches).
    let expected = 3.0 * (tau_exact(0.9) / (n - w.start) as f64).sqrt();
    assert!((w.sem - expected).abs() <= 0.4 * expected, "standard error {} vs {expected}", w.sem);
}

#[test]
fn step_is_found_in_correlated_noise() {
    let (n, step) = (4000, 1600);
    let x = ar1(22, n, 0.8, 3.0, |i| if i < step { 100.0 } else { 160.0 });
    let w = find(&times(n), &x, 0.0, 0.05).expect("a window");
    assert!(w.steady, "{w:?}");
    // Never before the step (the batch holding it is biased by 60 = 20σ), and within 5 % of the steady part after
    // it: MSER cuts whole batches, and a few more where the first batch means after the step happen to lie low.
    let late = (n - step) / 20;
    assert!(w.start >= step && w.start <= step + late, "window from {} vs step at {step} (b = {})", w.start, w.batch);
    assert!((w.mean - 160.0).abs() <= 0.01 * 160.0, "mean {}", w.mean);
}

#[test]
fn linear_ramp_is_refused_above_the_tolerance() {
    // 100 → 140 over the series: whatever window MSER keeps (at most the second half: 120 → 140), the fitted
    // rise over it relative to its mean is ≥ 20/130 ≈ 0.15, above the tolerance 0.1.
    let n = 4000;
    let x = ar1(23, n, 0.8, 1.0, |i| 100.0 + 40.0 * i as f64 / n as f64);
    let w = find(&times(n), &x, 0.0, 0.1).expect("a window");
    assert!(!w.steady, "{w:?}");
    assert!(w.drift >= 0.15, "drift {}", w.drift);
    // The same ramp, 100 → 101 (relative drift ≤ 0.01, under the noise): steady.
    let flat = ar1(23, n, 0.8, 1.0, |i| 100.0 + i as f64 / n as f64);
    let w = find(&times(n), &flat, 0.0, 0.1).expect("a window");
    assert!(w.drift.abs() <= 0.1 && w.steady, "{w:?}");
}

#[test]
fn no_window_before_the_minimum_transient() {
    let n = 2000;
    let t = times(n);
    let x = ar1(24, n, 0.5, 2.0, |_| 50.0);
    let t_min = t[700];
    let w = find(&t, &x, t_min, 0.1).expect("a window");
    assert!(w.start >= 700 && w.start_time >= t_min, "{w:?}");
    assert!(w.steady);
    // Fewer than 20 samples after t_min: nothing to report.
    assert_eq!(find(&t, &x, t[n - 19], 0.1), None);
    // Lengths differ, or a value is not finite.
    assert_eq!(find(&t[1..], &x, 0.0, 0.1), None);
    let mut bad = x.clone();
    bad[3] = f64::NAN;
    assert_eq!(find(&t, &bad, 0.0, 0.1), None);
}

#[test]
fn too_short_for_its_correlation_time_is_not_steady() {
    // One slow swing over the whole record (period = n) with a little noise: its autocorrelation cos(2πk/n) first
    // crosses zero at k = n/4, so τ_int ≈ 1 + 2 Σ_{k<n/4} cos(2πk/n) ≈ n/π, and fewer than 4 batches of τ_int fit:
    // the record cannot tell a steady level from a swing.
    let n = 600;
    let mut rng = SplitMix64::new(25);
    let x: Vec<f64> = (0..n)
        .map(|i| 80.0 + 5.0 * (2.0 * std::f64::consts::PI * i as f64 / n as f64).sin() + 0.1 * rng.normal())
        .collect();
    let w = find(&times(n), &x, 0.0, 0.1).expect("a window");
    // τ_int is estimated on MSER-5's candidate part (the last ~half of the record here): long against it.
    assert!(w.tau_samples >= 0.05 * n as f64, "{w:?}");
    assert!(!w.steady, "{w:?}");
}

#[test]
fn time_to_travel_inverts_the_tool_motion() {
    // Without a ramp: t = L/v. With a ramp t_r: s(t) = t²/(2 t_r) (during it), t − t_r/2 (after it).
    assert!((time_to_travel(3e-4, 6.0, 0.0) - 5e-5).abs() <= 1e-18);
    let (v, tr) = (2.0, 1e-5);
    let during = time_to_travel(0.25 * v * tr, v, tr); // s = t_r/4 = t²/(2 t_r) → t = t_r/√2
    assert!((during - tr / 2f64.sqrt()).abs() <= 1e-15, "{during}");
    let after = time_to_travel(v * 3.0 * tr, v, tr); // s = 3 t_r = t − t_r/2 → t = 3.5 t_r
    assert!((after - 3.5 * tr).abs() <= 1e-15, "{after}");
    assert_eq!(time_to_travel(0.0, 0.0, 0.0), 0.0);
    assert_eq!(time_to_travel(1e-3, 0.0, 0.0), f64::INFINITY);
}

// ---------------------------------------------------------------------------------------------------------------
// Early stop's verdict

/// Shortest early-stop window in these tests [s]: a third of the record.
const SPAN: f64 = 3e-4;

#[test]
fn early_stop_needs_both_forces_steady_and_precise() {
    let n = 3000;
    let t = times(n);
    let fc = ar1(31, n, 0.8, 3.0, |_| 150.0);
    let ff = ar1(32, n, 0.8, 3.0, |_| 110.0);
    let (wc, wf) = (find(&t, &fc, 0.0, 0.02), find(&t, &ff, 0.0, 0.02));
    // Standard errors ≈ 3 √(9/3000) ≈ 0.16, 0.1 % of the means: steady to 2 %.
    let mut e = EarlyStop::new(0.02, SPAN);
    assert!(e.check(wc.as_ref(), wf.as_ref(), 1.0, 7), "{}", e.reason);
    assert_eq!(e.at, Some((1.0, 7)));
    // 0.05 % is below the standard error of F_c's mean (≈ 0.1 %): not yet.
    let mut strict = EarlyStop::new(5e-4, SPAN);
    assert!(!strict.check(wc.as_ref(), wf.as_ref(), 1.0, 7));
    assert!(strict.reason.contains("F_c") && strict.reason.contains("standard error"), "{}", strict.reason);
    assert_eq!(strict.at, None);
    // F_f still ramping (110 → 130): not steady, whatever F_c does.
    let ramp = ar1(33, n, 0.8, 1.0, |i| 110.0 + 20.0 * i as f64 / n as f64);
    let wr = find(&t, &ramp, 0.0, 0.02);
    let mut e = EarlyStop::new(0.02, SPAN);
    assert!(!e.check(wc.as_ref(), wr.as_ref(), 1.0, 7));
    assert!(e.reason.starts_with("F_f"), "{}", e.reason);
    // No window yet.
    assert!(!EarlyStop::new(0.02, SPAN).check(None, wf.as_ref(), 1.0, 7));
    // A window shorter than the shortest span (here longer than the record, n DT ≈ 9.3e-4 s) is too young.
    let mut young = EarlyStop::new(0.02, 1e-3);
    assert!(!young.check(wc.as_ref(), wf.as_ref(), t[n - 1], 7));
    assert!(young.reason.contains("short of"), "{}", young.reason);
}

// ---------------------------------------------------------------------------------------------------------------
// Chip thickness normal to the chip's axis

use crate::common::station::{DX, EDGE, STATION, SURFACE, at, station};

/// Chip thickness of the synthetic strips: 12 layers of particles, i.e. 12 Δx of material.
const H: f64 = 12.0 * DX;

/// A straight strip of 12 layers on its own square lattice, leaving the face at angle `theta` (towards n) with its
/// inner surface through the face point at `lift` above the station: particles p = o + iΔx a + (j + ½)Δx m, with
/// o = (station, lift) in the face frame, a = d cos θ + n sin θ along it, m = −d sin θ + n cos θ across it.
fn tilted_strip(s: &Station, theta: f64, lift: f64) -> Vec<[f64; 2]> {
    let (st, ct) = theta.sin_cos();
    let mut p = Vec::new();
    for i in -60..=60 {
        for j in 0..12 {
            let (a, b) = (i as f64 * DX, (j as f64 + 0.5) * DX);
            let (u, w) = (STATION + a * ct - b * st, lift + a * st + b * ct);
            if w >= 0.0 {
                p.push(at(s, u, w));
            }
        }
    }
    p
}

#[test]
fn tilted_chip_is_measured_square() {
    for rake in [0.0, 10.0] {
        let s = station(rake);
        for theta_deg in [0.0f64, 20.0, 35.0] {
            let theta = theta_deg.to_radians();
            // Lifted off the face by enough that the strip clears it within the axis window (1.5 h around the
            // centre): a chip that has curled away.
            let p = tilted_strip(&s, theta, 2.0 * DX + 1.5 * H * theta.sin());
            let normal = chip_thickness_normal(&s, p.iter().copied()).expect("a thickness");
            // Its own lattice, cut square: 12 Δx within 1 % (the axis is exact by the strip's mirror symmetry but for
            // the particles the face cuts off at the window's edge; the face-normal slice is 6 % and 22 % off at
            // 20° and 35°).
            assert!((normal - H).abs() <= 0.01 * H, "γ {rake}°, θ {theta_deg}°: {normal} vs {H}");
            // The face-normal slice crosses it at θ: about h/cos θ (within one spacing of lattice granularity).
            let oblique = chip_thickness(&s, p.iter().copied()).expect("a thickness");
            assert!((oblique - H / theta.cos()).abs() <= DX, "θ {theta_deg}°: face-normal {oblique}");
        }
    }
}

#[test]
fn curved_chip_is_measured_along_its_radius() {
    // An annulus of 12 rings (r = ρ + (k + ½)Δx, ρ = 30Δx) on a polar lattice (arc spacing Δx), centred 15Δx down
    // the face from the station and 41Δx out of it: the face-normal line at the station crosses the lower arc at
    // 21–30° to its radius. The thickness normal to the local axis is the radial one, 12Δx; the tolerance is 3 %
    // (the polar lattice is not exactly symmetric about the slice's radius, so the principal axis tilts by up to
    // about half an arc spacing over the window, ≈ 1°, and the slice's particles sit up to Δx off the radius).
    let s = station(0.0);
    let (rho, c) = (30.0 * DX, at(&s, STATION - 15.0 * DX, 41.0 * DX));
    let mut p = Vec::new();
    for k in 0..12 {
        let r = rho + (k as f64 + 0.5) * DX;
        let m = (2.0 * std::f64::consts::PI * r / DX).round() as usize;
        for i in 0..m {
            let phi = 2.0 * std::f64::consts::PI * i as f64 / m as f64;
            let q = [c[0] + r * phi.cos(), c[1] + r * phi.sin()];
            // Only what is out of the tool (x ≥ the face for γ = 0) and above the uncut surface.
            if q[0] >= EDGE[0] && q[1] > SURFACE {
                p.push(q);
            }
        }
    }
    let normal = chip_thickness_normal(&s, p.iter().copied()).expect("a thickness");
    assert!((normal - H).abs() <= 0.03 * H, "{normal} vs {H}");
    let oblique = chip_thickness(&s, p.iter().copied()).expect("a thickness");
    assert!(oblique >= 1.05 * H, "the face-normal slice should overestimate: {oblique}");
}

// ---------------------------------------------------------------------------------------------------------------
// Segmentation

#[test]
fn saw_tooth_gives_crests_valleys_and_pitch() {
    // A saw-tooth chip: thickness rising linearly from 80 to 150 µm over 85 % of a period T = 8.5 µs, falling
    // back over the rest, sampled every DT = 0.31 µs over 40 periods, with ±1 µm uniform noise. Crest 150,
    // valley 80 (± the noise and the sampling: a sample lands within DT of the tip, 0.31/7.2 µs of the rise ≈ 3 µm
    // below it at worst), degree 70/150; the period from 39 crest intervals within one sample interval / 39.
    let period = 8.5e-6;
    let n = (40.0 * period / DT) as usize;
    let t = times(n);
    let mut rng = SplitMix64::new(41);
    let h: Vec<f64> = t
        .iter()
        .map(|&ti| {
            let ph = (ti / period).fract();
            let v = if ph < 0.85 { 80.0 + 70.0 * ph / 0.85 } else { 150.0 - 70.0 * (ph - 0.85) / 0.15 };
            (v + 2.0 * rng.uniform() - 1.0) * 1e-6
        })
        .collect();
    let s = crests_valleys(&t, &h, 20e-6).expect("segments");
    assert!(s.crests >= 39 && s.crests <= 40, "{s:?}");
    assert!(s.valleys >= 39 && s.valleys <= 40, "{s:?}");
    assert!((s.h_crest - 150e-6).abs() <= 4e-6, "crest {}", s.h_crest);
    assert!((s.h_valley - 80e-6).abs() <= 4e-6, "valley {}", s.h_valley);
    assert!((s.degree - 70.0 / 150.0).abs() <= 0.03, "degree {}", s.degree);
    assert!((s.period - period).abs() <= 2.0 * DT / 39.0, "period {} vs {period}", s.period);
    // l_seg = v_c t1/h_avg × T: V0060's v_c = 6.355 m/s, t1 = 100 µm, h_avg = 115 µm.
    let pitch = s.pitch(6.355, 100e-6, 115e-6);
    assert!((pitch - 6.355 * 100.0 / 115.0 * period).abs() <= 1e-3 * pitch, "pitch {pitch}");
    // A constant thickness with noise under the prominence has no crests.
    let flat: Vec<f64> = t.iter().map(|_| (100.0 + 2.0 * rng.uniform()) * 1e-6).collect();
    assert_eq!(crests_valleys(&t, &flat, 20e-6), None);
    assert_eq!(crests_valleys(&t, &h[1..], 20e-6), None, "lengths differ");
}
