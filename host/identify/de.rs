//! Differential Evolution (Storn and Price; klippel-constitutive.md §6.1, SciPy's `differential_evolution`, which
//! Klippel used): a population of `popsize · d` points, Latin-hypercube initialised; each generation makes one trial
//! per member by mutation (best/1 or rand/1, the scale F dithered in [F_lo, F_hi) per generation) and binomial
//! crossover (rate CR, at least one coordinate from the mutant), and a trial replaces its member when it is no
//! worse. Updating is deferred to the end of the generation (SciPy's `updating = "deferred"`), so a generation's
//! trials are independent and can be evaluated as one batch, and the result does not depend on how the batch is
//! split. It stops when the population's values have a standard deviation ≤ atol + tol·|mean| (SciPy's test).

use super::optimizer::{Optimizer, argmin, key, latin_hypercube};
use crate::rng::SplitMix64;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Strategy {
    /// v = x_best + F (x_r1 − x_r2) (SciPy's default).
    Best1Bin,
    /// v = x_r0 + F (x_r1 − x_r2) (Storn and Price's classic).
    Rand1Bin,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeSettings {
    /// Population size per parameter (SciPy: 15).
    pub popsize: usize,
    /// Dither range of the mutation scale F (SciPy: (0.5, 1)).
    pub mutation: (f64, f64),
    /// Crossover rate CR (SciPy: 0.7).
    pub recombination: f64,
    pub strategy: Strategy,
    /// Convergence: relative and absolute tolerance on the population's standard deviation (SciPy: 0.01, 0).
    pub tol: f64,
    pub atol: f64,
    pub seed: u64,
}

impl Default for DeSettings {
    fn default() -> Self {
        DeSettings {
            popsize: 15,
            mutation: (0.5, 1.0),
            recombination: 0.7,
            strategy: Strategy::Best1Bin,
            tol: 0.01,
            atol: 0.0,
            seed: 1,
        }
    }
}

pub struct DifferentialEvolution {
    s: DeSettings,
    d: usize,
    rng: SplitMix64,
    pop: Vec<Vec<f64>>,
    values: Vec<f64>,
    /// The points of the current round (the initial population, or a generation's trials) and their values.
    round: Vec<Vec<f64>>,
    round_values: Vec<f64>,
    /// How many of `round` were handed out, and how many of those in the last ask.
    handed: usize,
    last_ask: usize,
    initialised: bool,
    pub generations: usize,
}

impl DifferentialEvolution {
    pub fn new(d: usize, s: DeSettings) -> DifferentialEvolution {
        let mut rng = SplitMix64::new(s.seed);
        let n = (s.popsize * d).max(5);
        let round = latin_hypercube(&mut rng, n, d);
        DifferentialEvolution {
            s,
            d,
            rng,
            pop: Vec::new(),
            values: Vec::new(),
            round,
            round_values: Vec::new(),
            handed: 0,
            last_ask: 0,
            initialised: false,
            generations: 0,
        }
    }

    /// A distinct random member index other than those in `not`.
    fn pick(&mut self, not: &[usize]) -> usize {
        loop {
            let r = (self.rng.next_u64() % self.pop.len() as u64) as usize;
            if !not.contains(&r) {
                return r;
            }
        }
    }

    /// One trial per member, from the population as it stands (deferred updating).
    fn trials(&mut self) -> Vec<Vec<f64>> {
        let (lo, hi) = self.s.mutation;
        let f = lo + (hi - lo) * self.rng.uniform();
        let best = argmin(&self.values);
        let mut out = Vec::with_capacity(self.pop.len());
        for i in 0..self.pop.len() {
            let base = match self.s.strategy {
                Strategy::Best1Bin => best,
                Strategy::Rand1Bin => self.pick(&[i]),
            };
            let r1 = self.pick(&[i, base]);
            let r2 = self.pick(&[i, base, r1]);
            let jrand = (self.rng.next_u64() % self.d as u64) as usize;
            let mut t = self.pop[i].clone();
            for (j, tj) in t.iter_mut().enumerate() {
                if j == jrand || self.rng.uniform() < self.s.recombination {
                    let v = self.pop[base][j] + f * (self.pop[r1][j] - self.pop[r2][j]);
                    // Outside the box: a fresh uniform coordinate (SciPy's treatment).
                    *tj = if (0.0..=1.0).contains(&v) { v } else { self.rng.uniform() };
                }
            }
            out.push(t);
        }
        out
    }

    fn converged(&self) -> bool {
        let finite: Vec<f64> = self.values.iter().copied().filter(|v| v.is_finite()).collect();
        if finite.len() < self.values.len() || finite.is_empty() {
            return false;
        }
        let n = finite.len() as f64;
        let mean = finite.iter().sum::<f64>() / n;
        let sd = (finite.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n).sqrt();
        sd <= self.s.atol + self.s.tol * mean.abs()
    }

    /// Ends a round: the initial population's values, or the generation's selection.
    fn close_round(&mut self) {
        let points = std::mem::take(&mut self.round);
        let values = std::mem::take(&mut self.round_values);
        if !self.initialised {
            self.pop = points;
            self.values = values;
            self.initialised = true;
        } else {
            for (i, (t, v)) in points.into_iter().zip(values).enumerate() {
                if key(v) <= key(self.values[i]) {
                    self.pop[i] = t;
                    self.values[i] = v;
                }
            }
            self.generations += 1;
        }
        self.handed = 0;
    }
}

impl Optimizer for DifferentialEvolution {
    fn name(&self) -> &'static str {
        "differential evolution"
    }

    fn ask(&mut self, max: usize) -> Vec<Vec<f64>> {
        if self.handed == self.round.len() && self.round_values.len() == self.round.len() {
            self.close_round();
            if self.converged() {
                self.last_ask = 0;
                return Vec::new();
            }
            self.round = self.trials();
        }
        let end = (self.handed + max.max(1)).min(self.round.len());
        let out = self.round[self.handed..end].to_vec();
        self.last_ask = out.len();
        self.handed = end;
        out
    }

    fn tell(&mut self, values: &[f64]) {
        let n = values.len().min(self.last_ask);
        self.round_values.extend_from_slice(&values[..n]);
        self.last_ask = 0;
    }

    fn best(&self) -> Option<(Vec<f64>, f64)> {
        let mut all: Vec<(&Vec<f64>, f64)> = self.pop.iter().zip(self.values.iter().copied()).collect();
        // The current round's told points count too (the initial population before its round closes).
        all.extend(self.round.iter().zip(self.round_values.iter().copied()));
        let i = argmin(&all.iter().map(|(_, v)| *v).collect::<Vec<_>>());
        all.get(i).map(|(p, v)| ((*p).clone(), *v))
    }
}
