//! The per-particle pre-pass and the pair interaction of "Algorithm 1" (roethlin-solver.md §4.1, §5.2 steps
//! 4–10; klippel-constitutive.md §1.2), with the errata of §11 applied: continuity −ρ tr L (1), m_j (2), the
//! viscosity acting as a pressure −Π_ij I (3), μ_ij with r² + η²h² (4), XSPH with m_j/ρ̄_ij (5), the EOS
//! p = c0²(ρ − ρ0) (7), the correct cubic spline (24) and a cutoff relative to h (31). `model = "mfree_iwf"`
//! reproduces two of the old code's: W = 0.25 (2 − q)⁶ for XSPH and f_ij (24, `SphParams::model_flags`) and the
//! absolute cutoff r < 1 µm (31, through `SphParams::min_r2`).
//!
//! For sorted particle i, over neighbours j (j ≠ i, r < 2h), with V_j = m_j/ρ_j and ∇W_ij = W'(r) x_ij/r:
//!   L_i   = Σ_j V_j (v_j − v_i) ⊗ ∇W_ij
//!   v̇_i   = Σ_j m_j [σ_i/ρ_i² + σ_j/ρ_j² + f_ij^n (R_i + R_j) − Π_ij I] · ∇W_ij,   f_ij = W(r)/W(Δx)
//!   ẋ_i   = v_i + ε_X Σ_j (m_j/ρ̄_ij)(v_j − v_i) W_ij
//!   ρ̇_i   = −ρ_i tr L_i
//!   Ṡ_i   = 2G (D_i − ⅓ tr D_i I) + W_i S_i − S_i W_i
//! with Π_ij = μ (−α c̄ + β μ)/ρ̄ for v_ij·x_ij < 0 (else 0), μ = h v_ij·x_ij/(r² + η²h²), c̄ = (c_i + c_j)/2.
//! With the Balsara switch ([`balsara`]) the pre-pass writes f_i √(K/ρ_i) as c_i, so the linear term reads
//! c̄ = (f_i c_i + f_j c_j)/2 and the pair loop is the same code.
//! Every pair term is evaluated in the same order on CPU and GPU (the cell-list gather order).
//!
//! Divisions are costly in f64 on the GPU, so the pair term avoids them: V_j comes from the pre-pass, 1/ρ̄ is
//! taken once per pair (for Π and XSPH) and W'(r)/r divides only on 1 ≤ q < 2 (`CubicSpline::dw_dr_over_r`).

use super::heat::{HeatArrays, HeatParams, brookshaw_term, heat_finish, heat_own, heat_partner};
use super::lanes::{LaneSum, all_lanes, lane_share, map_real, map_vector};
use super::params::{SphParams, flags};
use super::tensor::TensorOps;
use crate::load::read;
use crate::material::eos::reference_density;
use crate::neighbour::Neighbours;
use crate::neighbour::grid::{Period, unswitch_period};
use crate::real::Real;
use crate::vector::{Dim, SymTensor, Vector};

/// Per-particle quantities the pair loop reads for every neighbour.
#[derive(Clone, Copy, Debug, Default)]
pub struct Prepared<R: Real, D: TensorOps<R>> {
    /// σ/ρ² (σ = S − p I).
    pub sig: D::Sym<R>,
    /// Artificial stress R (zero when off).
    pub art: D::Sym<R>,
    /// Sound speed √(K/ρ) (for the viscosity).
    pub c: R,
    /// Volume V = m/ρ with the particle's full mass (the tool's thermal-only particles conduct), read by the pair
    /// terms as V_j instead of one division per pair.
    pub vol: R,
}

/// EOS p = c0² (ρ − ρ0), pressure positive in compression (roethlin-solver.md §2.3, erratum 7).
#[inline(always)]
pub fn pressure<R: Real>(p: &SphParams<R>, rho: R) -> R {
    p.c0sq * (rho - p.rho0)
}

/// EOS with thermal expansion: p = c0² (ρ − ρ0(T)), ρ0(T) = ρ0/(1 + 3α (T − T0)); equal to [`pressure`] when
/// the expansion is off.
#[inline(always)]
pub fn pressure_at<R: Real>(p: &SphParams<R>, rho: R, temp: f64) -> R {
    if p.expansion == R::ZERO {
        return pressure(p, rho);
    }
    let rho0 = reference_density(p.rho0.to_f64(), p.expansion.to_f64(), p.expansion_t0.to_f64(), temp);
    p.c0sq * (rho - R::from_f64(rho0))
}

/// The EOS of a particle: [`pressure_at`] its temperature where the run models thermal expansion (`temp` given),
/// else [`pressure`].
#[inline(always)]
pub fn pressure_of<R: Real>(p: &SphParams<R>, rho: R, temp: Option<f64>) -> R {
    match temp {
        Some(t) => pressure_at(p, rho, t),
        None => pressure(p, rho),
    }
}

/// The pre-pass of one particle: EOS, σ/ρ², artificial stress, sound speed and volume V = m/ρ (`mass` the
/// particle's full mass). `temp` is the particle's temperature when the run models thermal expansion.
#[inline(always)]
pub fn prepare<R: Real, D: TensorOps<R>, const AV: bool, const AS: bool>(
    p: &SphParams<R>,
    rho: R,
    mass: R,
    s: &D::Sym<R>,
    temp: Option<f64>,
) -> Prepared<R, D> {
    let pr = pressure_of(p, rho, temp);
    Prepared {
        sig: D::stress_over_rho2(s, pr, rho),
        art: if AS { D::artificial_stress(s, pr, rho, p.as_eps) } else { Default::default() },
        c: if AV { (p.bulk / rho).sqrt() } else { R::ZERO },
        vol: mass / rho,
    }
}

/// The deviatoric stress `s` times `m` (the damage's degradation).
#[inline(always)]
pub fn scale_sym<R: Real, S: SymTensor<R>>(s: &S, m: R) -> S {
    let mut o = *s;
    for x in o.components_mut() {
        *x *= m;
    }
    o
}

/// [`prepare`] of a damaged run (docs/damage.md): the stored (undamaged) deviator times exp(−D) and the pressure
/// times exp(−D) only in tension (klippel §2.6, Eqs. 7.27–7.28; `damage::multiplier`, `damage::degraded_pressure`)
/// enter σ/ρ² and the artificial stress; also returns the interaction mask F_i (`damage::mask_value`, from the
/// undamaged pressure).
#[inline(always)]
pub fn prepare_damaged<R: Real, D: TensorOps<R>, const AV: bool, const AS: bool>(
    p: &SphParams<R>,
    rho: R,
    mass: R,
    s: &D::Sym<R>,
    temp: Option<f64>,
    damage: f64,
    damage_flags: u32,
) -> (Prepared<R, D>, f64) {
    let pr = pressure_of(p, rho, temp);
    let m = R::from_f64(crate::damage::multiplier(damage));
    let (sd, pd) = (scale_sym::<R, D::Sym<R>>(s, m), crate::damage::degraded_pressure(m, pr));
    let q = Prepared {
        sig: D::stress_over_rho2(&sd, pd, rho),
        art: if AS { D::artificial_stress(&sd, pd, rho, p.as_eps) } else { Default::default() },
        c: if AV { (p.bulk / rho).sqrt() } else { R::ZERO },
        vol: mass / rho,
    };
    (q, crate::damage::mask_value(damage_flags, damage, pr.to_f64()))
}

/// The damage's view in the pre-pass: D (null: no damage, the undamaged [`prepare`]), the `damage::switches` and
/// where the mask goes.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct PrepassDamage {
    pub damage: *const f64,
    pub mask: *mut f64,
    pub flags: u32,
    pub _pad: u32,
}

impl PrepassDamage {
    /// No damage.
    pub const OFF: PrepassDamage =
        PrepassDamage { damage: core::ptr::null(), mask: core::ptr::null_mut(), flags: 0, _pad: 0 };
}

/// Where the pre-pass writes (sorted order): σ/ρ² and V always, the artificial stress and the sound speed where
/// their stabiliser is on (null otherwise); `av_switch` is what it reads of the Balsara switch (null: off). One
/// struct in the standalone pre-pass's and the predictor's argument blocks (`pass::PrepareArgs`,
/// `pass::PredictArgs`), so that both launch it the same way.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct PrepassArrays<R: Real, S> {
    pub sig: *mut S,
    pub art: *mut S,
    pub sound: *mut R,
    pub vol: *mut R,
    /// The Balsara factor f_i of the last interaction ([`balsara`]): the sound speed written is f_i c_i. Null:
    /// c_i (a uniform branch; the pair loop reads `sound` either way).
    pub av_switch: *const R,
}

impl<R: Real, S> PrepassArrays<R, S> {
    /// Every array null: no pre-pass (the predictor without a fused one).
    pub const NONE: Self = PrepassArrays {
        sig: core::ptr::null_mut(),
        art: core::ptr::null_mut(),
        sound: core::ptr::null_mut(),
        vol: core::ptr::null_mut(),
        av_switch: core::ptr::null(),
    };
}

/// Balsara's switch of the artificial viscosity (D. S. Balsara, J. Comput. Phys. 121 (1995) 357; a project
/// decision, outside the reference digests: docs/solver.md, "The Balsara switch"):
///   f_i = |∇·v|_i / (|∇·v|_i + |∇×v|_i + 1e-4 c_i/h),  c_i = √(K/ρ_i),  f_i ∈ [0, 1],
/// with ∇·v = tr L_i and |∇×v| from L_i's antisymmetric part ([`TensorOps::curl_norm`]). 1 in compression (up to
/// the 1e-4 c/h guard), 0 in rigid rotation, simple shear and isochoric pure strain, so the viscosity stays at
/// shocks and leaves plastic shear flow. The interaction writes it from its L_i ([`finish_rates`]), the next
/// pre-pass scales the sound speed by it ([`prepare_store`]): Balsara multiplies the whole Π_ij by (f_i + f_j)/2,
/// here only the linear term α c̄ μ is switched, through c̄ = (f_i c_i + f_j c_j)/2, and the quadratic β μ² term,
/// which matters only at shocks (where f ≈ 1), is not: no change of the pair loop. A deleted particle (damage)
/// and a thermal-only one have L = 0, so f = 0; neither takes part in a viscous pair.
#[inline(always)]
pub fn balsara<R: Real, D: TensorOps<R>>(p: &SphParams<R>, l: &D::Grad, rho: R) -> R {
    let div = D::trace(l).abs();
    let c = (p.bulk / rho).sqrt();
    div / (div + D::curl_norm(l) + R::from_f64(1e-4) * c / p.kernel.h)
}

/// The pre-pass of particle i with stabilisers `AV`, `AS`, damaged with `DMG` (writing its mask).
///
/// # Safety
/// The arrays of `o` (`art`, `sound` where `AS`, `AV`; `av_switch` where not null) and of `dmg` (with `DMG`) hold
/// i + 1 elements.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub unsafe fn prepare_store<R: Real, D: TensorOps<R>, const AV: bool, const AS: bool, const DMG: bool>(
    p: &SphParams<R>,
    o: &PrepassArrays<R, D::Sym<R>>,
    dmg: &PrepassDamage,
    i: usize,
    rho: R,
    mass: R,
    s: &D::Sym<R>,
    temp: Option<f64>,
) {
    unsafe {
        let q = if DMG {
            let (q, f) = prepare_damaged::<R, D, AV, AS>(p, rho, mass, s, temp, *dmg.damage.add(i), dmg.flags);
            *dmg.mask.add(i) = f;
            q
        } else {
            prepare::<R, D, AV, AS>(p, rho, mass, s, temp)
        };
        *o.sig.add(i) = q.sig;
        *o.vol.add(i) = q.vol;
        if AS {
            *o.art.add(i) = q.art;
        }
        if AV {
            *o.sound.add(i) = if o.av_switch.is_null() { q.c } else { *o.av_switch.add(i) * q.c };
        }
    }
}

/// The pre-pass of particle i ([`prepare`], no thermal expansion) written to `o`, with the stabilisers whose
/// arrays are not null, damaged with `DMG`: the predictor's fused pre-pass (`sph::step`,
/// docs/measurements/notebook.md), on both backends.
///
/// # Safety
/// The non-null arrays of `o`, and those of `dmg` with `DMG`, hold at least i + 1 elements.
#[inline(always)]
pub unsafe fn prepare_particle<R: Real, D: TensorOps<R>, const DMG: bool>(
    p: &SphParams<R>,
    o: &PrepassArrays<R, D::Sym<R>>,
    dmg: &PrepassDamage,
    i: usize,
    rho: R,
    mass: R,
    s: &D::Sym<R>,
) {
    unsafe {
        match (!o.sound.is_null(), !o.art.is_null()) {
            (false, false) => prepare_store::<R, D, false, false, DMG>(p, o, dmg, i, rho, mass, s, None),
            (false, true) => prepare_store::<R, D, false, true, DMG>(p, o, dmg, i, rho, mass, s, None),
            (true, false) => prepare_store::<R, D, true, false, DMG>(p, o, dmg, i, rho, mass, s, None),
            (true, true) => prepare_store::<R, D, true, true, DMG>(p, o, dmg, i, rho, mass, s, None),
        }
    }
}

/// Time derivatives of one particle.
#[derive(Clone, Copy, Debug, Default)]
pub struct Rates<R: Real, D: Dim> {
    pub pos_t: D::Vec<R>,
    pub vel_t: D::Vec<R>,
    pub rho_t: R,
    pub stress_t: D::Sym<R>,
    /// The artificial viscosity's dissipation rate per unit mass (0 without it).
    pub dissipation_t: R,
    /// The Balsara factor of L_i ([`balsara`]), stored only where the switch is on (`pass::RatesArgs::store`;
    /// where it is not, nothing reads it and the compiler drops it).
    pub av_switch: R,
}

/// Read-only views of the sorted particle arrays (raw pointers: the same code runs on CPU and GPU). `#[repr(C)]`:
/// embedded in `pass::RatesArgs`, whose layout is the PTX entry's parameter block.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct Arrays<R: Real, D: Dim> {
    pub pos: *const D::Vec<R>,
    pub vel: *const D::Vec<R>,
    pub rho: *const R,
    /// Mechanical masses (zero for the tool's thermal-only particles).
    pub mass: *const R,
    /// V = m/ρ of the pre-pass, with the full masses.
    pub vol: *const R,
    pub stress: *const D::Sym<R>,
    pub sig: *const D::Sym<R>,
    /// Null unless the artificial stress is on.
    pub art: *const D::Sym<R>,
    /// Null unless the viscosity is on (f_i √(K/ρ_i) with the Balsara switch, [`balsara`]).
    pub sound: *const R,
    pub flags: *const u32,
    /// Prescribed velocities, indexed by the flags' velocity index.
    pub bc_vel: *const D::Vec<R>,
    /// Contact normal and friction forces of the last contact pass (`contact::penalty`); null without a tool.
    pub normal: *const D::Vec<R>,
    pub friction: *const D::Vec<R>,
    /// The damage's interaction mask F_j of the pre-pass (`damage::mask_value`: 1, 0 or `damage::DELETED`); null
    /// without damage (every F_j = 1).
    pub mask: *const f64,
    /// The kernel-gradient correction B_i⁻¹ (`sph::correction`); null unless the CSPM entries run.
    pub correction: *const D::Sym<R>,
}

#[inline(always)]
fn sub<R: Real, V: Vector<R>>(a: &V, b: &V) -> V {
    V::new([a.get(0) - b.get(0), a.get(1) - b.get(1), a.get(2) - b.get(2)])
}

#[inline(always)]
fn axpy<R: Real, V: Vector<R>>(acc: &mut V, w: R, x: &V) {
    *acc = V::new([acc.get(0) + w * x.get(0), acc.get(1) + w * x.get(1), acc.get(2) + w * x.get(2)]);
}

#[inline(always)]
fn dot<R: Real, V: Vector<R>>(a: &V, b: &V) -> R {
    let mut s = a.get(0) * b.get(0) + a.get(1) * b.get(1);
    if V::DIM == 3 {
        s += a.get(2) * b.get(2);
    }
    s
}

/// The pair sums of one particle (or one lane's share of them): the velocity gradient L = Σ V_j (v_j − v_i) ⊗ ∇W,
/// the acceleration Σ m_j f_ij and the XSPH sum. Plain data of R, so that lanes combine it by shuffles.
#[repr(C)]
#[derive(Clone, Copy, Default)]
pub struct PairSums<R: Real, D: TensorOps<R>> {
    pub l: D::Grad,
    pub acc: D::Vec<R>,
    pub xsph: D::Vec<R>,
    /// The artificial viscosity's dissipation rate per unit mass, ½ Σ_j m_j Π_ij v_ij·∇_i W_ij (≥ 0).
    pub dissipation: R,
}

impl<R: Real, D: TensorOps<R>> LaneSum for PairSums<R, D> {
    /// Component-wise self + o.
    #[inline(always)]
    fn add(&self, o: &Self) -> Self {
        let mut out = *self;
        for (a, b) in out.l.as_mut().iter_mut().zip(o.l.as_ref()) {
            *a += *b;
        }
        axpy(&mut out.acc, R::ONE, &o.acc);
        axpy(&mut out.xsph, R::ONE, &o.xsph);
        out.dissipation += o.dissipation;
        out
    }
    #[inline(always)]
    fn map_words<F: FnMut(u32) -> u32>(&self, f: &mut F) -> Self {
        let mut out = *self;
        for a in out.l.as_mut() {
            *a = map_real(*a, f);
        }
        out.acc = map_vector(&self.acc, f);
        out.xsph = map_vector(&self.xsph, f);
        out.dissipation = map_real(self.dissipation, f);
        out
    }
}

/// What a pair term needs of particle i.
#[derive(Clone, Copy)]
struct Own<R: Real, D: TensorOps<R>> {
    /// False for the tool's thermal-only particles: their mechanical rates are discarded (`finish_rates`), so
    /// their pair loop is skipped.
    mech: bool,
    x: D::Vec<R>,
    v: D::Vec<R>,
    rho: R,
    sig: D::Sym<R>,
    art: D::Sym<R>,
    c: R,
    /// B_i⁻¹ (with CSPM only).
    corr: D::Sym<R>,
    /// The side of the cohesive path i lies on and whether it is open (`flags::CUT_MASK` bits; `CUT` entries only).
    side: u32,
}

#[inline(always)]
unsafe fn own<R: Real, D: TensorOps<R>, const AV: bool, const AS: bool, const CS: bool>(
    a: &Arrays<R, D>,
    i: u32,
) -> Own<R, D> {
    let iu = i as usize;
    unsafe {
        let fl = *a.flags.add(iu);
        Own {
            mech: fl & flags::THERMAL_ONLY == 0,
            x: *a.pos.add(iu),
            v: *a.vel.add(iu),
            rho: *a.rho.add(iu),
            sig: *a.sig.add(iu),
            art: if AS { *a.art.add(iu) } else { Default::default() },
            c: if AV { *a.sound.add(iu) } else { R::ZERO },
            corr: if CS { *a.correction.add(iu) } else { Default::default() },
            side: fl & flags::CUT_MASK,
        }
    }
}

/// What the pair terms read of neighbour j. Loaded together at the head of each pair, before any branch: loads
/// under a branch wait for the condition, so reading each field where it is first needed (position → support
/// test → mass → velocity and density → artificial stress → sound speed → σ/ρ²) put one memory latency per
/// dependent branch on every pair's path; loaded together they share one.
#[derive(Clone, Copy)]
struct Partner<R: Real, D: TensorOps<R>> {
    x: D::Vec<R>,
    v: D::Vec<R>,
    /// Mechanical mass (zero for the tool's thermal-only particles).
    m: R,
    rho: R,
    /// V = m/ρ of the pre-pass (full mass).
    vol: R,
    /// Sound speed (zero without the viscosity).
    c: R,
    sig: D::Sym<R>,
    /// Artificial stress (zero without it).
    art: D::Sym<R>,
    /// The side of the cohesive path j lies on and whether it is open (0 unless `CUT`).
    side: u32,
}

#[inline(always)]
unsafe fn partner<R: Real, D: TensorOps<R>, const AV: bool, const AS: bool, const CUT: bool>(
    a: &Arrays<R, D>,
    j: u32,
) -> Partner<R, D> {
    let ju = j as usize;
    // `load::read`: the loads stay here, ahead of the branches (LLVM would sink them into the blocks that use them).
    unsafe {
        Partner {
            x: read(a.pos.add(ju)),
            v: read(a.vel.add(ju)),
            m: read(a.mass.add(ju)),
            rho: read(a.rho.add(ju)),
            vol: read(a.vol.add(ju)),
            c: if AV { read(a.sound.add(ju)) } else { R::ZERO },
            sig: read(a.sig.add(ju)),
            art: if AS { read(a.art.add(ju)) } else { Default::default() },
            side: if CUT { read(a.flags.add(ju)) & flags::CUT_MASK } else { 0 },
        }
    }
}

/// The constants a pair term reads: the kernel's, the skip distance and the stabilisers' as switched on, the rest
/// zero (so that the compiler sees the unused terms vanish). On the GPU the block is a kernel parameter passed by
/// value (`ptx::sph`): its fields sit in the constant bank, operands of the instructions that use them, with no
/// load and no register held across the pair loop (read through a pointer they were global loads, one more link
/// of each pair's chain of dependent latencies, and registers under the cap of 128).
#[inline(always)]
fn pair_params<R: Real, const AV: bool, const AS: bool>(p: &SphParams<R>) -> SphParams<R> {
    SphParams {
        kernel: p.kernel,
        min_r2: p.min_r2,
        as_inv_w_dx: if AS { p.as_inv_w_dx } else { R::ZERO },
        as_exponent: if AS { p.as_exponent } else { 0 },
        av_eta2h2: if AV { p.av_eta2h2 } else { R::ZERO },
        av_alpha: if AV { p.av_alpha } else { R::ZERO },
        av_beta: if AV { p.av_beta } else { R::ZERO },
        // Read only where W itself is (XSPH, artificial stress).
        model_flags: p.model_flags,
        ..Default::default()
    }
}

/// The geometry of a pair within the support: x_ij, r², r and W'(r)/r (∇W_ij = W'(r)/r x_ij), computed once for the
/// momentum and the conduction terms of the fused pass.
#[derive(Clone, Copy)]
struct Geometry<R: Real, V: Vector<R>> {
    xij: V,
    r2: R,
    r: R,
    dw: R,
}

/// The geometry of pair (i, j) with j at `xj`; None for j = i, beyond the support or closer than the skip distance.
#[inline(always)]
fn geometry<R: Real, D: TensorOps<R>, const PER: bool>(
    p: &SphParams<R>,
    per: &Period<R>,
    o: &Own<R, D>,
    i: u32,
    j: u32,
    xj: &D::Vec<R>,
) -> Option<Geometry<R, D::Vec<R>>> {
    let k = &p.kernel;
    let xij = if PER { per.displacement(&o.x, xj) } else { sub(&o.x, xj) };
    let r2 = dot(&xij, &xij);
    if j == i || r2 >= k.support2 || r2 < p.min_r2 {
        return None;
    }
    let r = r2.sqrt();
    Some(Geometry { xij, r2, r, dw: k.dw_dr_over_r(r) })
}

/// Adds the term of pair (i, j) to `sums` (nothing for j = i, beyond the support, or a massless j: every term
/// carries m_j, and the tool's thermal-only particles have zero mechanical mass). With `CUT`, nothing for a pair
/// across the cohesive path ([`cut_apart`]).
#[inline(always)]
unsafe fn add_pair<
    R: Real,
    D: TensorOps<R>,
    const AV: bool,
    const AS: bool,
    const XSPH: bool,
    const DMG: bool,
    const CS: bool,
    const CUT: bool,
    const PER: bool,
>(
    p: &SphParams<R>,
    per: &Period<R>,
    a: &Arrays<R, D>,
    o: &Own<R, D>,
    i: u32,
    j: u32,
    sums: &mut PairSums<R, D>,
) {
    let (q, p) = (unsafe { partner::<R, D, AV, AS, CUT>(a, j) }, pair_params::<R, AV, AS>(p));
    if CUT && cut_apart(o.side, q.side) {
        return;
    }
    if let Some(g) = geometry::<R, D, PER>(&p, per, o, i, j, &q.x) {
        if DMG {
            unsafe { masked_pair_term::<R, D, AV, AS, XSPH, CS>(&p, a, o, q, &g, i, j, sums) }
        } else {
            pair_term::<R, D, AV, AS, XSPH, CS>(&p, o, &q, &g, sums)
        }
    }
}

/// Whether particles of flags `a` and `b` (`flags::CUT_MASK` bits) lie on opposite sides of the cohesive path and
/// one of them is open (`flags::OPEN`): across it there is then no continuum interaction, only the bond's traction
/// (nairn-mpm.md §7.2, "no ordinary SPH stress interaction across the plane").
#[inline(always)]
pub fn cut_apart(a: u32, b: u32) -> bool {
    let c = a | b;
    c & flags::SIDE_MASK == flags::SIDE_MASK && c & flags::OPEN != 0
}

/// [`pair_term`] of a damaged run with the interaction mask F (klippel §2.6, Eqs. 7.30–7.34; docs/damage.md,
/// "Interaction mask"): 1 interacting, 0 fully damaged in tension, `damage::DELETED`. A deleted j takes no part.
/// - `model::MASK_PRINTED` (`damage.mask_form = "printed"`, the default), Klippel's form: for F_j = 0 the neighbour's
///   quantities only are masked: v_j F_j − v_i in the velocity gradient and XSPH (j at rest in the lab frame),
///   σ_j F_j = 0 in the momentum, μ_ij F_j = 0 (no viscosity).
/// - `"invariant"`: a pair with a masked particle exchanges no momentum, viscosity or XSPH; an unmasked i leaves a
///   masked j out of its velocity gradient, a masked i keeps its unmasked neighbours in it (its density, and so its
///   mask, follows the material around it). Velocity differences only, so Galilean invariant; and the stress power
///   σ_i : L_i of each particle that carries stress matches the work of its pair forces.
///
/// Only the damaged entries (`DMG`) call it: the others' pair loop is that of a run without damage, instruction for
/// instruction.
///
/// # Safety
/// `a.mask` holds max(i, j) + 1 elements.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
unsafe fn masked_pair_term<
    R: Real,
    D: TensorOps<R>,
    const AV: bool,
    const AS: bool,
    const XSPH: bool,
    const CS: bool,
>(
    p: &SphParams<R>,
    a: &Arrays<R, D>,
    o: &Own<R, D>,
    q: Partner<R, D>,
    g: &Geometry<R, D::Vec<R>>,
    i: u32,
    j: u32,
    sums: &mut PairSums<R, D>,
) {
    let fj = unsafe { *a.mask.add(j as usize) };
    if fj < 0.0 {
        return;
    }
    if p.model_flags & super::params::model::MASK_PRINTED != 0 {
        if fj > 0.0 {
            pair_term::<R, D, AV, AS, XSPH, CS>(p, o, &q, g, sums)
        } else {
            let q = Partner { v: Default::default(), sig: Default::default(), ..q };
            // Without the viscosity's terms: Π_ij F_j = 0 (its dissipation is then 0 as well).
            pair_term::<R, D, false, AS, XSPH, CS>(p, o, &q, g, sums)
        }
    } else if fj > 0.0 {
        if unsafe { *a.mask.add(i as usize) } > 0.0 {
            pair_term::<R, D, AV, AS, XSPH, CS>(p, o, &q, g, sums)
        } else {
            // A masked i: its velocity gradient only.
            let mut t = PairSums::<R, D>::default();
            pair_term::<R, D, false, false, false, CS>(p, o, &q, g, &mut t);
            for (l, dl) in sums.l.as_mut().iter_mut().zip(t.l.as_ref()) {
                *l += *dl;
            }
        }
    }
}

/// The momentum, velocity-gradient, XSPH and dissipation terms of pair (i, j) with j's data `q` and the pair's
/// geometry `g`; with `CS` the kernel gradient is the corrected B_i⁻¹ ∇W_ij (`sph::correction`).
#[inline(always)]
fn pair_term<R: Real, D: TensorOps<R>, const AV: bool, const AS: bool, const XSPH: bool, const CS: bool>(
    p: &SphParams<R>,
    o: &Own<R, D>,
    q: &Partner<R, D>,
    g: &Geometry<R, D::Vec<R>>,
    sums: &mut PairSums<R, D>,
) {
    let (vi, rhoi, sigi, arti, ci) = (o.v, o.rho, o.sig, o.art, o.c);
    let k = &p.kernel;
    let half = R::from_f64(0.5);
    let (xij, r2, r) = (g.xij, g.r2, g.r);
    {
        let gw = {
            let f = g.dw;
            D::Vec::<R>::new([f * xij.get(0), f * xij.get(1), f * xij.get(2)])
        };
        let gw = if CS { D::sym_apply(&o.corr, &gw) } else { gw };
        let mj = q.m;
        if mj == R::ZERO {
            return;
        }
        let (vj, rhoj) = (q.v, q.rho);
        let dv = sub(&vj, &vi);
        // V_j of the pre-pass: m_j/ρ_j with the full mass, which equals the mechanical m_j here (m_j ≠ 0).
        D::outer_add(&mut sums.l, q.vol, &dv, &gw);
        // W for XSPH and f_ij; `model = "mfree_iwf"` takes the old 2D code's (2 − q)⁶ (erratum 24; a uniform branch
        // on a kernel constant).
        let w = if !(AS || XSPH) {
            R::ZERO
        } else if p.model_flags & super::params::model::C2D_KERNEL_W != 0 {
            k.w_c2d(r)
        } else {
            k.w(r)
        };
        let fan = if AS { power(w * p.as_inv_w_dx, p.as_exponent) } else { R::ZERO };
        let artj = q.art;
        let rho_bar = half * (rhoi + rhoj);
        // Π and the XSPH weight need 1/ρ̄, Π (approaching pairs) also 1/(r² + η²h²): one division for both,
        // 1/(ρ̄ (r² + η²h²)), on every pair (a branch around it would run both ways in a warp). A division is a
        // reciprocal and its Newton steps, the longest chain of the pair term after the square root.
        let (inv_rb, pi) = if AV {
            let den = r2 + p.av_eta2h2;
            let inv = R::ONE / (rho_bar * den);
            let inv_rb = inv * den;
            let vx = -dot(&dv, &xij); // v_ij · x_ij with v_ij = v_i − v_j
            let pi = if vx < R::ZERO {
                let mu = k.h * vx * (inv * rho_bar);
                let c_bar = half * (ci + q.c);
                mu * (-p.av_alpha * c_bar + p.av_beta * mu) * inv_rb
            } else {
                R::ZERO
            };
            (inv_rb, pi)
        } else if XSPH {
            (R::ONE / rho_bar, R::ZERO)
        } else {
            (R::ZERO, R::ZERO)
        };
        if AV {
            // v_ij·∇W with v_ij = v_i − v_j = −dv: the energy the viscous pair force takes out of the motion.
            sums.dissipation -= half * mj * pi * dot(&dv, &gw);
        }
        let f = D::pair_force(&sigi, &q.sig, fan, &arti, &artj, pi, &gw);
        axpy(&mut sums.acc, mj, &f);
        if XSPH {
            axpy(&mut sums.xsph, mj * inv_rb * w, &dv);
        }
    }
}

/// xⁿ by repeated squaring: the artificial stress's f_ijⁿ (roethlin-solver.md §3.6, Gray–Monaghan, n = 4). For
/// n = 4 two dependent multiplications, (x²)², without the loop (the branch is on a kernel constant, uniform across
/// the warp); other n take the loop, which gives the same bits for n = 4. A loop of n multiplications was a chain of
/// n dependent latencies and a counter on every pair.
#[inline(always)]
pub fn power<R: Real>(x: R, n: u32) -> R {
    if n == 4 {
        let x2 = x * x;
        return x2 * x2;
    }
    let (mut acc, mut b, mut e) = (R::ONE, x, n);
    while e > 0 {
        if e & 1 == 1 {
            acc *= b;
        }
        e >>= 1;
        if e > 0 {
            b *= b;
        }
    }
    acc
}

/// Lane `lane` of `lanes`' share of the pair sums of sorted particle i ([`for_each_neighbour_strided`]).
///
/// # Safety
/// As [`rates`]; `lane < lanes`.
#[inline(always)]
pub unsafe fn pair_sums<
    R: Real,
    D: TensorOps<R>,
    const AV: bool,
    const AS: bool,
    const XSPH: bool,
    const DMG: bool,
    const CS: bool,
    const CUT: bool,
>(
    p: &SphParams<R>,
    nb: &Neighbours,
    a: &Arrays<R, D>,
    i: u32,
    lane: u32,
    lanes: u32,
) -> PairSums<R, D> {
    unsafe {
        let o = own::<R, D, AV, AS, CS>(a, i);
        if !o.mech {
            return PairSums::default();
        }
        let per = Period::<R>::of::<D>(nb.grid);
        unswitch_period!(per, PER =>
            lane_share::<R, D::Vec<R>, _, _>(nb, &o.x, i, lane, lanes, |j, s| {
                add_pair::<R, D, AV, AS, XSPH, DMG, CS, CUT, PER>(p, &per, a, &o, i, j, s)
            })
        )
    }
}

/// The pair sums of one particle with its Brookshaw conduction sum over the same candidates (sph::heat): the
/// fused pass of a conducting run, one neighbour walk where there were two.
#[repr(C)]
#[derive(Clone, Copy, Default)]
pub struct HeatPairSums<R: Real, D: TensorOps<R>> {
    pub mech: PairSums<R, D>,
    /// Σ_j V_j k_ij L_ij (`heat::heat_sum`).
    pub heat: f64,
}

impl<R: Real, D: TensorOps<R>> LaneSum for HeatPairSums<R, D> {
    #[inline(always)]
    fn add(&self, o: &Self) -> Self {
        HeatPairSums { mech: self.mech.add(&o.mech), heat: self.heat + o.heat }
    }
    #[inline(always)]
    fn map_words<F: FnMut(u32) -> u32>(&self, f: &mut F) -> Self {
        HeatPairSums { mech: self.mech.map_words(f), heat: map_real(self.heat, f) }
    }
}

/// Lane `lane` of `lanes`' share of [`HeatPairSums`] of sorted particle i: each candidate adds its conduction
/// term (unless i has a fixed temperature) and its mechanical term (unless i is thermal-only), in the order of
/// [`pair_sums`] and `heat::heat_sum`, so both parts equal the separate passes bit for bit.
///
/// # Safety
/// As [`rates`]; `h` holds the same sorted particles (V = m/ρ with the full masses), every body index has a
/// material.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub unsafe fn pair_sums_heat<
    R: Real,
    D: TensorOps<R>,
    const AV: bool,
    const AS: bool,
    const XSPH: bool,
    const DMG: bool,
    const CS: bool,
>(
    p: &SphParams<R>,
    hp: &HeatParams,
    nb: &Neighbours,
    a: &Arrays<R, D>,
    h: &HeatArrays<R, D::Vec<R>>,
    i: u32,
    lane: u32,
    lanes: u32,
) -> HeatPairSums<R, D> {
    unsafe {
        let o = own::<R, D, AV, AS, CS>(a, i);
        let ho = heat_own(h, i);
        if !o.mech && ho.is_none() {
            return HeatPairSums::default();
        }
        let per = Period::<R>::of::<D>(nb.grid);
        unswitch_period!(per, PER =>
            lane_share::<R, D::Vec<R>, _, _>(nb, &o.x, i, lane, lanes, |j, s: &mut HeatPairSums<R, D>| {
                heat_and_pair::<R, D, AV, AS, XSPH, DMG, CS, PER>(p, hp, &per, a, h, &o, ho.as_ref(), i, j, s)
            })
        )
    }
}

/// The conduction and mechanical terms of pair (i, j) of the fused pass.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
unsafe fn heat_and_pair<
    R: Real,
    D: TensorOps<R>,
    const AV: bool,
    const AS: bool,
    const XSPH: bool,
    const DMG: bool,
    const CS: bool,
    const PER: bool,
>(
    p: &SphParams<R>,
    hp: &HeatParams,
    per: &Period<R>,
    a: &Arrays<R, D>,
    h: &HeatArrays<R, D::Vec<R>>,
    o: &Own<R, D>,
    ho: Option<&super::heat::HeatOwn<D::Vec<R>>>,
    i: u32,
    j: u32,
    s: &mut HeatPairSums<R, D>,
) {
    // Both partners' data first (`Partner`); one geometry for both terms (the separate passes compute the same
    // r², r and W'(r)/r, bit for bit).
    let (q, hq) = unsafe { (partner::<R, D, AV, AS, false>(a, j), heat_partner(h, j)) };
    let (p, heat_min_r2) = (pair_params::<R, AV, AS>(p), hp.min_r2);
    let Some(g) = geometry::<R, D, PER>(&p, per, o, i, j, &q.x) else { return };
    if let Some(ho) = ho
        && g.r2 >= R::from_f64(heat_min_r2)
    {
        s.heat += brookshaw_term(hp, h, ho, &hq, g.dw.to_f64());
    }
    if o.mech {
        if DMG {
            unsafe { masked_pair_term::<R, D, AV, AS, XSPH, CS>(&p, a, o, q, &g, i, j, &mut s.mech) };
        } else {
            pair_term::<R, D, AV, AS, XSPH, CS>(&p, o, &q, &g, &mut s.mech);
        }
    }
}

/// The rates and Ṫ of sorted particle i from the fused pass, summed by `lanes` lanes combined as the GPU
/// combines them: equal to [`rates`] and `heat::heat_rate` (Brookshaw) bit for bit.
///
/// # Safety
/// As [`pair_sums_heat`].
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub unsafe fn rates_heat<
    R: Real,
    D: TensorOps<R>,
    const AV: bool,
    const AS: bool,
    const XSPH: bool,
    const DMG: bool,
    const CS: bool,
>(
    p: &SphParams<R>,
    hp: &HeatParams,
    nb: &Neighbours,
    a: &Arrays<R, D>,
    h: &HeatArrays<R, D::Vec<R>>,
    i: u32,
    lanes: u32,
) -> (Rates<R, D>, f64) {
    unsafe {
        let o = own::<R, D, AV, AS, CS>(a, i);
        let ho = heat_own(h, i);
        let sums = if !o.mech && ho.is_none() {
            HeatPairSums::default()
        } else {
            let per = Period::<R>::of::<D>(nb.grid);
            unswitch_period!(per, PER =>
                all_lanes::<R, D::Vec<R>, _, _>(nb, &o.x, i, lanes, |j, s: &mut HeatPairSums<R, D>| {
                    heat_and_pair::<R, D, AV, AS, XSPH, DMG, CS, PER>(p, hp, &per, a, h, &o, ho.as_ref(), i, j, s)
                })
            )
        };
        (finish_rates::<R, D, XSPH, DMG>(p, a, i, &sums.mech), heat_finish(hp, h, i, sums.heat))
    }
}

/// The rates of sorted particle i from its pair sums. The tool's contact forces of the previous step's contact
/// pass add v̇ += (f_c + f_t)/m_i (roethlin-solver.md §5.2 step 9). Boundary conditions are imposed here: a fixed
/// particle gets ẋ = v̇ = 0, a prescribed-velocity particle ẋ = v_bc and v̇ = 0 (its velocity was set to v_bc at
/// the start); a thermal-only particle moves likewise and keeps its density and stress (ρ̇ = 0, Ṡ = 0); a particle
/// held in plane strain (3D) gets ẋ_z = v̇_z = 0 and [`TensorOps::plane_strain`].
///
/// # Safety
/// As [`rates`].
#[inline(always)]
pub unsafe fn finish_rates<R: Real, D: TensorOps<R>, const XSPH: bool, const DMG: bool>(
    p: &SphParams<R>,
    a: &Arrays<R, D>,
    i: u32,
    sums: &PairSums<R, D>,
) -> Rates<R, D> {
    let iu = i as usize;
    if DMG && unsafe { *a.mask.add(iu) } < 0.0 {
        // Deleted by damage (`damage::switches::DELETE`): out of the interactions, it keeps its last position.
        return Rates::default();
    }
    let (vi, rhoi) = unsafe { (*a.vel.add(iu), *a.rho.add(iu)) };
    let (mut l, mut acc, xsph) = (sums.l, sums.acc, sums.xsph);
    let fl = unsafe { *a.flags.add(iu) };
    let kind = fl & flags::KIND_MASK;
    let plane = kind == flags::PLANE && D::D == 3;
    if plane {
        D::plane_strain(&mut l);
    }
    if !a.normal.is_null() && fl & flags::THERMAL_ONLY == 0 {
        let (f_n, f_t, m) = unsafe { (*a.normal.add(iu), *a.friction.add(iu), *a.mass.add(iu)) };
        let inv_m = R::ONE / m;
        axpy(&mut acc, inv_m, &f_n);
        axpy(&mut acc, inv_m, &f_t);
    }
    let si = unsafe { *a.stress.add(iu) };
    let mut out = Rates::<R, D> {
        pos_t: vi,
        vel_t: acc,
        rho_t: -rhoi * D::trace(&l),
        stress_t: D::jaumann(&l, &si, p.shear),
        dissipation_t: sums.dissipation,
        av_switch: balsara::<R, D>(p, &l, rhoi),
    };
    if XSPH {
        axpy(&mut out.pos_t, p.xsph_eps, &xsph);
        // The PIC-damping analogue (Eq. 8 with the smoothed velocity for v_g→p): XSPH's sum is v̄_i − v_i where the
        // kernel is whole. α = 0 adds exact zeros.
        axpy(&mut out.vel_t, p.pic_alpha, &xsph);
    }
    if fl & flags::THERMAL_ONLY != 0 {
        out.rho_t = R::ZERO;
        out.stress_t = Default::default();
    }
    if kind == flags::FIXED {
        out.pos_t = Default::default();
        out.vel_t = Default::default();
    } else if kind == flags::VELOCITY {
        let idx = ((fl >> flags::VEL_INDEX_SHIFT) & flags::VEL_INDEX_MASK) as usize;
        out.pos_t = unsafe { *a.bc_vel.add(idx) };
        out.vel_t = Default::default();
    } else if plane {
        out.pos_t = D::Vec::<R>::new([out.pos_t.get(0), out.pos_t.get(1), R::ZERO]);
        out.vel_t = D::Vec::<R>::new([out.vel_t.get(0), out.vel_t.get(1), R::ZERO]);
    }
    out
}

/// The rates of sorted particle i, summed by `lanes` lanes combined as the GPU combines them (`sph::lanes`).
///
/// # Safety
/// All arrays hold the sorted particles of the cell list (and Verlet list) `nb`; `i` is in range; `art` and `sound`
/// are valid when AS and AV are on.
#[inline(always)]
pub unsafe fn rates<
    R: Real,
    D: TensorOps<R>,
    const AV: bool,
    const AS: bool,
    const XSPH: bool,
    const DMG: bool,
    const CS: bool,
    const CUT: bool,
>(
    p: &SphParams<R>,
    nb: &Neighbours,
    a: &Arrays<R, D>,
    i: u32,
    lanes: u32,
) -> Rates<R, D> {
    unsafe {
        let o = own::<R, D, AV, AS, CS>(a, i);
        let sums = if o.mech {
            let per = Period::<R>::of::<D>(nb.grid);
            unswitch_period!(per, PER =>
                all_lanes::<R, D::Vec<R>, _, _>(nb, &o.x, i, lanes, |j, s| {
                    add_pair::<R, D, AV, AS, XSPH, DMG, CS, CUT, PER>(p, &per, a, &o, i, j, s)
                })
            )
        } else {
            PairSums::default()
        };
        finish_rates::<R, D, XSPH, DMG>(p, a, i, &sums)
    }
}
