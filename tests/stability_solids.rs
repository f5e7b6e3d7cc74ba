//! Hard cases for solids (issue 8), on the CPU: the tensile instability in a notched bar under plane-strain
//! tension (klippel-constitutive.md §8 H1(b), roethlin-solver.md §9 F1; cases/hard/tensile-notched-bar.toml) and
//! the checkerboard (zero-energy) mode of a free elastic block (klippel-constitutive.md §8 H3;
//! cases/hard/checkerboard-block.toml). Each test prints its measurements (`--nocapture`).

use crate::common;
use crate::on_test_backend;

use swarf::analysis::{components_per_group, min_pair_distances};
use swarf::backend::{AnyBackend, Backend};
use swarf::kernels::{Dim, Dim2, Vector};
use swarf::run::{RunOptions, Snapshot, run_observed, setup};
use swarf::scene::Scene;
use swarf::solver::Solver;
use swarf::solver::diagnostics::compute;

const BAR: &str = "cases/hard/tensile-notched-bar.toml";
const BLOCK: &str = "cases/hard/checkerboard-block.toml";

fn cpu() -> AnyBackend {
    common::test_backend()
}

fn opts(name: &str) -> RunOptions {
    RunOptions::quiet(std::env::temp_dir().join(format!("swarf-test-stability-{name}-{}", std::process::id())))
}

/// The smallest distance between two particles and where it is (brute force: the bar holds 912 particles).
fn closest_pair(pos: &[[f64; 3]]) -> (f64, [f64; 2]) {
    let mut best = (f64::INFINITY, [0.0; 2]);
    for (i, a) in pos.iter().enumerate() {
        for b in &pos[i + 1..] {
            let r2 = (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2);
            if r2 < best.0 {
                best = (r2, [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])]);
            }
        }
    }
    (best.0.sqrt(), best.1)
}

/// One output frame of the notched bar.
#[derive(Clone, Copy, Debug)]
struct BarFrame {
    /// Elongation: span of the particles along x over its initial value, minus 1 (the grips' outer columns move
    /// with the prescribed velocity, so this is 10 m/s · t / 29.5 mm).
    elongation: f64,
    /// Minimum pair distance / dx, and the midpoint of that pair [m].
    dmin: f64,
    at: [f64; 2],
    /// Connected pieces of the whole bar (particles closer than 2 dx connected, as in the rings' test).
    pieces: usize,
    /// Largest equivalent plastic strain.
    eps_max: f64,
}

/// Runs the bar with `overrides`, stopping after the first frame in more than one piece.
fn pull_bar(tag: &str, overrides: &[String]) -> (Vec<BarFrame>, Result<(), String>) {
    let scene = Scene::load(BAR, overrides).expect("scene");
    let dx = scene.discretisation.dx;
    let mut frames = Vec::new();
    let mut length0 = None;
    let mut obs = |s: &Snapshot| {
        let (lo, hi) = s.pos.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| (l.min(p[0]), h.max(p[0])));
        let l0 = *length0.get_or_insert(hi - lo);
        let whole = vec![0u32; s.pos.len()];
        let pieces = components_per_group(&s.pos, &whole, 2.0 * dx).expect("components")[0];
        let (d, at) = closest_pair(&s.pos);
        let eps_max = s.plastic_strain.map_or(f64::NAN, |e| e.iter().copied().fold(0.0, f64::max));
        frames.push(BarFrame { elongation: (hi - lo) / l0 - 1.0, dmin: d / dx, at, pieces, eps_max });
        pieces == 1
    };
    let r = run_observed(&cpu(), &scene, &opts(tag), Some(&mut obs)).map(|_| ()).map_err(|e| e.to_string());
    for f in &frames {
        eprintln!(
            "{tag}: elongation {:6.2} %  min pair {:.3} dx at ({:.2}, {:.2}) mm  pieces {}  max ε̄ {:.3}",
            100.0 * f.elongation,
            f.dmin,
            1e3 * f.at[0],
            1e3 * f.at[1],
            f.pieces,
            f.eps_max
        );
    }
    (frames, r)
}

/// Elongation up to which the pairing criterion is checked, for both runs.
const PAIRING_WINDOW: f64 = 0.12;

/// H1(b), with artificial stress (AV α = β = 1, η = 0.1; AS ε = 0.3, n = 4): the notched AISI 4340 bar pulled
/// at 10 m/s (339 1/s), 912 particles, Δx = 0.5 mm, 6400 steps.
/// Criterion (klippel-constitutive.md §8 H1(b): "no particle pairs, minimum pair distance > 0.5Δp, until ω-based
/// failure"; swarf has no damage model, so the limit is a stated elongation): the minimum pair distance stays
/// above 0.5 Δx up to 12 % elongation, and the bar stays one connected piece (neighbours closer than 2 Δx) up
/// to the end of the run, 20.3 % elongation.
/// Measured (f64, CPU, frames every 0.34 % elongation): min pair distance ≥ 0.615 Δx up to 12 % (0.606 Δx at
/// 12.5 %, 0.555 Δx at 13.6 %, where max ε̄ = 0.48); it falls below 0.5 Δx at 13.9 % and to 0.17 Δx at 17 %,
/// across the centre line of the necking section (max ε̄ ≈ 0.8), then recovers to 0.49 Δx at 20.3 %: at large
/// strain the artificial stress no longer prevents pairing (roethlin-solver.md §9 F1: UL strong forms still fail
/// at large extension). One piece throughout; max ε̄ = 1.2 at the end. Run time 15 s alone, 20 s beside the
/// other tests of this file.
#[test]
fn notched_bar_with_artificial_stress_stays_whole() {
    let t0 = std::time::Instant::now();
    let (frames, r) = pull_bar("as", &[]);
    eprintln!("with artificial stress: {:.1} s", t0.elapsed().as_secs_f64());
    r.expect("the run with artificial stress reaches its end");
    let last = frames.last().expect("frames");
    assert!(last.elongation > 0.2, "the run must reach 20 % elongation (got {:.3})", last.elongation);
    let window = frames.iter().filter(|f| f.elongation <= PAIRING_WINDOW);
    let worst = window.fold(f64::INFINITY, |m, f| m.min(f.dmin));
    eprintln!("min pair distance up to {} % elongation: {worst:.3} dx", 100.0 * PAIRING_WINDOW);
    assert!(worst > 0.5, "particles paired ({worst:.3} dx) before {} % elongation", 100.0 * PAIRING_WINDOW);
    for f in &frames {
        assert_eq!(f.pieces, 1, "numerical fracture at {:.2} % elongation", 100.0 * f.elongation);
    }
}

/// H1(b) ablation: the same bar without artificial stress (AV still on) shows the known failure.
/// Criterion (klippel-constitutive.md §8 H1, roethlin-solver.md §9 F1: without artificial stress particles pair
/// and the body fractures numerically): within 12 % elongation the minimum pair distance falls below 0.5 Δx and
/// the bar breaks into more than one piece.
/// Measured (f64, CPU): min pair distance 0.56 Δx at 8.8 %, 0.47 Δx at 9.2 %, 0.008 Δx at 9.8 % elongation,
/// at the middle of the reduced section (x = 15 mm); the bar is in 3 pieces at 10.85 % (the run stops there).
/// With artificial stress the same frames keep ≥ 0.615 Δx and one piece. Run time 5 s alone, 12 s beside the others.
#[test]
fn notched_bar_without_artificial_stress_pairs_and_breaks() {
    let t0 = std::time::Instant::now();
    let (frames, r) = pull_bar("no-as", &["stabilisation.artificial_stress.enabled=false".into()]);
    eprintln!("without artificial stress: {:.1} s, run: {r:?}", t0.elapsed().as_secs_f64());
    let window: Vec<&BarFrame> = frames.iter().filter(|f| f.elongation <= PAIRING_WINDOW).collect();
    let paired = window.iter().find(|f| f.dmin < 0.5).expect("no pairing within 12 % elongation");
    let broken = window.iter().find(|f| f.pieces > 1).expect("no fracture within 12 % elongation");
    eprintln!(
        "pairing (< 0.5 dx) from {:.2} %, {} pieces at {:.2} %",
        100.0 * paired.elongation,
        broken.pieces,
        100.0 * broken.elongation
    );
}

/// The free block of `overrides` with the checkerboard velocity v = A (−1)^(ix+iy) e_x on the lattice indices,
/// A = 0.1 % of c0 (4.6 m/s: strains of order A/c0 = 1e-3), stepped `steps` times with the CFL Δt. Returns the
/// kinetic and total (kinetic + elastic) energies after every step, the first at t = 0, and the largest
/// |Σ m v| / Σ m|v|.
fn checkerboard(overrides: &[String], steps: usize) -> (Vec<f64>, Vec<f64>, f64) {
    on_test_backend!(checkerboard_on(overrides, steps))
}

fn checkerboard_on<B: Backend>(b: &B, overrides: &[String], steps: usize) -> (Vec<f64>, Vec<f64>, f64) {
    let scene = Scene::load(BLOCK, overrides).expect("scene");
    let dx = scene.discretisation.dx;
    let mut s = setup::<f64, Dim2>(&scene).expect("setup");
    let amp = 1e-3 * s.c0;
    let lo = s.particles.pos.iter().fold([f64::INFINITY; 2], |m, p| [m[0].min(p.get(0)), m[1].min(p.get(1))]);
    for (p, v) in s.particles.pos.iter().zip(s.particles.vel.iter_mut()) {
        let ix = ((p.get(0) - lo[0]) / dx).round() as i64;
        let iy = ((p.get(1) - lo[1]) / dx).round() as i64;
        let sign = if (ix + iy) % 2 == 0 { 1.0 } else { -1.0 };
        *v = <Dim2 as Dim>::Vec::<f64>::new([sign * amp, 0.0, 0.0]);
    }
    let mut solver = Solver::<_, f64, Dim2>::new(b, &s).expect("solver");
    let (mut ek, mut et, mut worst_p) = (Vec::new(), Vec::new(), 0.0f64);
    for k in 0..=steps {
        let p = solver.download(b).expect("download");
        let d = compute(&p, &solver.host_params, solver.time, solver.steps, None, None);
        assert!(d.non_finite.is_none(), "non-finite {:?} at step {k}", d.non_finite);
        ek.push(d.kinetic);
        et.push(d.total());
        worst_p = worst_p.max(d.momentum[0].hypot(d.momentum[1]) / d.momentum_scale);
        if k < steps {
            solver.step(b, s.dt).expect("step");
        }
    }
    (ek, et, worst_p)
}

/// H3 with the theses' default stabilisers, artificial viscosity (α = β = 1, η = 0.1) and XSPH (ε = 0.5): the
/// checkerboard perturbation of a free 20 × 20 steel block (400 particles, E = 200 GPa, ν = 0.3) decays without
/// growth over 4000 steps (3.7e-4 s, 45 transits of the block by the sound).
/// Criteria (klippel-constitutive.md §8 H3: "decays without growth"): Σ m v stays 0 within 1e-12 of Σ m|v|; the
/// kinetic and the total energy at every step are ≤ their initial value × (1 + 1e-9) (no growth); the total
/// energy never rises from one step to the next by more than 1e-9 of the initial one (the viscosity only
/// dissipates); after 4000 steps the kinetic energy is below 1e-7 of the initial one.
/// Measured (f64, CPU): E_kin/E_kin,0 = 2.5e-3 after 50 steps, 2.0e-5 after 1000, 2.9e-9 after 4000 (the bound
/// 1e-7 leaves a factor 30); E_total/E_0 = 9.6e-6 at the end; |Σ m v|/Σ m|v| ≤ 1.6e-13 (largest at the end,
/// where Σ m|v| has decayed by 5 orders). The damping is the viscosity's: AV alone gives the same 2.9e-9, while
/// XSPH alone blows up like the unstabilised run below. Run time 3 s alone, 5 s beside the others.
#[test]
fn checkerboard_decays_with_viscosity_and_xsph() {
    let t0 = std::time::Instant::now();
    let (ek, et, p) = checkerboard(&[], 4000);
    eprintln!("AV + XSPH: {:.1} s, max |Σ m v|/Σ m|v| = {p:.2e}", t0.elapsed().as_secs_f64());
    for k in [0, 50, 100, 500, 1000, 2000, 3000, 4000] {
        eprintln!("  step {k:5}: E_kin/E_kin0 = {:.3e}  E_total/E0 = {:.3e}", ek[k] / ek[0], et[k] / et[0]);
    }
    assert!(p < 1e-12, "|Σ m v| / Σ m|v| reached {p:e}");
    for (k, (&a, &e)) in ek.iter().zip(&et).enumerate() {
        assert!(a <= ek[0] * (1.0 + 1e-9), "kinetic energy grew to {} of its initial value at step {k}", a / ek[0]);
        assert!(e <= et[0] * (1.0 + 1e-9), "total energy grew to {} of its initial value at step {k}", e / et[0]);
    }
    let rise = et.windows(2).map(|w| (w[1] - w[0]) / et[0]).fold(f64::NEG_INFINITY, f64::max);
    eprintln!("  largest step-to-step rise of E_total: {rise:.2e} of E0");
    assert!(rise <= 1e-9, "the total energy rose by {rise:e} of E0 in one step");
    let end = ek[ek.len() - 1] / ek[0];
    assert!(end < 1e-7, "the checkerboard mode kept {end:e} of its kinetic energy after 4000 steps");
}

/// H3 without any stabiliser: the same block and perturbation. What happens is not a neutral zero-energy mode
/// but a blow-up, and it comes from the time integration: the explicit midpoint predictor–corrector
/// (kernels/src/sph/integrate.rs: predictor from the previous midpoint's rates, one evaluation per step) has,
/// for an undamped oscillation y' = iωy, the growth factor |μ| of μ² − (1 + 3z/2) μ + z/2 = 0, z = iωΔt:
/// |μ| = 1.00003, 1.0027, 1.027, 1.52 per step for ωΔt = 0.1, 0.3, 0.5, 1. Without viscosity nothing damps the
/// high-frequency modes the checkerboard excites, so energy conservation does not hold.
/// Criterion (asserted as measured, a known-defect regression like disk_rotation_reproduces_the_uncorrected_defect):
/// Σ m v stays 0 within 1e-12 of Σ m|v| while the total energy rises above 10× its initial value within 200 steps.
/// Measured (f64, CPU, cfl 0.5): E_total/E0 = 1.033 after 5 steps, 1.20 after 50, 800 after 100, and the block
/// flies apart by step 130; the same growth with A = 1e-5 c0 (a linear instability). With a smaller step the
/// growth slows as the analysis says: after 1950 steps E_total/E0 = 2.06 at cfl 0.25 and 1.0049 at cfl 0.1.
/// Run time < 1 s.
#[test]
fn checkerboard_without_stabilisers_is_not_energy_conserving() {
    let off =
        ["stabilisation.artificial_viscosity.enabled=false".to_string(), "stabilisation.xsph.enabled=false".into()];
    let (ek, et, p) = checkerboard(&off, 200);
    for k in [0, 5, 10, 25, 50, 75, 100, 125, 150, 200] {
        eprintln!("  none, step {k:4}: E_kin/E_kin0 = {:.3e}  E_total/E0 = {:.3e}", ek[k] / ek[0], et[k] / et[0]);
    }
    eprintln!("  max |Σ m v|/Σ m|v| = {p:.2e}");
    assert!(p < 1e-12, "|Σ m v| / Σ m|v| reached {p:e}");
    let grown = et.iter().position(|&e| e > 10.0 * et[0]);
    eprintln!("  E_total > 10 E0 from step {grown:?}");
    assert!(grown.is_some(), "the unstabilised checkerboard no longer blows up: update H3 (max E/E0 {})", {
        et.iter().fold(0.0f64, |m, &e| m.max(e / et[0]))
    });
}

// ---------------------------------------------------------------------------------------------------------------
// Where the closest contact is (issue 8, chip self-contact): analysis::min_pair_distances on hand-built particles

/// Relative difference.
fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(f64::MIN_POSITIVE)
}

/// The closest pair of particles that started at least 2h apart, on a configuration built by hand so that the
/// answer is known by construction (2h = `R` = 1; every group lies more than 1 from the others):
/// - ids 11 and 3 started 5 apart and are now D_A = 0.3 apart about the midpoint M_A = (1.25, −0.5, 0.75), along
///   (3, 0, 4)/5 (offsets ±(0.09, 0, 0.12)): the expected pair, distance and midpoint;
/// - ids 7 and 5 started 0.5 apart (within 2h: one piece of material) and are now 0.1 apart: the closest pair
///   over all pairs (the first value), ignored for the contact;
/// - ids 2 and 9 started 3 apart and are now 0.6 apart: in contact, but farther than 11 and 3;
/// - id 4 is excluded (`include` false, as the tool's thermal-only particles) and lies 0.05 from id 3: ignored.
///
/// The ids are not the indices, so the test tells the stable ids from positions in the arrays.
#[test]
fn closest_contact_pair_is_located_by_ids_and_midpoint() {
    const R: f64 = 1.0;
    const D_A: f64 = 0.3;
    const M_A: [f64; 3] = [1.25, -0.5, 0.75];
    // (position now, position at t = 0, id, included)
    let particles = [
        ([10.0, 10.0, 10.0], [10.0, 10.0, 10.0], 7, true),
        ([M_A[0] + 0.09, M_A[1], M_A[2] + 0.12], [0.0, 0.0, 0.0], 11, true),
        ([-10.0, 0.0, 0.0], [-10.0, 0.0, 0.0], 2, true),
        ([10.1, 10.0, 10.0], [10.5, 10.0, 10.0], 5, true),
        ([M_A[0] - 0.09, M_A[1], M_A[2] - 0.12], [5.0, 0.0, 0.0], 3, true),
        ([-9.4, 0.0, 0.0], [-7.0, 0.0, 0.0], 9, true),
        ([M_A[0] - 0.09 + 0.05, M_A[1], M_A[2] - 0.12], [20.0, 0.0, 0.0], 4, false),
    ];
    let pos: Vec<[f64; 3]> = particles.iter().map(|p| p.0).collect();
    let initial: Vec<[f64; 3]> = particles.iter().map(|p| p.1).collect();
    let id: Vec<u32> = particles.iter().map(|p| p.2).collect();
    let include: Vec<bool> = particles.iter().map(|p| p.3).collect();
    let (all, contact) = min_pair_distances(&pos, &include, R, &initial, &id).expect("min_pair_distances");
    let all = all.expect("pairs within 2h");
    let c = contact.expect("a pair that started apart within 2h");
    eprintln!("  all pairs: {all:.15}; contact: {c:?}");
    assert!(rel(all, 0.1) < 1e-12, "closest pair over all: {all}, expected 0.1 (ids 7 and 5)");
    assert_eq!(c.ids, [3, 11], "the contact pair's ids, smaller first");
    assert!(rel(c.distance, D_A) < 1e-12, "contact distance {}, expected {D_A}", c.distance);
    let off = c.midpoint.iter().zip(M_A).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(off <= 1e-12 * 1.25, "midpoint {:?}, expected {M_A:?}", c.midpoint);
}

/// The pair search of both analyses (each pair once, from the stencil walk) against brute force over all pairs, on
/// 600 random points in clusters of varied density, with an eighth of them ejected far away (the bounded search
/// box clamps those into its boundary cells): the closest distance over all pairs, the closest pair that started
/// apart, and the number of components per group are the same, exactly.
#[test]
fn the_pair_search_equals_brute_force() {
    let mut rng = swarf::rng::SplitMix64::new(0x5eed);
    let (r, n) = (0.35, 600usize);
    let mut pos: Vec<[f64; 3]> = Vec::with_capacity(n);
    for k in 0..n {
        let centre = [(k % 5) as f64 * 2.0, (k % 3) as f64 * 1.5, 0.0];
        let spread = if k % 8 == 7 { 400.0 } else { 1.0 + (k % 4) as f64 * 0.5 };
        pos.push(std::array::from_fn(|a| centre[a] + spread * (rng.uniform() - 0.5)));
    }
    let initial: Vec<[f64; 3]> = (0..n).map(|k| [k as f64 * 0.1, 0.0, 0.0]).collect();
    let id: Vec<u32> = (0..n as u32).map(|k| (k * 7919) % 1009).collect();
    let include: Vec<bool> = (0..n).map(|k| k % 11 != 0).collect();
    let group: Vec<u32> = (0..n as u32).map(|k| k % 3).collect();
    let d2 = |a: &[f64; 3], c: &[f64; 3]| (a[0] - c[0]).powi(2) + (a[1] - c[1]).powi(2) + (a[2] - c[2]).powi(2);
    // Brute force.
    let mut all = f64::INFINITY;
    let mut apart: Option<(f64, [u32; 2])> = None;
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(p: &mut [usize], mut a: usize) -> usize {
        while p[a] != a {
            a = p[a];
        }
        a
    }
    for i in 0..n {
        for j in i + 1..n {
            let r2 = d2(&pos[i], &pos[j]);
            if r2 >= r * r {
                continue;
            }
            if group[i] == group[j] {
                let (a, c) = (find(&mut parent, i), find(&mut parent, j));
                parent[a] = c;
            }
            if include[i] && include[j] {
                all = all.min(r2);
                if d2(&initial[i], &initial[j]) >= r * r {
                    let ids = if id[i] <= id[j] { [id[i], id[j]] } else { [id[j], id[i]] };
                    if apart.is_none_or(|best| (r2, ids) < best) {
                        apart = Some((r2, ids));
                    }
                }
            }
        }
    }
    let mut roots: Vec<Vec<usize>> = vec![Vec::new(); 3];
    for i in 0..n {
        let root = find(&mut parent, i);
        roots[group[i] as usize].push(root);
    }
    let expect: Vec<usize> = roots
        .into_iter()
        .map(|mut v| {
            v.sort_unstable();
            v.dedup();
            v.len()
        })
        .collect();
    assert_eq!(components_per_group(&pos, &group, r).unwrap(), expect);
    assert!(expect.iter().all(|&c| c > 1), "the clusters and ejected points make several pieces: {expect:?}");
    let (got_all, got) = min_pair_distances(&pos, &include, r, &initial, &id).unwrap();
    assert_eq!(got_all, Some(all.sqrt()));
    let (r2, ids) = apart.expect("a pair that started apart");
    let got = got.expect("the search's pair");
    assert_eq!((got.distance, got.ids), (r2.sqrt(), ids));
}

/// No pair that started apart: the contact is None (energy.csv writes NaN) while the pair distance is not; two
/// contact pairs at the same distance (exact binary values: 0.25 apart) give the smaller ids whatever their order;
/// arrays of the wrong length are an error, not a panic.
#[test]
fn closest_contact_pair_none_ties_and_lengths() {
    // Two particles that started 0.5 apart (< 2h = 1), now 0.25 apart.
    let pos = [[0.0, 0.0, 0.0], [0.25, 0.0, 0.0]];
    let (all, contact) = min_pair_distances(&pos, &[true; 2], 1.0, &[[0.0; 3], [0.5, 0.0, 0.0]], &[0, 1]).unwrap();
    assert_eq!((all, contact), (Some(0.25), None));
    // Two pairs that started 4 apart, both now exactly 0.25 apart; listed with the larger ids first.
    let pos = [[0.0, 0.0, 0.0], [0.25, 0.0, 0.0], [5.0, 0.0, 0.0], [5.25, 0.0, 0.0]];
    let initial = [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [10.0, 0.0, 0.0], [14.0, 0.0, 0.0]];
    for (id, expected) in [([8, 9, 1, 2], [1, 2]), ([1, 2, 8, 9], [1, 2])] {
        let c = min_pair_distances(&pos, &[true; 4], 1.0, &initial, &id).unwrap().1.expect("contact");
        assert_eq!((c.distance, c.ids), (0.25, expected), "ids {id:?}");
        let mid = if expected == [id[0], id[1]] { [0.125, 0.0, 0.0] } else { [5.125, 0.0, 0.0] };
        assert_eq!(c.midpoint, mid, "ids {id:?}");
    }
    let err = min_pair_distances(&pos, &[true; 4], 1.0, &initial, &[1, 2, 3]).expect_err("3 ids for 4 particles");
    assert!(matches!(err, swarf::Error::Length { expected: 4, got: 3, .. }), "{err:?}");
}

/// Particles ejected far from the rest (an unstable run) do not make the contact search build a grid over the whole
/// span: a 40 × 40 × 10 lattice of spacing 1 and a pair 0.4 apart 10⁶ away give the pair's distance, exactly, where
/// the bounding box alone asked for about 10¹⁸ cells and was refused (the multi-grain runs at CFL 0.5 stopped
/// answering on such grids; `analysis::search_box`).
#[test]
fn ejected_particles_do_not_blow_up_the_contact_search() {
    let mut pos: Vec<[f64; 3]> = Vec::new();
    for i in 0..40 {
        for j in 0..40 {
            for k in 0..10 {
                pos.push([i as f64, j as f64, k as f64]);
            }
        }
    }
    pos.push([1.0e6, 1.0e6, 1.0e6]);
    pos.push([1.0e6 + 0.4, 1.0e6, 1.0e6]);
    let include = vec![true; pos.len()];
    let id: Vec<u32> = (0..pos.len() as u32).collect();
    let t0 = std::time::Instant::now();
    let (all, _) = min_pair_distances(&pos, &include, 2.5, &pos, &id).expect("the search runs");
    eprintln!("{} particles, 2 of them 1e6 away: closest pair {all:?} in {:?}", pos.len(), t0.elapsed());
    assert!((all.expect("a pair") - 0.4).abs() < 1e-9, "closest pair {all:?}, expected 0.4");
}

/// H1(b) with ductile damage (issue 25: "damage and the mask add no non-finite value to the hard-case suite"): the
/// same bar with Johnson–Cook fracture (AISI 4340, Johnson and Cook 1985: D1 0.05, D2 3.44, D3 −2.12, D4 0.002,
/// D5 0.61; no G_f, so damage is full at initiation) and the interaction mask, pulled to the end of the run.
/// Criteria: the run reaches its end with no non-finite position or velocity; the bar comes apart only after a
/// particle is fully damaged (the fracture is the damage's, not numerical: without damage it stays whole, above),
/// and into more than one piece; the minimum pair distance stays above 0.5 Δx up to 12 % elongation, as without
/// damage. Measured (f64, CPU): 0.606 Δx at 12.5 %, 0.497 Δx at 13.9 %, the first full damage at 14.2 % (so
/// klippel H1(b)'s "> 0.5 Δx until ω-based failure" fails by one frame, as the pairing of the undamaged bar
/// starts at 13.9 % too), separated at 16.6 %, 14 pieces (the fully damaged particles come off one by one),
/// damaged volume 7.2e-6 m² per m (29 particles), finite to the end. 4.5 s.
#[test]
fn notched_bar_with_damage_fails_by_damage_and_stays_finite() {
    let sets: Vec<String> =
        vec!["damage={ model = \"jc\", D1 = 0.05, D2 = 3.44, D3 = -2.12, D4 = 0.002, D5 = 0.61, mask = true }".into()];
    let scene = Scene::load(BAR, &sets).expect("scene");
    let dx = scene.discretisation.dx;
    let mut frames: Vec<(f64, f64, usize, f64)> = Vec::new();
    let mut length0 = None;
    let mut obs = |s: &Snapshot| {
        let (lo, hi) = s.pos.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| (l.min(p[0]), h.max(p[0])));
        let l0 = *length0.get_or_insert(hi - lo);
        let pieces = components_per_group(&s.pos, &vec![0u32; s.pos.len()], 2.0 * dx).expect("components")[0];
        let finite = s.pos.iter().chain(&s.vel).all(|v| v.iter().all(|c| c.is_finite()));
        assert!(finite, "a non-finite position or velocity at {:.2} % elongation", 100.0 * ((hi - lo) / l0 - 1.0));
        frames.push(((hi - lo) / l0 - 1.0, closest_pair(&s.pos).0 / dx, pieces, s.diagnostics.damaged_volume));
        true
    };
    run_observed(&cpu(), &scene, &opts("damage"), Some(&mut obs)).expect("the damaged bar reaches its end");
    for (e, d, p, v) in &frames {
        eprintln!("damage: elongation {:6.2} %  min pair {d:.3} dx  pieces {p}  damaged volume {v:.3e} m²", 100.0 * e);
    }
    let failed = frames.iter().position(|f| f.3 > 0.0).expect("no particle was fully damaged");
    let apart = frames.iter().position(|f| f.2 > 1).expect("the damaged bar did not come apart");
    let worst = frames.iter().filter(|f| f.0 <= PAIRING_WINDOW).fold(f64::INFINITY, |m, f| m.min(f.1));
    eprintln!(
        "first full damage at {:.2} %, apart at {:.2} % elongation; min pair distance to {} %: {worst:.3} dx",
        100.0 * frames[failed].0,
        100.0 * frames[apart].0,
        100.0 * PAIRING_WINDOW
    );
    assert!(apart > failed, "the bar came apart before any particle was fully damaged");
    assert!(worst > 0.5, "particles paired ({worst:.3} dx) before {} % elongation", 100.0 * PAIRING_WINDOW);
    assert!(frames.last().expect("frames").2 > 1, "the damaged bar joined again");
}
