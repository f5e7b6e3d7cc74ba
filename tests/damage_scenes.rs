//! The damage scenes of issue 25 item 5 (docs/damage.md, "Scenes"): every scene file parses and passes `swarf
//! check`'s validation; the CT specimen, coarse and pulled hard, grows its damage from the pre-crack's tip with the
//! interaction mask and keeps its crack closed without it; at its own spacing its crack runs from the tip with the
//! mask and the ligament holds without it; a load reversal flips the pins' velocity.

use std::path::{Path, PathBuf};
use swarf::analysis::neck;
use swarf::backend::{AnyBackend, BackendChoice};
use swarf::output::vtu::{self, OwnedValues, ReadFrame};
use swarf::run::RunOptions;
use swarf::scene::Scene;

fn cpu() -> AnyBackend {
    AnyBackend::select(BackendChoice::Cpu).expect("cpu").0
}

fn out_dir(tag: &str) -> PathBuf {
    std::env::temp_dir().join(format!("swarf-test-dscenes-{tag}-{}", std::process::id()))
}

/// Every `.vtu` file below `dir`, sorted by path (the frames' names count up).
fn frames(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).into_iter().flatten().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "vtu") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

fn f64s(v: &OwnedValues) -> Vec<f64> {
    match v {
        OwnedValues::F64(x) => x.clone(),
        OwnedValues::F32(x) => x.iter().map(|&a| a as f64).collect(),
        OwnedValues::U32(x) => x.iter().map(|&a| a as f64).collect(),
        OwnedValues::I32(x) => x.iter().map(|&a| a as f64).collect(),
    }
}

fn field(f: &ReadFrame, name: &str) -> Vec<f64> {
    let (_, _, v) = f.point_data.iter().find(|(n, _, _)| n == name).unwrap_or_else(|| panic!("no field {name}"));
    f64s(v)
}

/// A CT particle of a frame: σ_yy = S_yy − p of the undamaged stress (the actual stress where D = 0).
#[derive(Clone, Copy, Debug)]
struct Ct {
    id: usize,
    x: f64,
    y: f64,
    syy: f64,
    damage: f64,
    omega: f64,
    /// The stored von Mises stress and pressure, and those the particle acts with (`von_mises_acting`,
    /// `pressure_acting`).
    vm: f64,
    p: f64,
    vm_acting: f64,
    p_acting: f64,
}

fn ct_particles(f: &ReadFrame) -> Vec<Ct> {
    let p = f64s(&f.points);
    let (id, s, p_eos, d, w) =
        (field(f, "id"), field(f, "stress"), field(f, "pressure"), field(f, "damage"), field(f, "damage_initiation"));
    let (vm, vma, pa) = (field(f, "von_mises"), field(f, "von_mises_acting"), field(f, "pressure_acting"));
    (0..f.n)
        .map(|i| Ct {
            id: id[i] as usize,
            x: p[3 * i],
            y: p[3 * i + 1],
            syy: s[6 * i + 1] - p_eos[i],
            damage: d[i],
            omega: w[i],
            vm: vm[i],
            p: p_eos[i],
            vm_acting: vma[i],
            p_acting: pa[i],
        })
        .collect()
}

const CT: &str = "cases/damage/ct-specimen.toml";
/// The coarse CT of the tests: Δx = 1.25 mm, the pre-crack's two rows y = 0 and y = −Δx.
const COARSE: [&str; 2] = ["discretisation.dx=1.25e-3", "damage.pre_crack.0.min=[-13.0e-3,-1.3e-3]"];

/// Runs the coarse CT with `extra` overrides; returns its frames (first at t = 0) and removes the folder.
fn run_ct(tag: &str, extra: &[String]) -> Vec<Vec<Ct>> {
    run_ct_with(tag, &COARSE, extra)
}

/// Runs the CT with the `base` overrides, then `extra`; returns its frames (first at t = 0) and removes the folder.
fn run_ct_with(tag: &str, base: &[&str], extra: &[String]) -> Vec<Vec<Ct>> {
    let over: Vec<String> = base.iter().map(|s| s.to_string()).chain(extra.iter().cloned()).collect();
    let scene = Scene::load(CT, &over).expect("scene");
    let dir = out_dir(tag);
    let opts = RunOptions { frames: true, ..RunOptions::quiet(dir.clone()) };
    let rep = swarf::run::run(&cpu(), &scene, &opts).expect("run");
    assert!(rep.history.iter().all(|h| h.non_finite.is_none()), "{tag}: non-finite values");
    let out = frames(&dir).iter().map(|p| ct_particles(&vtu::read(p).expect("frame"))).collect();
    let _ = std::fs::remove_dir_all(&dir);
    out
}

/// Pins at ±`v` m/s to `end` s with the mask on or off, frames every `every` s.
fn pulled(v: f64, end: f64, every: f64, mask: bool) -> Vec<String> {
    vec![
        format!("boundary.0.velocity=[0.0,{v}]"),
        format!("boundary.1.velocity=[0.0,{}]", -v),
        format!("time.end={end}"),
        format!("output.every={every}"),
        format!("damage.mask={mask}"),
    ]
}

/// The pre-crack at t = 0 (ω = 1): its tip (largest x) and its rows' y range.
fn pre_crack(first: &[Ct]) -> (f64, f64, f64) {
    let crack = first.iter().filter(|p| p.omega >= 1.0);
    crack.fold((f64::MIN, f64::MAX, f64::MIN), |(x, lo, hi), p| (x.max(p.x), lo.min(p.y), hi.max(p.y)))
}

/// The crack's opening: the mean y displacement of the undamaged row just above the pre-crack minus that of the
/// row just below, over the particles behind the tip by more than 2Δx.
fn opening(first: &[Ct], now: &[Ct], dx: f64) -> f64 {
    let (tip, lo, hi) = pre_crack(first);
    let by_id: std::collections::HashMap<usize, &Ct> = now.iter().map(|p| (p.id, p)).collect();
    let mean_dy = |y0: f64| {
        let row: Vec<f64> = first
            .iter()
            .filter(|p| (p.y - y0).abs() < 1e-3 * dx && p.x < tip - 2.0 * dx)
            .map(|p| by_id[&p.id].y - p.y)
            .collect();
        assert!(row.len() > 5, "row y0 = {y0}: {} particles", row.len());
        row.iter().sum::<f64>() / row.len() as f64
    };
    mean_dy(hi + dx) - mean_dy(lo - dx)
}

/// With the interaction mask, the coarse CT with a one-row pre-crack (y = 0) pulled at ±10 m/s (a faster load
/// than Klippel's ±20 m/min, so that damage initiates within 240 steps) grows its damage from the pre-crack's tip:
/// at 4.8e-5 s (Fig. 7.26's instant) the largest opening stress σ_yy of the undamaged particles lies within 2Δx of
/// the tip (the digest's criterion, klippel-constitutive.md §8 H6), and damage initiates there (at least 3
/// particles initiated since t = 0 within 3Δx of the tip). Not asserted, printed: particles also initiate along
/// the kerf near the front face (up to 15.7Δx from the tip); with the scene's two-row pre-crack the same load puts
/// the peak stress there too (docs/damage.md, "Scenes": not Klippel's result).
#[test]
fn ct_with_the_mask_grows_damage_from_the_pre_crack_tip() {
    let dx = 1.25e-3;
    let mut over = pulled(10.0, 4.8e-5, 1.2e-5, true);
    over.push("damage.pre_crack.0.min=[-13.0e-3,-1.0e-4]".into());
    let fr = run_ct("tip", &over);
    let (first, last) = (&fr[0], fr.last().expect("frames"));
    let (tip, lo, hi) = pre_crack(first);
    let centre = 0.5 * (lo + hi);
    let peak = last.iter().filter(|p| p.damage == 0.0).max_by(|a, b| a.syy.total_cmp(&b.syy)).expect("particles");
    let d_peak = ((peak.x - tip).powi(2) + (peak.y - centre).powi(2)).sqrt();
    let fresh: Vec<&Ct> = last.iter().filter(|p| p.omega >= 1.0 && first[p.id].omega < 1.0).collect();
    let dist: Vec<f64> = fresh.iter().map(|p| ((p.x - tip).powi(2) + (p.y - centre).powi(2)).sqrt()).collect();
    let far = dist.iter().copied().fold(0.0, f64::max);
    let near = dist.iter().filter(|&&d| d <= 3.0 * dx).count();
    eprintln!(
        "tip ({:.2}, {:.2}) mm; peak σ_yy {:.3e} Pa at ({:.2}, {:.2}) mm, {:.2} Δx from the tip; {} initiated, {} within 3Δx \
         of the tip, the farthest {:.2} Δx from it",
        tip * 1e3,
        centre * 1e3,
        peak.syy,
        peak.x * 1e3,
        peak.y * 1e3,
        d_peak / dx,
        fresh.len(),
        near,
        far / dx
    );
    assert!(d_peak <= 2.0 * dx, "peak σ_yy {:.2} Δx from the tip", d_peak / dx);
    assert!(near >= 3, "{near} particles initiated within 3Δx of the tip");
}

/// Klippel's CT criterion (§4.5, Figs. 7.24–7.27) at the scene's own spacing (Δx = 0.625 mm, 9 797 particles) with a
/// one-row pre-crack, the pins pulled at ±10 m/s (Klippel's ±20 m/min moves them 84 µm by his 2.52e-4 s, short of
/// what initiates a crack here; docs/damage.md, "The CT crack at the scene's spacing"), to 1.6e-4 s: with the mask
/// the crack runs from the pre-crack's tip, without it no particle ahead of the tip is fully damaged. "Runs from the
/// tip":
/// the first fully damaged particle of the ligament (the rows |y| ≤ Δx ahead of the tip) lies within 2Δx of the
/// tip, and at the end at least 12 consecutive ligament columns from the tip on hold a fully damaged particle.
/// Measured: first at 80 µs, 0.6 mm (1Δx) ahead of the tip; at 160 µs 49 of the ligament's particles fully damaged,
/// 18 columns from the tip (to x = 21.2 mm); without the mask none (the damage gathers at the bonded pins' corners).
/// The coarse CT (Δx = 1.25 mm) does not resolve the tip: with the mask or without, its damage runs along the faces
/// beside the pre-crack, not ahead of it. The frames' acting stress on the way: zero von Mises at full damage, the
/// pressure only in compression, an undamaged particle's stored state.
#[test]
fn ct_at_the_scene_spacing_runs_its_crack_from_the_tip_only_with_the_mask() {
    let dx = 6.25e-4;
    let one_row = ["damage.pre_crack.0.min=[-13.0e-3,-1.0e-4]"];
    let ligament = |first: &[Ct], now: &[Ct], tip: f64| -> Vec<(f64, bool)> {
        let by_id: std::collections::HashMap<usize, &Ct> = now.iter().map(|p| (p.id, p)).collect();
        first
            .iter()
            .filter(|p| p.y.abs() <= 1.01 * dx && p.x > tip + 1e-3 * dx)
            .map(|p| (p.x, swarf::kernels::damage::is_full(by_id[&p.id].damage)))
            .collect()
    };
    for mask in [true, false] {
        let fr = run_ct_with(&format!("tip-{mask}"), &one_row, &pulled(10.0, 1.6e-4, 2.0e-5, mask));
        let first = &fr[0];
        let (tip, _, _) = pre_crack(first);
        let at_end = ligament(first, fr.last().expect("frames"), tip);
        let full = at_end.iter().filter(|(_, f)| *f).count();
        // The columns of the ligament ahead of the tip, in order, and whether each holds a fully damaged particle.
        let mut cols: std::collections::BTreeMap<i64, bool> = std::collections::BTreeMap::new();
        for (x, f) in &at_end {
            *cols.entry(((x - tip) / dx).round() as i64).or_default() |= *f;
        }
        let run = cols.values().take_while(|f| **f).count();
        let onset = fr.iter().find_map(|now| {
            let l = ligament(first, now, tip);
            l.iter().filter(|(_, f)| *f).map(|(x, _)| x - tip).reduce(f64::min)
        });
        eprintln!(
            "CT at Δx = 0.625 mm, mask {mask}: tip x = {:.2} mm; {full} ligament particles fully damaged, {run} columns \
             from the tip; the first {:?} Δx ahead of it",
            tip * 1e3,
            onset.map(|d| d / dx)
        );
        // The frames' acting stress (Eqs. 7.27–7.28): a fully damaged particle acts with no deviatoric stress, and
        // with no pressure in tension but its whole pressure in compression; an undamaged one with its stored state.
        let last = fr.last().expect("frames");
        let broken: Vec<&Ct> = last.iter().filter(|p| swarf::kernels::damage::is_full(p.damage)).collect();
        assert!(broken.iter().any(|p| p.vm > 0.0), "no fully damaged particle with a stored deviator: vacuous");
        for p in &broken {
            assert_eq!(p.vm_acting, 0.0, "a fully damaged particle acts with von Mises {}", p.vm_acting);
            let want = if p.p < 0.0 { 0.0 } else { p.p };
            assert_eq!(p.p_acting, want, "a fully damaged particle at p = {} acts with {}", p.p, p.p_acting);
        }
        for p in last.iter().filter(|p| p.damage == 0.0) {
            assert_eq!((p.vm_acting, p.p_acting), (p.vm, p.p), "an undamaged particle acts with its stored stress");
        }
        if mask {
            let d = onset.expect("with the mask the ligament must fail");
            assert!(d <= 2.0 * dx, "the ligament's first full damage {:.2} Δx ahead of the tip", d / dx);
            assert!(run >= 12, "the crack reaches {run} columns from the tip (at least 12 asked)");
        } else {
            assert_eq!(full, 0, "without the mask {full} ligament particles are fully damaged");
        }
    }
}

/// Without the mask the crack opens less: the coarse CT (two-row pre-crack) pulled at ±2 m/s to 1.2e-4 s (the pins
/// 480 µm apart) opens its crack faces (the rows beside the pre-crack, more than 2Δx behind the tip) by more than
/// the pins' separation with the mask (the arms turn about the tip: the faces ahead of the load line open more than
/// the pins), and by less than 3/4 of the masked opening without it: the fully damaged kerf, seen by its
/// neighbours' velocity gradients, holds the faces back. "Closed" is relative: the faces still open. The invariant
/// form of the mask (`mask_form = "invariant"`, docs/damage.md) opens the faces by more than 1.05× the unmasked
/// opening (measured 1.115×, 0.989 of the pins): it cuts the pairs across the kerf, but not the printed form's pull
/// of a kerf at rest on its neighbours.
#[test]
fn ct_without_the_mask_keeps_its_crack_closed() {
    let (dx, v, end) = (1.25e-3, 2.0, 1.2e-4);
    let pins = 2.0 * v * end;
    let mut ratio = Vec::new();
    for (mask, form) in [(true, "printed"), (false, "printed"), (true, "invariant")] {
        let mut over = pulled(v, end, 3.0e-5, mask);
        over.push(format!("damage.mask_form=\"{form}\""));
        let fr = run_ct(&format!("closed-{mask}-{form}"), &over);
        let open = opening(&fr[0], fr.last().expect("frames"), dx);
        eprintln!(
            "mask {mask} ({form}): opening {:.1} µm, {:.3} of the pins' {:.0} µm",
            open * 1e6,
            open / pins,
            pins * 1e6
        );
        ratio.push(open / pins);
    }
    assert!(ratio[0] >= 1.0, "with the mask the crack opens: {:.3} of the pins' separation", ratio[0]);
    let rel = ratio[1] / ratio[0];
    eprintln!("opening without the mask / with it: {rel:.3}; invariant / without: {:.3}", ratio[2] / ratio[1]);
    assert!(rel < 0.75, "without the mask the crack opens {rel:.3} of the masked opening");
    assert!(ratio[2] > 1.05 * ratio[1], "the invariant mask opens {:.3} of the unmasked opening", ratio[2] / ratio[1]);
}

/// The load reversal of the CT variant (`reverse_at`): the pins' velocity changes sign at each listed time.
#[test]
fn ct_load_reversal_flips_the_pins_velocity() {
    let over: Vec<String> = COARSE
        .iter()
        .map(|s| s.to_string())
        .chain(
            [
                "boundary.0.reverse_at=[2.5e-6,5.5e-6]",
                "boundary.1.reverse_at=[2.5e-6,5.5e-6]",
                "time.end=8.0e-6",
                "output.every=1.0e-6",
            ]
            .map(String::from),
        )
        .collect();
    let scene = Scene::load(CT, &over).expect("scene");
    let dir = out_dir("reversal");
    swarf::run::run(&cpu(), &scene, &RunOptions { frames: true, ..RunOptions::quiet(dir.clone()) }).expect("run");
    let paths = frames(&dir);
    assert_eq!(paths.len(), 9, "frames at 0, 1, …, 8 µs");
    let v = 0.333333333333;
    for (k, p) in paths.iter().enumerate() {
        let f = vtu::read(p).expect("frame");
        let (pos, vel) = (f64s(&f.points), field(&f, "velocity"));
        // A particle of the upper pin's square (x in ±6.25 mm, y in 7.5..20 mm at t = 0: it moves < 3 µm).
        let i = (0..f.n).find(|&i| pos[3 * i].abs() < 5e-3 && (9e-3..18e-3).contains(&pos[3 * i + 1])).unwrap();
        let sign = if (3..=5).contains(&k) { -1.0 } else { 1.0 };
        assert_eq!(vel[3 * i + 1], sign * v, "frame {k}: the upper pin's v_y");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every damage scene and each documented variant parses and passes `swarf check` (one probe step).
#[test]
fn every_damage_scene_and_variant_checks() {
    let rev = |k: usize| format!("boundary.{k}.reverse_at=[5.0e-5,1.5e-4]");
    let cases: Vec<(&str, Vec<String>)> = vec![
        (CT, vec![]),
        (CT, vec!["damage.mask=false".into()]),
        (CT, vec![rev(0), rev(1), "time.end=4.52e-4".into()]),
        (CT, COARSE.map(String::from).to_vec()),
        ("cases/damage/shtb-50sib8.toml", vec![]),
        ("cases/damage/shtb-50sib8.toml", vec!["material.name=\"50SiB8-Klippel-JCGG\"".into()]),
        ("cases/cutting/v0060-damage.toml", vec![]),
        ("cases/cutting/v0060-damage.toml", vec!["discretisation.dx=5.0e-6".into()]),
        ("cases/cutting/ducobu.toml", vec!["discretisation.dx=4.65e-6".into()]),
    ];
    let mut all = cases;
    for m in ["JC", "TANH2008", "TANH2010", "TANHSO3"] {
        for on in [true, false] {
            let set = vec![format!("material.name=\"Ti6Al4V-Klippel-{m}\""), format!("damage.enabled={on}")];
            all.push(("cases/cutting/ducobu.toml", set));
        }
    }
    let any = cpu();
    for (path, set) in &all {
        let scene = Scene::load(path, set).unwrap_or_else(|e| panic!("{path} {set:?}: {e}"));
        let on = !set.iter().any(|s| s == "damage.enabled=false");
        assert_eq!(scene.damage.is_some(), on, "{path} {set:?}");
        if let Some(d) = &scene.damage {
            assert!(d.model == "jc" || d.model == "jc_gg", "{path}: {}", d.model);
        }
        // The 3D SHTB's probe step takes seconds on the CPU: its default once.
        if path.contains("shtb") && !set.is_empty() {
            continue;
        }
        let r = swarf::check::check(&any, &scene, None, 1).unwrap_or_else(|e| panic!("{path} {set:?}: {e}"));
        assert!(r.particles > 0 && r.dt > 0.0, "{path}");
    }
    let shtb = Scene::load("cases/damage/shtb-50sib8.toml", &[]).unwrap();
    let d = shtb.damage.as_ref().unwrap();
    assert!(d.delete && d.fracture_energy == 0.0 && shtb.dim == 3, "SHTB: deletion at ω = 1, no G_f");
    let gg = Scene::load("cases/damage/shtb-50sib8.toml", &["material.name=\"50SiB8-Klippel-JCGG\"".into()]).unwrap();
    assert_eq!(gg.damage.as_ref().unwrap().model, "jc_gg");
}

/// The new keys' errors name the file, the key and what was expected.
#[test]
fn reverse_at_and_damage_enabled_errors_name_the_key() {
    let err = |set: &str| Scene::load(CT, &[set.to_string()]).expect_err(set).to_string();
    let e = err("boundary.0.reverse_at=[1.0e-4,5.0e-5]");
    assert!(e.contains("--set boundary.0.reverse_at=") && e.contains("increasing positive times"), "{e}");
    let e = err("boundary.0.reverse_at=-1.0");
    assert!(e.contains("boundary.0.reverse_at") && e.contains("positive times"), "{e}");
    let e = err("damage.enabled=1");
    assert!(e.contains("damage.enabled") && e.contains("true or false"), "{e}");
}

/// The neck of a bar with a thinner middle (host/analysis/neck.rs): found there, with the lattice's outer
/// diameter; a deleted slab across it separates the bar; ε_f = 2 ln(d0/d_f).
#[test]
fn the_neck_is_the_thinnest_slab_and_a_deleted_slab_separates() {
    let dx = 0.1e-3;
    let cylinder = |r: f64, z0: f64, layers: i64| {
        let k = (r / dx).ceil() as i64;
        let mut out = Vec::new();
        for l in 0..layers {
            for i in -k..=k {
                for j in -k..=k {
                    let (x, y) = (i as f64 * dx, j as f64 * dx);
                    if (x * x + y * y).sqrt() < r {
                        out.push([x + 1e-3, y - 2e-3, z0 + l as f64 * dx]);
                    }
                }
            }
        }
        out
    };
    let mut pos = cylinder(1.5e-3, 0.0, 41);
    pos.extend(cylinder(1.0e-3, 4.1e-3, 10));
    pos.extend(cylinder(1.5e-3, 5.1e-3, 40));
    let live = vec![true; pos.len()];
    let n = neck::neck(&pos, &live, 0.34e-3, dx).expect("a neck");
    assert!((4.1e-3..=5.0e-3).contains(&n.z), "neck at z = {}", n.z);
    // The largest node radius below 1 mm on a 0.1 mm lattice, √(0.7² + 0.7²) = 0.98995 mm, twice, plus dx.
    let expect = 2.0 * (0.98e-6f64).sqrt() + dx;
    assert!((n.diameter - expect).abs() < 1e-12, "{} vs {expect}", n.diameter);
    assert!(!neck::separated(&pos, &live, 0.34e-3).unwrap());
    let cut: Vec<bool> = pos.iter().map(|p| !(4.35e-3..4.75e-3).contains(&p[2])).collect();
    assert!(neck::separated(&pos, &cut, 0.34e-3).unwrap());
    // A deleted slab does not count in the neck: the thinnest live slab is still in the middle section.
    assert!(neck::neck(&pos, &cut, 0.34e-3, dx).unwrap().diameter <= expect + 1e-12);
}

/// `swarf neck` measures a run at the spacing it ran with: a run folder's `--set discretisation.dx` (recorded in
/// its summary.json) sets the slab width and connection radius 2h and the particles' extent Δx, not the scene
/// file's spacing. (A Δx = 0.1 mm SHTB run was measured at the file's 0.2 mm before this: d0 3.197 mm instead of
/// the 3.097 mm of its lattice.)
#[test]
fn the_neck_of_a_run_uses_the_spacing_it_ran_with() {
    let dir = out_dir("neck-spacing");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy("cases/damage/shtb-50sib8.toml", dir.join("scene.toml")).unwrap();
    let file = Scene::load(dir.join("scene.toml"), &[]).unwrap();
    assert_eq!(neck::run_spacing(&dir).unwrap(), (2.0 * file.h(), 2.0e-4), "without overrides: the file's");
    std::fs::write(dir.join("summary.json"), r#"{"overrides": ["discretisation.dx=1.0e-4"]}"#).unwrap();
    let (support, dx) = neck::run_spacing(&dir).unwrap();
    assert_eq!(dx, 1.0e-4);
    assert!((support - 2.0 * 1.7 * 1.0e-4).abs() < 1e-15, "support {support}");
    let _ = std::fs::remove_dir_all(&dir);
}
