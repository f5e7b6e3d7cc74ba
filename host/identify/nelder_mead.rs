//! Nelder–Mead simplex search (klippel-constitutive.md §6.1 "SIMPLEX"), with the standard coefficients (reflection
//! 1, expansion 2, contraction ½, shrink ½) and SciPy's acceptance rules, in the unit cube: trial points are
//! clipped to [0, 1]. It stops when every vertex lies within `xatol` of the best (each coordinate) and every value
//! within `fatol` of the best's (SciPy's test). Each step asks one point (a shrink asks d).

use super::optimizer::{Optimizer, key};

#[derive(Clone, Debug, PartialEq)]
pub struct NelderMeadSettings {
    /// The start point (unit coordinates); the initial simplex adds `step` along each axis (subtracting it where
    /// that would leave the cube).
    pub start: Vec<f64>,
    pub step: f64,
    /// An explicit initial simplex (d + 1 vertices, unit coordinates), e.g. Klippel's Tabs. 9.24/9.40; replaces
    /// `start`/`step` when given.
    pub simplex: Option<Vec<Vec<f64>>>,
    pub xatol: f64,
    pub fatol: f64,
}

impl NelderMeadSettings {
    pub fn from_start(start: Vec<f64>) -> NelderMeadSettings {
        NelderMeadSettings { start, step: 0.1, simplex: None, xatol: 1e-6, fatol: 1e-10 }
    }
}

/// What the told values answer.
#[derive(Clone, Debug, PartialEq)]
enum Stage {
    /// The initial vertices.
    Init,
    Reflect,
    /// Expansion after a reflection better than the best (its point and value).
    Expand {
        xr: Vec<f64>,
        fr: f64,
    },
    /// Contraction after a reflection no better than the second worst.
    Contract {
        fr: f64,
        inside: bool,
    },
    /// The shrunk vertices 1..=d.
    Shrink,
}

pub struct NelderMead {
    s: NelderMeadSettings,
    /// Vertices and values, sorted best first after each step.
    x: Vec<Vec<f64>>,
    f: Vec<f64>,
    stage: Stage,
    pending: Vec<Vec<f64>>,
    pub iterations: usize,
}

fn clip(v: Vec<f64>) -> Vec<f64> {
    v.into_iter().map(|x| x.clamp(0.0, 1.0)).collect()
}

/// a + t (b − a).
fn lerp(a: &[f64], b: &[f64], t: f64) -> Vec<f64> {
    a.iter().zip(b).map(|(a, b)| a + t * (b - a)).collect()
}

impl NelderMead {
    pub fn new(s: NelderMeadSettings) -> NelderMead {
        let d = s.start.len();
        let init = match &s.simplex {
            Some(v) => v.iter().cloned().map(clip).collect(),
            None => {
                let mut v = vec![clip(s.start.clone())];
                for k in 0..d {
                    let mut p = v[0].clone();
                    p[k] = if p[k] + s.step <= 1.0 { p[k] + s.step } else { p[k] - s.step };
                    v.push(p);
                }
                v
            }
        };
        NelderMead { s, x: Vec::new(), f: Vec::new(), stage: Stage::Init, pending: init, iterations: 0 }
    }

    fn sort(&mut self) {
        let mut idx: Vec<usize> = (0..self.x.len()).collect();
        idx.sort_by(|&a, &b| key(self.f[a]).total_cmp(&key(self.f[b])));
        self.x = idx.iter().map(|&i| self.x[i].clone()).collect();
        self.f = idx.iter().map(|&i| self.f[i]).collect();
    }

    fn centroid(&self) -> Vec<f64> {
        let n = self.x.len() - 1;
        let mut c = vec![0.0; self.x[0].len()];
        for v in &self.x[..n] {
            for (c, v) in c.iter_mut().zip(v) {
                *c += v / n as f64;
            }
        }
        c
    }

    fn converged(&self) -> bool {
        let (x0, f0) = (&self.x[0], self.f[0]);
        self.x.iter().all(|v| v.iter().zip(x0).all(|(a, b)| (a - b).abs() <= self.s.xatol))
            && self.f.iter().all(|f| (key(*f) - key(f0)).abs() <= self.s.fatol)
    }

    fn replace_worst(&mut self, p: Vec<f64>, v: f64) {
        let w = self.x.len() - 1;
        self.x[w] = p;
        self.f[w] = v;
        self.next_reflection();
    }

    /// Sorts, counts the iteration and proposes the reflection of the worst vertex (or nothing once converged).
    fn next_reflection(&mut self) {
        self.sort();
        self.iterations += 1;
        if self.converged() {
            self.pending.clear();
            return;
        }
        let c = self.centroid();
        let worst = &self.x[self.x.len() - 1];
        self.pending = vec![clip(lerp(&c, worst, -1.0))];
        self.stage = Stage::Reflect;
    }

    fn on_reflect(&mut self, xr: Vec<f64>, fr: f64) {
        let (best, second, worst) = (self.f[0], self.f[self.f.len() - 2], self.f[self.f.len() - 1]);
        let c = self.centroid();
        if key(fr) < key(best) {
            self.pending = vec![clip(lerp(&c, &xr, 2.0))];
            self.stage = Stage::Expand { xr, fr };
        } else if key(fr) < key(second) {
            self.replace_worst(xr, fr);
        } else {
            let inside = key(fr) >= key(worst);
            let target = if inside { self.x[self.x.len() - 1].clone() } else { xr };
            self.pending = vec![clip(lerp(&c, &target, 0.5))];
            self.stage = Stage::Contract { fr, inside };
        }
    }

    fn shrink(&mut self) {
        let best = self.x[0].clone();
        self.pending = self.x[1..].iter().map(|v| lerp(&best, v, 0.5)).collect();
        self.stage = Stage::Shrink;
    }
}

impl Optimizer for NelderMead {
    fn name(&self) -> &'static str {
        "Nelder-Mead"
    }

    /// Asks the pending points (the initial simplex and a shrink may exceed `max`: they are asked whole).
    fn ask(&mut self, _max: usize) -> Vec<Vec<f64>> {
        self.pending.clone()
    }

    fn tell(&mut self, values: &[f64]) {
        let points = std::mem::take(&mut self.pending);
        if points.is_empty() || values.len() < points.len() {
            self.pending = points;
            return;
        }
        match std::mem::replace(&mut self.stage, Stage::Reflect) {
            Stage::Init => {
                self.x = points;
                self.f = values[..self.x.len()].to_vec();
                self.iterations = 0;
                self.sort();
                let c = self.centroid();
                self.pending = vec![clip(lerp(&c, &self.x[self.x.len() - 1], -1.0))];
                self.stage = Stage::Reflect;
            }
            Stage::Reflect => {
                let xr = points.into_iter().next().unwrap_or_default();
                self.on_reflect(xr, values[0]);
            }
            Stage::Expand { xr, fr } => {
                let xe = points.into_iter().next().unwrap_or_default();
                if key(values[0]) < key(fr) { self.replace_worst(xe, values[0]) } else { self.replace_worst(xr, fr) }
            }
            Stage::Contract { fr, inside } => {
                let xc = points.into_iter().next().unwrap_or_default();
                let fc = values[0];
                let worst = self.f[self.f.len() - 1];
                let accept = if inside { key(fc) < key(worst) } else { key(fc) <= key(fr) };
                if accept {
                    self.replace_worst(xc, fc);
                } else {
                    self.shrink();
                }
            }
            Stage::Shrink => {
                for (k, (p, v)) in points.into_iter().zip(values).enumerate() {
                    self.x[k + 1] = p;
                    self.f[k + 1] = *v;
                }
                self.next_reflection();
            }
        }
    }

    fn best(&self) -> Option<(Vec<f64>, f64)> {
        self.x.first().map(|x| (x.clone(), self.f[0]))
    }
}
