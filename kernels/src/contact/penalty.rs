//! Penalty contact with the rigid tool and LS-DYNA incremental stick/slip friction (roethlin-solver.md §5.4 (5.116),
//! (5.129–5.130) with the relative-velocity fix of errata 25; klippel-constitutive.md §1.3 (4.45–4.48), the
//! shear-stress limit (9.21–9.22) and §7.5.1.3 (7.6)/(7.7)), run once per step after the corrector and the
//! plastic update (roethlin §5.2 steps 12, 15). The forces act on the workpiece in the next step's momentum
//! balance as v̇ += (f_c + f_t)/m.
//!
//! For a particle of mass m at penetration depth d = −g_N > 0 with outward tool normal n, the penalty spring k_n
//! and the friction's stick stiffness k_v (per unit slip velocity) come from one of two laws (`law`):
//!   STEP  k_n = κ m/Δt²,        k_v = κ_t m/Δt       (Nianfei (5.116): removes the fraction κ of the penetration
//!                                                    per step; the theses' codes, Δt the nominal step)
//!   BULK  k_n = κ K A²/V,       k_v = κ_t K A²/V Δt  (LS-DYNA (5.117): a spring of the workpiece's bulk modulus K,
//!                                                    A²/V = 1 per unit depth in 2D, V^(1/3) in 3D; independent
//!                                                    of Δt: k_v/Δt = κ_t K A²/V is the stick stiffness per unit
//!                                                    slip, Δt this step's length)
//! and then
//!   normal force    f_c = max(0, k_n d − c v_n) n,  c = 2ξ √(k_n m),  v_n = (v − v_tool)·n   (ξ: the fraction
//!                                                    of critical damping of the penalty spring; 0: undamped)
//!   trial friction  f*  = P_t f_t,old − k_v v_t,      v_t = (v − v_tool) − ((v − v_tool)·n) n
//!   friction        f_t = f* if |f*| ≤ F_max, else F_max f*/|f*|,  F_max = min(μ |f_c|, τ_max A)
//! with P_t the projection onto the current tangent (the normal turns along the edge arc), τ_max = κ_fric σ_y/√3
//! (the optional shear-stress cap; σ_y static A or current), A the particle's face per unit depth, √(m/ρ) in 2D ((m/ρ)^(2/3) in 3D), and
//! κ_t the friction stiffness (κ in Röthlin's code, 1 in the theses' equations).
//! Without penetration both forces and the friction history are zero.
//!
//! Friction heat ΔT = η Δt |f_t| |v_t| / (m c_p) (Δt: this step's length) goes to the workpiece particle (roethlin §5.2 step 12). The
//! Usui wear rate Ẇ = Ψ exp(−ξ/T) p |v_t| with p = |f_c|/A is an optional output; the theses print exp(+ξ/T),
//! Usui's law has the minus sign (roethlin erratum 16).

use super::geometry::{ToolArg, ToolGeometry};
use super::motion::ToolState;
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

/// How the penalty and friction stiffnesses are set (module docs).
pub mod law {
    /// κ m/Δt² and κ_t m/Δt (the theses' codes).
    pub const STEP: u32 = 0;
    /// κ K A²/V and κ_t K A²/V Δt (LS-DYNA's penalty, independent of the time step).
    pub const BULK: u32 = 1;
}

/// Constants of the contact law (uploaded once; the tool's shape is its own parameter, a [`ToolGeometry`], and its
/// position and velocity are the step's [`ToolState`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ContactParams {
    /// Penalty fraction κ (0 < κ ≤ 1).
    pub kappa: f64,
    /// Stiffness fraction κ_t of the friction update (`law::STEP`: f* = f_old − κ_t m v_t/Δt; `law::BULK`: the
    /// fraction of K A²/V per unit slip): Röthlin's code uses κ_t = κ,
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
    /// Fraction ξ of critical damping of the normal penalty spring, c = 2ξ√(k_n m) (0: undamped).
    pub damping: f64,
    /// The workpiece's bulk modulus K [Pa] (`law::BULK`).
    pub bulk: f64,
    /// `cap::NONE`, `cap::STATIC` or `cap::CURRENT`.
    pub cap_mode: u32,
    /// `law::STEP` or `law::BULK`.
    pub law: u32,
    /// `slip::PROJECTED` (swarf's) or `slip::C2D` (the original code's, `model = "mfree_iwf"`).
    pub slip_mode: u32,
    /// Keeps the struct a multiple of 8 bytes (Pod: no implicit padding).
    pub _pad: u32,
}

/// How the sliding velocity and the friction history are taken (`ContactParams::slip_mode`).
pub mod slip {
    /// v_t = v_r − (v_r·n) n, the history projected on the current tangent (the module doc).
    pub const PROJECTED: u32 = 0;
    /// Röthlin's 2D code [C2D] (`tool_gpu.cu`, `actions_gpu.cu`), reproduced for `model = "mfree_iwf"`: the friction's
    /// v_t = v_r − v_r∘n with GLM's componentwise product, (v_x(1 − n_x), v_y(1 − n_y)) (**a bug**, roethlin-solver.md
    /// §11 erratum 25: right only on faces normal to an axis), the history f_old not projected, and the friction
    /// heat's sliding speed |(v_x − v_r·n, v_y − v_r·n)| (**another bug** of the same code: the scalar v_r·n
    /// subtracted from each component).
    pub const C2D: u32 = 1;
}

/// a·b over the first D components, summed in index order (a₀b₀ + a₁b₁ in 2D).
#[inline(always)]
fn dot<const D: usize>(a: &[f64; D], b: &[f64; D]) -> f64 {
    let mut s = a[0] * b[0];
    let mut k = 1;
    while k < D {
        s += a[k] * b[k];
        k += 1;
    }
    s
}

/// The first D components of a 3-vector.
#[inline(always)]
fn narrow<const D: usize>(a: [f64; 3]) -> [f64; D] {
    let mut r = [0.0; D];
    let mut k = 0;
    while k < D {
        r[k] = a[k];
        k += 1;
    }
    r
}

/// A D-vector as a 3-vector (z = 0 in 2D).
#[inline(always)]
fn widen<const D: usize>(a: &[f64; D]) -> [f64; 3] {
    let mut r = [0.0; 3];
    let mut k = 0;
    while k < D {
        r[k] = a[k];
        k += 1;
    }
    r
}

/// The LS-DYNA incremental stick/slip update (4.47–4.48): the trial force f* = f_old − k v_t (k = κ m/Δt) sticks
/// when |f*| ≤ f_max and slides at f_max along f* otherwise.
#[inline(always)]
pub fn friction_update<const D: usize>(f_old: [f64; D], v_t: [f64; D], k: f64, f_max: f64) -> [f64; D] {
    let mut fs = [0.0; D];
    let mut j = 0;
    while j < D {
        fs[j] = f_old[j] - k * v_t[j];
        j += 1;
    }
    let m2 = dot(&fs, &fs);
    if m2 <= f_max * f_max {
        fs
    } else {
        let s = f_max / <f64 as Real>::sqrt(m2);
        let mut out = [0.0; D];
        let mut j = 0;
        while j < D {
            out[j] = s * fs[j];
            j += 1;
        }
        out
    }
}

/// The friction heat's sliding speed in [C2D] (`slip::C2D`): |v_r − (v_r·n)(1, …, 1)|, the scalar subtracted from
/// every component.
#[inline(always)]
fn c2d_heat_slip<const D: usize>(vr: &[f64; D], vn: f64) -> f64 {
    let mut v = [0.0; D];
    let mut k = 0;
    while k < D {
        v[k] = vr[k] - vn;
        k += 1;
    }
    <f64 as Real>::sqrt(dot(&v, &v))
}

/// Contact forces and their by-products for one particle (D components: 2 or 3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactResult<const D: usize> {
    pub normal: [f64; D],
    pub friction: [f64; D],
    /// Temperature rise from friction [K].
    pub heating: f64,
    /// Usui wear rate [m/s] (0 without contact or with wear off).
    pub wear: f64,
    /// The particle lies inside the tool (the forces may still be zero: a damper that would pull it in).
    pub touching: bool,
}

impl<const D: usize> Default for ContactResult<D> {
    #[inline(always)]
    fn default() -> Self {
        ContactResult { normal: [0.0; D], friction: [0.0; D], heating: 0.0, wear: 0.0, touching: false }
    }
}

/// The contact of one particle at world position `x` and velocity `v` (D components: 2 or 3), with the friction
/// history `f_old`, mass `m`, density `rho`, temperature `temp`, specific heat `cp` and current yield stress
/// `yield_stress` (used by the CURRENT cap only), against the tool of shape `g` in the motion `s`. The particle is
/// mapped into the tool's frame ([`ToolState::to_tool`]), the normal back into the world's, and the relative
/// velocity is taken against the tool's material velocity at the particle ([`ToolState::velocity_at`]).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn contact_force<const D: usize, G: ToolGeometry>(
    c: &ContactParams,
    g: &G,
    s: &ToolState,
    x: [f64; D],
    v: [f64; D],
    f_old: [f64; D],
    m: f64,
    rho: f64,
    temp: f64,
    cp: f64,
    yield_stress: f64,
) -> ContactResult<D> {
    let xw = widen(&x);
    let q = g.query(s.to_tool(xw));
    // Outside, on the outline, or NaN: no contact.
    if q.distance.partial_cmp(&0.0) != Some(core::cmp::Ordering::Less) {
        return ContactResult::default();
    }
    let n: [f64; D] = narrow(s.direction_to_world(q.normal));
    let v_tool: [f64; D] = narrow(s.velocity_at(xw));
    let dt = s.dt;
    let depth = -q.distance;
    let mut vr = [0.0; D];
    let mut k = 0;
    while k < D {
        vr[k] = v[k] - v_tool[k];
        k += 1;
    }
    let vn = dot(&vr, &n);
    // The spring k_n, the penalty force k_n d and the friction's k_v (STEP keeps the theses' expressions as they
    // were written, bit for bit).
    let (k_n, mut fc, k_v) = if c.law == law::BULK {
        let geo = if D == 2 { 1.0 } else { libm::cbrt(m / rho) };
        let k_n = c.kappa * c.bulk * geo;
        (k_n, k_n * depth, c.friction_kappa * c.bulk * geo * s.step)
    } else {
        (c.kappa * m / (dt * dt), c.kappa * m * depth / (dt * dt), c.friction_kappa * m / dt)
    };
    if c.damping > 0.0 {
        // A dashpot in parallel with the spring; it may push out harder but never pull the particle in.
        fc -= 2.0 * c.damping * <f64 as Real>::sqrt(k_n * m) * vn;
        if fc.partial_cmp(&0.0) != Some(core::cmp::Ordering::Greater) {
            fc = 0.0;
        }
    }
    let mut normal = [0.0; D];
    let mut k = 0;
    while k < D {
        normal[k] = fc * n[k];
        k += 1;
    }
    let on = dot(&f_old, &n);
    let mut vt = [0.0; D];
    let mut f_prev = [0.0; D];
    let c2d = c.slip_mode == slip::C2D;
    let mut k = 0;
    while k < D {
        vt[k] = if c2d { vr[k] - vr[k] * n[k] } else { vr[k] - vn * n[k] };
        f_prev[k] = if c2d { f_old[k] } else { f_old[k] - on * n[k] };
        k += 1;
    }
    // The particle's face: √V per unit depth in 2D, V^(2/3) in 3D.
    let area = if D == 2 {
        <f64 as Real>::sqrt(m / rho)
    } else {
        let l = libm::cbrt(m / rho);
        l * l
    };
    let mut f_max = c.friction * fc;
    if c.cap_mode != cap::NONE {
        let tau = if c.cap_mode == cap::CURRENT { c.cap_stress * yield_stress } else { c.cap_stress };
        let lim = tau * area;
        if lim < f_max {
            f_max = lim;
        }
    }
    let friction = friction_update(f_prev, vt, k_v, f_max);
    let ft = <f64 as Real>::sqrt(dot(&friction, &friction));
    let slip = <f64 as Real>::sqrt(dot(&vt, &vt));
    let heat_slip = if c2d { c2d_heat_slip(&vr, vn) } else { slip };
    let heating =
        if c.heat_fraction > 0.0 && cp > 0.0 { c.heat_fraction * s.step * ft * heat_slip / (m * cp) } else { 0.0 };
    let wear = if c.usui_psi > 0.0 && temp > 0.0 {
        c.usui_psi * libm::exp(-c.usui_xi / temp) * (fc / area) * slip
    } else {
        0.0
    };
    ContactResult { normal, friction, heating, wear, touching: true }
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

/// The tools of a contact pass: `count` ≥ 1 rigid tools, tool k with its law's constants `params[k]`, its shape
/// `tools.geometry(k)` and its motion this step `states[k]`. `owner` (null with one tool) holds, per particle, the
/// tool its friction history `friction` belongs to: the last tool it touched.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct ToolSet<T> {
    pub tools: T,
    pub params: *const ContactParams,
    pub states: *const ToolState,
    pub owner: *mut u32,
    pub count: u32,
    pub _pad: u32,
}

/// The contact pass for sorted particle i against the tools of `set`: writes its normal and friction forces, heats
/// it and records its wear rate. Fixed and thermal-only particles carry no contact force. With several tools the
/// first tool (in the scene's order) the particle lies inside takes it, with the friction history if it owned it,
/// else none (rigid tools do not overlap where particles are; a particle between two tools at once is pushed by
/// the first); one tool gives the bits of a single-tool pass.
///
/// # Safety
/// All non-null arrays hold at least i + 1 particles; `materials` covers every body index; `set`'s arrays hold
/// `count` entries.
#[inline(always)]
pub unsafe fn contact_particle<R: Real, V: Vector<R>, T: ToolArg>(set: &ToolSet<T>, a: &ContactArrays<R, V>, i: usize) {
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
        let temp = if a.temp.is_null() { 0.0 } else { *a.temp.add(i) };
        let cp = if a.materials.is_null() {
            0.0
        } else {
            (*a.materials.add((fl >> flags::BODY_SHIFT) as usize)).specific_heat
        };
        let sy = if a.yield_stress.is_null() { 0.0 } else { *a.yield_stress.add(i) };
        let p = ParticleIn { m: (*a.mass.add(i)).to_f64(), rho: (*a.rho.add(i)).to_f64(), temp, cp, sy };
        let (heating, wear, melt) = if V::DIM == 2 {
            particle_tools::<R, V, T, 2>(set, a, i, &p)
        } else {
            particle_tools::<R, V, T, 3>(set, a, i, &p)
        };
        if heating > 0.0 && !a.temp.is_null() && fl & flags::FIXED_TEMPERATURE == 0 {
            *a.temp.add(i) = crate::material::heated_temperature(temp, heating, melt);
        }
        if !a.wear.is_null() {
            *a.wear.add(i) = wear;
        }
    }
}

/// A particle's scalars the contact law reads: mass, density, temperature, specific heat and current yield stress.
struct ParticleIn {
    m: f64,
    rho: f64,
    temp: f64,
    cp: f64,
    sy: f64,
}

/// Particle i against the tools in order until one touches it (the last one's answer, no contact, otherwise):
/// stores the forces and the owner; returns the heating, the wear rate and the melt cap of the tool that answered.
///
/// # Safety
/// As [`contact_particle`].
#[inline(always)]
unsafe fn particle_tools<R: Real, V: Vector<R>, T: ToolArg, const D: usize>(
    set: &ToolSet<T>,
    a: &ContactArrays<R, V>,
    i: usize,
    p: &ParticleIn,
) -> (f64, f64, f64) {
    unsafe {
        let (x, v) = (load::<R, V, D>(a.pos, i), load::<R, V, D>(a.vel, i));
        let own = if set.owner.is_null() { 0 } else { *set.owner.add(i) };
        let mut k = 0;
        loop {
            let c = &*set.params.add(k);
            let f_old = if own as usize == k { load::<R, V, D>(a.friction, i) } else { [0.0; D] };
            let r = contact_force::<D, T::Geometry>(
                c,
                set.tools.geometry(k),
                &*set.states.add(k),
                x,
                v,
                f_old,
                p.m,
                p.rho,
                p.temp,
                p.cp,
                p.sy,
            );
            if r.touching || k + 1 >= set.count as usize {
                store(a, i, r.normal, r.friction);
                if r.touching && !set.owner.is_null() {
                    *set.owner.add(i) = k as u32;
                }
                return (r.heating, r.wear, c.melt);
            }
            k += 1;
        }
    }
}

/// The first D components of particle i's vector, in f64.
///
/// # Safety
/// `p` holds at least i + 1 vectors.
#[inline(always)]
unsafe fn load<R: Real, V: Vector<R>, const D: usize>(p: *const V, i: usize) -> [f64; D] {
    let x = unsafe { *p.add(i) };
    let mut r = [0.0; D];
    let mut k = 0;
    while k < D {
        r[k] = x.get(k).to_f64();
        k += 1;
    }
    r
}

/// Writes particle i's normal and friction forces, rounded to R.
///
/// # Safety
/// `a.normal` and `a.friction` hold at least i + 1 vectors.
#[inline(always)]
unsafe fn store<R: Real, V: Vector<R>, const D: usize>(
    a: &ContactArrays<R, V>,
    i: usize,
    normal: [f64; D],
    friction: [f64; D],
) {
    let (mut n, mut f) = ([R::ZERO; 3], [R::ZERO; 3]);
    let mut k = 0;
    while k < D {
        n[k] = R::from_f64(normal[k]);
        f[k] = R::from_f64(friction[k]);
        k += 1;
    }
    unsafe {
        *a.normal.add(i) = V::new(n);
        *a.friction.add(i) = V::new(f);
    }
}
