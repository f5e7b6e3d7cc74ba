//! Deriving the kernel constants of a run from the material, the resolution and the stabiliser settings.

use crate::kernels::Real;
use crate::kernels::sph::{CubicSpline, SphParams, Stabilisers};

pub use crate::material::Elastic;

/// The artificial viscosity's constants (roethlin-solver.md §4.1) and its Balsara switch
/// (`kernels::sph::interact::balsara`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Viscosity {
    pub alpha: f64,
    pub beta: f64,
    pub eta: f64,
    pub balsara: bool,
}

/// Stabiliser constants (roethlin-solver.md §4.1 defaults); `Default` is all off.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StabiliserSettings {
    pub viscosity: Option<Viscosity>,
    pub stress: Option<(f64, u32)>,
    pub xsph: Option<f64>,
    /// The CSPM kernel-gradient correction (`kernels::sph::correction`); None: off.
    pub cspm: Option<CspmSettings>,
}

/// The CSPM correction's settings (`[stabilisation.cspm]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CspmSettings {
    /// det B at or below which a particle keeps the plain gradient.
    pub min_det: f64,
    /// Only the particles with a neighbour across the cohesive path are corrected (`scope = "path"`).
    pub path_only: bool,
}

impl StabiliserSettings {
    /// All three on with the theses' constants: α = β = 1, η = 0.1; ε_s = 0.3, n = 4; ε_X = 0.5.
    pub fn theses() -> Self {
        StabiliserSettings {
            viscosity: Some(Viscosity { alpha: 1.0, beta: 1.0, eta: 0.1, balsara: false }),
            stress: Some((0.3, 4)),
            xsph: Some(0.5),
            cspm: None,
        }
    }

    /// Whether the Balsara switch acts (it belongs to the viscosity, so it cannot be on without it).
    pub fn balsara_on(&self) -> bool {
        self.viscosity.is_some_and(|v| v.balsara)
    }

    pub fn switches(&self) -> Stabilisers {
        Stabilisers { viscosity: self.viscosity.is_some(), stress: self.stress.is_some(), xsph: self.xsph.is_some() }
    }
}

/// The parameter block for material `m`, lattice spacing `dx`, smoothing length `h` and dimension `dim`.
pub fn sph_params<R: Real>(m: &Elastic, dx: f64, h: f64, dim: usize, s: &StabiliserSettings) -> SphParams<R> {
    let kernel = CubicSpline::<f64>::new(h, dim);
    let Viscosity { alpha, beta, eta, .. } =
        s.viscosity.unwrap_or(Viscosity { alpha: 0.0, beta: 0.0, eta: 0.1, balsara: false });
    let (eps, exponent) = s.stress.unwrap_or((0.0, 4));
    SphParams {
        kernel: CubicSpline::new(h, dim),
        rho0: R::from_f64(m.density),
        c0sq: R::from_f64(m.bulk_modulus() / m.density),
        bulk: R::from_f64(m.bulk_modulus()),
        shear: R::from_f64(m.shear_modulus()),
        av_alpha: R::from_f64(alpha),
        av_beta: R::from_f64(beta),
        av_eta2h2: R::from_f64(eta * eta * h * h),
        as_eps: R::from_f64(eps),
        as_inv_w_dx: R::from_f64(1.0 / kernel.w(dx)),
        xsph_eps: R::from_f64(s.xsph.unwrap_or(0.0)),
        // Set by the set-up once the step is known (α = (1 − β)/Δt).
        pic_alpha: R::ZERO,
        min_r2: R::from_f64((1e-6 * h) * (1e-6 * h)),
        expansion: R::ZERO,
        expansion_t0: R::ZERO,
        as_exponent: exponent,
        model_flags: 0,
    }
}

/// Stable time step Δt = CFL · h / (c0 + |v|max) (roethlin-solver.md (7.1), erratum 13).
pub fn cfl_time_step(cfl: f64, h: f64, c0: f64, vmax: f64) -> f64 {
    cfl * h / (c0 + vmax)
}
