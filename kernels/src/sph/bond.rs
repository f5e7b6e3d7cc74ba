//! The cohesive path in SPH (nairn-mpm.md §7.2; docs/mpm.md "The cohesive path in SPH"): a predefined horizontal
//! cut plane whose two faces are joined by bonds, one per pair of particles that faced each other across the plane
//! at t = 0, each carrying Nairn's cubic law (Eq. 3) with the decoupled failure criterion (Eq. 4) over its
//! tributary area (`crate::cohesive`, the law the MPM's crack points use). Across the plane there is no continuum
//! interaction (`interact::cut_apart`): until a bond fails its traction is the only coupling, and after it fails
//! only the law's closing stiffness (crack-face contact) remains.
//!
//! A bond belongs to its particle above the plane (the owner), which holds its partner's id, the reference offset
//! X_owner − X_partner and the history; the owner's thread adds the bond's force to both particles' accelerations
//! after the pair interaction, so no particle is written by two threads (each has at most one bond). The ids map to
//! sorted indices through [`index_particle`], rerun each step before the bonds (the reorder moves the particles).

use super::params::flags;
use crate::cohesive::{Cohesive, CrackState, traction};
use crate::real::Real;
use crate::vector::Vector;
use bytemuck::{Pod, Zeroable};

/// No bond (a particle that owns none).
pub const NONE: u32 = u32::MAX;

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
}

/// A bond's history: the cohesive state (`cohesive::CrackState`: the largest openings, failed, mode-I share)
/// followed by the opening (δ_t, δ_n) and tractions (t_t, t_n) of its last evaluation, for the work's trapezoid.
pub type BondState<R> = [R; 8];

/// The bond pass's arrays, in sorted order except `index` (by id).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct BondArrays<R: Real, V> {
    /// Sorted index of each particle id ([`index_particle`]).
    pub index: *const u32,
    /// The partner's id of each bond's owner ([`NONE`] elsewhere).
    pub partner: *const u32,
    /// X_owner − X_partner at t = 0.
    pub reference: *const V,
    pub state: *mut BondState<R>,
    /// The work the bond's tractions have taken from the particles so far, per unit depth in 2D [J/m]: the energy
    /// the path has absorbed (released, once the bond has failed).
    pub work: *mut f64,
    /// The energy the bond's damper ([`damper`]) has dissipated so far [J/m in 2D].
    pub damping: *mut f64,
    pub pos: *const V,
    pub vel: *const V,
    pub mass: *const R,
    pub flags: *const u32,
    /// The accelerations of the pair interaction, to which the bonds' forces are added.
    pub vel_t: *mut V,
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
/// δ_t (x) and opening δ_n (y), the law's tractions (`cohesive::traction`, history updated), the force
/// F = −(t_t, t_n) A on the owner (above) and −F on the partner added to their accelerations, and the work
/// Δw = A ½ (t_old + t_new)·(δ_new − δ_old) added to the bond's tally. While the bond holds, its damper ([`damper`])
/// resists the relative velocity in both directions; once failed, in the normal direction while the faces close
/// (the law's closing stiffness); the damper's power c |Δv|² Δt is tallied apart.
///
/// # Safety
/// i < the sorted particle count; every array holds the sorted particles (`index` every id), and the partner of
/// a bond owns none.
#[inline(always)]
pub unsafe fn bond_particle<R: Real, V: Vector<R>>(p: &BondParams, a: &BondArrays<R, V>, i: usize) {
    unsafe {
        let pid = *a.partner.add(i);
        if pid == NONE {
            return;
        }
        let j = *a.index.add(pid as usize) as usize;
        let (xi, xj, x0) = (*a.pos.add(i), *a.pos.add(j), *a.reference.add(i));
        let (vi, vj) = (*a.vel.add(i), *a.vel.add(j));
        let st = &mut *a.state.add(i);
        let slide = xi.get(0) - xj.get(0) - x0.get(0);
        let open = xi.get(1) - xj.get(1) - x0.get(1);
        let mut crack: CrackState<R> = [st[0], st[1], st[2], st[3]];
        let (tt, tn) = traction(&p.law, &mut crack, slide, open);
        let area = R::from_f64(p.area);
        let half = R::from_f64(0.5);
        let dw = half * ((st[6] + tt) * (slide - st[4]) + (st[7] + tn) * (open - st[5])) * area;
        *a.work.add(i) += dw.to_f64();
        *st = [crack[0], crack[1], crack[2], crack[3], slide, open, tt, tn];
        let held = crack[crate::cohesive::FAILED] == R::ZERO;
        let dt_step = R::from_f64(p.dt);
        let cn = if held || open < R::ZERO { damper(p.law.mode1.stiffness::<R>() * area, dt_step) } else { R::ZERO };
        let ct = if held { damper(p.law.mode2.stiffness::<R>() * area, dt_step) } else { R::ZERO };
        let (ut, un) = (vi.get(0) - vj.get(0), vi.get(1) - vj.get(1));
        *a.damping.add(i) += ((ct * ut * ut + cn * un * un) * dt_step).to_f64();
        let f = V::new([-tt * area - ct * ut, -tn * area - cn * un, R::ZERO]);
        if moves(*a.flags.add(i)) {
            let acc = &mut *a.vel_t.add(i);
            let inv = R::ONE / *a.mass.add(i);
            *acc = V::new([acc.get(0) + f.get(0) * inv, acc.get(1) + f.get(1) * inv, acc.get(2)]);
        }
        if moves(*a.flags.add(j)) {
            let acc = &mut *a.vel_t.add(j);
            let inv = R::ONE / *a.mass.add(j);
            *acc = V::new([acc.get(0) - f.get(0) * inv, acc.get(1) - f.get(1) * inv, acc.get(2)]);
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
