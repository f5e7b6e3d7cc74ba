//! Penalty contact with the rigid tool and LS-DYNA incremental stick/slip friction (roethlin-solver.md §5.4 (5.116),
//! (5.129–5.130) with the relative-velocity fix of errata 25; klippel-constitutive.md §1.3 (4.45–4.48), the
//! shear-stress limit (9.21–9.22) and §7.5.1.3 (7.6)/(7.7)), run once per step after the corrector and the
//! plastic update (roethlin §5.2 steps 12, 15). The forces act on the workpiece in the next step's momentum
//! balance as v̇ += (f_c + f_t)/m.
//!
//! For a particle of mass m at penetration depth d = −g_N > 0 with outward tool normal n:
//!   normal force    f_c = κ m d n / Δt²                      (removes the fraction κ of the penetration per step)
//!   trial friction  f*  = P_t f_t,old − κ_t m v_t / Δt,        v_t = (v − v_tool) − ((v − v_tool)·n) n
//!   friction        f_t = f* if |f*| ≤ F_max, else F_max f*/|f*|,  F_max = min(μ |f_c|, τ_max A)
//! with P_t the projection onto the current tangent (the normal turns along the edge arc), τ_max = κ_fric σ_y/√3
//! (the optional shear-stress cap; σ_y static A or current), A the particle's face per unit depth, √(m/ρ) in 2D, and
//! κ_t the friction stiffness (κ in Röthlin's code, 1 in the theses' equations).
//! Without penetration both forces and the friction history are zero.
//!
//! Friction heat ΔT = η Δt |f_t| |v_t| / (m c_p) (Δt: this step's length) goes to the workpiece particle (roethlin §5.2 step 12). The
//! Usui wear rate Ẇ = Ψ exp(−ξ/T) p |v_t| with p = |f_c|/A is an optional output; the theses print exp(+ξ/T),
//! Usui's law has the minus sign (roethlin erratum 16).

use super::tool2d::Tool2d;
use crate::real::Real;
use crate::sph::params::flags;
use crate::vector::Vector;
use bytemuck::{Pod, Zeroable};

/// How the friction force is capped beyond Coulomb.
pub mod cap {
    /// Coulomb only.
    pub const NONE: u32 = 0;
    /// τ_max from a fixed yield stress (the static yield A of (7.6)).
    pub const STATIC: u32 = 1;
    /// τ_max from each particle's current yield stress (7.7), (9.21).
    pub const CURRENT: u32 = 2;
}

/// Constants of the contact pass (uploaded once; the tool's position and velocity are launch arguments).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ContactParams {
    pub tool: Tool2d,
    /// Penalty fraction κ (0 < κ ≤ 1).
    pub kappa: f64,
    /// Stiffness fraction κ_t of the friction update f* = f_old − κ_t m v_t/Δt: Röthlin's code uses κ_t = κ,
    /// Klippel's (4.47) and Röthlin's thesis (5.129) write m/Δt, i.e. κ_t = 1.
    pub friction_kappa: f64,
    /// Coulomb coefficient μ.
    pub friction: f64,
    /// κ_fric/√3 · σ_y of the STATIC cap, or κ_fric/√3 for the CURRENT cap (multiplied by each particle's σ_y).
    pub cap_stress: f64,
    /// Fraction η of the friction work that heats the workpiece (0: no friction heating).
    pub heat_fraction: f64,
    /// Usui Ψ [1/Pa] and ξ [K] (Ψ = 0: no wear output).
    pub usui_psi: f64,
    pub usui_xi: f64,
    /// Temperature cap of friction heating (the workpiece's melt temperature; infinity without one) [K].
    pub melt: f64,
    /// `cap::NONE`, `cap::STATIC` or `cap::CURRENT`.
    pub cap_mode: u32,
    pub _pad: u32,
}

/// Where the tool is at the end of the step (the frame translation of [`Tool2d`]) and how fast it moves.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ToolState {
    pub offset: [f64; 2],
    pub velocity: [f64; 2],
    /// The run's time step Δt, which scales the penalty and friction stiffness (κ m/Δt², κ m/Δt). A step cut short
    /// to land on an output time must not stiffen the contact by (Δt/step)², so this is the nominal step.
    pub dt: f64,
    /// The length of this step, for the friction heat.
    pub step: f64,
}

/// The LS-DYNA incremental stick/slip update (4.47–4.48): the trial force f* = f_old − k v_t (k = κ m/Δt) sticks
/// when |f*| ≤ f_max and slides at f_max along f* otherwise.
#[inline(always)]
pub fn friction_update(f_old: [f64; 2], v_t: [f64; 2], k: f64, f_max: f64) -> [f64; 2] {
    let fs = [f_old[0] - k * v_t[0], f_old[1] - k * v_t[1]];
    let m2 = fs[0] * fs[0] + fs[1] * fs[1];
    if m2 <= f_max * f_max {
        fs
    } else {
        let s = f_max / <f64 as Real>::sqrt(m2);
        [s * fs[0], s * fs[1]]
    }
}

/// Contact forces and their by-products for one particle.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactResult {
    pub normal: [f64; 2],
    pub friction: [f64; 2],
    /// Temperature rise from friction [K].
    pub heating: f64,
    /// Usui wear rate [m/s] (0 without contact or with wear off).
    pub wear: f64,
}

/// The contact of one particle at position `x` and velocity `v`, with the friction history `f_old`, mass `m`,
/// density `rho`, temperature `temp`, specific heat `cp` and current yield stress `yield_stress` (used by the
/// CURRENT cap only).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn contact_force(
    c: &ContactParams,
    s: &ToolState,
    x: [f64; 2],
    v: [f64; 2],
    f_old: [f64; 2],
    m: f64,
    rho: f64,
    temp: f64,
    cp: f64,
    yield_stress: f64,
) -> ContactResult {
    let q = c.tool.closest([x[0] - s.offset[0], x[1] - s.offset[1]]);
    // Outside, on the outline, or NaN: no contact.
    if q.distance.partial_cmp(&0.0) != Some(core::cmp::Ordering::Less) {
        return ContactResult::default();
    }
    let n = q.normal;
    let dt = s.dt;
    let depth = -q.distance;
    let fc = c.kappa * m * depth / (dt * dt);
    let normal = [fc * n[0], fc * n[1]];
    let vr = [v[0] - s.velocity[0], v[1] - s.velocity[1]];
    let vn = vr[0] * n[0] + vr[1] * n[1];
    let vt = [vr[0] - vn * n[0], vr[1] - vn * n[1]];
    let on = f_old[0] * n[0] + f_old[1] * n[1];
    let f_prev = [f_old[0] - on * n[0], f_old[1] - on * n[1]];
    let area = <f64 as Real>::sqrt(m / rho);
    let mut f_max = c.friction * fc;
    if c.cap_mode != cap::NONE {
        let tau = if c.cap_mode == cap::CURRENT { c.cap_stress * yield_stress } else { c.cap_stress };
        let lim = tau * area;
        if lim < f_max {
            f_max = lim;
        }
    }
    let friction = friction_update(f_prev, vt, c.friction_kappa * m / dt, f_max);
    let ft = <f64 as Real>::sqrt(friction[0] * friction[0] + friction[1] * friction[1]);
    let slip = <f64 as Real>::sqrt(vt[0] * vt[0] + vt[1] * vt[1]);
    let heating = if c.heat_fraction > 0.0 && cp > 0.0 { c.heat_fraction * s.step * ft * slip / (m * cp) } else { 0.0 };
    let wear = if c.usui_psi > 0.0 && temp > 0.0 {
        c.usui_psi * libm::exp(-c.usui_xi / temp) * (fc / area) * slip
    } else {
        0.0
    };
    ContactResult { normal, friction, heating, wear }
}

/// Per-particle arrays of the contact pass (sorted order). Optional arrays are null when their physics is off.
#[derive(Clone, Copy)]
pub struct ContactArrays<R: Real, V> {
    pub pos: *const V,
    pub vel: *const V,
    /// The particles' own masses (not the mechanical masses, which are zero for thermal-only tool particles).
    pub mass: *const R,
    pub rho: *const R,
    pub flags: *const u32,
    pub normal: *mut V,
    pub friction: *mut V,
    /// Temperature (heated by friction; read by the wear law); null without a temperature field.
    pub temp: *mut f64,
    /// Specific heat by body (`ThermalMaterial`); null without friction heating.
    pub materials: *const crate::sph::heat::ThermalMaterial,
    /// Current yield stress per particle (the CURRENT cap); null otherwise.
    pub yield_stress: *const f64,
    /// Wear rate output; null when wear is off.
    pub wear: *mut f64,
}

/// The contact pass for sorted particle i: writes its normal and friction forces, heats it and records its wear
/// rate. Fixed and thermal-only particles carry no contact force.
///
/// # Safety
/// All non-null arrays hold at least i + 1 particles; `materials` covers every body index.
#[inline(always)]
pub unsafe fn contact_particle<R: Real, V: Vector<R>>(
    c: &ContactParams,
    s: &ToolState,
    a: &ContactArrays<R, V>,
    i: usize,
) {
    unsafe {
        let fl = *a.flags.add(i);
        let kind = fl & flags::KIND_MASK;
        if kind == flags::FIXED || fl & flags::THERMAL_ONLY != 0 {
            *a.normal.add(i) = V::default();
            *a.friction.add(i) = V::default();
            if !a.wear.is_null() {
                *a.wear.add(i) = 0.0;
            }
            return;
        }
        let (x, v, f) = (*a.pos.add(i), *a.vel.add(i), *a.friction.add(i));
        let temp = if a.temp.is_null() { 0.0 } else { *a.temp.add(i) };
        let cp = if a.materials.is_null() {
            0.0
        } else {
            (*a.materials.add((fl >> flags::BODY_SHIFT) as usize)).specific_heat
        };
        let sy = if a.yield_stress.is_null() { 0.0 } else { *a.yield_stress.add(i) };
        let r = contact_force(
            c,
            s,
            [x.get(0).to_f64(), x.get(1).to_f64()],
            [v.get(0).to_f64(), v.get(1).to_f64()],
            [f.get(0).to_f64(), f.get(1).to_f64()],
            (*a.mass.add(i)).to_f64(),
            (*a.rho.add(i)).to_f64(),
            temp,
            cp,
            sy,
        );
        *a.normal.add(i) = V::new([R::from_f64(r.normal[0]), R::from_f64(r.normal[1]), R::ZERO]);
        *a.friction.add(i) = V::new([R::from_f64(r.friction[0]), R::from_f64(r.friction[1]), R::ZERO]);
        if r.heating > 0.0 && !a.temp.is_null() && fl & flags::FIXED_TEMPERATURE == 0 {
            *a.temp.add(i) = crate::material::heated_temperature(temp, r.heating, c.melt);
        }
        if !a.wear.is_null() {
            *a.wear.add(i) = r.wear;
        }
    }
}
