//! A Gaussian-process regression for the Bayesian optimiser: Matérn 5/2 kernel with one length scale (chosen from
//! a grid by the log marginal likelihood) on standardised values, with a noise term: Klippel's fixed 1e-5 (the SPH is
//! deterministic; klippel-constitutive.md §6.1), or chosen with the length by the same likelihood from a grid, for
//! objectives whose runs scatter (a chaotic cut: docs/identification.md "Noise"). Dense Cholesky; n stays in the
//! hundreds.

/// k(r) = (1 + √5 r/ℓ + 5r²/(3ℓ²)) exp(−√5 r/ℓ), unit signal variance.
pub fn matern52(a: &[f64], b: &[f64], length: f64) -> f64 {
    let r = a.iter().zip(b).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt() / length;
    let s = 5f64.sqrt() * r;
    (1.0 + s + s * s / 3.0) * (-s).exp()
}

/// Lower-triangular L with L Lᵀ = A (row-major n×n), or None when A is not positive definite.
pub fn cholesky(a: &[f64], n: usize) -> Option<Vec<f64>> {
    let mut l = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..=i {
            let mut s = a[i * n + j];
            for k in 0..j {
                s -= l[i * n + k] * l[j * n + k];
            }
            if i == j {
                if s <= 0.0 || !s.is_finite() {
                    return None;
                }
                l[i * n + i] = s.sqrt();
            } else {
                l[i * n + j] = s / l[j * n + j];
            }
        }
    }
    Some(l)
}

/// Solves L y = b (forward substitution).
fn forward(l: &[f64], n: usize, b: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; n];
    for i in 0..n {
        let s: f64 = (0..i).map(|k| l[i * n + k] * y[k]).sum();
        y[i] = (b[i] - s) / l[i * n + i];
    }
    y
}

/// Solves Lᵀ x = y (back substitution).
fn backward(l: &[f64], n: usize, y: &[f64]) -> Vec<f64> {
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        let s: f64 = (i + 1..n).map(|k| l[k * n + i] * x[k]).sum();
        x[i] = (y[i] - s) / l[i * n + i];
    }
    x
}

/// A fitted process: predictions of the mean and standard deviation in the data's units.
pub struct Gp {
    x: Vec<Vec<f64>>,
    l: Vec<f64>,
    alpha: Vec<f64>,
    length: f64,
    noise: f64,
    mean: f64,
    scale: f64,
}

/// Length scales tried (unit-cube coordinates).
const LENGTHS: [f64; 8] = [0.05, 0.1, 0.15, 0.2, 0.3, 0.5, 0.8, 1.2];

/// Noise variances tried when the noise is fitted (on standardised values: a fraction of the data's variance).
pub const NOISES: [f64; 9] = [1e-6, 1e-5, 1e-4, 1e-3, 3e-3, 1e-2, 3e-2, 0.1, 0.3];

impl Gp {
    /// Fits to (x, y) with the noise (a variance, on standardised values) and the length scale of largest marginal
    /// likelihood among `noises` × the length grid; None if no covariance matrix factorises (duplicate points with
    /// no noise).
    pub fn fit(x: &[Vec<f64>], y: &[f64], noises: &[f64]) -> Option<Gp> {
        let n = y.len();
        let mean = y.iter().sum::<f64>() / n as f64;
        let var = y.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n as f64;
        let scale = if var > 0.0 { var.sqrt() } else { 1.0 };
        let z: Vec<f64> = y.iter().map(|v| (v - mean) / scale).collect();
        let mut best: Option<(f64, Gp)> = None;
        for &length in &LENGTHS {
            // The kernel matrix once per length; each noise only adds to its diagonal.
            let mut kernel = vec![0.0; n * n];
            for i in 0..n {
                for j in 0..n {
                    kernel[i * n + j] = matern52(&x[i], &x[j], length);
                }
            }
            for &noise in noises {
                let mut k = kernel.clone();
                for i in 0..n {
                    k[i * n + i] += noise + 1e-10;
                }
                let Some(l) = cholesky(&k, n) else { continue };
                let alpha = backward(&l, n, &forward(&l, n, &z));
                // log p(z) = −½ zᵀα − Σ ln L_ii − n/2 ln 2π (the constant is dropped).
                let fit = -0.5 * z.iter().zip(&alpha).map(|(a, b)| a * b).sum::<f64>()
                    - (0..n).map(|i| l[i * n + i].ln()).sum::<f64>();
                if best.as_ref().is_none_or(|(b, _)| fit > *b) {
                    best = Some((fit, Gp { x: x.to_vec(), l, alpha, length, noise, mean, scale }));
                }
            }
        }
        best.map(|(_, g)| g)
    }

    /// The chosen noise variance in the data's units (squared).
    pub fn noise_variance(&self) -> f64 {
        self.noise * self.scale * self.scale
    }

    /// Posterior mean and standard deviation at `p`.
    pub fn predict(&self, p: &[f64]) -> (f64, f64) {
        let n = self.x.len();
        let ks: Vec<f64> = self.x.iter().map(|xi| matern52(xi, p, self.length)).collect();
        let mu = ks.iter().zip(&self.alpha).map(|(a, b)| a * b).sum::<f64>();
        let v = forward(&self.l, n, &ks);
        let var = (1.0 - v.iter().map(|a| a * a).sum::<f64>()).max(0.0);
        (self.mean + self.scale * mu, self.scale * var.sqrt())
    }
}

/// The standard normal density.
pub fn normal_pdf(z: f64) -> f64 {
    (-0.5 * z * z).exp() / (2.0 * std::f64::consts::PI).sqrt()
}

/// The standard normal distribution function, through erfc (Numerical Recipes' Chebyshev fit, relative error
/// below 1.2e-7: ample for an acquisition function).
pub fn normal_cdf(z: f64) -> f64 {
    0.5 * erfc(-z / std::f64::consts::SQRT_2)
}

fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let poly = -z * z - 1.26551223
        + t * (1.00002368
            + t * (0.37409196
                + t * (0.09678418
                    + t * (-0.18628806
                        + t * (0.27886807
                            + t * (-1.13520398 + t * (1.48851587 + t * (-0.82215223 + t * 0.17087277))))))));
    let r = t * poly.exp();
    if x >= 0.0 { r } else { 2.0 - r }
}

/// Expected improvement below `best` (minimisation) of a normal prediction (μ, s), with exploration margin ξ.
pub fn expected_improvement(mu: f64, s: f64, best: f64, xi: f64) -> f64 {
    if s <= 0.0 {
        return (best - mu - xi).max(0.0);
    }
    let z = (best - mu - xi) / s;
    (best - mu - xi) * normal_cdf(z) + s * normal_pdf(z)
}
