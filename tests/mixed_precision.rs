//! The mixed precision (issue 7: "positions kept exact enough, stress in f32"): an f32 state whose positions are
//! f32 pairs hi + lo, the corrector's position sum compensated (`sph::integrate::advance_compensated`). The
//! facts tested: TwoSum's error term is exact; a compensated sum keeps every increment where a rounded f32 sum
//! loses a fixed share of each; a rigidly translating block (every rate but ẋ = v exactly zero) keeps its exact
//! positions through the solver's steps, rebuilds and reorders, where plain f32 drifts.

use swarf::backend::CpuBackend;
use swarf::kernels::sph::integrate::{advance_compensated, two_sum};
use swarf::kernels::vector::V2f32;
use swarf::kernels::{Dim2, Vector};
use swarf::rng::SplitMix64;
use swarf::run::setup;
use swarf::scene::{Precision, Scene};
use swarf::solver::Solver;

/// The distance from x to the next f32 above it (x > 0, normal).
fn ulp32(x: f64) -> f64 {
    let f = x as f32;
    (f32::from_bits(f.to_bits() + 1) - f) as f64
}

/// TwoSum (Knuth, TAOCP vol. 2 §4.2.2): for f32 operands whose exponents differ by at most 21, a + b is exact in
/// f64 (at most 46 significant bits), and s + e must equal it exactly, for every one of 10⁵ random pairs of
/// either sign.
#[test]
fn two_sum_error_term_is_exact() {
    let mut rng = SplitMix64::new(7);
    for _ in 0..100_000 {
        let a = (1e-4 + 1e-2 * rng.uniform()) as f32;
        let sign = if rng.uniform() < 0.5 { -1.0 } else { 1.0 };
        let b = (sign * a as f64 * 10f64.powf(-6.0 * rng.uniform())) as f32;
        let (s, e) = two_sum(a, b);
        assert_eq!(s, a + b, "s is the rounded sum");
        assert_eq!(s as f64 + e as f64, a as f64 + b as f64, "a = {a:e}, b = {b:e}: s = {s:e}, e = {e:e}");
    }
}

/// 10⁶ steps of Δt = 2.87e-10 s at v = (1, −0.37) m/s from x0 = (7.3e-4, 4.1e-4) m: the 150k cut's step, where
/// one step moves a coordinate by 2.5–5 f32 ulps (docs/stability.md). The exact result of summing the f32
/// increments d = fl(c·v) is x0 + N d (N d has at most 44 bits: exact in f64). The compensated sum may err by
/// at most ½ ulp(lo + d) ≤ ½ ulp(2|d|) per step; the plain f32 sum rounds every step to the ulp grid and must
/// be at least 1000 times further off (it is, by about 10⁵: each step's 4.9 ulps become 5).
#[test]
fn compensated_sum_keeps_every_increment() {
    let n = 1_000_000u32;
    let x0 = [7.3e-4f64, 4.1e-4];
    let (c, v) = (2.87e-10f32, V2f32([1.0, -0.37]));
    let d: [f32; 2] = [c * v.0[0], c * v.0[1]];
    let split = |x: f64| (x as f32, (x - (x as f32) as f64) as f32);
    let (h0, l0) = (split(x0[0]), split(x0[1]));
    let (mut hi, mut lo) = (V2f32([h0.0, l0.0]), V2f32([h0.1, l0.1]));
    let mut plain = V2f32([x0[0] as f32, x0[1] as f32]);
    for _ in 0..n {
        (hi, lo) = advance_compensated(&hi, &lo, c, &v);
        plain = V2f32([plain.0[0] + c * v.0[0], plain.0[1] + c * v.0[1]]);
    }
    for k in 0..2 {
        let exact = x0[k] + n as f64 * d[k] as f64;
        let comp = (hi.get(k) as f64 + lo.get(k) as f64 - exact).abs();
        let rounded = (plain.get(k) as f64 - exact).abs();
        let bound = n as f64 * 0.5 * ulp32(2.0 * (d[k] as f64).abs());
        eprintln!("component {k}: compensated {comp:e} m, rounded {rounded:e} m, bound {bound:e} m");
        assert!(comp <= bound, "component {k}: compensated error {comp:e} m above the bound {bound:e} m");
        assert!(rounded > 1e3 * bound, "component {k}: the plain f32 sum erred by only {rounded:e} m");
    }
}

/// AT-60's block (cases/block-translation.toml: 1600 particles, every stabiliser on) translating at 100 m/s for
/// 600 steps of the scene's Δt: v_ij = 0 and σ = 0 make every rate but ẋ = v exactly zero, so the exact
/// positions are x0 + N d with d = fl(fl(Δt) · 100) per step. Mixed: within N · ½ ulp(2d) of that for every
/// particle, through the step loop's rebuilds and reorders (the low parts move with their particles). Plain f32:
/// at least ten times further off.
#[test]
fn mixed_block_translation_keeps_exact_positions() {
    let base = Scene::load("cases/block-translation.toml", &[]).expect("scene");
    let steps = 600usize;
    let b = CpuBackend::new();
    let run = |p: Precision| {
        let scene = base.with_precision(Some(p));
        let s = setup::<f32, Dim2>(&scene).expect("setup");
        assert_eq!(s.pos_lo.is_some(), p == Precision::Mixed, "low parts exactly in the mixed precision");
        let x0: Vec<[f64; 2]> = {
            let g = scene.generate().expect("generate");
            g.pos.iter().map(|p| [p[0], p[1]]).collect()
        };
        let mut solver = Solver::<_, f32, Dim2>::new(&b, &s).expect("solver");
        assert_eq!(solver.precision(), p.as_str());
        solver.advance(&b, s.dt, steps).expect("steps");
        let h = solver.download(&b).expect("download");
        let lo = solver.download_pos_lo(&b).expect("low parts");
        let d = (s.dt as f32 * 100.0f32) as f64;
        let err = (0..h.len())
            .map(|i| {
                let x = |k: usize| h.pos[i].get(k) as f64 + lo.as_ref().map_or(0.0, |l| l[i].get(k) as f64);
                let id = h.id[i] as usize;
                (x(0) - (x0[id][0] + steps as f64 * d)).abs().max((x(1) - x0[id][1]).abs())
            })
            .fold(0.0f64, f64::max);
        let reordered = h.id.iter().enumerate().any(|(i, &id)| id as usize != i);
        (err, solver.cell_rebuilds(&b).expect("rebuilds"), reordered, d)
    };
    let (mixed, rebuilds, reordered, d) = run(Precision::Mixed);
    let (f32_err, _, _, _) = run(Precision::F32);
    let bound = steps as f64 * 0.5 * ulp32(2.0 * d);
    eprintln!("block: mixed error {mixed:e} m, f32 error {f32_err:e} m, bound {bound:e} m, {rebuilds} rebuilds");
    assert!(rebuilds >= 3 && reordered, "the run must rebuild and reorder ({rebuilds} rebuilds)");
    assert!(mixed <= bound, "mixed: largest position error {mixed:e} m, bound {bound:e} m");
    assert!(f32_err > 10.0 * bound, "plain f32 erred by only {f32_err:e} m (bound {bound:e} m)");
}
