//! One explicit MPM step (nairn-mpm.md §1.2, §7.1), as four passes, each the work of one crack point, node or
//! particle, so that no two threads write one value and the sums run in a fixed order (bitwise the same on
//! every backend):
//! 1. [`crack_point`]: each crack point reads the opening between the two particles that face each other across
//!    it, updates its tractions and gives the two particles its force;
//! 2. [`p2g_node`]: each node sums its fields' mass, momentum, internal and cohesive force and volume over the
//!    particles of the 4 × 4 cells around it, in the cell list's order;
//! 3. [`node_update`]: each node applies the boundary conditions and the tool's contact, and advances its
//!    momentum;
//!    During the ramp, [`ke_tile`] and [`feedback`] sum the grid's kinetic energy (tiles, then one thread) and
//!    update the start-up damping.
//! 4. [`g2p_particle`]: each particle reads its nodes' velocities and accelerations, moves by the PIC-damped
//!    update with the second-order position update (Eqs. 8, 10), and updates its stress.

use super::grid::{MpmParams, MpmStep, POSITION_FIRST, POSITION_SECOND, TOOL};
use super::hyperelastic::{det, relative_gradient, update};
use super::shape::ugimp;
use crate::cohesive::{CrackState, FAILED, traction};
use crate::real::Real;
use crate::vector::Vector;

/// The particles' arrays (id order; the cell list's permutation finds them by cell).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct Particles<R: Real> {
    pub pos: *mut R::V2,
    /// Positions at t = 0 (the displacement u = x − X; the tool's particles ride on them).
    pub ref_pos: *const R::V2,
    pub vel: *mut R::V2,
    /// B̄_e (xx, xy, yy, zz), J = det F, the equivalent plastic strain, the Cauchy stress (xx, xy, yy, zz).
    pub be: *mut R::S2,
    pub jac: *mut R,
    pub eps: *mut R,
    pub stress: *mut R::S2,
    pub mass: *const R,
    /// Volume at t = 0 (the current one is J V0).
    pub vol0: *const R,
    /// `grid::BELOW`, `ABOVE` or `TOOL`.
    pub kind: *const u32,
    /// The cohesive force on the particle (its crack point's, per unit thickness; zero off the crack).
    pub fext: *mut R::V2,
    /// The deformation gradient F (xx, xy, yx, yy; F_zz = 1), F ← (I + L Δt) F each step: what draws a particle's
    /// deformed domain (the glyph test, V14; docs/mpm.md "Position updates").
    pub def: *mut [R; 4],
}

/// The nodes' arrays. The specimen's quantities hold two fields per node (index 2·node + field: 0 the node's
/// own side of the crack, 1 the other side); the tool has its mass only (it is rigid). The impulse tallies are
/// the momentum each node's tool contact and grip gave the specimen, summed over the steps (f64).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct Nodes<R: Real> {
    pub mass: *mut R,
    pub mom: *mut R::V2,
    pub force: *mut R::V2,
    /// Σ S V: the fields' and the tool's volume at the node (the contact's volume check).
    pub vol: *mut R,
    pub tool_vol: *mut R,
    /// The velocity at the step's start, the acceleration and the velocity at its end, after contact.
    pub vel: *mut R::V2,
    pub acc: *mut R::V2,
    pub vel1: *mut R::V2,
    pub imp_tool: *mut [f64; 2],
    pub imp_grip: *mut [f64; 2],
    /// Σ Δp·v_grip: the work the grip did on the specimen.
    pub work_grip: *mut f64,
    /// Each node's kinetic energy over the specimen's fields at the step's start, Σ_f ½ m v² [J/m]; the sums of
    /// its tiles of [`KE_TILE`] nodes; and the start-up damping α_g [1/s], one value ([`feedback`]).
    pub ke: *mut f64,
    pub ke_tiles: *mut f64,
    pub damping: *mut f64,
}

/// The nodes whose kinetic energies one thread of [`ke_tile`] sums.
pub const KE_TILE: usize = 256;

/// The crack points' arrays: history, and the two particles that face each other across each point at t = 0
/// (above, below). The point's force is their `fext`.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct Crack<R: Real> {
    pub state: *mut CrackState<R>,
    pub pair: *const [u32; 2],
}

/// The cell list of the particles on the grid's cells: bucket c holds perm[starts[c] .. starts[c + 1]].
#[repr(C)]
#[derive(Clone, Copy)]
pub struct Cells {
    pub starts: *const u32,
    pub perm: *const u32,
}

/// A particle flag of [`g2p_particle`]: a non-finite position or velocity.
pub const NON_FINITE: u32 = 1;
/// A particle flag: a particle left the part of the grid where all its nodes exist.
pub const ESCAPED: u32 = 2;

/// The share of its nodes' mass above which a specimen particle is a fragment ([`g2p_particle`]): its own share
/// Σ S_i (m_p S_i / m_i) over its nodes i (m_i its field's mass there) is 1 for a particle alone on its nodes, and
/// on the set-up's lattice 0.098 inside, 0.18 on a face and 0.33 at a corner (docs/mpm.md "Fragments").
pub const FRAGMENT_SHARE: f64 = 0.6;

#[inline(always)]
fn v2<R: Real>(x: R, y: R) -> R::V2 {
    <R::V2 as Vector<R>>::new([x, y, R::ZERO])
}

/// Node i's sums over the particles of the 4 × 4 cells whose particles can reach it (|x_p − x_i| < Δx + l_p):
/// mass m = Σ m_p S, momentum Σ m_p v_p S, force Σ (S f_p − V_p σ_p ∇S) (f_p the cohesive force) and volume
/// Σ V_p S (V_p = J_p V0_p), per field; the tool's volume Σ V0_p S over its particles.
///
/// # Safety
/// i < nodes; the arrays hold the grid's nodes and the cell list's particles.
#[inline(always)]
pub unsafe fn p2g_node<R: Real>(p: &MpmParams, pa: &Particles<R>, cells: &Cells, nd: &Nodes<R>, i: usize) {
    let [cx, cy] = p.cells();
    let (a, b) = p.node_ab(i);
    let node = p.node_pos(a, b);
    let (xi, yi) = (R::from_f64(node[0]), R::from_f64(node[1]));
    let (dx, lp) = (R::from_f64(p.dx), R::from_f64(p.lp));
    let z = R::ZERO;
    let (mut m, mut px, mut py, mut fx, mut fy) = ([z; 2], [z; 2], [z; 2], [z; 2], [z; 2]);
    let (mut vf, mut vt) = ([z; 2], z);
    // The cells a − 2 ..= a + 1 (and b − 2 ..= b + 1) that lie on the grid.
    let (x0, x1) = (a.saturating_sub(2), (a + 1).min(cx.saturating_sub(1)));
    let mut yc = b.saturating_sub(2);
    while yc <= (b + 1).min(cy.saturating_sub(1)) {
        let mut xc = x0;
        while xc <= x1 {
            let c = (yc * cx + xc) as usize;
            let (s0, s1) = unsafe { (*cells.starts.add(c), *cells.starts.add(c + 1)) };
            let mut j = s0;
            while j < s1 {
                let q = unsafe { *cells.perm.add(j as usize) } as usize;
                let x = unsafe { *pa.pos.add(q) };
                let (sx, gx) = ugimp(x.get(0) - xi, dx, lp);
                let (sy, gy) = ugimp(x.get(1) - yi, dx, lp);
                let w = sx * sy;
                j += 1;
                if w == z {
                    continue;
                }
                let kind = unsafe { *pa.kind.add(q) };
                if kind == TOOL {
                    vt += unsafe { *pa.vol0.add(q) } * w;
                    continue;
                }
                let mq = unsafe { *pa.mass.add(q) };
                // 0 or 1 (masked, so that indexing has no panic path).
                let f = p.field_of(kind, x.get(0).to_f64(), x.get(1).to_f64(), node) & 1;
                let (v, fe) = unsafe { (*pa.vel.add(q), *pa.fext.add(q)) };
                let s = unsafe { *pa.stress.add(q) };
                let s = <R::S2 as crate::vector::SymTensor<R>>::components(&s);
                let vol = unsafe { *pa.jac.add(q) * *pa.vol0.add(q) };
                let (dwx, dwy) = (gx * sy, sx * gy);
                let mw = mq * w;
                m[f] += mw;
                vf[f] += vol * w;
                px[f] += mw * v.get(0);
                py[f] += mw * v.get(1);
                // S is (xx, xy, yy, zz).
                fx[f] += w * fe.get(0) - vol * (s[0] * dwx + s[1] * dwy);
                fy[f] += w * fe.get(1) - vol * (s[1] * dwx + s[2] * dwy);
            }
            xc += 1;
        }
        yc += 1;
    }
    let mut f = 0;
    while f < 2 {
        let k = 2 * i + f;
        unsafe {
            *nd.mass.add(k) = m[f];
            *nd.mom.add(k) = v2(px[f], py[f]);
            *nd.force.add(k) = v2(fx[f], fy[f]);
            *nd.vol.add(k) = vf[f];
        }
        f += 1;
    }
    unsafe { *nd.tool_vol.add(i) = vt };
}

/// Crack point k: the opening δ = u_a − u_b between the particles a (above) and b (below) that faced each other
/// across it at t = 0 (u = x − X), its tractions (`cohesive::traction`; once failed, closing only while the two
/// still face each other, |δ_t| < ds), and its force −t ds on a and +t ds on b (per unit thickness), which the
/// node gather adds to their fields. The pair's relative displacement is the opening, so the force does work at the rate of
/// the opening, whatever the opening's size against the cell (docs/mpm.md "Crack").
///
/// # Safety
/// k < crack points; the pairs name live particles.
#[inline(always)]
pub unsafe fn crack_point<R: Real>(p: &MpmParams, pa: &Particles<R>, cr: &Crack<R>, k: usize) {
    let [a, b] = unsafe { *cr.pair.add(k) };
    let (a, b) = (a as usize, b as usize);
    let (xa, xb, ya, yb) = unsafe { (*pa.pos.add(a), *pa.pos.add(b), *pa.ref_pos.add(a), *pa.ref_pos.add(b)) };
    let dt_open = (xa.get(0) - ya.get(0)) - (xb.get(0) - yb.get(0));
    let dn_open = (xa.get(1) - ya.get(1)) - (xb.get(1) - yb.get(1));
    let st = unsafe { &mut *cr.state.add(k) };
    let ds = R::from_f64(p.crack_ds);
    let (tt, mut tn) = traction(&p.cohesive, st, dt_open, dn_open);
    if st[FAILED] != R::ZERO && dt_open.abs() >= ds {
        // A failed point whose faces have slid apart: the pair no longer faces each other, nor closes.
        tn = R::ZERO;
    }
    unsafe {
        *pa.fext.add(a) = v2(-tt * ds, -tn * ds);
        *pa.fext.add(b) = v2(tt * ds, tn * ds);
    }
}

/// Node i's update: the momentum p = Σ m v S is constrained (boundary conditions, then the tool's contact),
/// advanced by f Δt and constrained again (nairn-mpm.md §1.2 Eq. 5; §1.6 step 5), and the node stores its
/// velocity at both ends of the step and the acceleration between them. A field lighter than `mass_floor` keeps
/// zero velocity.
///
/// # Safety
/// i < nodes; the arrays hold the grid's nodes.
#[inline(always)]
pub unsafe fn node_update<R: Real>(p: &MpmParams, s: &MpmStep, nd: &Nodes<R>, i: usize) {
    let (a, b) = p.node_ab(i);
    let node = p.node_pos(a, b);
    let dt = R::from_f64(s.dt);
    let tool_v = unsafe { *nd.tool_vol.add(i) };
    let mut imp_t = [0.0f64; 2];
    let mut imp_g = [0.0f64; 3];
    let mut ke = 0.0f64;
    let mut f = 0;
    while f < 2 {
        let (k, field) = (2 * i + f, f);
        let m = unsafe { *nd.mass.add(k) };
        f += 1;
        if m.to_f64() <= p.mass_floor {
            unsafe {
                *nd.vel.add(k) = v2(R::ZERO, R::ZERO);
                *nd.acc.add(k) = v2(R::ZERO, R::ZERO);
                *nd.vel1.add(k) = v2(R::ZERO, R::ZERO);
            }
            continue;
        }
        let (mom, force) = unsafe { (*nd.mom.add(k), *nd.force.add(k)) };
        // The tool touches this field where their volumes fill the node's cell (nairn-mpm.md §1.6; docs/mpm.md
        // "Contact").
        let touch = tool_v > R::ZERO && (unsafe { *nd.vol.add(k) } + tool_v).to_f64() >= p.contact_fill * p.dx * p.dx;
        let mut q = [mom.get(0), mom.get(1)];
        let at = (node, field);
        constrain(p, s, at, m, touch, &mut q, &mut imp_t, &mut imp_g);
        let mut q1 = [q[0] + force.get(0) * dt, q[1] + force.get(1) * dt];
        constrain(p, s, at, m, touch, &mut q1, &mut imp_t, &mut imp_g);
        let (v0, v1) = ([q[0] / m, q[1] / m], [q1[0] / m, q1[1] / m]);
        ke += 0.5 * (m * (v0[0] * v0[0] + v0[1] * v0[1])).to_f64();
        unsafe {
            *nd.vel.add(k) = v2(v0[0], v0[1]);
            *nd.vel1.add(k) = v2(v1[0], v1[1]);
            *nd.acc.add(k) = v2((v1[0] - v0[0]) / dt, (v1[1] - v0[1]) / dt);
        }
    }
    unsafe {
        let t = &mut *nd.imp_tool.add(i);
        *t = [t[0] + imp_t[0], t[1] + imp_t[1]];
        let g = &mut *nd.imp_grip.add(i);
        *g = [g[0] + imp_g[0], g[1] + imp_g[1]];
        *nd.work_grip.add(i) += imp_g[2];
        *nd.ke.add(i) = ke;
    }
}

/// Tile t's kinetic energy: Σ ke over nodes t·KE_TILE .. (t + 1)·KE_TILE (below `nodes`), in node order.
///
/// # Safety
/// t·KE_TILE < nodes; `ke` holds `nodes` values and `ke_tiles` the tiles.
#[inline(always)]
pub unsafe fn ke_tile<R: Real>(nd: &Nodes<R>, nodes: usize, t: usize) {
    let (lo, hi) = (t * KE_TILE, ((t + 1) * KE_TILE).min(nodes));
    let mut sum = 0.0;
    let mut i = lo;
    while i < hi {
        sum += unsafe { *nd.ke.add(i) };
        i += 1;
    }
    unsafe { *nd.ke_tiles.add(t) = sum };
}

/// The start-up damping's update (nairn-mpm.md §1.3, a Nosé–Hoover-style feedback on the grid's kinetic energy
/// K = Σ tiles): α_g ← max(0, α_g + (2K − 2K_target) Δt/(Q M)) with K_target = 0, the gain 1/(Q M) the step's
/// `feedback`; a step without feedback (after the ramp) resets α_g to 0. One thread.
///
/// # Safety
/// `ke_tiles` holds `tiles` values; `damping` is one live value.
#[inline(always)]
pub unsafe fn feedback<R: Real>(s: &MpmStep, nd: &Nodes<R>, tiles: usize) {
    let a = unsafe { &mut *nd.damping };
    if s.feedback <= 0.0 {
        *a = 0.0;
        return;
    }
    let mut k = 0.0;
    let mut t = 0;
    while t < tiles {
        k += unsafe { *nd.ke_tiles.add(t) };
        t += 1;
    }
    let next = *a + s.feedback * 2.0 * k * s.dt;
    *a = if next > 0.0 { next } else { 0.0 };
}

/// A field's momentum under the boundary conditions (a fixed node: 0; a gripped one: m v_grip) or else the
/// tool's contact, where the field touches the tool (`touch`) and approaches it along the prescribed normal n of
/// the field (`MpmParams::tool_normal`; (v − v_tool)·n > 0): Δp = m v_tool − p, its normal part whole and its
/// tangential part capped at μ|Δp·n| (nairn-mpm.md §1.6). The tool's and the grip's changes are added to their tallies (the grip's third entry: its
/// work Δp·v).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn constrain<R: Real>(
    p: &MpmParams,
    s: &MpmStep,
    (node, field): ([f64; 2], usize),
    m: R,
    touch: bool,
    q: &mut [R; 2],
    imp_t: &mut [f64; 2],
    imp_g: &mut [f64; 3],
) {
    if node[1] <= p.fix_below {
        *q = [R::ZERO, R::ZERO];
        return;
    }
    if node[1] >= p.pull_above {
        let v = s.pull_vel;
        let t = [m * R::from_f64(v[0]), m * R::from_f64(v[1])];
        let d = [(t[0] - q[0]).to_f64(), (t[1] - q[1]).to_f64()];
        *imp_g = [imp_g[0] + d[0], imp_g[1] + d[1], imp_g[2] + d[0] * v[0] + d[1] * v[1]];
        *q = t;
        return;
    }
    if !touch {
        return;
    }
    let n = p.tool_normal(node, s.tool_tip, field);
    let (nx, ny) = (R::from_f64(n[0]), R::from_f64(n[1]));
    let (vtx, vty) = (R::from_f64(s.tool_vel[0]), R::from_f64(s.tool_vel[1]));
    let (dpx, dpy) = (m * vtx - q[0], m * vty - q[1]);
    let dn = dpx * nx + dpy * ny;
    if dn >= R::ZERO {
        // Separating or at rest along n: no contact.
        return;
    }
    let (tx, ty) = (dpx - dn * nx, dpy - dn * ny);
    let tlen = (tx * tx + ty * ty).sqrt();
    let cap = R::from_f64(p.friction) * (-dn);
    let k = if tlen > cap && tlen > R::ZERO { cap / tlen } else { R::ONE };
    let (cx, cy) = (dn * nx + k * tx, dn * ny + k * ty);
    *q = [q[0] + cx, q[1] + cy];
    *imp_t = [imp_t[0] + cx.to_f64(), imp_t[1] + cy.to_f64()];
}

/// Particle i's update. A tool particle rides with the tool: x = X + d_tool, v = v_tool. A specimen particle
/// reads, over its nodes (its own field at each), v_g→p = Σ S v_i, a_g→p = Σ S a_i and the velocity gradient
/// L = Σ v_i^{n+1} ⊗ ∇S, then (nairn-mpm.md §1.2, Eqs. 8 and 10 in the derived form)
/// a* = a_g→p − α_PIC (v_p − v_g→p) − α_g v_g→p (α_g the start-up damping, [`feedback`]),
/// x += (v_g→p + ½ a* Δt) Δt (`POSITION_SECOND`; the other orders of Fig. 2 by `MpmParams::position_order`),
/// v += a* Δt, and updates its stress with L (`hyperelastic::update`) and its deformation gradient F; a fragment
/// (its own share of its nodes' mass above [`FRAGMENT_SHARE`]) unloads instead. Returns [`NON_FINITE`] |
/// [`ESCAPED`] flags.
///
/// # Safety
/// i < particles; the arrays hold the particles and the grid's nodes.
#[inline(always)]
pub unsafe fn g2p_particle<R: Real>(p: &MpmParams, s: &MpmStep, pa: &Particles<R>, nd: &Nodes<R>, i: usize) -> u32 {
    let x = unsafe { *pa.pos.add(i) };
    let kind = unsafe { *pa.kind.add(i) };
    if kind == TOOL {
        let x0 = unsafe { *pa.ref_pos.add(i) };
        unsafe {
            *pa.pos.add(i) = v2(x0.get(0) + R::from_f64(s.tool_disp[0]), x0.get(1) + R::from_f64(s.tool_disp[1]));
            *pa.vel.add(i) = v2(R::from_f64(s.tool_vel[0]), R::from_f64(s.tool_vel[1]));
        }
        return 0;
    }
    let (xf, yf) = (x.get(0).to_f64(), x.get(1).to_f64());
    let ca = crate::real::floor_f64((xf - p.origin[0]) / p.dx);
    let cb = crate::real::floor_f64((yf - p.origin[1]) / p.dx);
    if !(ca >= 1.0 && cb >= 1.0 && ca + 3.0 <= p.nodes[0] as f64 && cb + 3.0 <= p.nodes[1] as f64) {
        // Not finite, or too near the grid's edge for all its nodes to exist.
        return if xf.is_finite() && yf.is_finite() { ESCAPED } else { NON_FINITE };
    }
    let (dx, lp) = (R::from_f64(p.dx), R::from_f64(p.lp));
    let z = R::ZERO;
    let (mut vg, mut ag, mut l) = ([z; 2], [z; 2], [[z; 2]; 2]);
    let mq = unsafe { *pa.mass.add(i) };
    let mut share = z;
    let (a0, b0) = (ca as u32 - 1, cb as u32 - 1);
    let mut b = b0;
    while b < b0 + 4 {
        let mut a = a0;
        while a < a0 + 4 {
            let node = p.node_pos(a, b);
            let (sx, gx) = ugimp(x.get(0) - R::from_f64(node[0]), dx, lp);
            let (sy, gy) = ugimp(x.get(1) - R::from_f64(node[1]), dx, lp);
            let w = sx * sy;
            if w != z {
                let k = 2 * (b * p.nodes[0] + a) as usize + p.field_of(kind, xf, yf, node);
                let (v, acc, v1) = unsafe { (*nd.vel.add(k), *nd.acc.add(k), *nd.vel1.add(k)) };
                let mk = unsafe { *nd.mass.add(k) };
                if mk > z {
                    share += w * (mq * w / mk);
                }
                let (dwx, dwy) = (gx * sy, sx * gy);
                vg = [vg[0] + w * v.get(0), vg[1] + w * v.get(1)];
                ag = [ag[0] + w * acc.get(0), ag[1] + w * acc.get(1)];
                l = [
                    [l[0][0] + v1.get(0) * dwx, l[0][1] + v1.get(0) * dwy],
                    [l[1][0] + v1.get(1) * dwx, l[1][1] + v1.get(1) * dwy],
                ];
            }
            a += 1;
        }
        b += 1;
    }
    let dt = R::from_f64(s.dt);
    let alpha = R::from_f64(s.alpha_pic);
    // The start-up damping acts on the grid velocity (α_g of nairn-mpm.md §1.2's general form).
    let ag_damp = R::from_f64(unsafe { *nd.damping });
    let half = R::from_f64(0.5);
    let v = unsafe { *pa.vel.add(i) };
    let ad =
        [ag[0] - alpha * (v.get(0) - vg[0]) - ag_damp * vg[0], ag[1] - alpha * (v.get(1) - vg[1]) - ag_damp * vg[1]];
    let xn = match p.position_order {
        POSITION_SECOND => [x.get(0) + (vg[0] + half * ad[0] * dt) * dt, x.get(1) + (vg[1] + half * ad[1] * dt) * dt],
        // v_g→p⁽ⁿ⁺¹⁾ = v_g→p + a_g→p Δt, less half the damping's part of a* (first) or nothing (zeroth).
        order => {
            let d = if order == POSITION_FIRST { half * dt } else { z };
            let next = |c: usize| vg[c] + ag[c] * dt + d * (ad[c] - ag[c]);
            [x.get(0) + next(0) * dt, x.get(1) + next(1) * dt]
        }
    };
    let vn = [v.get(0) + ad[0] * dt, v.get(1) + ad[1] * dt];
    // F ← f F with the step's relative gradient f, the one `hyperelastic::update` applies to B̄_e and J.
    let f = relative_gradient(l, dt);
    let fd = unsafe { &mut *pa.def.add(i) };
    let [f00, f01, f10, f11] = *fd;
    let [[g00, g01], [g10, g11]] = f;
    *fd = [g00 * f00 + g01 * f10, g00 * f01 + g01 * f11, g10 * f00 + g11 * f10, g10 * f01 + g11 * f11];
    let (be, jac, eps) = unsafe { (&mut *pa.be.add(i), &mut *pa.jac.add(i), &mut *pa.eps.add(i)) };
    let mut b4 = [z; 4];
    b4.copy_from_slice(<R::S2 as crate::vector::SymTensor<R>>::components(be));
    let sig = if share.to_f64() > FRAGMENT_SHARE {
        // A fragment: a particle the flow has parted from the material (numerical fracture) has no neighbours
        // to carry its stress, and the tool's contact would throw it off by its own stress's reaction. It
        // unloads (B̄_e = I, σ = 0) and keeps its volume and plastic strain until it joins the material again.
        *jac *= det(f);
        b4 = [R::ONE, z, R::ONE, R::ONE];
        [z; 4]
    } else {
        update(&p.material, f, &mut b4, jac, eps)
    };
    <R::S2 as crate::vector::SymTensor<R>>::components_mut(be).copy_from_slice(&b4);
    unsafe {
        <R::S2 as crate::vector::SymTensor<R>>::components_mut(&mut *pa.stress.add(i)).copy_from_slice(&sig);
        *pa.pos.add(i) = v2(xn[0], xn[1]);
        *pa.vel.add(i) = v2(vn[0], vn[1]);
    }
    let ok = xn[0].is_finite() && xn[1].is_finite() && vn[0].is_finite() && vn[1].is_finite() && jac.is_finite();
    if ok { 0 } else { NON_FINITE }
}
