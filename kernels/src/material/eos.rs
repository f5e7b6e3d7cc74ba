//! The reference density of the EOS p = c0² (ρ − ρ0(T)), with the thermal expansion of a run that models it:
//! one formula for the SPH pre-pass (`sph::interact::pressure_at`) and the damage's triaxiality
//! (`sph::plastic`; klippel-constitutive.md §2.6), so that both read the same pressure (docs/solver.md).

/// ρ0(T) = ρ0/(1 + 3α (T − T0)), `expansion` = 3α [1/K] (0: no expansion, ρ0 itself) and T0 its reference
/// temperature [K].
#[inline(always)]
pub fn reference_density(rho0: f64, expansion: f64, t0: f64, temp: f64) -> f64 {
    if expansion == 0.0 { rho0 } else { rho0 / (1.0 + expansion * (temp - t0)) }
}
