//! A uniform grid of square cells over a frame's chip particles (2D), for the frame-based chip analysis
//! ([`super::chip_profile`], [`super::shear_band`]): the particles near a point, and the particles of a subset
//! connected to a seed through short links (a flood fill). Built once per frame.

use std::collections::HashMap;

/// Particle indices by cell; cells are `cell` wide.
pub struct Cells {
    cell: f64,
    map: HashMap<(i64, i64), Vec<usize>>,
}

impl Cells {
    /// The grid of `pts` with cells `cell` wide (> 0). Points with a non-finite coordinate are left out.
    pub fn new(pts: &[[f64; 2]], cell: f64) -> Cells {
        let mut map: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
        for (i, p) in pts.iter().enumerate().filter(|(_, p)| p[0].is_finite() && p[1].is_finite()) {
            map.entry(key(*p, cell)).or_default().push(i);
        }
        Cells { cell, map }
    }

    /// Indices of the points of `pts` (the grid's own) within `radius` of `c`.
    pub fn within(&self, pts: &[[f64; 2]], c: [f64; 2], radius: f64) -> Vec<usize> {
        let reach = (radius / self.cell).ceil() as i64;
        let (cx, cy) = key(c, self.cell);
        let mut out = Vec::new();
        for x in cx - reach..=cx + reach {
            for y in cy - reach..=cy + reach {
                let Some(v) = self.map.get(&(x, y)) else { continue };
                out.extend(v.iter().copied().filter(|&i| dist2(pts[i], c) <= radius * radius));
            }
        }
        out
    }

    /// Indices of the points of `pts` (the grid's own) in the slab through `c` across the unit direction `m`:
    /// |(x − c)·m| ≤ `half_len` and |(x − c)·a| ≤ `half_width`, a ⟂ m (the cells along the slab only).
    pub fn slab(&self, pts: &[[f64; 2]], c: [f64; 2], m: [f64; 2], half_len: f64, half_width: f64) -> Vec<usize> {
        let mut keys = std::collections::HashSet::new();
        let steps = (half_len / (0.5 * self.cell)).ceil() as i64;
        let spread = (half_width / self.cell).ceil() as i64 + 1;
        for k in -steps..=steps {
            let t = k as f64 * 0.5 * self.cell;
            let (cx, cy) = key([c[0] + t * m[0], c[1] + t * m[1]], self.cell);
            for x in cx - spread..=cx + spread {
                keys.extend((cy - spread..=cy + spread).map(|y| (x, y)));
            }
        }
        let a = [-m[1], m[0]];
        let along = |x: [f64; 2], e: [f64; 2]| (x[0] - c[0]) * e[0] + (x[1] - c[1]) * e[1];
        let mut out: Vec<usize> = keys
            .iter()
            .filter_map(|k| self.map.get(k))
            .flatten()
            .copied()
            .filter(|&i| along(pts[i], m).abs() <= half_len && along(pts[i], a).abs() <= half_width)
            .collect();
        out.sort_unstable();
        out
    }

    /// The members of `subset` (indices into `pts`) connected to `seed` (one of them) through links no longer
    /// than `link` ≤ the cell width, each link between two members of `subset`.
    pub fn connected(&self, pts: &[[f64; 2]], subset: &[usize], seed: usize, link: f64) -> Vec<usize> {
        let mut free = vec![false; pts.len()];
        subset.iter().for_each(|&i| free[i] = true);
        if !free.get(seed).copied().unwrap_or(false) {
            return Vec::new();
        }
        self.fill(pts, &mut free, seed, link)
    }

    /// The connected pieces of `subset` (as [`Cells::connected`]), largest first.
    pub fn components(&self, pts: &[[f64; 2]], subset: &[usize], link: f64) -> Vec<Vec<usize>> {
        let mut free = vec![false; pts.len()];
        subset.iter().for_each(|&i| free[i] = true);
        let mut out: Vec<Vec<usize>> = Vec::new();
        for &i in subset {
            if free[i] {
                out.push(self.fill(pts, &mut free, i, link));
            }
        }
        out.sort_by_key(|c| std::cmp::Reverse(c.len()));
        out
    }

    /// The flood fill from `seed` over the points still `free`, which it takes.
    fn fill(&self, pts: &[[f64; 2]], free: &mut [bool], seed: usize, link: f64) -> Vec<usize> {
        free[seed] = false;
        let (mut stack, mut out) = (vec![seed], Vec::new());
        while let Some(i) = stack.pop() {
            out.push(i);
            for j in self.within(pts, pts[i], link) {
                if free[j] {
                    free[j] = false;
                    stack.push(j);
                }
            }
        }
        out
    }
}

fn key(p: [f64; 2], cell: f64) -> (i64, i64) {
    ((p[0] / cell).floor() as i64, (p[1] / cell).floor() as i64)
}

/// Squared distance.
pub fn dist2(p: [f64; 2], q: [f64; 2]) -> f64 {
    (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)
}
