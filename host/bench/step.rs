//! `swarf bench step`: the whole step of a scene, as a run takes it (captured batches where the backend has
//! graphs), with the time of each phase, the interactions it computes, the bytes it must move against the device's
//! measured copy bandwidth, and the step cost of each physics option switched off (docs/measurements/notebook.md).

use crate::Result;
use crate::backend::Backend;
use crate::kernels::Real;
use crate::kernels::sph::TensorOps;
use crate::kernels::sph::params::flags;
use crate::solver::{GRAPH_STEPS, Phase, Setup, Solver};

/// One configuration's figures.
#[derive(Clone, Debug)]
pub struct StepTimes {
    pub label: String,
    pub particles: usize,
    pub precision: &'static str,
    /// Mean step time over the timed batches, as a run takes them.
    pub ms_per_step: f64,
    /// Mean time of each phase of [`Phase::ALL`] over the profiled steps (each phase waited for).
    pub phases_ms: [f64; 8],
    /// Directed mechanical pairs within the kernel support (i ≠ j, neither a thermal-only tool particle: the
    /// pair terms the interaction evaluates) at the start of the timing.
    pub pairs: u64,
    /// Bytes a step must move at least (every array read or written once per pass that touches it).
    pub bytes_per_step: f64,
    /// Cell-list rebuilds per step over the timed batches (1 without a skin).
    pub rebuilds_per_step: f64,
}

impl StepTimes {
    /// Mechanical pair terms per second of the interaction phase (which, with fused conduction, also sums the
    /// conduction of every pair).
    pub fn interactions_per_s(&self) -> f64 {
        self.pairs as f64 / (self.phases_ms[4] * 1e-3)
    }
    pub fn particle_steps_per_s(&self) -> f64 {
        self.particles as f64 / (self.ms_per_step * 1e-3)
    }
    /// Achieved bandwidth of the whole step on its compulsory traffic [GB/s].
    pub fn bandwidth_gb_s(&self) -> f64 {
        self.bytes_per_step / (self.ms_per_step * 1e-3) / 1e9
    }
}

/// A saved state to time the step from: a run folder's checkpoint (`swarf bench step --from`).
pub type Saved = (crate::checkpoint::Header, crate::solver::StateBlobs);

/// Times `steps` steps (rounded up to whole graph batches) of `setup`, or of the state `from` of a run of it,
/// after a warm-up that captures the graphs, then profiles `profiled` single steps phase by phase.
#[allow(clippy::too_many_arguments)]
pub fn step<B: Backend, R: Real, D: TensorOps<R>>(
    b: &B,
    setup: &Setup<R, D>,
    label: &str,
    steps: usize,
    profiled: usize,
    lanes: Option<u32>,
    fuse: bool,
    from: Option<&Saved>,
) -> Result<StepTimes> {
    let mut sv = Solver::<B, R, D>::new(b, setup)?;
    if let Some(l) = lanes {
        sv.lanes = l;
    }
    sv.fuse_conduction = fuse;
    let mut dt = setup.dt;
    if let Some((h, blobs)) = from {
        sv.load_state(b, blobs)?;
        sv.time = h.time;
        sv.steps = h.steps;
        sv.set_nominal_dt(h.dt);
        dt = h.dt;
    }
    // Plain steps upload the reorder tables; the batches capture the graph and warm up.
    sv.advance(b, dt, 2 + 2 * GRAPH_STEPS)?;
    b.synchronize()?;
    let pairs = {
        let (counts, offsets, list) =
            sv.cells.csr_neighbours::<R, D>(b, &sv.particles.pos.cur, setup.params.kernel.support2)?;
        let fl = b.read(&sv.particles.flags.cur)?;
        let mech = |i: usize| fl[i] & flags::THERMAL_ONLY == 0;
        (0..counts.len())
            .filter(|&i| mech(i))
            .map(|i| list[offsets[i] as usize..offsets[i + 1] as usize].iter().filter(|&&j| mech(j as usize)).count())
            .sum::<usize>() as u64
    };
    let batches = steps.div_ceil(GRAPH_STEPS).max(1);
    let rebuilds0 = sv.cell_rebuilds(b)?;
    let ms = b.time_ms(&mut || sv.advance(b, dt, batches * GRAPH_STEPS))?;
    let rebuilds = (sv.cell_rebuilds(b)? - rebuilds0) as f64 / (batches * GRAPH_STEPS) as f64;
    let mut phases = [0.0; 8];
    for _ in 0..profiled.max(1) {
        let p = sv.profile_step(b, dt)?;
        for (a, x) in phases.iter_mut().zip(p) {
            *a += x / profiled.max(1) as f64;
        }
    }
    Ok(StepTimes {
        label: label.to_string(),
        particles: sv.n,
        precision: sv.precision(),
        ms_per_step: ms / (batches * GRAPH_STEPS) as f64,
        phases_ms: phases,
        pairs,
        bytes_per_step: compulsory_bytes(
            setup,
            sv.n,
            Fusion { conduction: fuse, prepare: sv.fuse_prepare, contact: sv.fuse_contact },
            rebuilds,
        ),
        rebuilds_per_step: rebuilds,
    })
}

/// Which passes of the step run fused (`Solver`'s `fuse_conduction`, `fuse_prepare`, `fuse_contact`).
#[derive(Clone, Copy, Debug)]
pub struct Fusion {
    pub conduction: bool,
    pub prepare: bool,
    pub contact: bool,
}

/// The least traffic of one step, per pass: predictor (reads y, ẏ and the binned positions, writes y and y0); on
/// a fraction `rebuilds` of the steps the cell list (positions, keys, slots, permutation) and the in-place reorder
/// (every stateful field read and written twice: the gather and the copy back); pre-pass (ρ, S in; σ/ρ² and the
/// stabilisers' fields out), interaction (every input once, the rates out), conduction, corrector with the
/// plastic fields, contact. Neighbour data re-read from cache is not counted: this is the bound a perfect cache
/// reaches. With fused conduction the interaction reads T and the full masses and writes Ṫ, and the conduction
/// pass is gone; with the pre-pass fused into the predictor it does not read ρ and S again, and with the contact
/// fused into the plastic corrector (plastic 2D runs) the contact does not read x, v, ρ, the flags and T again.
/// In the mixed precision the corrector also reads and writes the positions' low parts, and a reorder moves them.
pub fn compulsory_bytes<R: Real, D: TensorOps<R>>(s: &Setup<R, D>, n: usize, fused: Fusion, rebuilds: f64) -> f64 {
    let (v, r, sym) = (size_of::<D::Vec<R>>(), size_of::<R>(), size_of::<D::Sym<R>>());
    let y = 2 * v + r + sym; // x, v, ρ, S
    let stab = s.stabilisers.switches();
    let heat = s.temperature.is_some();
    let cond = s.thermal.as_ref().is_some_and(|t| t.conduction.is_some());
    let plastic = s.plastic.is_some();
    let contact = s.contact.is_some();
    // The mixed precision's position low parts: read and written by the corrector, moved by a reorder.
    let lo = if s.pos_lo.is_some() { v } else { 0 };
    let mut per = 0;
    per += 4 * y + v + if cond { 4 * 8 } else { 0 }; // predict
    let staged = 4 + 4 + y + r + y // id, flags, state, mass, start copies
        + if heat { 8 } else { 0 }
        + if cond { 8 } else { 0 }
        + if plastic { 3 * 8 } else { 0 }
        + if contact { 2 * v } else { 0 }
        + lo;
    // Hash and count (x in, key and slot out), scatter (key, slot in, perm out), sort (perm), gather (perm, every
    // field in and out, the binned positions out), copy back (every field in and out).
    let rebuild = v + 8 + 3 * 4 + 4 + (2 * staged + 4 + v) + 2 * staged;
    let prepare_fused = fused.prepare && s.params.expansion == R::ZERO;
    per += if prepare_fused { 0 } else { r + sym }
        + sym
        + if stab.stress { sym } else { 0 }
        + if stab.viscosity { r } else { 0 };
    per += y + r + sym + 4 + if stab.stress { sym } else { 0 } + if stab.viscosity { r } else { 0 };
    per += if contact { 2 * v } else { 0 } + y; // contact forces in, rates out
    let brookshaw = s.thermal.as_ref().is_some_and(|t| t.conduction == Some(false));
    if cond && fused.conduction && brookshaw {
        per += 8 + r + 8;
    } else if cond {
        per += v + 2 * r + 8 + 4 + 8;
    }
    per += 3 * y + 2 * lo + if cond { 3 * 8 } else { 0 } + if plastic { 2 * (3 * 8) + 8 } else { 0 };
    if contact && fused.contact && plastic && D::D == 2 {
        per += r + 2 * 2 * v + if heat { 8 } else { 0 }; // mass in, forces in and out, T out
    } else if contact {
        per += 2 * v + 2 * r + 4 + 2 * 2 * v + if heat { 2 * 8 } else { 0 };
    }
    (per as f64 + rebuilds * rebuild as f64) * n as f64
}

/// The device's copy bandwidth [GB/s]: a gather through the identity permutation of 2²⁴ 16-byte elements (reads
/// 16 + 4 bytes and writes 16 per element), best of five.
pub fn copy_bandwidth<B: Backend>(b: &B) -> Result<f64> {
    let n = 1 << 24;
    let perm: Vec<u32> = (0..n as u32).collect();
    let perm = b.upload(&perm, "identity permutation")?;
    let src = b.alloc::<[u32; 4]>(n, "copy source")?;
    let mut dst = b.alloc::<[u32; 4]>(n, "copy destination")?;
    b.gather(n, &perm, &src, &mut dst)?;
    let mut best = f64::INFINITY;
    for _ in 0..5 {
        best = best.min(b.time_ms(&mut || b.gather(n, &perm, &src, &mut dst))?);
    }
    Ok(36.0 * n as f64 / (best * 1e-3) / 1e9)
}

/// The setup with one physics option switched off, for the step cost of each option; None where the scene does
/// not model it.
pub fn without<R: Real, D: TensorOps<R>>(s: &Setup<R, D>, option: &str) -> Option<Setup<R, D>> {
    let mut o = s.clone();
    match option {
        "artificial viscosity" => o.stabilisers.viscosity.take().map(|_| ())?,
        "artificial stress" => o.stabilisers.stress.take().map(|_| ())?,
        "XSPH" => o.stabilisers.xsph.take().map(|_| ())?,
        "heat conduction" => o.thermal.as_mut()?.conduction.take().map(|_| ())?,
        "friction" => {
            let c = o.contact.as_mut()?;
            c.tools.iter().any(|t| t.params.friction > 0.0).then_some(())?;
            c.tools.iter_mut().for_each(|t| t.params.friction = 0.0);
        }
        "plasticity" => {
            use crate::kernels::contact::penalty::cap;
            o.plastic.take()?;
            if let Some(c) = o.contact.as_mut() {
                // The current-yield cap reads the plastic pass' yield stress: fall back to the static cap.
                for t in c.tools.iter_mut().filter(|t| t.params.cap_mode == cap::CURRENT) {
                    t.params.cap_mode = cap::STATIC;
                }
            }
        }
        "thermal tool" => {
            let keep: Vec<bool> = o.particles.flags.iter().map(|f| f & flags::THERMAL_ONLY == 0).collect();
            keep.iter().any(|k| !k).then_some(())?;
            let p = &mut o.particles;
            macro_rules! filter {
                ($v:expr) => {{
                    let mut k = keep.iter();
                    $v.retain(|_| *k.next().unwrap_or(&true));
                }};
            }
            filter!(p.id);
            filter!(p.flags);
            filter!(p.pos);
            filter!(p.vel);
            filter!(p.mass);
            filter!(p.rho);
            filter!(p.stress);
            if let Some(t) = o.temperature.as_mut() {
                filter!(t);
            }
            // Renumber so that ids stay a permutation of 0..n.
            for (k, id) in o.particles.id.iter_mut().enumerate() {
                *id = k as u32;
            }
        }
        _ => return None,
    }
    Some(o)
}

/// The options `without` knows, in report order.
pub const OPTIONS: [&str; 7] =
    ["heat conduction", "thermal tool", "artificial stress", "XSPH", "artificial viscosity", "friction", "plasticity"];

pub fn header(peak_gb_s: f64) -> String {
    // The first row of a workload is its default lanes per particle (`solver::default_lanes`).
    let phases: Vec<&str> = Phase::ALL.iter().map(|p| p.name()).collect();
    format!(
        "copy bandwidth (measured): {peak_gb_s:.0} GB/s\n\n| workload | N | prec | ms/step | particle-steps/s | \
         interactions/s | compulsory MB/step | GB/s (% of copy) | steps per rebuild | {} |\n|---|---|---|---|---|---|---|---|---|{}",
        phases.iter().map(|p| format!("{p} ms")).collect::<Vec<_>>().join(" | "),
        "---|".repeat(phases.len())
    )
}

pub fn row(t: &StepTimes, peak_gb_s: f64) -> String {
    format!(
        "| {} | {} | {} | {:.4} | {:.3e} | {:.3e} | {:.2} | {:.0} ({:.0} %) | {:.1} | {} |",
        t.label,
        t.particles,
        t.precision,
        t.ms_per_step,
        t.particle_steps_per_s(),
        t.interactions_per_s(),
        t.bytes_per_step / 1e6,
        t.bandwidth_gb_s(),
        100.0 * t.bandwidth_gb_s() / peak_gb_s,
        1.0 / t.rebuilds_per_step.max(1e-9),
        t.phases_ms.iter().map(|m| format!("{m:.4}")).collect::<Vec<_>>().join(" | ")
    )
}

/// Benchmarks each scene at each precision and prints the table; with `options`, also the step cost of each
/// physics option the scene models, switched off one at a time, measured side by side in the same process.
pub fn scenes<B: Backend>(
    b: &B,
    paths: &[std::path::PathBuf],
    precisions: &[crate::scene::Precision],
    steps: usize,
    options: bool,
) -> Result<()> {
    let peak = copy_bandwidth(b)?;
    println!("{}", header(peak));
    let mut costs = Vec::new();
    for path in paths {
        let scene = crate::scene::Scene::load(path, &[])
            .map_err(|e| crate::Error::Scene(format!("{}: {e}", path.display())))?;
        let label = scene.name.clone();
        for &p in precisions {
            use crate::kernels::{Dim2, Dim3};
            let sc = &*scene.with_precision(Some(p));
            let r = match (scene.dim, p == crate::scene::Precision::F64) {
                (3, false) => one::<B, f32, Dim3>(b, sc, &label, steps, options, peak)?,
                (3, true) => one::<B, f64, Dim3>(b, sc, &label, steps, options, peak)?,
                (_, false) => one::<B, f32, Dim2>(b, sc, &label, steps, options, peak)?,
                (_, true) => one::<B, f64, Dim2>(b, sc, &label, steps, options, peak)?,
            };
            costs.extend(r);
        }
    }
    if options {
        println!("\n| workload | prec | switched off | N | ms/step | base ms/step | step cost of the option |");
        println!("|---|---|---|---|---|---|---|");
        for c in costs {
            println!("{c}");
        }
    }
    Ok(())
}

/// Times the step of each run folder's checkpoint (`swarf bench step --from`): the state a run reached (a cut
/// with its chip, plastic flow and contact) rather than the scene's start, beside the same scene at t = 0 and the
/// saved state without the Verlet list, side by side.
pub fn checkpoints<B: Backend>(b: &B, dirs: &[std::path::PathBuf], steps: usize) -> Result<()> {
    let peak = copy_bandwidth(b)?;
    println!("{}", header(peak));
    for dir in dirs {
        // A measurement, not a continuation: a checkpoint of another build or an edited scene is timed as it is
        // (its buffers and header are still checked), with what differs said.
        let r = crate::resume::open(dir, true)?;
        for d in &r.accepted {
            eprintln!("note: {}: {d}", dir.display());
        }
        let scene = r.scene;
        let saved = crate::checkpoint::read(&dir.join("checkpoint.bin"))?;
        use crate::kernels::{Dim2, Dim3};
        use crate::scene::Precision;
        let p = Precision::from_name(&saved.0.precision).unwrap_or(Precision::F64);
        let sc = &*scene.with_precision(Some(p));
        match (scene.dim, p == Precision::F64) {
            (3, false) => saved_rows::<B, f32, Dim3>(b, sc, &saved, steps, peak)?,
            (3, true) => saved_rows::<B, f64, Dim3>(b, sc, &saved, steps, peak)?,
            (_, false) => saved_rows::<B, f32, Dim2>(b, sc, &saved, steps, peak)?,
            (_, true) => saved_rows::<B, f64, Dim2>(b, sc, &saved, steps, peak)?,
        }
    }
    Ok(())
}

/// `scene` with its neighbour search changed, each with its label: the pair loops walking the stencil, and in 3D the
/// Verlet list with the other offset width than `wide` (the base setup's; docs/neighbour-search.md, "Wide offsets");
/// none where the scene has no Verlet list anyway. Scenes, not setups: each is set up when its row is timed, so
/// that a large scene's variants are not held in memory together.
fn list_variants(scene: &crate::scene::Scene, wide: bool) -> Vec<(String, crate::scene::Scene)> {
    if !scene.discretisation.verlet_list {
        return Vec::new();
    }
    let mut walk = scene.clone();
    walk.discretisation.verlet_list = false;
    let mut out = vec![("no Verlet list (stencil walk)".to_string(), walk)];
    if scene.dim == 3 {
        let bits = if wide { 16 } else { 32 };
        let mut other = scene.clone();
        other.discretisation.verlet_offsets = Some(bits);
        out.push((format!("Verlet offsets of {bits} bits"), other));
    }
    out
}

fn saved_rows<B: Backend, R: Real, D: TensorOps<R>>(
    b: &B,
    scene: &crate::scene::Scene,
    saved: &Saved,
    steps: usize,
    peak: f64,
) -> Result<()> {
    let h = &saved.0;
    let s = crate::run::setup::<R, D>(scene)?;
    if h.precision != s.precision() || h.dim != D::D {
        return Err(crate::Error::Checkpoint(format!(
            "a {}D {} checkpoint for a {}D {} scene",
            h.dim,
            h.precision,
            D::D,
            s.precision()
        )));
    }
    let at = format!("{} at t = {:.4e} s (step {})", scene.name, h.time, h.steps);
    let t = step::<B, R, D>(b, &s, &at, steps, 5, None, true, Some(saved))?;
    println!("{}", row(&t, peak));
    let t = step::<B, R, D>(b, &s, &format!("{} at t = 0", scene.name), steps, 5, None, true, None)?;
    println!("{}", row(&t, peak));
    for (what, sc) in list_variants(scene, s.grid.list_wide != 0) {
        let sa = crate::run::setup::<R, D>(&sc)?;
        let t = step::<B, R, D>(b, &sa, &format!("{at}, {what}"), steps, 5, None, true, Some(saved))?;
        println!("{}", row(&t, peak));
    }
    Ok(())
}

fn one<B: Backend, R: Real, D: TensorOps<R>>(
    b: &B,
    scene: &crate::scene::Scene,
    label: &str,
    steps: usize,
    options: bool,
    peak: f64,
) -> Result<Vec<String>> {
    let s = crate::run::setup::<R, D>(scene)?;
    // The default lanes per particle, then every other choice side by side.
    let base = step::<B, R, D>(b, &s, label, steps, 5, None, true, None)?;
    println!("{}", row(&base, peak));
    let default = crate::solver::default_lanes(s.particles.len(), D::D);
    for l in [1, 2, 4, 8].into_iter().filter(|&l| l != default) {
        let alt = step::<B, R, D>(b, &s, &format!("{label}, {l} lane(s)"), steps, 5, Some(l), true, None)?;
        println!("{}", row(&alt, peak));
    }
    if s.thermal.as_ref().is_some_and(|t| t.conduction == Some(false)) {
        let sep = step::<B, R, D>(b, &s, &format!("{label}, separate conduction pass"), steps, 5, None, false, None)?;
        println!("{}", row(&sep, peak));
    }
    // The Verlet list against the stencil walk and the other offset width (docs/neighbour-search.md, "Verlet
    // list", "Wide offsets"), side by side.
    for (what, sc) in list_variants(scene, s.grid.list_wide != 0) {
        let sa = crate::run::setup::<R, D>(&sc)?;
        let t = step::<B, R, D>(b, &sa, &format!("{label}, {what}"), steps, 5, None, true, None)?;
        println!("{}", row(&t, peak));
    }
    // The skin (docs/neighbour-search.md, "Skin"): none (a rebuild whenever anything moved) and others beside
    // the scene's, side by side.
    let skin = scene.discretisation.skin_over_h;
    for alt in [0.0, 0.05, 0.2].into_iter().filter(|&k| k != skin) {
        let mut sc = scene.clone();
        sc.discretisation.skin_over_h = alt;
        // A skin whose cells no longer fit the scene (a z period of fewer than 5 cells) is reported, not run.
        let sa = match crate::run::setup::<R, D>(&sc) {
            Ok(sa) => sa,
            Err(e) => {
                println!("| {label}, skin {alt} h (scene: {skin} h) | not run: {e} |");
                continue;
            }
        };
        let t =
            step::<B, R, D>(b, &sa, &format!("{label}, skin {alt} h (scene: {skin} h)"), steps, 5, None, true, None)?;
        println!("{}", row(&t, peak));
    }
    let mut out = Vec::new();
    if options {
        for o in OPTIONS {
            if let Some(v) = without(&s, o) {
                let t = step::<B, R, D>(b, &v, label, steps, 1, None, true, None)?;
                out.push(format!(
                    "| {label} | {} | {o} | {} | {:.4} | {:.4} | {:+.1} % |",
                    s.precision(),
                    t.particles,
                    t.ms_per_step,
                    base.ms_per_step,
                    100.0 * (base.ms_per_step - t.ms_per_step) / t.ms_per_step
                ));
            }
        }
    }
    Ok(out)
}
