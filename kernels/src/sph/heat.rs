//! Heat conduction (roethlin-solver.md §2.5, §3.4; klippel-constitutive.md §1.2):
//! ρ_i c_i Ṫ_i = Σ_j V_j k_ij · L_ij(T), with V_j = m_j/ρ_j and the conductivity of a pair k_ij = 2 k_i k_j/(k_i + k_j)
//! (the harmonic mean: heat leaving i equals heat entering j between different materials; for one material
//! it is k and the sum is α ∇²T of the theses).
//!
//! Brookshaw (4.70): L_ij = 2 (T_i − T_j) W'(r)/r. Since W' < 0, every pair moves heat from the hotter to the
//! colder particle (H12), on any particle arrangement.
//! PSE (4.74): L_ij = (T_j − T_i) K(r), K = 4/(π h⁴) e^(−r²/h²) in 2D and 4/(π^(3/2) h⁵) e^(−r²/h²) in 3D (second
//! moment 2 per axis, so Σ V_j (f_j − f_i) K → ∇²f). The Gaussian needs neighbours to 3h: with the theses' 2h
//! stencil the Laplacian of x² + y² comes out 13 % low (AT-11, erratum 26); the PSE pass uses a ±3 cell stencil.
//!
//! Temperatures are f64 in every precision (with the plastic state: the constitutive layer is f64).

use super::kernel::CubicSpline;
use super::lanes::{all_lanes, lane_share};
use crate::load::read;
use crate::neighbour::Neighbours;
use crate::real::Real;
use crate::vector::Vector;
use bytemuck::{Pod, Zeroable};

/// Thermal constants of one material (indexed by the particle's body).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ThermalMaterial {
    /// Conductivity k [W/(m K)].
    pub conductivity: f64,
    /// Specific heat c_p [J/(kg K)].
    pub specific_heat: f64,
}

/// Kernel constants of the conduction pass.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct HeatParams {
    /// Normalisation of the PSE Gaussian (dimension dependent).
    pub pse_norm: f64,
    /// 1/h².
    pub inv_h2: f64,
    /// Squared cutoff of the PSE sum ((3h)²).
    pub pse_cut2: f64,
    /// Pairs closer than this (squared) are skipped (as in the momentum pass).
    pub min_r2: f64,
    /// The workpiece's reference density ρ0, by which [`heat_flags::C2D`] divides instead of the particle's ρ.
    pub rho0: f64,
    /// [`heat_flags`] (0: swarf's conduction), set from the scene's `model` only.
    pub flags: u32,
    pub _pad: u32,
}

/// The bits of [`HeatParams::flags`].
pub mod heat_flags {
    /// Röthlin's 2D code's conduction [C2D] (`interactions_gpu.cu`), reproduced for `model = "mfree_iwf"`:
    /// Ṫ_i = k_i/(ρ0_i c_i) Σ_j V_j L_ij with the receiving particle's own conductivity (no harmonic mean: between
    /// the workpiece and the tool heat is not conserved) and its reference density ρ0 (the workpiece's; the tool's
    /// density does not change). (Its V_j = m_workpiece/ρ_j for tool neighbours too comes from the host, which
    /// gives the tool particles the workpiece's particle mass.)
    pub const C2D: u32 = 1;
}

impl HeatParams {
    pub fn new(h: f64, dim: usize) -> Self {
        let pi = core::f64::consts::PI;
        let norm = if dim == 3 { 4.0 / (pi * libm::sqrt(pi) * h * h * h * h * h) } else { 4.0 / (pi * h * h * h * h) };
        HeatParams {
            pse_norm: norm,
            inv_h2: 1.0 / (h * h),
            pse_cut2: 9.0 * h * h,
            min_r2: (1e-6 * h) * (1e-6 * h),
            rho0: 0.0,
            flags: 0,
            _pad: 0,
        }
    }
}

/// Read-only inputs of the conduction pass, sorted order.
#[derive(Clone, Copy)]
pub struct HeatArrays<R: Real, V: Vector<R>> {
    pub pos: *const V,
    pub rho: *const R,
    /// V = m/ρ of the pre-pass (`interact::prepare`), with the full masses: the tool's particles conduct.
    pub vol: *const R,
    pub temp: *const f64,
    pub flags: *const u32,
    /// Thermal materials, indexed by the body index in the flags.
    pub materials: *const ThermalMaterial,
}

/// Lane `lane` of `lanes`' share of the conduction sum Σ_j V_j k_ij L_ij of sorted particle i (0 for a particle
/// with a fixed temperature). `PSE` selects the Gaussian kernel (else Brookshaw); `nb.grid` must have stencil 2 for
/// Brookshaw and 3 for PSE, and PSE no Verlet list (its support is wider than the list's).
///
/// # Safety
/// Arrays hold the sorted particles of `nb` (`neighbour::for_each_candidate`); `i` is in range; every body index has a material.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub unsafe fn heat_sum<R: Real, V: Vector<R>, const PSE: bool>(
    hp: &HeatParams,
    k: &CubicSpline<R>,
    nb: &Neighbours,
    a: &HeatArrays<R, V>,
    i: u32,
    lane: u32,
    lanes: u32,
) -> f64 {
    unsafe {
        match heat_own(a, i) {
            Some(o) => lane_share::<R, V, f64, _>(nb, &o.x, i, lane, lanes, |j, s| {
                *s += heat_pair::<R, V, PSE>(hp, k, nb.grid, a, &o, i, j)
            }),
            None => 0.0,
        }
    }
}

/// What a conduction term needs of particle i; None for a particle with a fixed temperature.
#[derive(Clone, Copy)]
pub struct HeatOwn<V> {
    pub(crate) x: V,
    t: f64,
    material: ThermalMaterial,
    /// The body index of the flags (its material's index).
    body: u32,
    /// A thermal-only (tool) particle.
    tool: bool,
}

#[inline(always)]
pub(crate) unsafe fn heat_own<R: Real, V: Vector<R>>(a: &HeatArrays<R, V>, i: u32) -> Option<HeatOwn<V>> {
    use super::params::flags;
    let iu = i as usize;
    unsafe {
        let fl = *a.flags.add(iu);
        if fl & flags::FIXED_TEMPERATURE != 0 {
            return None;
        }
        let body = fl >> flags::BODY_SHIFT;
        Some(HeatOwn {
            x: *a.pos.add(iu),
            t: *a.temp.add(iu),
            material: *a.materials.add(body as usize),
            body,
            tool: fl & flags::THERMAL_ONLY != 0,
        })
    }
}

/// What a conduction term reads of neighbour j: its body index, temperature and volume, loaded together
/// (`interact::Partner` says why).
#[derive(Clone, Copy)]
pub struct HeatPartner {
    body: u32,
    t: f64,
    vol: f64,
}

/// # Safety
/// `j` is in range of the arrays.
#[inline(always)]
pub(crate) unsafe fn heat_partner<R: Real, V: Vector<R>>(a: &HeatArrays<R, V>, j: u32) -> HeatPartner {
    use super::params::flags;
    let ju = j as usize;
    unsafe {
        // `load::read`: ahead of the pair's branches (`interact::Partner`).
        HeatPartner {
            body: read(a.flags.add(ju)) >> flags::BODY_SHIFT,
            t: read(a.temp.add(ju)),
            vol: read(a.vol.add(ju)).to_f64(),
        }
    }
}

/// The term of pair (i, j) (0 for j = i or beyond the cutoff).
#[inline(always)]
pub(crate) unsafe fn heat_pair<R: Real, V: Vector<R>, const PSE: bool>(
    hp: &HeatParams,
    k: &CubicSpline<R>,
    grid: &crate::neighbour::GridParams,
    a: &HeatArrays<R, V>,
    o: &HeatOwn<V>,
    i: u32,
    j: u32,
) -> f64 {
    let cut2 = if PSE { R::from_f64(hp.pse_cut2) } else { k.support2 };
    let ju = j as usize;
    let (xj, q) = unsafe { (*a.pos.add(ju), heat_partner(a, j)) };
    let r2 = grid.dist2::<R, V>(&o.x, &xj);
    if j == i || r2 >= cut2 || r2 < R::from_f64(hp.min_r2) {
        return 0.0;
    }
    if PSE {
        let (kij, vj, tj) = unsafe { conductance(hp, a, o, &q) };
        let r2f = r2.to_f64();
        vj * kij * (tj - o.t) * hp.pse_norm * libm::exp(-r2f * hp.inv_h2)
    } else {
        let r = r2.sqrt();
        // The same W'(r)/r as the fused pass's geometry (`interact::geometry`), so both agree bit for bit.
        brookshaw_term(hp, a, o, &q, k.dw_dr_over_r(r).to_f64())
    }
}

/// The Brookshaw term V_j k_ij 2 (T_i − T_j) W'(r)/r of pair (i, j) within the support, with j's data `q` and
/// `dw` = W'(r)/r (shared with the momentum term in the fused pass).
#[inline(always)]
pub(crate) fn brookshaw_term<R: Real, V: Vector<R>>(
    hp: &HeatParams,
    a: &HeatArrays<R, V>,
    o: &HeatOwn<V>,
    q: &HeatPartner,
    dw: f64,
) -> f64 {
    // SAFETY: the body index of a particle's flags has a material (`heat_sum`'s contract).
    let (kij, vj, tj) = unsafe { conductance(hp, a, o, q) };
    vj * kij * 2.0 * (o.t - tj) * dw
}

/// k_ij, V_j and T_j of pair (i, j).
///
/// # Safety
/// `materials` covers j's body index.
#[inline(always)]
unsafe fn conductance<R: Real, V: Vector<R>>(
    hp: &HeatParams,
    a: &HeatArrays<R, V>,
    o: &HeatOwn<V>,
    q: &HeatPartner,
) -> (f64, f64, f64) {
    let mi = o.material;
    // One material: k_ij = k exactly (the harmonic mean would round it), without the second table load. [C2D]: the
    // receiver's k always.
    let kij = if q.body == o.body || hp.flags & heat_flags::C2D != 0 {
        mi.conductivity
    } else {
        let mj = unsafe { *a.materials.add(q.body as usize) };
        2.0 * mi.conductivity * mj.conductivity / (mi.conductivity + mj.conductivity)
    };
    (kij, q.vol, q.t)
}

/// Ṫ_i from the combined conduction sum: Σ / (ρ_i c_i) ([`heat_flags::C2D`]: ρ0 for a workpiece particle); 0 for
/// a particle with a fixed temperature.
///
/// # Safety
/// As [`heat_sum`].
#[inline(always)]
pub unsafe fn heat_finish<R: Real, V: Vector<R>>(hp: &HeatParams, a: &HeatArrays<R, V>, i: u32, sum: f64) -> f64 {
    match unsafe { heat_own(a, i) } {
        Some(o) => {
            let rho = if hp.flags & heat_flags::C2D != 0 && !o.tool {
                hp.rho0
            } else {
                unsafe { *a.rho.add(i as usize) }.to_f64()
            };
            sum / (rho * o.material.specific_heat)
        }
        None => 0.0,
    }
}

/// Ṫ_i from conduction, summed by `lanes` lanes combined as the GPU combines them (`sph::lanes`). Particles
/// flagged with a fixed temperature get Ṫ = 0.
///
/// # Safety
/// As [`heat_sum`].
#[inline(always)]
pub unsafe fn heat_rate<R: Real, V: Vector<R>, const PSE: bool>(
    hp: &HeatParams,
    k: &CubicSpline<R>,
    nb: &Neighbours,
    a: &HeatArrays<R, V>,
    i: u32,
    lanes: u32,
) -> f64 {
    unsafe {
        let sum = match heat_own(a, i) {
            Some(o) => all_lanes::<R, V, f64, _>(nb, &o.x, i, lanes, |j, s| {
                *s += heat_pair::<R, V, PSE>(hp, k, nb.grid, a, &o, i, j)
            }),
            None => 0.0,
        };
        heat_finish(hp, a, i, sum)
    }
}
