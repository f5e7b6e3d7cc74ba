//! Energies and momenta of a particle, for the diagnostics of every output step.
//!
//! Kinetic ½ m v². Stored elastic energy of the linear hypoelastic model per particle, V (S:S/(4G) + p²/(2K)),
//! with V = m/ρ: the deviatoric part S:S/(4G) and the volumetric part ½ K ε_v² with ε_v = p/K, exact for the
//! small elastic strains the model assumes (roethlin-solver.md §2.3).

use super::interact::pressure_of;
use super::params::SphParams;
use super::tensor::TensorOps;
use crate::real::Real;
use crate::vector::Vector;

#[inline(always)]
pub fn kinetic<R: Real, V: Vector<R>>(m: R, v: &V) -> R {
    let mut s = R::ZERO;
    for k in 0..V::DIM {
        s += v.get(k) * v.get(k);
    }
    R::from_f64(0.5) * m * s
}

#[inline(always)]
pub fn elastic<R: Real, D: TensorOps<R>>(p: &SphParams<R>, m: R, rho: R, s: &D::Sym<R>) -> R {
    elastic_at::<R, D>(p, m, rho, s, None)
}

/// The same with the temperature of a run with thermal expansion (the pressure is the mechanical one).
#[inline(always)]
pub fn elastic_at<R: Real, D: TensorOps<R>>(p: &SphParams<R>, m: R, rho: R, s: &D::Sym<R>, temp: Option<f64>) -> R {
    elastic_damaged_at::<R, D>(p, m, rho, s, temp, 0.0)
}

/// The elastic energy of a particle with damage D (docs/damage.md, "Energy"; klippel §2.6, Eqs. 7.27–7.28, the
/// interaction's `prepare_damaged`): V ψ with ψ of `damage::elastic_density` at k = exp(−D)
/// (`damage::multiplier`, 0 at full damage), V (k S:S/(4G) + k_p p²/(2K)), k_p = k in tension, 1 in compression:
/// the energy of the degraded stress kS in the damaged moduli kG, kK. D = 0 gives the undamaged energy bit for
/// bit (k = 1).
#[inline(always)]
pub fn elastic_damaged_at<R: Real, D: TensorOps<R>>(
    p: &SphParams<R>,
    m: R,
    rho: R,
    s: &D::Sym<R>,
    temp: Option<f64>,
    damage: f64,
) -> R {
    let pr = pressure_of(p, rho, temp);
    let k = R::from_f64(crate::damage::multiplier(damage));
    let vol = m / rho;
    vol * crate::damage::elastic_density(k, D::double_dot(s), p.shear, pr, p.bulk)
}

/// Von Mises equivalent stress √(3/2 S:S).
#[inline(always)]
pub fn von_mises<R: Real, D: TensorOps<R>>(s: &D::Sym<R>) -> R {
    (R::from_f64(1.5) * D::double_dot(s)).sqrt()
}
