//! The interface every optimiser implements: minimisation over a box, in the unit cube [0, 1]^d, by batches.
//!
//! `ask` hands out the next points, `tell` takes their objective values in the same order. The methods are
//! deterministic for a given seed and given values, so a stopped identification resumes exactly by building the
//! optimiser again and telling it its recorded history in the same batches (tests/identify_optim.rs).

use std::fmt;

/// The search box: parameter k lies in [lo[k], hi[k]]. Optimisers work in unit coordinates u ∈ [0, 1]^d,
/// x = lo + u (hi − lo), so that every parameter has the same scale whatever its units.
#[derive(Clone, Debug, PartialEq)]
pub struct Bounds {
    lo: Vec<f64>,
    hi: Vec<f64>,
}

/// Why a box is refused.
#[derive(Clone, Debug, PartialEq)]
pub enum BoundsError {
    Empty,
    Lengths {
        lo: usize,
        hi: usize,
    },
    /// Parameter `index` has a non-finite bound or lo ≥ hi.
    Inverted {
        index: usize,
        lo: f64,
        hi: f64,
    },
}

impl fmt::Display for BoundsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BoundsError::Empty => write!(f, "no parameters: expected at least one bounded parameter"),
            BoundsError::Lengths { lo, hi } => write!(f, "{lo} lower and {hi} upper bounds: expected as many of each"),
            BoundsError::Inverted { index, lo, hi } => {
                write!(f, "parameter {index}: bounds [{lo}, {hi}], expected finite bounds with lower < upper")
            }
        }
    }
}

impl std::error::Error for BoundsError {}

impl Bounds {
    pub fn new(lo: Vec<f64>, hi: Vec<f64>) -> Result<Bounds, BoundsError> {
        if lo.len() != hi.len() {
            return Err(BoundsError::Lengths { lo: lo.len(), hi: hi.len() });
        }
        if lo.is_empty() {
            return Err(BoundsError::Empty);
        }
        for (index, (&l, &h)) in lo.iter().zip(&hi).enumerate() {
            if !(l.is_finite() && h.is_finite() && l < h) {
                return Err(BoundsError::Inverted { index, lo: l, hi: h });
            }
        }
        Ok(Bounds { lo, hi })
    }

    pub fn dim(&self) -> usize {
        self.lo.len()
    }

    pub fn lower(&self) -> &[f64] {
        &self.lo
    }

    pub fn upper(&self) -> &[f64] {
        &self.hi
    }

    /// x = lo + u (hi − lo).
    pub fn to_params(&self, u: &[f64]) -> Vec<f64> {
        u.iter().zip(self.lo.iter().zip(&self.hi)).map(|(u, (l, h))| l + u * (h - l)).collect()
    }

    /// u = (x − lo)/(hi − lo).
    pub fn to_unit(&self, x: &[f64]) -> Vec<f64> {
        x.iter().zip(self.lo.iter().zip(&self.hi)).map(|(x, (l, h))| (x - l) / (h - l)).collect()
    }
}

/// A minimiser with a batch ask/tell interface over the unit cube.
pub trait Optimizer {
    /// The method's name, for reports.
    fn name(&self) -> &'static str;
    /// The next points to evaluate, in unit coordinates: at least one and at most `max` (≥ 1) while the method
    /// goes on, none once it has converged. Every point asked must be told before the next ask.
    fn ask(&mut self, max: usize) -> Vec<Vec<f64>>;
    /// The objective values of the points of the last ask, in order. A non-finite value (a failed simulation)
    /// counts as worse than every finite one.
    fn tell(&mut self, values: &[f64]);
    /// The best point told so far and its value.
    fn best(&self) -> Option<(Vec<f64>, f64)>;
}

/// One evaluated point of an identification's history.
#[derive(Clone, Debug, PartialEq)]
pub struct Evaluation {
    /// The parameters (the box's units).
    pub params: Vec<f64>,
    pub value: f64,
}

/// Runs `opt` on `f` until `budget` evaluations are spent or the method converges, asking at most `batch` points
/// at a time (a method whose next step needs more points, Nelder–Mead's initial simplex or shrink, asks them whole,
/// so the budget may be passed by fewer than d points); `f` gets each batch's parameters in the box's units and returns their values. Returns every
/// evaluation in order.
pub fn minimise(
    opt: &mut dyn Optimizer,
    bounds: &Bounds,
    budget: usize,
    batch: usize,
    f: &mut dyn FnMut(&[Vec<f64>]) -> Vec<f64>,
) -> Vec<Evaluation> {
    let mut history = Vec::new();
    while history.len() < budget {
        let asked = opt.ask(batch.max(1).min(budget - history.len()));
        if asked.is_empty() {
            break;
        }
        let params: Vec<Vec<f64>> = asked.iter().map(|u| bounds.to_params(u)).collect();
        let values = f(&params);
        opt.tell(&values);
        history.extend(params.into_iter().zip(values).map(|(params, value)| Evaluation { params, value }));
    }
    history
}

/// A value's rank key: non-finite values sort after every finite one.
pub(crate) fn key(v: f64) -> f64 {
    if v.is_finite() { v } else { f64::INFINITY }
}

/// The index of the smallest value (non-finite ones last; the first of equals).
pub(crate) fn argmin(values: &[f64]) -> usize {
    let mut best = 0;
    for (i, &v) in values.iter().enumerate() {
        if key(v) < key(values[best]) {
            best = i;
        }
    }
    best
}

/// n points of a Latin hypercube in [0, 1]^d: each coordinate takes one value in each of n equal strata, in a
/// random order.
pub(crate) fn latin_hypercube(rng: &mut crate::rng::SplitMix64, n: usize, d: usize) -> Vec<Vec<f64>> {
    let mut pts = vec![vec![0.0; d]; n];
    for k in 0..d {
        let mut strata: Vec<usize> = (0..n).collect();
        rng.shuffle(&mut strata);
        for (p, s) in pts.iter_mut().zip(strata) {
            p[k] = (s as f64 + rng.uniform()) / n as f64;
        }
    }
    pts
}
