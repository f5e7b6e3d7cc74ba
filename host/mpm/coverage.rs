//! The glyph test of the position update (nairn-mpm.md §1.2 Fig. 2, V14): each specimen particle drawn as its
//! deformed domain, the parallelogram F·[−l/2, l/2]² about its position (l = √V0, the side of its square at t = 0),
//! rasterised onto a fine pixel grid. Where the particles move as their F says, the domains tile the body: their
//! union covers Σ J V0 and leaves no holes. Where the position update and F disagree (the zeroth- and first-order
//! updates with PIC damping), domains overlap (the union falls short of Σ J V0) and pull apart (small enclosed
//! holes: gaps). docs/mpm.md "Position updates".

use super::output::Snapshot;
use crate::kernels::mpm::grid::TOOL;
use serde::Serialize;

/// Pixels along a particle's side at t = 0.
pub const PIXELS_PER_SIDE: usize = 8;
/// An enclosed empty region of at most this many particle domains is a gap; larger ones are the body's own
/// cavities (a chip curled onto the surface, the crack's mouth).
pub const GAP_DOMAINS: f64 = 4.0;

/// The coverage of the specimen's particles' domains [m² per m of depth in 2D].
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Coverage {
    /// Σ J V0, the volume the particles stand for.
    pub volume: f64,
    /// The union of their domains, rasterised.
    pub covered: f64,
    /// The enclosed empty regions of at most [`GAP_DOMAINS`] domains, and how many there are.
    pub gaps: f64,
    pub gap_count: u64,
    /// The pixel's side [m].
    pub pixel: f64,
    /// The area mismatch |Σ J V0 − covered| / Σ J V0 (V14: < 2 % proposed), and the gaps' area over Σ J V0.
    pub mismatch: f64,
    pub gap_share: f64,
}

/// The parallelogram of particle i: its centre, F and half-side.
struct Glyph {
    centre: [f64; 2],
    f: [f64; 4],
    half: f64,
}

impl Glyph {
    /// The corners' bounding box (x0, y0, x1, y1).
    fn bounds(&self) -> [f64; 4] {
        let [a, b, c, d] = self.f;
        let (ex, ey) = (self.half * (a.abs() + b.abs()), self.half * (c.abs() + d.abs()));
        [self.centre[0] - ex, self.centre[1] - ey, self.centre[0] + ex, self.centre[1] + ey]
    }

    /// Whether q lies in F·[−half, half]² about the centre (u = F⁻¹ (q − x)), its edges widened by 1e-9 of the
    /// side so that a pixel centre on the edge two domains share is not lost to rounding in both.
    fn holds(&self, q: [f64; 2], inv: [f64; 4]) -> bool {
        let (dx, dy) = (q[0] - self.centre[0], q[1] - self.centre[1]);
        let (u, v) = (inv[0] * dx + inv[1] * dy, inv[2] * dx + inv[3] * dy);
        let h = self.half * (1.0 + 1e-9);
        u.abs() <= h && v.abs() <= h
    }
}

/// The coverage of `snap`'s specimen particles (tool particles apart) that `keep` takes (by id), or None without
/// any or with a degenerate F.
pub fn coverage(snap: &Snapshot, keep: impl Fn(usize) -> bool) -> Option<Coverage> {
    let ids: Vec<usize> = (0..snap.pos.len()).filter(|&i| snap.kind[i] != TOOL && keep(i)).collect();
    let glyphs: Vec<Glyph> =
        ids.iter().map(|&i| Glyph { centre: snap.pos[i], f: snap.def[i], half: 0.5 * snap.vol0[i].sqrt() }).collect();
    let side = glyphs.iter().map(|g| 2.0 * g.half).fold(f64::INFINITY, f64::min);
    if glyphs.is_empty() || side.is_nan() || side <= 0.0 {
        return None;
    }
    let volume: f64 = ids.iter().map(|&i| snap.jac[i] * snap.vol0[i]).sum();
    let pixel = side / PIXELS_PER_SIDE as f64;
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for g in &glyphs {
        let b = g.bounds();
        lo = [lo[0].min(b[0]), lo[1].min(b[1])];
        hi = [hi[0].max(b[2]), hi[1].max(b[3])];
    }
    // One empty pixel of margin on every side, so that the outside is one connected region.
    let origin = [lo[0] - pixel, lo[1] - pixel];
    let (nx, ny) = (((hi[0] - origin[0]) / pixel) as usize + 2, ((hi[1] - origin[1]) / pixel) as usize + 2);
    // A body spread so wide that its raster would pass 10⁸ pixels (100 MB) is not drawn: no coverage.
    if nx.saturating_mul(ny) > 100_000_000 {
        return None;
    }
    let mut full = vec![false; nx * ny];
    for g in &glyphs {
        let [a, b, c, d] = g.f;
        let det = a * d - b * c;
        if det.is_nan() || det <= 0.0 {
            return None;
        }
        let inv = [d / det, -b / det, -c / det, a / det];
        let bb = g.bounds();
        let i0 = ((bb[0] - origin[0]) / pixel).floor().max(0.0) as usize;
        let j0 = ((bb[1] - origin[1]) / pixel).floor().max(0.0) as usize;
        let i1 = (((bb[2] - origin[0]) / pixel).ceil() as usize).min(nx - 1);
        let j1 = (((bb[3] - origin[1]) / pixel).ceil() as usize).min(ny - 1);
        for j in j0..=j1 {
            for i in i0..=i1 {
                let q = [origin[0] + (i as f64 + 0.5) * pixel, origin[1] + (j as f64 + 0.5) * pixel];
                if g.holds(q, inv) {
                    full[j * nx + i] = true;
                }
            }
        }
    }
    let covered = full.iter().filter(|&&f| f).count() as f64 * pixel * pixel;
    let (gap_pixels, gap_count) =
        enclosed_gaps(&full, nx, ny, GAP_DOMAINS * (PIXELS_PER_SIDE * PIXELS_PER_SIDE) as f64);
    let gaps = gap_pixels as f64 * pixel * pixel;
    let (mismatch, gap_share) = ((volume - covered).abs() / volume, gaps / volume);
    Some(Coverage { volume, covered, gaps, gap_count, pixel, mismatch, gap_share })
}

/// The empty pixels not connected (4-neighbours) to the grid's edge, in regions of at most `max_region` pixels:
/// their total and the regions' count.
fn enclosed_gaps(full: &[bool], nx: usize, ny: usize, max_region: f64) -> (u64, u64) {
    let mut seen = full.to_vec();
    let mut stack = Vec::new();
    let region = |start: usize, seen: &mut Vec<bool>, stack: &mut Vec<usize>| -> (u64, bool) {
        let (mut size, mut edge) = (0u64, false);
        seen[start] = true;
        stack.push(start);
        while let Some(k) = stack.pop() {
            size += 1;
            let (i, j) = (k % nx, k / nx);
            edge |= i == 0 || j == 0 || i + 1 == nx || j + 1 == ny;
            let mut visit = |n: usize| {
                if !seen[n] {
                    seen[n] = true;
                    stack.push(n);
                }
            };
            if i > 0 {
                visit(k - 1);
            }
            if i + 1 < nx {
                visit(k + 1);
            }
            if j > 0 {
                visit(k - nx);
            }
            if j + 1 < ny {
                visit(k + nx);
            }
        }
        (size, edge)
    };
    let (mut total, mut count) = (0u64, 0u64);
    for k in 0..nx * ny {
        if !seen[k] {
            let (size, edge) = region(k, &mut seen, &mut stack);
            if !edge && size as f64 <= max_region {
                total += size;
                count += 1;
            }
        }
    }
    (total, count)
}
