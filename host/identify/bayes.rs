//! Gaussian-process Bayesian optimisation (klippel-constitutive.md §6.1 "BAYES"): a Latin-hypercube initial
//! design, then each batch maximises the expected improvement of a Matérn 5/2 process (`gp`) over random candidates
//! refined around the best ones; a batch of q points is chosen by the kriging believer (each chosen point joins the
//! data with its predicted mean before the next is chosen), so that q simulations run at once. Klippel's runs
//! stalled because his GP overhead grew to 20 min per iteration; here a fit of a few hundred points takes
//! milliseconds. Non-finite values (failed runs) enter as the worst finite value seen, so the search avoids them.

use super::gp::{Gp, NOISES, expected_improvement};
use super::optimizer::{Optimizer, argmin, key, latin_hypercube};
use crate::rng::SplitMix64;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BayesSettings {
    /// Points of the initial design (0: max(2d + 1, 10)).
    pub initial: usize,
    /// Random candidates per acquisition.
    pub candidates: usize,
    /// Exploration margin ξ of the expected improvement, as a fraction of the values' standard deviation.
    pub xi: f64,
    /// The process's noise (Klippel: a fixed 1e-5).
    pub noise: Noise,
    pub seed: u64,
}

/// The noise term of the process.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Noise {
    /// A fixed variance on standardised values; the improvement is measured from the best value seen.
    Fixed(f64),
    /// Chosen with the length scale by the marginal likelihood (`gp::NOISES`); the improvement is measured from the
    /// smallest posterior mean at the points run, so that one lucky run does not set the bar (the "plug-in" expected
    /// improvement for noisy values).
    Fit,
}

impl Default for BayesSettings {
    fn default() -> Self {
        BayesSettings { initial: 0, candidates: 2000, xi: 1e-3, noise: Noise::Fixed(1e-5), seed: 1 }
    }
}

pub struct Bayes {
    s: BayesSettings,
    d: usize,
    rng: SplitMix64,
    x: Vec<Vec<f64>>,
    y: Vec<f64>,
    design: Vec<Vec<f64>>,
    pending: Vec<Vec<f64>>,
}

impl Bayes {
    pub fn new(d: usize, s: BayesSettings) -> Bayes {
        let mut rng = SplitMix64::new(s.seed);
        let n = if s.initial == 0 { (2 * d + 1).max(10) } else { s.initial };
        let design = latin_hypercube(&mut rng, n, d);
        Bayes { s, d, rng, x: Vec::new(), y: Vec::new(), design, pending: Vec::new() }
    }

    /// The data with failed runs replaced by the worst finite value.
    fn data(&self) -> Vec<f64> {
        let worst = self.y.iter().copied().filter(|v| v.is_finite()).fold(f64::NEG_INFINITY, f64::max);
        let worst = if worst.is_finite() { worst } else { 0.0 };
        self.y.iter().map(|&v| if v.is_finite() { v } else { worst }).collect()
    }

    /// The candidate of largest expected improvement: random points, then Gaussian steps around the best few.
    fn acquire(&mut self, gp: &Gp, best: f64, sd: f64) -> Vec<f64> {
        let xi = self.s.xi * sd;
        let ei = |p: &[f64]| {
            let (mu, sd) = gp.predict(p);
            expected_improvement(mu, sd, best, xi)
        };
        let mut scored: Vec<(f64, Vec<f64>)> = (0..self.s.candidates)
            .map(|_| {
                let p: Vec<f64> = (0..self.d).map(|_| self.rng.uniform()).collect();
                (ei(&p), p)
            })
            .collect();
        scored.sort_by(|a, b| b.0.total_cmp(&a.0));
        scored.truncate(5);
        for entry in scored.iter_mut() {
            for sigma in [0.05, 0.01, 0.002] {
                for _ in 0..20 {
                    let p: Vec<f64> = entry.1.iter().map(|v| (v + sigma * self.rng.normal()).clamp(0.0, 1.0)).collect();
                    let e = ei(&p);
                    if e > entry.0 {
                        *entry = (e, p);
                    }
                }
            }
        }
        scored.sort_by(|a, b| b.0.total_cmp(&a.0));
        scored.into_iter().next().map(|(_, p)| p).unwrap_or_else(|| vec![0.5; self.d])
    }
}

impl Optimizer for Bayes {
    fn name(&self) -> &'static str {
        "Bayesian optimisation"
    }

    fn ask(&mut self, max: usize) -> Vec<Vec<f64>> {
        let max = max.max(1);
        if !self.design.is_empty() {
            let k = max.min(self.design.len());
            self.pending = self.design.drain(..k).collect();
            return self.pending.clone();
        }
        let mut x = self.x.clone();
        let mut y = self.data();
        let mut out = Vec::with_capacity(max);
        for _ in 0..max {
            let noises = match &self.s.noise {
                Noise::Fixed(v) => std::slice::from_ref(v),
                Noise::Fit => &NOISES[..],
            };
            let Some(gp) = Gp::fit(&x, &y, noises) else { break };
            let best = match self.s.noise {
                Noise::Fixed(_) => y.iter().copied().fold(f64::INFINITY, f64::min),
                Noise::Fit => x.iter().map(|p| gp.predict(p).0).fold(f64::INFINITY, f64::min),
            };
            let mean = y.iter().sum::<f64>() / y.len() as f64;
            let sd = (y.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / y.len() as f64).sqrt();
            let p = self.acquire(&gp, best, sd);
            // Kriging believer: the chosen point joins the data with its predicted mean.
            let (mu, _) = gp.predict(&p);
            x.push(p.clone());
            y.push(mu);
            out.push(p);
        }
        self.pending = out.clone();
        out
    }

    fn tell(&mut self, values: &[f64]) {
        for (p, &v) in std::mem::take(&mut self.pending).into_iter().zip(values) {
            self.x.push(p);
            self.y.push(v);
        }
    }

    fn best(&self) -> Option<(Vec<f64>, f64)> {
        if self.y.is_empty() {
            return None;
        }
        let i = argmin(&self.y);
        Some((self.x[i].clone(), key(self.y[i])))
    }
}
