//! Diagnostics of a particle state: energies, momenta and the first non-finite value, summed in f64 in particle
//! order (deterministic) from the per-particle functions of `kernels::sph::energy`.

use crate::kernels::sph::energy::{elastic_damaged_at, kinetic};
use crate::kernels::sph::{SphParams, TensorOps};
use crate::kernels::{Real, Vector};
use crate::state::HostParticles;

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Diagnostics {
    pub time: f64,
    pub step: u64,
    pub kinetic: f64,
    pub elastic: f64,
    /// Linear momentum Σ m v (per unit depth in 2D).
    pub momentum: [f64; 3],
    /// Angular momentum Σ m x × v about the origin (2D: z component only).
    pub angular: [f64; 3],
    /// Σ m |v|, the scale for relative momentum errors.
    pub momentum_scale: f64,
    /// Largest speed.
    pub vmax: f64,
    /// Largest temperature [K] (NaN when not modelled).
    pub temperature_max: f64,
    /// Largest equivalent plastic strain (NaN when not modelled).
    pub plastic_strain_max: f64,
    /// Plastic work dissipated so far, Σ m_i Σ_steps σ_y Δε̄/ρ [J, per m of depth in 2D] (0 without plasticity):
    /// the heat t_q W_p of plastic heating is part of it.
    pub plastic_work: f64,
    /// Energy the artificial viscosity has taken out of the motion so far, Σ m_i ∫ ½ Σ_j m_j Π_ij v_ij·∇W dt
    /// (0 without it).
    pub viscous_dissipation: f64,
    /// Smallest distance between two mechanical particles [m] (NaN when none are within 2h; set by the run loop).
    pub min_pair_distance: f64,
    /// The same over pairs that started at least 2h apart: contact of material that was apart (NaN when none).
    pub min_contact_distance: f64,
    /// Where that pair is: its midpoint [m] (z = 0 in 2D; NaN when none).
    pub min_contact_midpoint: [f64; 3],
    /// Its particles' stable ids, the smaller first (None when none).
    pub min_contact_ids: Option<[u32; 2]>,
    /// Volume Σ m/ρ of the fully damaged particles (D ≥ −ln 0.01) [m³, m² per m of depth in 2D] (NaN without
    /// damage).
    pub damaged_volume: f64,
    /// Volume of the particles where damage has initiated (ω ≥ 1) (NaN without damage).
    pub initiated_volume: f64,
    /// The elastic energy the damage's degradation has released so far, Σ m_i Σ_steps (k_old − k_new)(S:S/(4G) +
    /// [p < 0] p²/(2K))/ρ [J, per m of depth in 2D] (NaN without damage; docs/damage.md, "Energy").
    pub damage_dissipation: f64,
    /// The work the cohesive path's bonds have taken from the motion, Σ ∫ t·dδ A [J, per m of depth in 2D]:
    /// stored while a bond holds, dissipated once it fails (NaN without a cohesive path).
    pub cohesive_work: f64,
    /// The energy the bonds' dampers have dissipated [J, per m of depth in 2D] (NaN without a cohesive path).
    pub bond_damping: f64,
    /// Bonds of the cohesive path that have failed (NaN without one).
    pub bonds_failed: f64,
    /// The mean mode-I share J_I/(J_I + J_II) at failure over the failed bonds (nairn-mpm.md Fig. 16; NaN when none
    /// has failed).
    pub mode_i_share: f64,
    /// A non-finite value: (particle id, field), of the smallest id that has one ([`Diagnostics::note_non_finite`]).
    pub non_finite: Option<(u32, &'static str)>,
    /// Where the particles with a non-finite position, velocity, density or stress are.
    pub non_finite_region: NonFiniteRegion,
}

/// One column of `energy.csv`: its name and its value in a row, read from the diagnostics. [`ENERGY_COLUMNS`] is the
/// file's only list of columns: the header and every row are written from it.
pub struct EnergyColumn {
    pub name: &'static str,
    pub value: fn(&Diagnostics) -> f64,
}

/// An id of the nearest contact pair as a CSV value (NaN when there is none).
fn contact_id(d: &Diagnostics, k: usize) -> f64 {
    d.min_contact_ids.map_or(f64::NAN, |p| f64::from(p[k]))
}

/// The columns of `energy.csv`, in order (read by `plot::plot_run` and by tools that post-process runs).
pub const ENERGY_COLUMNS: &[EnergyColumn] = &[
    EnergyColumn { name: "time", value: |d| d.time },
    EnergyColumn { name: "step", value: |d| d.step as f64 },
    EnergyColumn { name: "kinetic", value: |d| d.kinetic },
    EnergyColumn { name: "elastic", value: |d| d.elastic },
    EnergyColumn { name: "total", value: Diagnostics::total },
    EnergyColumn { name: "momentum_x", value: |d| d.momentum[0] },
    EnergyColumn { name: "momentum_y", value: |d| d.momentum[1] },
    EnergyColumn { name: "momentum_z", value: |d| d.momentum[2] },
    EnergyColumn { name: "angular_x", value: |d| d.angular[0] },
    EnergyColumn { name: "angular_y", value: |d| d.angular[1] },
    EnergyColumn { name: "angular_z", value: |d| d.angular[2] },
    EnergyColumn { name: "vmax", value: |d| d.vmax },
    EnergyColumn { name: "temperature_max", value: |d| d.temperature_max },
    EnergyColumn { name: "plastic_strain_max", value: |d| d.plastic_strain_max },
    EnergyColumn { name: "plastic_work", value: |d| d.plastic_work },
    EnergyColumn { name: "viscous_dissipation", value: |d| d.viscous_dissipation },
    EnergyColumn { name: "balance", value: Diagnostics::balance },
    EnergyColumn { name: "min_pair_distance", value: |d| d.min_pair_distance },
    EnergyColumn { name: "min_contact_distance", value: |d| d.min_contact_distance },
    EnergyColumn { name: "min_contact_x", value: |d| d.min_contact_midpoint[0] },
    EnergyColumn { name: "min_contact_y", value: |d| d.min_contact_midpoint[1] },
    EnergyColumn { name: "min_contact_z", value: |d| d.min_contact_midpoint[2] },
    EnergyColumn { name: "min_contact_id_a", value: |d| contact_id(d, 0) },
    EnergyColumn { name: "min_contact_id_b", value: |d| contact_id(d, 1) },
    EnergyColumn { name: "damaged_volume", value: |d| d.damaged_volume },
    EnergyColumn { name: "initiated_volume", value: |d| d.initiated_volume },
    EnergyColumn { name: "cohesive_work", value: |d| d.cohesive_work },
    EnergyColumn { name: "bond_damping", value: |d| d.bond_damping },
    EnergyColumn { name: "bonds_failed", value: |d| d.bonds_failed },
    EnergyColumn { name: "mode_i_share", value: |d| d.mode_i_share },
    EnergyColumn { name: "damage_dissipation", value: |d| d.damage_dissipation },
];

/// The header of `energy.csv`.
pub fn energy_header() -> Vec<&'static str> {
    ENERGY_COLUMNS.iter().map(|c| c.name).collect()
}

/// Where a blow-up is: how many particles have a non-finite value, and the box of those whose position is still
/// finite. Within a batch of steps a blow-up spreads through the neighbours before the host sees it, so the particle
/// it names is any of them; the box of their finite positions shows where it happened.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NonFiniteRegion {
    pub dim: usize,
    pub count: u64,
    /// Of `count`, those with a finite position, inside [lo, hi].
    pub located: u64,
    pub lo: [f64; 3],
    pub hi: [f64; 3],
}

impl Default for NonFiniteRegion {
    fn default() -> Self {
        NonFiniteRegion { dim: 3, count: 0, located: 0, lo: [f64::INFINITY; 3], hi: [f64::NEG_INFINITY; 3] }
    }
}

impl NonFiniteRegion {
    /// An empty region of a `dim`-dimensional run.
    pub fn new(dim: usize) -> Self {
        NonFiniteRegion { dim, ..Default::default() }
    }

    /// Counts a particle with a non-finite value at `x` (None where its position is non-finite too).
    pub fn note(&mut self, x: Option<[f64; 3]>) {
        self.count += 1;
        if let Some(x) = x {
            self.located += 1;
            for (k, xk) in x.iter().enumerate().take(self.dim) {
                self.lo[k] = self.lo[k].min(*xk);
                self.hi[k] = self.hi[k].max(*xk);
            }
        }
    }

    /// The error message's part: "; N particles non-finite, M of them at x in [a, b], y in [c, d] m" (empty when
    /// none was counted).
    pub fn describe(&self) -> String {
        if self.count == 0 {
            return String::new();
        }
        let mut s = format!("; {} particle(s) non-finite", self.count);
        if self.located > 0 {
            let axes: Vec<String> = (0..self.dim)
                .map(|k| format!("{} in [{:.4e}, {:.4e}]", ["x", "y", "z"][k], self.lo[k], self.hi[k]))
                .collect();
            s += &format!(", {} of them with a finite position at {} m", self.located, axes.join(", "));
        }
        s
    }
}

impl Diagnostics {
    /// Notes a non-finite `field` of particle `id`, keeping the smallest id (the first field noted for it): the
    /// report does not depend on the particles' order, which the void bucket of non-finite positions leaves
    /// arbitrary on a GPU (`backend::CellBuffers::sorted_buckets`).
    pub fn note_non_finite(&mut self, id: u32, field: &'static str) {
        if self.non_finite.is_none_or(|(first, _)| id < first) {
            self.non_finite = Some((id, field));
        }
    }

    /// This state's row of `energy.csv`, in [`ENERGY_COLUMNS`]' order.
    pub fn energy_row(&self) -> Vec<f64> {
        ENERGY_COLUMNS.iter().map(|c| (c.value)(self)).collect()
    }

    pub fn total(&self) -> f64 {
        self.kinetic + self.elastic
    }

    /// The energy balance's left side: kinetic + elastic + plastic work + viscous dissipation (+ the damage's
    /// release, + the cohesive path's work). Constant up to the time-integration error and the work of prescribed
    /// motions and the tool (docs/stability.md).
    pub fn balance(&self) -> f64 {
        let cohesive = if self.cohesive_work.is_nan() { 0.0 } else { self.cohesive_work + self.bond_damping };
        let damage = if self.damage_dissipation.is_nan() { 0.0 } else { self.damage_dissipation };
        self.kinetic + self.elastic + self.plastic_work + self.viscous_dissipation + cohesive + damage
    }
}

/// `temp`: the particles' temperatures when the run models thermal expansion (the pressure then depends on T).
/// `damage`: the particles' damage D where modelled: a damaged particle's elastic energy is that of the degraded
/// stress it acts with (`kernels::sph::energy::elastic_damaged_at`), not of its stored stress (a fully damaged
/// particle pulled apart stores a growing tensile pressure it no longer exerts).
pub fn compute<R: Real, D: TensorOps<R>>(
    p: &HostParticles<R, D>,
    params: &SphParams<R>,
    time: f64,
    step: u64,
    temp: Option<&[f64]>,
    damage: Option<&[f64]>,
) -> Diagnostics {
    let mut d = Diagnostics {
        time,
        step,
        temperature_max: f64::NAN,
        plastic_strain_max: f64::NAN,
        min_pair_distance: f64::NAN,
        min_contact_distance: f64::NAN,
        min_contact_midpoint: [f64::NAN; 3],
        damaged_volume: f64::NAN,
        initiated_volume: f64::NAN,
        damage_dissipation: f64::NAN,
        cohesive_work: f64::NAN,
        bond_damping: f64::NAN,
        bonds_failed: f64::NAN,
        mode_i_share: f64::NAN,
        non_finite_region: NonFiniteRegion::new(D::D),
        ..Default::default()
    };
    for i in 0..p.len() {
        let (x, v, m, rho) = (&p.pos[i], &p.vel[i], p.mass[i], p.rho[i]);
        let vals: [(&'static str, bool); 4] = [
            ("position", (0..D::D).all(|k| x.get(k).is_finite())),
            ("velocity", (0..D::D).all(|k| v.get(k).is_finite())),
            ("density", rho.is_finite()),
            ("stress", bytemuck::cast_slice::<_, R>(std::slice::from_ref(&p.stress[i])).iter().all(|s| s.is_finite())),
        ];
        if let Some((field, _)) = vals.iter().find(|(_, ok)| !ok) {
            d.note_non_finite(p.id[i], field);
            d.non_finite_region.note(vals[0].1.then(|| std::array::from_fn(|k| x.get(k).to_f64())));
            continue;
        }
        // The tool's thermal-only particles carry no mechanics (roethlin-solver.md §5.6).
        if p.flags[i] & crate::kernels::sph::params::flags::THERMAL_ONLY != 0 {
            continue;
        }
        d.kinetic += kinetic(m, v).to_f64();
        let (t, dmg) = (temp.map(|t| t[i]), damage.map_or(0.0, |d| d[i]));
        d.elastic += elastic_damaged_at::<R, D>(params, m, rho, &p.stress[i], t, dmg).to_f64();
        let mf = m.to_f64();
        let xv: [f64; 3] = std::array::from_fn(|k| x.get(k).to_f64());
        let vv: [f64; 3] = std::array::from_fn(|k| v.get(k).to_f64());
        let speed = (vv[0] * vv[0] + vv[1] * vv[1] + vv[2] * vv[2]).sqrt();
        for (m, v) in d.momentum.iter_mut().zip(vv) {
            *m += mf * v;
        }
        d.angular[0] += mf * (xv[1] * vv[2] - xv[2] * vv[1]);
        d.angular[1] += mf * (xv[2] * vv[0] - xv[0] * vv[2]);
        d.angular[2] += mf * (xv[0] * vv[1] - xv[1] * vv[0]);
        d.momentum_scale += mf * speed;
        d.vmax = d.vmax.max(speed);
    }
    d
}

/// Adds the maxima of temperature and plastic strain (where modelled) and reports a non-finite one.
pub fn internal(d: &mut Diagnostics, id: &[u32], temp: Option<&[f64]>, eps: Option<&[f64]>) {
    if let Some(v) = temp {
        d.temperature_max = finite_max(d, id, "temperature", v);
    }
    if let Some(v) = eps {
        d.plastic_strain_max = finite_max(d, id, "plastic strain", v);
    }
}

/// The largest finite value of a per-particle `field` (−∞ when none), noting its non-finite ones.
fn finite_max(d: &mut Diagnostics, id: &[u32], field: &'static str, v: &[f64]) -> f64 {
    let mut max = f64::NEG_INFINITY;
    for (i, x) in v.iter().enumerate() {
        if !x.is_finite() {
            d.note_non_finite(id[i], field);
        } else if *x > max {
            max = *x;
        }
    }
    max
}

/// The per-particle specific dissipated energies [J/kg] (state order), each where modelled.
#[derive(Clone, Debug, Default)]
pub struct Dissipated {
    /// The plastic work Σ e^{−D} σ_y Δε̄/ρ.
    pub plastic: Option<Vec<f64>>,
    /// The artificial viscosity's dissipation.
    pub viscous: Option<Vec<f64>>,
    /// The elastic energy the damage's degradation has released (`kernels::damage::released_density`).
    pub damage: Option<Vec<f64>>,
}

/// Adds the dissipated energies Σ m_i w_i of the per-particle specific plastic work, viscous dissipation and
/// damage release (thermal-only particles carry no mechanics and are left out; the damage's is NaN without damage).
pub fn dissipated<R: Real, D: TensorOps<R>>(d: &mut Diagnostics, p: &HostParticles<R, D>, w: &Dissipated) {
    let mech = |i: usize| p.flags[i] & crate::kernels::sph::params::flags::THERMAL_ONLY == 0;
    let sum = |w: &Vec<f64>| (0..p.len()).filter(|&i| mech(i)).map(|i| p.mass[i].to_f64() * w[i]).sum::<f64>();
    d.plastic_work = w.plastic.as_ref().map_or(0.0, sum);
    d.viscous_dissipation = w.viscous.as_ref().map_or(0.0, sum);
    d.damage_dissipation = w.damage.as_ref().map_or(f64::NAN, sum);
}

/// Adds the damaged and initiated volumes (`omega`, `damage`: the frames' `damage_initiation` and `damage`, where
/// modelled), Σ m/ρ over the mechanical particles with full damage and with ω ≥ 1, and reports a non-finite one.
pub fn damaged<R: Real, D: TensorOps<R>>(
    d: &mut Diagnostics,
    p: &HostParticles<R, D>,
    omega: Option<&[f64]>,
    damage: Option<&[f64]>,
) {
    let (Some(omega), Some(damage)) = (omega, damage) else { return };
    let (mut full, mut initiated) = (0.0, 0.0);
    for i in 0..p.len() {
        if !(omega[i].is_finite() && damage[i].is_finite()) {
            d.note_non_finite(p.id[i], "damage");
            continue;
        }
        if p.flags[i] & crate::kernels::sph::params::flags::THERMAL_ONLY != 0 {
            continue;
        }
        let vol = p.mass[i].to_f64() / p.rho[i].to_f64();
        if crate::kernels::damage::is_full(damage[i]) {
            full += vol;
        }
        if omega[i] >= 1.0 {
            initiated += vol;
        }
    }
    d.damaged_volume = full;
    d.initiated_volume = initiated;
}

/// The cohesive path's tally at one instant ([`crate::solver::Solver::bond_tally`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BondTally {
    pub failed: usize,
    /// Σ of the bonds' work [J, per m of depth in 2D].
    pub work: f64,
    /// Σ of the bonds' dampers' dissipation.
    pub damping: f64,
    /// Mean mode-I share at failure over the failed bonds (NaN when none).
    pub mode_i_share: f64,
}

/// Adds the cohesive path's work, failed bonds and mode-I share (where a path is modelled).
pub fn cohesive(d: &mut Diagnostics, tally: Option<&BondTally>) {
    if let Some(t) = tally {
        d.cohesive_work = t.work;
        d.bond_damping = t.damping;
        d.bonds_failed = t.failed as f64;
        d.mode_i_share = t.mode_i_share;
    }
}
