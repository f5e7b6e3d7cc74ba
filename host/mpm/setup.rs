//! From an MPM scene to its particles, grid, crack and motions (nairn-mpm.md §3; docs/mpm.md "Set-up"): plain
//! data, before anything is allocated.

use crate::kernels::cohesive::{Cohesive, TractionLaw};
use crate::kernels::mpm::grid::{ABOVE, BELOW, MpmParams, TOOL};
use crate::kernels::mpm::hyperelastic::NeoHookeanJ2;
use crate::scene::mpm::{BondSetup, CutSetup, MpmScene, Setup};
use crate::{Error, Result};

/// A prescribed velocity ramped linearly from 0 over `ramp` seconds: v(t) = v min(t/ramp, 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ramp {
    pub velocity: [f64; 2],
    pub ramp: f64,
}

impl Ramp {
    /// The velocity at t.
    pub fn velocity(&self, t: f64) -> [f64; 2] {
        let f = if self.ramp > 0.0 { (t / self.ramp).min(1.0) } else { 1.0 };
        [self.velocity[0] * f, self.velocity[1] * f]
    }

    /// The displacement ∫₀ᵗ v: v t²/(2 ramp) during the ramp, v (t − ramp/2) after it.
    pub fn displacement(&self, t: f64) -> [f64; 2] {
        let s = if t < self.ramp { t * t / (2.0 * self.ramp) } else { t - 0.5 * self.ramp };
        [self.velocity[0] * s, self.velocity[1] * s]
    }
}

/// The particles at t = 0, in id order (f64; the solver narrows them to the run's precision).
#[derive(Clone, Debug, Default)]
pub struct Points {
    pub pos: Vec<[f64; 2]>,
    pub mass: Vec<f64>,
    pub vol: Vec<f64>,
    pub kind: Vec<u32>,
}

impl Points {
    fn push(&mut self, x: [f64; 2], mass: f64, vol: f64, kind: u32) {
        self.pos.push(x);
        self.mass.push(mass);
        self.vol.push(vol);
        self.kind.push(kind);
    }
}

/// Everything a run of an MPM scene needs, computed from the scene alone.
#[derive(Clone, Debug)]
pub struct MpmSetup {
    pub params: MpmParams,
    pub points: Points,
    /// The crack points failed from the start (the traction-free starter): those with x below this.
    pub starter_end: f64,
    /// Each crack point's two particles, facing each other across it (above, below).
    pub pairs: Vec<[u32; 2]>,
    /// The tool's motion and its cutting edge at t = 0 (a cut), or the grip's (a bond).
    pub tool: Option<(Ramp, [f64; 2])>,
    pub grip: Option<Ramp>,
    /// Δt and the step count.
    pub dt: f64,
    pub steps: u64,
    /// The specimen's particles (not the tool's).
    pub specimen: usize,
    /// The start-up damping's gain 1/(Q M) during the ramp (`MpmStep::feedback`; 0: none).
    pub feedback: f64,
}

/// Builds the set-up of `scene`.
pub fn setup(scene: &MpmScene) -> Result<MpmSetup> {
    let m = &scene.material;
    let bad = |key: &str, what: String| Error::Scene(format!("{}: {key}: {what}", scene.origin));
    let plastic = NeoHookeanJ2::plastic_modulus_of(scene.young(), m.tangent_modulus);
    let c = &scene.cohesive;
    let base = MpmParams {
        mass_floor: 0.0,
        position_order: scene.damping.position_update.kernel(),
        material: NeoHookeanJ2 {
            bulk: m.bulk_modulus,
            shear: m.shear_modulus,
            yield_stress: m.yield_stress,
            plastic_modulus: plastic,
        },
        cohesive: Cohesive {
            mode1: TractionLaw::of_toughness(c.law.kernel(), c.toughness, c.peak),
            mode2: TractionLaw::of_toughness(c.law.kernel(), c.toughness_shear, c.peak_shear),
        },
        // Contact where the tool's and the field's volumes fill the cell: they meet (docs/mpm.md "Contact").
        contact_fill: 1.0,
        fix_below: f64::NEG_INFINITY,
        pull_above: f64::INFINITY,
        flank_normal: [0.0, 1.0],
        ..Default::default()
    };
    if let Setup::Cut(cut) = &scene.setup {
        // Beyond the crack's end the tool would plough into uncracked material (docs/mpm.md "Scenes").
        let travel = cut.speed * scene.time.end * (1.0 - 0.5 * cut.ramp) / cut.depth;
        if travel > cut.crack - 1.0 {
            return Err(bad(
                "cut.cut_length",
                format!(
                    "the tool travels {travel:.3} h by time.end, past the crack's end less one h ({} h): expected a \
                     cut_length (or time.end) whose travel is at most cut.crack - 1, or a longer cut.crack",
                    cut.crack - 1.0
                ),
            ));
        }
    }
    let mut s = match &scene.setup {
        Setup::Cut(cut) => cut_setup(scene, cut, base),
        Setup::Bond(bond) => bond_setup(scene, bond, base),
    };
    s.pairs = pairs(&s.params, &s.points).map_err(|what| bad("crack", what))?;
    let particle_mass = s.points.mass.iter().copied().fold(f64::INFINITY, f64::min);
    // A field lighter than 10⁻⁵ of the lightest particle carries no velocity (docs/mpm.md, "Small masses").
    s.params.mass_floor = 1e-5 * particle_mass;
    s.dt = scene.time.cfl * s.params.dx / scene.wave_speed();
    let steps = (scene.time.end / s.dt).ceil();
    if !(1.0..=1e10).contains(&steps) {
        return Err(bad("time.end", format!("{steps} steps of {:.3e} s: expected 1 to 1e10", s.dt)));
    }
    s.steps = steps as u64;
    s.feedback = feedback_gain(scene.damping.feedback, &s);
    Ok(s)
}

impl MpmSetup {
    /// The ramp that drives the scene: the tool's, else the grip's.
    pub fn driving_ramp(&self) -> Option<Ramp> {
        self.tool.map(|(r, _)| r).or(self.grip)
    }
}

/// The start-up damping's gain 1/(Q M) (nairn-mpm.md §1.3) of the dimensionless gain g: 1/Q = g/(v² t_ramp²) on
/// the driving ramp, M the specimen's mass; 0 without a ramp.
fn feedback_gain(g: f64, s: &MpmSetup) -> f64 {
    let Some(ramp) = s.driving_ramp() else { return 0.0 };
    let v2 = ramp.velocity[0] * ramp.velocity[0] + ramp.velocity[1] * ramp.velocity[1];
    let mass: f64 = s.points.mass.iter().zip(&s.points.kind).filter(|(_, k)| **k != TOOL).map(|(m, _)| m).sum();
    if g <= 0.0 || ramp.ramp <= 0.0 || v2 <= 0.0 || mass <= 0.0 {
        return 0.0;
    }
    g / (v2 * ramp.ramp * ramp.ramp * mass)
}

/// The grid's nodes along one axis from `lo` to `hi` with node 0 at `origin`: (origin, count).
fn axis(lo: f64, hi: f64, dx: f64, anchor: f64) -> (f64, u32) {
    // Nodes sit at anchor + k dx; the first at or below lo, the last at or above hi.
    let k0 = ((lo - anchor) / dx).floor();
    let k1 = ((hi - anchor) / dx).ceil();
    (anchor + k0 * dx, (k1 - k0) as u32 + 1)
}

/// Fills the rectangle [x0, x1] × [y0, y1] with particles at spacing sp, 2 × 2 per cell: the particle at the
/// centre of each sp × sp square; `kind` by the side of the plane y = 0.
fn fill(points: &mut Points, lo: [f64; 2], hi: [f64; 2], sp: f64, density: f64) {
    let (nx, ny) = (((hi[0] - lo[0]) / sp).round() as usize, ((hi[1] - lo[1]) / sp).round() as usize);
    let vol = sp * sp;
    for j in 0..ny {
        for i in 0..nx {
            let x = [lo[0] + (i as f64 + 0.5) * sp, lo[1] + (j as f64 + 0.5) * sp];
            points.push(x, density * vol, vol, if x[1] > 0.0 { ABOVE } else { BELOW });
        }
    }
}

/// Nairn's cut (nairn-mpm.md §3): the specimen [0, w h] × [−d h, h] with the cut plane y = 0, 2 × 2 particles per
/// cell of 2h/n, the crack from the left edge to a h (its first `starter` h traction-free), the bottom edge held,
/// and the tool (rake α from the vertical, clearance θ, edge on the plane) starting one particle spacing left of
/// the specimen and moving along +x.
fn cut_setup(scene: &MpmScene, c: &CutSetup, mut p: MpmParams) -> MpmSetup {
    let h = c.depth;
    let dx = 2.0 * h / c.particles_across as f64;
    let sp = 0.5 * dx;
    let (alpha, theta) = (c.rake.to_radians(), c.clearance.to_radians());
    let mut points = Points::default();
    fill(&mut points, [0.0, -c.base * h], [c.width * h, h], sp, scene.material.density);
    let specimen = points.pos.len();
    // The tool: edge T, rake top R, back top B, flank end F (counter-clockwise), filled on the particle lattice.
    let tip = [-sp, 0.0];
    let th = c.tool_height * h;
    let back = th * alpha.tan() + 2.0 * h;
    let poly =
        [tip, [tip[0] - th * alpha.tan(), th], [tip[0] - back, th], [tip[0] - back, back * theta.tan().min(th / back)]];
    let (lo, hi) = ([tip[0] - back, 0.0], [tip[0], th]);
    let (i0, i1) = ((lo[0] / sp).floor() as i64, (hi[0] / sp).ceil() as i64);
    let (j0, j1) = ((lo[1] / sp).floor() as i64, (hi[1] / sp).ceil() as i64);
    for j in j0..j1 {
        for i in i0..i1 {
            let x = [(i as f64 + 0.5) * sp, (j as f64 + 0.5) * sp];
            if inside(&poly, x) {
                points.push(x, scene.material.density * sp * sp, sp * sp, TOOL);
            }
        }
    }
    // Node rows at (k + ½) Δx from the plane, so that the plane lies mid-cell; node columns on x = 0.
    // Room above the specimen and behind the tool, where the chip curls (over the tool's top, at times).
    let margin = 3.0 * dx;
    let (ox, nx) = axis(tip[0] - back - 0.5 * c.room * h - margin, c.width * h + margin, dx, 0.0);
    let (oy, ny) = axis(-c.base * h - margin, h + c.room * h + margin, dx, 0.5 * dx);
    p.origin = [ox, oy];
    p.dx = dx;
    p.lp = 0.25 * dx;
    p.nodes = [nx, ny];
    // The crack: from two cells left of the specimen to a h; its points from the specimen's edge, at the
    // particle spacing.
    p.crack_lo = -2.0 * dx;
    let count = (c.crack * h / sp).round();
    p.crack_points = count as u32;
    p.crack_ds = sp;
    p.points_lo = 0.0;
    p.crack_hi = count * sp;
    p.crack_y = 0.0;
    p.fix_below = -c.base * h + 1e-9 * dx;
    p.friction = c.friction;
    p.rake_normal = [-alpha.cos(), -alpha.sin()];
    let split = 0.5 * (std::f64::consts::PI * 1.5 + alpha - theta);
    p.face_split = [split.cos(), split.sin()];
    let ramp_time = c.ramp * scene.time.end;
    MpmSetup {
        params: p,
        points,
        starter_end: c.starter * h,
        tool: Some((Ramp { velocity: [c.speed, 0.0], ramp: ramp_time }, tip)),
        grip: None,
        dt: 0.0,
        steps: 0,
        specimen,
        feedback: 0.0,
        pairs: Vec::new(),
    }
}

/// The bonded block (V15): [0, W] × [−H, H], joined along y = 0 over its whole width, the bottom held and the top
/// gripped.
fn bond_setup(scene: &MpmScene, b: &BondSetup, mut p: MpmParams) -> MpmSetup {
    let dx = b.cell;
    let sp = 0.5 * dx;
    let (w, hh) = ((b.width / dx).round() * dx, (b.height / dx).round() * dx);
    let mut points = Points::default();
    fill(&mut points, [0.0, -hh], [w, hh], sp, scene.material.density);
    let specimen = points.pos.len();
    let margin = 3.0 * dx;
    // Room for the grip's travel over the run.
    let travel = [b.pull[0].abs() * scene.time.end, b.pull[1].abs() * scene.time.end];
    let (ox, nx) = axis(-margin - travel[0], w + margin + travel[0], dx, 0.0);
    let (oy, ny) = axis(-hh - margin, hh + margin + travel[1], dx, 0.5 * dx);
    p.origin = [ox, oy];
    p.dx = dx;
    p.lp = 0.25 * dx;
    p.nodes = [nx, ny];
    // The fields separate across the whole plane and beyond its edges; the points cover the block's width.
    p.crack_lo = -2.0 * dx;
    p.crack_hi = w + 2.0 * dx;
    let count = (w / sp).round();
    p.crack_points = count as u32;
    p.crack_ds = sp;
    p.points_lo = 0.0;
    p.crack_y = 0.0;
    p.fix_below = -hh;
    p.pull_above = hh;
    MpmSetup {
        params: p,
        points,
        starter_end: f64::NEG_INFINITY,
        tool: None,
        grip: Some(Ramp { velocity: b.pull, ramp: b.ramp * scene.time.end }),
        dt: 0.0,
        steps: 0,
        specimen,
        feedback: 0.0,
        pairs: Vec::new(),
    }
}

/// Each crack point's facing particles: in the particle column at the point's x, the lowest particle above the
/// plane and the highest below it.
fn pairs(p: &MpmParams, points: &Points) -> std::result::Result<Vec<[u32; 2]>, String> {
    let n = p.crack_points as usize;
    let mut best: Vec<[Option<(f64, u32)>; 2]> = vec![[None, None]; n];
    for (i, x) in points.pos.iter().enumerate() {
        if points.kind[i] == TOOL {
            continue;
        }
        let k = ((x[0] - p.points_lo) / p.crack_ds - 0.5).round();
        if k < 0.0 || k >= n as f64 || (p.crack_x(k as u32) - x[0]).abs() > 0.25 * p.crack_ds {
            continue;
        }
        let (side, d) = if x[1] > p.crack_y { (0, x[1] - p.crack_y) } else { (1, p.crack_y - x[1]) };
        let slot = &mut best[k as usize][side];
        if slot.is_none_or(|(d0, _)| d < d0) {
            *slot = Some((d, i as u32));
        }
    }
    best.iter()
        .enumerate()
        .map(|(k, b)| match b {
            [Some((_, a)), Some((_, c))] => Ok([*a, *c]),
            _ => Err(format!("crack point {k} at x = {:.4e} m has no particle on one side", p.crack_x(k as u32))),
        })
        .collect()
}

/// Whether x lies inside the convex polygon `poly` (counter-clockwise corners).
fn inside(poly: &[[f64; 2]], x: [f64; 2]) -> bool {
    (0..poly.len()).all(|k| {
        let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
        (b[0] - a[0]) * (x[1] - a[1]) - (b[1] - a[1]) * (x[0] - a[0]) >= 0.0
    })
}
