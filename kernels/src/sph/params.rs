//! Constants of one SPH run, precomputed on the host and read by the kernels through one small buffer.

use super::kernel::CubicSpline;
use crate::real::Real;
use bytemuck::{Pod, Zeroable};

/// Material and stabiliser constants (roethlin-solver.md §4.1, §3.6; defaults α = β = 1, η = 0.1, ε_s = 0.3,
/// n = 4, ε_X = 0.5). Which stabilisers run is chosen by the entry point (const generics), not read from here.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SphParams<R: Real> {
    pub kernel: CubicSpline<R>,
    /// Reference density ρ0 [kg/m³].
    pub rho0: R,
    /// c0² = K/ρ0 [m²/s²]; the EOS is p = c0² (ρ − ρ0).
    pub c0sq: R,
    /// Bulk modulus K = ρ0 c0² [Pa], for the particle sound speed c_i = √(K/ρ_i) of the viscosity.
    pub bulk: R,
    /// Shear modulus G [Pa].
    pub shear: R,
    /// Monaghan viscosity α, β and η² h² (the regulariser of μ_ij).
    pub av_alpha: R,
    pub av_beta: R,
    pub av_eta2h2: R,
    /// Artificial stress ε_s and 1/W(Δx) (f_ij = W(r)/W(Δx)); the exponent n is `as_exponent`.
    pub as_eps: R,
    pub as_inv_w_dx: R,
    /// XSPH ε_X.
    pub xsph_eps: R,
    /// The PIC-damping analogue's rate α = (1 − β)/Δt [1/s] (nairn-mpm.md §7.2, Eq. 8; 0: off): with XSPH, the
    /// velocity relaxes toward the kernel-smoothed velocity, v̇ += α Σ_j (m_j/ρ̄_ij)(v_j − v_i) W_ij.
    pub pic_alpha: R,
    /// Pairs closer than this (squared) are skipped: coincident particles have no gradient direction
    /// (erratum 31: relative to h, (1e-6 h)², not an absolute 1e-8).
    pub min_r2: R,
    /// Volumetric thermal expansion 3α [1/K] (0: off) and its reference temperature T0 [K]: the EOS uses
    /// ρ0(T) = ρ0/(1 + 3α (T − T0)) (klippel-constitutive.md §1.1 [NOTE]).
    pub expansion: R,
    pub expansion_t0: R,
    pub as_exponent: u32,
    /// Switches of the original code's model ([`model`]; 0: swarf's), set from the scene's `model` only.
    pub model_flags: u32,
}

/// The bits of [`SphParams::model_flags`]: parts of Röthlin's 2D code [C2D] reproduced under the scene's
/// `model = "mfree_iwf"` (docs/validation.md, "The original model"); each is a documented bug or quirk of that code.
pub mod model {
    /// W for XSPH and the artificial stress's f_ij from [`super::CubicSpline::w_c2d`], 0.25 (2 − q)⁶ on 1 < q < 2
    /// (roethlin-solver.md §11 erratum 24), instead of the spline's cube.
    pub const C2D_KERNEL_W: u32 = 1;
    /// The damage mask as Klippel prints it (Eqs. 7.30–7.34: the masked neighbour's v_j F_j and σ_j F_j), instead
    /// of the Galilean-invariant pair cut (`sph::interact`'s masked pair term; `damage.mask_form`).
    pub const MASK_PRINTED: u32 = 2;
}

// SAFETY: repr(C), fields of one float type followed by two u32; R is 4 or 8 bytes, so with 18 floats and two
// u32 there is no padding for f32 (80 bytes) and none for f64 (152 bytes).
unsafe impl<R: Real> Zeroable for SphParams<R> {}
unsafe impl<R: Real> Pod for SphParams<R> {}

/// Stabiliser switches of a run (the interaction entry point is chosen from them).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stabilisers {
    pub viscosity: bool,
    pub stress: bool,
    pub xsph: bool,
}

/// Particle flags: bits 0..3 the mechanical boundary-condition kind, bit 3 open across a cohesive cut plane, bits
/// 4..6 the side of the plane, bit 6 thermal-only, bit 7 a fixed temperature, 8..16 the index
/// into the prescribed-velocity table, 16..32 the body index (materials, output, per-body diagnostics).
pub mod flags {
    pub const BODY_SHIFT: u32 = 16;
    /// Held at its initial temperature (no conduction, no heating).
    pub const FIXED_TEMPERATURE: u32 = 0x80;
    /// A thermal-only particle (the tool's heat sink, roethlin-solver.md §5.6): it moves with its prescribed
    /// velocity, conducts heat, and takes no part in the mechanics (zero mechanical mass, no contact).
    pub const THERMAL_ONLY: u32 = 0x40;
    pub const FREE: u32 = 0;
    pub const FIXED: u32 = 1;
    pub const VELOCITY: u32 = 2;
    /// Held in its x–y plane (3D): the z components of its velocity and position rates are zero, so that its
    /// initial v_z = 0 stays (plane strain, `kind = "plane_strain"`).
    pub const PLANE: u32 = 3;
    pub const KIND_MASK: u32 = 0x07;
    /// Cut from the particles across the cohesive path (`sph::bond`): a pair on opposite sides of it interacts
    /// through the continuum only while neither is open. With `coupling = "bonds"` every sided particle is open
    /// from the start; with `"continuum"` those near the plane open when their column's bond initiates
    /// (`sph::bond::open_particle`).
    pub const OPEN: u32 = 0x08;
    /// The side of the cohesive path (`sph::bond`; docs/mpm.md "The cohesive path in SPH") a particle lies on in
    /// the reference configuration: above or below the plane, within the crack's extent (0: neither). Two
    /// particles on opposite sides, one of them [`OPEN`], do not interact through the continuum; only their bond
    /// couples them.
    pub const SIDE_ABOVE: u32 = 0x10;
    pub const SIDE_BELOW: u32 = 0x20;
    pub const SIDE_MASK: u32 = 0x30;
    /// The bits [`crate::sph::interact::cut_apart`] reads.
    pub const CUT_MASK: u32 = SIDE_MASK | OPEN;
    pub const VEL_INDEX_SHIFT: u32 = 8;
    pub const VEL_INDEX_MASK: u32 = 0xff;
}
