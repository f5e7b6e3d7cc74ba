//! Constitutive models: flow stress (Johnson–Cook family, Sima–Özel, SCGL, bilinear) and the radial return, always
//! in f64 (the return "converges reliably only in f64": roethlin-solver.md §2.4, klippel-constitutive.md §2.2).
//!
//! Units everywhere: σ_y in Pa, ε̄ (equivalent plastic strain) dimensionless, ε̄̇ in 1/s, T in K.
//!
//! Every model is a `#[repr(C)]` Pod parameter struct implementing [`FlowStress`]; the radial return
//! ([`return_map::radial_return`]) is generic over it, so the same code runs on the CPU and, through the
//! `ptx_probe` entry points, on the GPU. Nothing here can panic: no indexing, no integer division, and the
//! transcendental functions come from `libm` (pure Rust, so host and GPU evaluate the same instructions).
//!
//! Common conventions of all models (each model's doc says how it applies them):
//! * **Temperature**: clamped to T ≤ T_m − 1 K inside σ_y ([C3D]'s choice, roethlin-solver.md §2.4), so the
//!   thermal factor stays positive and finite at and above the melt; T below the reference temperature gives no
//!   thermal hardening (θ = 0, klippel-constitutive.md §2.1). SCGL is the exception: its shear modulus drops to 0
//!   at the (pressure-dependent) melt, so σ_y = 0 there (klippel §2.4, "μ is set to 0 as T → T_f").
//! * **Low rates**: the Johnson–Cook rate factor never softens below the reference rate: either the ln form with
//!   ε̇* clamped ≥ 1 (erratum 9's clamp, Klippel's VUMAT floor) or the Uintah form (1 + ε̇*)^C for ε̇* ≤ 1
//!   ([C2D], Klippel Eq. 7.20). Both give the factor 1 at ε̇ = 0, which the elastic check uses.
//! * **Zero strain**: ε̄ⁿ with n < 1 has an infinite slope at ε̄ = 0; the derivatives are evaluated at
//!   max(ε̄, [`STRAIN_FLOOR`]) so that they stay finite (the value itself uses ε̄ as given).
//! * σ_y is clamped at 0 from below (NaN propagates); where the clamp is active the derivatives are 0.

pub mod bilinear;
pub mod c2d_return;
pub mod eos;
pub mod johnson_cook;
pub mod return_map;
pub mod scgl;
pub mod tanh;

pub use bilinear::Bilinear;
pub use c2d_return::c2d_return;
pub use johnson_cook::{JohnsonCook, RATE_FORM_CLAMP, RATE_FORM_UINTAH};
pub use return_map::{
    ReturnOptions, ReturnResult, ReturnStatus, Solver, deviatoric_norm, heated_temperature, plastic_heating,
    radial_return, von_mises,
};
pub use scgl::Scgl;
pub use tanh::{Calamaz2008, Calamaz2010, Calamaz2011, SimaOzel1, SimaOzel2, SimaOzel3};

use crate::real::Real;

/// ε̄ below which the strain derivatives are evaluated at this value instead (ε̄ⁿ has an infinite slope at 0 for
/// n < 1; with n = 0.34 the slope at 1e-12 is ≈ 1e8·B, large but finite, which is all Newton needs).
pub const STRAIN_FLOOR: f64 = 1e-12;

/// The flow stress and its two partial derivatives at one (ε̄, ε̄̇, T).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Flow {
    /// σ_y [Pa].
    pub sigma: f64,
    /// ∂σ_y/∂ε̄ at fixed ε̄̇ and T [Pa].
    pub d_eps: f64,
    /// ∂σ_y/∂ε̄̇ at fixed ε̄ and T [Pa·s].
    pub d_rate: f64,
}

impl Flow {
    /// The total derivative along the return-map path ε̄ = ε̄₀ + Δε̄, ε̄̇ = Δε̄/Δt:
    /// dσ_y/dΔε̄ = ∂σ_y/∂ε̄ + (∂σ_y/∂ε̄̇)/Δt (klippel-constitutive.md §2.2, Eqs. 7.10–7.15).
    #[inline(always)]
    pub fn path_slope(&self, dt: f64) -> f64 {
        self.d_eps + self.d_rate / dt
    }

    /// All zero (σ_y clamped at 0: no strength, no slope).
    pub const ZERO: Flow = Flow { sigma: 0.0, d_eps: 0.0, d_rate: 0.0 };

    /// Applies the σ_y ≥ 0 clamp: a negative σ_y becomes 0 with zero slopes; NaN passes through.
    #[inline(always)]
    pub(crate) fn clamped(self) -> Flow {
        if self.sigma < 0.0 { Flow::ZERO } else { self }
    }
}

/// A flow-stress model σ_y(ε̄, ε̄̇, T).
///
/// Newton's derivative: the return map varies ε̄ and ε̄̇ together (ε̄ = ε̄₀ + Δε̄, ε̄̇ = Δε̄/Δt), so it needs
/// dσ_y/dΔε̄ = ∂σ_y/∂ε̄ + (∂σ_y/∂ε̄̇)/Δt. A model therefore provides both partials ([`FlowStress::flow`]);
/// [`FlowStress::path_slope`] combines them with Δt. The partials are separate so each can be checked against
/// finite differences and so that the rate term's 1/Δt is applied in exactly one place.
pub trait FlowStress {
    /// σ_y [Pa], ≥ 0 (or NaN for NaN input), finite for finite input.
    fn sigma_y(&self, eps: f64, rate: f64, temp: f64) -> f64;

    /// σ_y and its partials ∂σ_y/∂ε̄ (fixed rate) and ∂σ_y/∂ε̄̇ (fixed strain) in one evaluation. At a kink of a
    /// clamp the one-sided derivative of the branch that `sigma_y` evaluates is returned.
    fn flow(&self, eps: f64, rate: f64, temp: f64) -> Flow;

    /// The temperature at which the model's strength vanishes (or is clamped) [K].
    fn melt_temperature(&self) -> f64;

    /// The part of [`FlowStress::flow`] that depends on the temperature alone, for a return at a temperature held
    /// fixed (roethlin-solver.md §2.4: T is frozen during the return): evaluated once per return instead of once per
    /// Newton iteration, and handed to [`FlowStress::flow_at`]. Johnson–Cook's 1 − θᵐ (a `pow`); the models that
    /// do not split (the default) return NaN, which `flow_at` ignores.
    #[inline(always)]
    fn thermal_part(&self, temp: f64) -> f64 {
        let _ = temp;
        f64::NAN
    }

    /// [`FlowStress::flow`] with `thermal` = [`FlowStress::thermal_part`] at the same `temp`: the same result bit for
    /// bit.
    #[inline(always)]
    fn flow_at(&self, eps: f64, rate: f64, temp: f64, thermal: f64) -> Flow {
        let _ = thermal;
        self.flow(eps, rate, temp)
    }

    /// [`FlowStress::flow_at`] and the [`FlowStress::strength_part`] of its σ_y at the same (ε̄, ε̄̇), bit for bit: the
    /// return map's last Newton evaluation hands both on as its result's, instead of evaluating them again. The
    /// default's strength is NaN (the models that do not split).
    #[inline(always)]
    fn flow_and_strength_at(&self, eps: f64, rate: f64, temp: f64, thermal: f64) -> (Flow, f64) {
        (self.flow_at(eps, rate, temp, thermal), f64::NAN)
    }

    /// The part of σ_y that depends on ε̄ and ε̄̇ alone, for a model whose σ_y is their product with
    /// [`FlowStress::thermal_part`] (Johnson–Cook's (A + B ε̄ⁿ)(1 + C ln ε̄̇*)); NaN for the models that do not split
    /// (the default), which [`FlowStress::sigma_y_parts`] ignores.
    #[inline(always)]
    fn strength_part(&self, eps: f64, rate: f64) -> f64 {
        let _ = (eps, rate);
        f64::NAN
    }

    /// [`FlowStress::sigma_y`] from `strength` = [`FlowStress::strength_part`] at (ε̄, ε̄̇) and `thermal` =
    /// [`FlowStress::thermal_part`] at T: the same result bit for bit, so that a caller that holds either part (the
    /// return map's frozen temperature, the plastic update's σ_y before and after its heating) does not evaluate it
    /// again. The default ignores the parts.
    #[inline(always)]
    fn sigma_y_parts(&self, eps: f64, rate: f64, temp: f64, strength: f64, thermal: f64) -> f64 {
        let _ = (strength, thermal);
        self.sigma_y(eps, rate, temp)
    }

    /// ∂σ_y/∂ε̄ at fixed ε̄̇ and T [Pa]; evaluated at max(ε̄, [`STRAIN_FLOOR`]) where ε̄ⁿ is singular.
    #[inline(always)]
    fn d_sigma_d_eps(&self, eps: f64, rate: f64, temp: f64) -> f64 {
        self.flow(eps, rate, temp).d_eps
    }

    /// ∂σ_y/∂ε̄̇ at fixed ε̄ and T [Pa·s].
    #[inline(always)]
    fn d_sigma_d_rate(&self, eps: f64, rate: f64, temp: f64) -> f64 {
        self.flow(eps, rate, temp).d_rate
    }

    /// The total derivative along the return-map path, d σ_y(ε̄₀ + Δε̄, Δε̄/Δt, T)/dΔε̄ evaluated at
    /// ε̄ = ε̄₀ + Δε̄, ε̄̇ = Δε̄/Δt: ∂σ_y/∂ε̄ + (∂σ_y/∂ε̄̇)/Δt [Pa]. This is what Newton uses.
    #[inline(always)]
    fn path_slope(&self, eps: f64, rate: f64, temp: f64, dt: f64) -> f64 {
        self.flow(eps, rate, temp).path_slope(dt)
    }
}

// Small scalar helpers shared by the models. min/max written out so that NaN propagates from the first argument
// and nothing depends on the platform's minNum semantics.

#[inline(always)]
pub(crate) fn fmax(a: f64, b: f64) -> f64 {
    if b > a { b } else { a }
}

#[inline(always)]
pub(crate) fn fmin(a: f64, b: f64) -> f64 {
    if b < a { b } else { a }
}

#[inline(always)]
pub(crate) fn sqrt(x: f64) -> f64 {
    <f64 as Real>::sqrt(x)
}

/// x^y for x ≥ 0, as exp(y ln x): 0^y = 0 for y > 0 and +∞ for y < 0; x⁰ = 1 and x¹ = x exactly.
/// Not `libm::pow`: its y = 0.5 branch calls libm's software sqrt, whose lookup table is a `static` of the libm
/// crate and would stay an unresolved `.extern` in the PTX. The relative error is ≈ 2ε·|y ln x| (≤ 1e-13 for
/// every exponent and argument the models use).
#[inline(always)]
pub(crate) fn pow(x: f64, y: f64) -> f64 {
    if y == 0.0 {
        1.0
    } else if y == 1.0 {
        x
    } else {
        libm::exp(y * libm::log(x))
    }
}

/// (x^y1, x^y2) for x ≥ 0, bit for bit [`pow`]'s, with one logarithm where both need it.
#[inline(always)]
pub(crate) fn pow_pair(x: f64, y1: f64, y2: f64) -> (f64, f64) {
    let general = |y: f64| y != 0.0 && y != 1.0;
    if general(y1) && general(y2) {
        let l = libm::log(x);
        (libm::exp(y1 * l), libm::exp(y2 * l))
    } else {
        (pow(x, y1), pow(x, y2))
    }
}

/// Temperature used inside σ_y: T clamped to ≤ T_m − 1 K (roethlin-solver.md §2.4, [C3D]). NaN passes through.
#[inline(always)]
pub(crate) fn clamp_below_melt(temp: f64, melt: f64) -> f64 {
    let top = melt - 1.0;
    if temp > top { top } else { temp }
}

/// sech²(x) for x ≥ 0, accurate also where 1 − tanh²(x) would round to 0; 0 for x > 350 (and for +inf).
#[inline(always)]
pub(crate) fn sech2(x: f64) -> f64 {
    if x > 350.0 {
        0.0
    } else {
        let t = libm::exp(-2.0 * x);
        4.0 * t / ((1.0 + t) * (1.0 + t))
    }
}

/// GPU entry points over arrays, one per model: the radial return with the default options (Newton, relative
/// tolerance 1e-12, at most 100 iterations). They are the GPU benchmark of the return map and the GPU side of the
/// GPU-against-CPU check (the CPU twin is [`radial_return`] with [`ReturnOptions::default`]).
///
/// Arguments: `n` states; `params` one parameter block (device memory); per state the 3D deviatoric trial stress
/// (xx, xy, xz, yy, yz, zz; plane strain has xz = yz = 0 and carries zz), ε̄_old, ε̄̇_old (used only for the initial
/// guess) and T; the shear modulus G [Pa] and Δt [s]. Outputs: S_new, ε̄_new, ε̄̇_new and the iteration count
/// with bit 31 set when the iteration cap was reached ([`ReturnResult::packed_iterations`]).
#[cfg(target_arch = "nvptx64")]
pub mod ptx_probe {
    use super::*;

    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    unsafe fn run<M: FlowStress>(
        n: u32,
        params: *const M,
        s_trial: *const [f64; 6],
        eps: *const f64,
        rate: *const f64,
        temp: *const f64,
        shear: f64,
        dt: f64,
        s_out: *mut [f64; 6],
        eps_out: *mut f64,
        rate_out: *mut f64,
        iters_out: *mut u32,
    ) {
        use core::arch::nvptx::*;
        let i = unsafe { _block_idx_x() * _block_dim_x() + _thread_idx_x() };
        if i < n {
            let i = i as usize;
            // SAFETY: the caller passes arrays of n elements and one parameter block.
            unsafe {
                let r = radial_return(
                    &*params,
                    &*s_trial.add(i),
                    *eps.add(i),
                    *rate.add(i),
                    *temp.add(i),
                    shear,
                    dt,
                    &ReturnOptions::DEFAULT,
                );
                *s_out.add(i) = r.stress;
                *eps_out.add(i) = r.eps;
                *rate_out.add(i) = r.rate;
                *iters_out.add(i) = r.packed_iterations();
            }
        }
    }

    macro_rules! return_map_entry {
        ($name:ident, $p:ty) => {
            /// Radial return over `n` states with the parameter block `params` (see the module doc).
            #[unsafe(no_mangle)]
            pub unsafe extern "ptx-kernel" fn $name(
                n: u32,
                params: *const $p,
                s_trial: *const [f64; 6],
                eps: *const f64,
                rate: *const f64,
                temp: *const f64,
                shear: f64,
                dt: f64,
                s_out: *mut [f64; 6],
                eps_out: *mut f64,
                rate_out: *mut f64,
                iters_out: *mut u32,
            ) {
                unsafe {
                    run::<$p>(n, params, s_trial, eps, rate, temp, shear, dt, s_out, eps_out, rate_out, iters_out)
                }
            }
        };
    }

    return_map_entry!(swarf_return_map_jc, JohnsonCook);
    return_map_entry!(swarf_return_map_calamaz_2008, Calamaz2008);
    return_map_entry!(swarf_return_map_calamaz_2010, Calamaz2010);
    return_map_entry!(swarf_return_map_calamaz_2011, Calamaz2011);
    return_map_entry!(swarf_return_map_sima_ozel_1, SimaOzel1);
    return_map_entry!(swarf_return_map_sima_ozel_2, SimaOzel2);
    return_map_entry!(swarf_return_map_sima_ozel_3, SimaOzel3);
    return_map_entry!(swarf_return_map_scgl, Scgl);
    return_map_entry!(swarf_return_map_bilinear, Bilinear);
}
