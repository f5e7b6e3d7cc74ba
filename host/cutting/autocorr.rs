//! The integrated autocorrelation time of a sampled signal: how many consecutive samples carry about one sample's
//! worth of independent information, the length the batches of the steady-state rule are matched to.
//!
//! Method (Sokal 1997, "Monte Carlo methods in statistical mechanics: foundations and new algorithms", in
//! Functional Integration, NATO ASI Series B 361, §3, Eqs. 3.17–3.19 and the automatic window of §3; Madras & Sokal
//! 1988, J. Stat. Phys. 50, 109–186): with the sample autocorrelation
//!
//! ρ_k = Σ_{i<n−k} (x_i − x̄)(x_{i+k} − x̄) / Σ_i (x_i − x̄)²,
//!
//! τ_int(M) = 1 + 2 Σ_{k=1}^{M} ρ_k, the variance of the mean of n samples being σ² τ_int / n. The window M is the
//! smallest lag with M ≥ c τ_int(M), c = 5 (Sokal's choice for exponentially decaying correlations), and the sum
//! stops earlier at the first lag where ρ_k ≤ 0 (its first zero crossing: past it the estimate is noise) or at
//! n/2. For an AR(1) series x_{i+1} = φ x_i + ε the exact value is τ_int = (1 + φ)/(1 − φ).

/// Sokal's window factor c.
const WINDOW_FACTOR: f64 = 5.0;

/// τ_int in samples (≥ 1) of `x`; None for fewer than 4 samples, a non-finite value or a constant series.
pub fn integrated_time(x: &[f64]) -> Option<f64> {
    let n = x.len();
    if n < 4 || !x.iter().all(|v| v.is_finite()) {
        return None;
    }
    let mean = x.iter().sum::<f64>() / n as f64;
    let c: Vec<f64> = x.iter().map(|v| v - mean).collect();
    let c0: f64 = c.iter().map(|v| v * v).sum();
    if c0 <= 0.0 {
        return None;
    }
    let mut tau = 1.0;
    for k in 1..n / 2 {
        let rho = c[..n - k].iter().zip(&c[k..]).map(|(a, b)| a * b).sum::<f64>() / c0;
        if rho <= 0.0 {
            break;
        }
        tau += 2.0 * rho;
        if k as f64 >= WINDOW_FACTOR * tau {
            break;
        }
    }
    Some(tau.max(1.0))
}
