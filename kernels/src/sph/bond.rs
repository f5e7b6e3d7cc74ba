//! The cohesive path in SPH (nairn-mpm.md §7.2; docs/mpm.md "The cohesive path in SPH"): a predefined horizontal
//! cut plane whose two faces are joined by bonds, one per pair of particles that faced each other across the plane
//! at t = 0. Two couplings (`BondParams::coupling`):
//! - [`BONDS`]: each bond carries Nairn's cubic law (Eq. 3) with the decoupled failure criterion (Eq. 4) over its
//!   tributary area (`crate::cohesive`, the law the MPM's crack points use) from the start. Across the plane there is
//!   no continuum interaction (`interact::cut_apart`): until a bond fails its traction is the only coupling, and
//!   after it fails only the law's closing stiffness (crack-face contact) remains.
//! - [`CONTINUUM`]: the plane is continuum until the traction it carries at a bond, t = ½(σ_i + σ_j)·ŷ, reaches the
//!   strength ([`onset_reached`]); the bond's column then opens (`open_particle`: no continuum pair across it any
//!   more) and the bond takes over at the strength, softening linearly to zero over the opening that dissipates
//!   G_c (`cohesive::softening`; an extrinsic cohesive law, Camacho and Ortiz 1996; docs/mpm.md "Continuum until
//!   onset").
//!
//! A bond belongs to its particle above the plane (the owner), which holds its partner's id, the reference offset
//! X_owner − X_partner and the history; the owner's thread adds the bond's force to both particles' accelerations
//! after the pair interaction, so no particle is written by two threads (each has at most one bond). The ids map to
//! sorted indices through [`index_particle`], rerun each step before the bonds (the reorder moves the particles).

use super::params::flags;
use super::tensor::TensorOps;
use crate::cohesive::{Cohesive, CrackState, FAILED, MODE_I, softening, strength_ratio, traction};
use crate::real::Real;
use crate::vector::Vector;
use bytemuck::{Pod, Zeroable};

/// No bond (a particle that owns none).
pub const NONE: u32 = u32::MAX;

/// [`BondParams::coupling`]: the faces are joined by their bonds from t = 0 (Nairn's intrinsic law).
pub const BONDS: u32 = 0;
/// [`BondParams::coupling`]: the plane is continuum until the onset, then the bond softens linearly ([`softening`]).
pub const CONTINUUM: u32 = 1;

/// The cohesive path's constants.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BondParams {
    /// The laws of mode I (normal, along y) and mode II (sliding, along x).
    pub law: Cohesive,
    /// A bond's tributary area: Δx per unit depth in 2D [m], Δx² in 3D [m²].
    pub area: f64,
    /// The run's nominal time step Δt [s], which sets the bond's damper ([`damper`]).
    pub dt: f64,
    /// [`BONDS`] or [`CONTINUUM`].
    pub coupling: u32,
    pub _pad: u32,
}

/// A bond's history: the cohesive state (`cohesive::CrackState`: the largest openings, failed, mode-I share; under
/// [`CONTINUUM`] the largest normalised opening of [`softening`] in place of the openings) followed by the opening
/// (δ_t, δ_n) and tractions (t_t, t_n) of its last evaluation, for the work's trapezoid.
pub type BondState<R> = [R; 8];

/// A bond's onset under [`CONTINUUM`]: [`ONSET`] (0/1), the opening (δ_t, δ_n) it started from, and the work of its
/// normal traction since, per unit depth in 2D [J/m] (the mode-I share at failure).
pub type OnsetState<R> = [R; 4];

/// Index of the onset flag in an [`OnsetState`].
pub const ONSET: usize = 0;

/// The bond pass's arrays, in sorted order except `index` (by id).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct BondArrays<R: Real, D: TensorOps<R>> {
    /// Sorted index of each particle id ([`index_particle`]).
    pub index: *const u32,
    /// The partner's id of each bond's owner ([`NONE`] elsewhere).
    pub partner: *const u32,
    /// X_owner − X_partner at t = 0.
    pub reference: *const D::Vec<R>,
    pub state: *mut BondState<R>,
    pub onset: *mut OnsetState<R>,
    /// The work the bond's tractions have taken from the particles so far, per unit depth in 2D [J/m]: the energy
    /// the path has absorbed (released, once the bond has failed).
    pub work: *mut f64,
    /// The energy the bond's damper ([`damper`]) has dissipated so far [J/m in 2D].
    pub damping: *mut f64,
    pub pos: *const D::Vec<R>,
    pub vel: *const D::Vec<R>,
    pub mass: *const R,
    pub flags: *const u32,
    /// σ/ρ² and ρ of the pair interaction (the continuum's traction at the onset).
    pub sig: *const D::Sym<R>,
    pub rho: *const R,
    /// The accelerations of the pair interaction, to which the bonds' forces are added.
    pub vel_t: *mut D::Vec<R>,
}

/// Whether a particle of flags `fl` takes forces into its acceleration (free, or held in plane; not fixed, not
/// driven, not thermal-only).
#[inline(always)]
fn moves(fl: u32) -> bool {
    let kind = fl & flags::KIND_MASK;
    fl & flags::THERMAL_ONLY == 0 && (kind == flags::FREE || kind == flags::PLANE)
}

/// The largest ωΔt of a bond (ω = √(k/m_r), k its stiffest mode's initial stiffness times its area, m_r the
/// reduced mass of its two particles) the run's time step allows ([`damper`]; the set-up shortens Δt to it).
pub const MAX_OMEGA_DT: f64 = 0.7;

/// The damping coefficient c = k Δt [N s/m per m of depth in 2D] of a bond of stiffness k (the law's initial
/// stiffness times the area) at time step Δt: stiffness-proportional (Rayleigh) damping of ratio ζ = ωΔt/2. The
/// step's predictor–corrector (the predictor takes the last step's rates) amplifies an undamped oscillation of
/// ωΔt = 0.5 by 2.7 % a step, and a bond has no artificial viscosity across the plane to absorb it; with the damper
/// the amplification is below 1 up to ωΔt = 0.85 (0.85 a step at 0.5), and the force c δ̇ on an opening slower
/// than one step's, k Δt δ̇ ≪ k δ, vanishes as Δt is refined (docs/mpm.md "The cohesive path in SPH").
#[inline(always)]
pub fn damper<R: Real>(k: R, dt: R) -> R {
    k * dt
}

/// The bond owned by sorted particle i, if any: its opening δ = (x_i − x_j) − (X_i − X_j) split into sliding
/// δ_t (x) and opening δ_n (y), the law's tractions (history updated), the force F = −(t_t, t_n) A on the owner
/// (above) and −F on the partner added to their accelerations, and the work Δw = A ½ (t_old + t_new)·(δ_new − δ_old)
/// added to the bond's tally. While the bond holds, its damper ([`damper`]) resists the relative velocity in both
/// directions; once failed, in the normal direction while the faces close (the law's closing stiffness); the
/// damper's power c |Δv|² Δt is tallied apart. The law: `cohesive::traction` under [`BONDS`]; under [`CONTINUUM`]
/// nothing until the onset ([`onset_reached`]: the continuum carried the step), `cohesive::softening` after it.
///
/// # Safety
/// i < the sorted particle count; every array holds the sorted particles (`index` every id), and the partner of
/// a bond owns none.
#[inline(always)]
pub unsafe fn bond_particle<R: Real, D: TensorOps<R>>(p: &BondParams, a: &BondArrays<R, D>, i: usize) {
    unsafe {
        let pid = *a.partner.add(i);
        if pid == NONE {
            return;
        }
        let j = *a.index.add(pid as usize) as usize;
        let (xi, xj, x0) = (*a.pos.add(i), *a.pos.add(j), *a.reference.add(i));
        let st = &mut *a.state.add(i);
        let slide = xi.get(0) - xj.get(0) - x0.get(0);
        let open = xi.get(1) - xj.get(1) - x0.get(1);
        let area = R::from_f64(p.area);
        let half = R::from_f64(0.5);
        let was_failed = st[FAILED] != R::ZERO;
        let mut crack: CrackState<R> = [st[0], st[1], st[2], st[3]];
        let (tt, tn) = if p.coupling == CONTINUUM {
            let on = &mut *a.onset.add(i);
            if on[ONSET] == R::ZERO {
                if onset_reached(&p.law, a, i, j) {
                    // The bond's force this step is nil (the continuum carried it): its work's trapezoid starts
                    // from zero traction at the onset opening.
                    *on = [R::ONE, slide, open, R::ZERO];
                    *st = [R::ZERO, R::ZERO, R::ZERO, R::ZERO, slide, open, R::ZERO, R::ZERO];
                }
                return;
            }
            let t = softening(&p.law, &mut crack, slide - on[1], open - on[2]);
            on[3] += half * (st[7] + t.1) * (open - st[5]) * area;
            t
        } else {
            traction(&p.law, &mut crack, slide, open)
        };
        st[..4].copy_from_slice(&crack);
        let dw = half * ((st[6] + tt) * (slide - st[4]) + (st[7] + tn) * (open - st[5])) * area;
        let work = &mut *a.work.add(i);
        *work += dw.to_f64();
        if p.coupling == CONTINUUM && !was_failed && st[FAILED] != R::ZERO {
            // The mode-I share of the work since the onset (`cohesive::traction` takes it from the law's energies).
            let share = if *work > 0.0 { (*a.onset.add(i))[3].to_f64() / *work } else { 0.0 };
            st[MODE_I] = R::from_f64(share);
        }
        st[4] = slide;
        st[5] = open;
        st[6] = tt;
        st[7] = tn;
        let held = st[FAILED] == R::ZERO;
        let dt_step = R::from_f64(p.dt);
        let cn = if held || open < R::ZERO { damper(p.law.mode1.stiffness::<R>() * area, dt_step) } else { R::ZERO };
        let ct = if held { damper(p.law.mode2.stiffness::<R>() * area, dt_step) } else { R::ZERO };
        let (vi, vj) = (*a.vel.add(i), *a.vel.add(j));
        let (ut, un) = (vi.get(0) - vj.get(0), vi.get(1) - vj.get(1));
        *a.damping.add(i) += ((ct * ut * ut + cn * un * un) * dt_step).to_f64();
        let f = D::Vec::<R>::new([-tt * area - ct * ut, -tn * area - cn * un, R::ZERO]);
        if moves(*a.flags.add(i)) {
            let acc = &mut *a.vel_t.add(i);
            let inv = R::ONE / *a.mass.add(i);
            *acc = D::Vec::<R>::new([acc.get(0) + f.get(0) * inv, acc.get(1) + f.get(1) * inv, acc.get(2)]);
        }
        if moves(*a.flags.add(j)) {
            let acc = &mut *a.vel_t.add(j);
            let inv = R::ONE / *a.mass.add(j);
            *acc = D::Vec::<R>::new([acc.get(0) - f.get(0) * inv, acc.get(1) - f.get(1) * inv, acc.get(2)]);
        }
    }
}

/// Whether the [`CONTINUUM`] bond of owner i and partner j has reached its onset: the traction the continuum carries
/// across the plane there, t = ½(σ_i + σ_j)·ŷ = (t_t, t_n) (σ = ρ² (σ/ρ²) of the pair interaction), has a strength
/// ratio λ ≥ 1 (`cohesive::strength_ratio`).
///
/// # Safety
/// i, j < the sorted particle count.
#[inline(always)]
unsafe fn onset_reached<R: Real, D: TensorOps<R>>(law: &Cohesive, a: &BondArrays<R, D>, i: usize, j: usize) -> bool {
    let (ri, rj) = unsafe { (*a.rho.add(i), *a.rho.add(j)) };
    let y = D::Vec::<R>::new([R::ZERO, R::ONE, R::ZERO]);
    let (ti, tj) = unsafe { (D::sym_apply(&*a.sig.add(i), &y), D::sym_apply(&*a.sig.add(j), &y)) };
    let half = R::from_f64(0.5);
    let tt = half * (ti.get(0) * ri * ri + tj.get(0) * rj * rj);
    let tn = half * (ti.get(1) * ri * ri + tj.get(1) * rj * rj);
    strength_ratio(law, tt, tn) >= R::ONE
}

/// Opens sorted particle i (`flags::OPEN`: no continuum pair across the path any more) once the bond of its column
/// (`column`: the owner's id; [`NONE`] for a particle that belongs to none) has passed its onset. Run after the bond
/// pass: only i's flags are written, from the owner's onset state.
///
/// # Safety
/// i < the sorted particle count; `index` holds every id.
#[inline(always)]
pub unsafe fn open_particle<R: Real>(
    index: *const u32,
    column: *const u32,
    onset: *const OnsetState<R>,
    fl: *mut u32,
    i: usize,
) {
    unsafe {
        let c = *column.add(i);
        if c == NONE {
            return;
        }
        let owner = *index.add(c as usize) as usize;
        if (*onset.add(owner))[ONSET] != R::ZERO {
            *fl.add(i) |= flags::OPEN;
        }
    }
}

/// index[id_i] = i for sorted particle i.
///
/// # Safety
/// i < the sorted particle count; `index` holds every id.
#[inline(always)]
pub unsafe fn index_particle(id: *const u32, index: *mut u32, i: usize) {
    unsafe { *index.add(*id.add(i) as usize) = i as u32 };
}
