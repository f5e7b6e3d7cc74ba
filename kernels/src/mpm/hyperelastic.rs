//! The specimen's material in Nairn's cutting simulations (nairn-mpm.md §1.4): neo-Hookean hyperelasticity with
//! J2 plasticity and linear hardening, in plane strain, updated on the isochoric elastic left Cauchy–Green tensor
//! B̄_e by Simo's radial return.

use crate::material::return_map::SQRT_2_3;
use crate::real::Real;
use bytemuck::{Pod, Zeroable};

/// K, G, σ_y0 and the plastic modulus E_p = E E_T/(E − E_T) (nairn-mpm.md §1.4, Eq. 2; §2 for the paper's values).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct NeoHookeanJ2 {
    /// Bulk modulus K [Pa].
    pub bulk: f64,
    /// Shear modulus G [Pa].
    pub shear: f64,
    /// Initial yield stress σ_y0 [Pa].
    pub yield_stress: f64,
    /// Plastic modulus E_p [Pa]: f(ε) = σ_y0 + E_p ε.
    pub plastic_modulus: f64,
}

impl NeoHookeanJ2 {
    /// The plastic modulus E_p = E E_T/(E − E_T) of Young's modulus E and a tangent modulus E_T (nairn-mpm.md
    /// §1.4).
    pub fn plastic_modulus_of(young: f64, tangent: f64) -> f64 {
        young * tangent / (young - tangent)
    }
}

/// The cube root of a > 0 by Newton's iteration from 1, a fixed six steps: exact to rounding for the relative
/// volume change of one step (|a − 1| ≪ 1), and the same operations on every backend (no `cbrt` in `core`).
#[inline(always)]
pub fn cbrt_near_one<R: Real>(a: R) -> R {
    let three = R::from_f64(3.0);
    let mut c = R::ONE;
    let mut k = 0;
    while k < 6 {
        c = c - (c * c * c - a) / (three * c * c);
        k += 1;
    }
    c
}

/// The relative deformation gradient of one step, f = I + L Δt (in-plane; f_zz = 1, plane strain).
#[inline(always)]
pub fn relative_gradient<R: Real>(l: [[R; 2]; 2], dt: R) -> [[R; 2]; 2] {
    [[R::ONE + l[0][0] * dt, l[0][1] * dt], [l[1][0] * dt, R::ONE + l[1][1] * dt]]
}

/// det f of an in-plane gradient (f_zz = 1): the step's volume ratio J_f.
#[inline(always)]
pub fn det<R: Real>(f: [[R; 2]; 2]) -> R {
    f[0][0] * f[1][1] - f[0][1] * f[1][0]
}

/// One step of the material: the relative deformation gradient f ([`relative_gradient`]) updates
/// B̄_e (xx, xy, yy, zz) and J; the trial deviatoric Kirchhoff stress s = G dev B̄_e is returned to the yield
/// surface ‖s‖ = √(2/3)(σ_y0 + E_p ε) by Simo's radial return (nairn-mpm.md §1.4 steps 1–4), with
/// Δγ = φ/(2μ̄(1 + E_p/(3μ̄))), μ̄ = G tr(B̄_e)/3, ε += √(2/3) Δγ and B̄_e = s/G + (tr B̄_e/3) I. Returns the Cauchy
/// stress σ = τ/J, τ = (K/2)(J² − 1) I + s (xx, xy, yy, zz).
#[inline(always)]
pub fn update<R: Real>(m: &NeoHookeanJ2, f: [[R; 2]; 2], be: &mut [R; 4], jac: &mut R, eps: &mut R) -> [R; 4] {
    let one = R::ONE;
    let [[f00, f01], [f10, f11]] = f;
    let jf = det(f);
    let c = cbrt_near_one(jf);
    // f̄ = f / J_f^{1/3}; f̄_zz = 1/J_f^{1/3}.
    let (g00, g01, g10, g11, gzz) = (f00 / c, f01 / c, f10 / c, f11 / c, one / c);
    let [bxx, bxy, byy, bzz] = *be;
    // B̄_tr = f̄ B̄ f̄ᵀ (in-plane 2×2 block, zz apart).
    let (t00, t01) = (g00 * bxx + g01 * bxy, g00 * bxy + g01 * byy);
    let (t10, t11) = (g10 * bxx + g11 * bxy, g10 * bxy + g11 * byy);
    let nxx = t00 * g00 + t01 * g01;
    let nxy = t00 * g10 + t01 * g11;
    let nyy = t10 * g10 + t11 * g11;
    let nzz = gzz * bzz * gzz;
    *jac *= jf;
    let g = R::from_f64(m.shear);
    let ibar = (nxx + nyy + nzz) / R::from_f64(3.0);
    let mut s = [g * (nxx - ibar), g * nxy, g * (nyy - ibar), g * (nzz - ibar)];
    let norm = (s[0] * s[0] + s[2] * s[2] + s[3] * s[3] + R::from_f64(2.0) * s[1] * s[1]).sqrt();
    let r23 = R::from_f64(SQRT_2_3);
    let ep = R::from_f64(m.plastic_modulus);
    let phi = norm - r23 * (R::from_f64(m.yield_stress) + ep * *eps);
    if phi > R::ZERO {
        let mubar = g * ibar;
        let dgamma = phi / (R::from_f64(2.0) * mubar * (one + ep / (R::from_f64(3.0) * mubar)));
        let k = one - R::from_f64(2.0) * mubar * dgamma / norm;
        s = [s[0] * k, s[1] * k, s[2] * k, s[3] * k];
        *eps += r23 * dgamma;
        *be = [s[0] / g + ibar, s[1] / g, s[2] / g + ibar, s[3] / g + ibar];
    } else {
        *be = [nxx, nxy, nyy, nzz];
    }
    let j = *jac;
    let p = R::from_f64(0.5 * m.bulk) * (j * j - one);
    [(p + s[0]) / j, s[1] / j, (p + s[2]) / j, (p + s[3]) / j]
}

/// The strain energy per reference volume W = (K/2)(½(J² − 1) − ln J) + (G/2)(tr B̄_e − 3) (nairn-mpm.md §1.4,
/// Eq. 1), with ln J given by the caller (the kernels have no logarithm): the energy balances of tests/mpm.rs.
#[inline(always)]
pub fn strain_energy(m: &NeoHookeanJ2, be: [f64; 4], jac: f64, ln_jac: f64) -> f64 {
    0.5 * m.bulk * (0.5 * (jac * jac - 1.0) - ln_jac) + 0.5 * m.shear * (be[0] + be[2] + be[3] - 3.0)
}
