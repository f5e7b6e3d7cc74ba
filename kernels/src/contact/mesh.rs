//! The rigid triangle-mesh tool of 3D (roethlin-solver.md §5.5): the triangles are hashed once into a uniform grid
//! on the host, and each query reads the cells within the contact's cut-off distance.
//!
//! - Closest point: Ericson's closest point on a triangle (Real-Time Collision Detection, §5.1.5), which also names
//!   the closest feature (a vertex, an edge or the face).
//! - Sign: (p − q)·n < 0 means inside, with n the angle-weighted pseudo-normal of the closest feature (Bærentzen &
//!   Aanæs 2005; Thürrner & Wüthrich 1998): the face normal on a face, the sum of the two face normals on an edge,
//!   the sum of the incident face normals weighted by their angles at a vertex. This sign is exact for a closed,
//!   consistently oriented mesh, whatever the feature.
//! - Safe mode (an option, §5.5): the sign from the parity of the crossings of a ray from p along a fixed direction
//!   (Möller–Trumbore), odd meaning inside (the digest notes the thesis prose swaps this; its Fig 5.14 is right).
//!
//! The contact only needs points within the cut-off distance `cutoff`, so the search reads only the cells that
//! the cube of half-width `cutoff` about p overlaps: every triangle within `cutoff` of p is found and the answer is
//! exact there. A point farther from every triangle is "far": it reports |distance| = `cutoff` (its true distance
//! is ≥ `cutoff`), a zero normal and `point` = p, and its sign from, in order: outside the grid, outside; in a cell
//! no triangle overlaps, that cell's side (precomputed on the host by ray parity at its centre); in a cell with
//! triangles, the pseudo-normal of the closest triangle within one cell width, when there is one; else (or in safe
//! mode) ray parity over all triangles, O(triangles).

use super::geometry::{SurfacePoint, ToolGeometry};
use crate::real::Real;
use bytemuck::{Pod, Zeroable};
use core::marker::PhantomData;

/// The default ray of safe mode and of far points: a direction with no simple ratio between its components, so
/// that a ray from a point of an axis-aligned or symmetric lattice does not run along an edge or through a vertex.
pub const RAY_DIR: [f64; 3] = [0.548_120_703_851_3, 0.726_170_394_226_1, 0.415_006_138_479_6];

/// The grid's scalars: plain data, copied by value to the GPU.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct MeshGrid {
    /// The lowest corner of the grid (the mesh's bounding box grown by the margin).
    pub origin: [f64; 3],
    /// Cell edge length (cubic cells) and its inverse.
    pub cell: f64,
    pub inv_cell: f64,
    /// Search radius: points farther than this from every triangle report "far" (module doc).
    pub cutoff: f64,
    /// Unit direction of the parity ray.
    pub ray: [f64; 3],
    /// Cells along x, y, z.
    pub dims: [u32; 3],
    /// 1: the sign of every query comes from ray parity (safe mode); 0: from the pseudo-normal.
    pub safe: u32,
}

/// A cell's side (`MeshTool` cell flags): wholly outside, wholly inside, or overlapped by triangles.
pub const CELL_OUT: u32 = 0;
pub const CELL_IN: u32 = 1;
pub const CELL_MIXED: u32 = 2;

/// The closest feature of a triangle: a vertex, an edge (k from vertex k to vertex k+1 mod 3) or the face.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Feature {
    Vertex(u32),
    Edge(u32),
    Face,
}

/// The closest point of one triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Nearest {
    /// Squared distance |p − point|².
    pub d2: f64,
    pub point: [f64; 3],
    pub triangle: u32,
    pub feature: Feature,
}

/// A triangle-mesh tool: the grid's scalars and pointers to flat arrays built on the host (`swarf::mesh::grid`),
/// host or device memory alike. Every read is bounds-checked against the stored lengths, so a query cannot panic
/// or read out of range; the lifetime ties a tool built from slices to them.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct MeshTool<'a> {
    pub grid: MeshGrid,
    /// Triangle vertices, 3 per triangle (counter-clockwise seen from outside).
    verts: *const [f64; 3],
    /// Unit face normal per triangle.
    face_n: *const [f64; 3],
    /// Pseudo-normal per triangle edge k (3 per triangle), the same for both triangles of an edge.
    edge_n: *const [f64; 3],
    /// Pseudo-normal per triangle corner k (3 per triangle), the same for every triangle of a vertex.
    vert_n: *const [f64; 3],
    /// Start of cell c's triangle list in `cell_tri` (cells + 1 entries).
    cell_start: *const u32,
    cell_tri: *const u32,
    /// Per cell: [`CELL_OUT`], [`CELL_IN`] or [`CELL_MIXED`].
    cell_side: *const u32,
    n_tri: u32,
    n_cell_tri: u32,
    _arrays: PhantomData<&'a [f64]>,
}

/// The flat arrays of a [`MeshTool`] (lengths: verts, edge_n, vert_n 3·n; face_n n; cell_start cells + 1;
/// cell_side cells).
#[derive(Clone, Copy)]
pub struct MeshArrays<'a> {
    pub verts: &'a [[f64; 3]],
    pub face_n: &'a [[f64; 3]],
    pub edge_n: &'a [[f64; 3]],
    pub vert_n: &'a [[f64; 3]],
    pub cell_start: &'a [u32],
    pub cell_tri: &'a [u32],
    pub cell_side: &'a [u32],
}

/// Why arrays cannot make a [`MeshTool`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LengthMismatch;

impl<'a> MeshTool<'a> {
    /// A tool over host slices; the lengths must agree with each other and with `grid.dims`.
    pub fn from_slices(grid: MeshGrid, a: MeshArrays<'a>) -> Result<Self, LengthMismatch> {
        let n = a.face_n.len();
        let cells = grid.dims[0] as usize * grid.dims[1] as usize * grid.dims[2] as usize;
        let ok = a.verts.len() == 3 * n
            && a.edge_n.len() == 3 * n
            && a.vert_n.len() == 3 * n
            && a.cell_start.len() == cells + 1
            && a.cell_side.len() == cells
            && a.cell_start.last().is_some_and(|&e| e as usize <= a.cell_tri.len())
            && n <= u32::MAX as usize / 3
            && a.cell_tri.len() <= u32::MAX as usize;
        if !ok {
            return Err(LengthMismatch);
        }
        // SAFETY: the slices live for 'a and their lengths were checked above.
        Ok(unsafe {
            Self::from_raw(
                grid,
                a.verts.as_ptr(),
                a.face_n.as_ptr(),
                a.edge_n.as_ptr(),
                a.vert_n.as_ptr(),
                a.cell_start.as_ptr(),
                a.cell_tri.as_ptr(),
                a.cell_side.as_ptr(),
                n as u32,
                a.cell_tri.len() as u32,
            )
        })
    }

    /// A tool over raw (e.g. device) pointers.
    ///
    /// # Safety
    /// While the tool is used, `verts`, `edge_n` and `vert_n` hold 3·`n_tri` entries, `face_n` `n_tri`,
    /// `cell_start` dims[0]·dims[1]·dims[2] + 1, `cell_side` dims[0]·dims[1]·dims[2] and `cell_tri` `n_cell_tri`,
    /// in memory the querying thread can read.
    #[allow(clippy::too_many_arguments)]
    pub unsafe fn from_raw(
        grid: MeshGrid,
        verts: *const [f64; 3],
        face_n: *const [f64; 3],
        edge_n: *const [f64; 3],
        vert_n: *const [f64; 3],
        cell_start: *const u32,
        cell_tri: *const u32,
        cell_side: *const u32,
        n_tri: u32,
        n_cell_tri: u32,
    ) -> Self {
        MeshTool {
            grid,
            verts,
            face_n,
            edge_n,
            vert_n,
            cell_start,
            cell_tri,
            cell_side,
            n_tri,
            n_cell_tri,
            _arrays: PhantomData,
        }
    }

    /// Number of triangles.
    #[inline(always)]
    pub fn triangles(&self) -> u32 {
        self.n_tri
    }

    /// Triangle t's vertices (zeros for t out of range).
    #[inline(always)]
    pub fn triangle(&self, t: u32) -> [[f64; 3]; 3] {
        let i = 3 * t;
        [
            read3(self.verts, 3 * self.n_tri, i),
            read3(self.verts, 3 * self.n_tri, i + 1),
            read3(self.verts, 3 * self.n_tri, i + 2),
        ]
    }

    /// The pseudo-normal of triangle t's feature.
    #[inline(always)]
    fn pseudo_normal(&self, t: u32, f: Feature) -> [f64; 3] {
        match f {
            Feature::Face => read3(self.face_n, self.n_tri, t),
            Feature::Edge(k) => read3(self.edge_n, 3 * self.n_tri, 3 * t + k),
            Feature::Vertex(k) => read3(self.vert_n, 3 * self.n_tri, 3 * t + k),
        }
    }

    /// The closest point over the triangles of the cells within `radius` of p (None: no triangle there); exact
    /// when its distance is at most `radius`.
    #[inline(always)]
    pub fn nearest_in_grid(&self, p: [f64; 3], radius: f64) -> Option<Nearest> {
        let g = &self.grid;
        let mut lo = [0u32; 3];
        let mut hi = [0u32; 3];
        for k in 0..3 {
            let a = floor((p[k] - radius - g.origin[k]) * g.inv_cell);
            let b = floor((p[k] + radius - g.origin[k]) * g.inv_cell);
            let top = g.dims[k] as f64 - 1.0;
            // NaN fails both comparisons and leaves the range empty.
            if !(b >= 0.0 && a <= top) {
                return None;
            }
            lo[k] = a.max(0.0) as u32;
            hi[k] = b.min(top) as u32;
        }
        let mut best: Option<Nearest> = None;
        for cz in lo[2]..=hi[2] {
            for cy in lo[1]..=hi[1] {
                for cx in lo[0]..=hi[0] {
                    let d2_box = self.cell_distance2(p, [cx, cy, cz]);
                    if best.is_some_and(|b| d2_box > b.d2) {
                        continue;
                    }
                    let cell = (cz * g.dims[1] + cy) * g.dims[0] + cx;
                    let cells = g.dims[0] * g.dims[1] * g.dims[2];
                    let (Some(s), Some(e)) =
                        (read(self.cell_start, cells + 1, cell), read(self.cell_start, cells + 1, cell + 1))
                    else {
                        continue;
                    };
                    for j in s..e {
                        if let Some(t) = read(self.cell_tri, self.n_cell_tri, j) {
                            best = closer(best, self.nearest_on(p, t));
                        }
                    }
                }
            }
        }
        best
    }

    /// The squared distance from p to cell c's box.
    #[inline(always)]
    fn cell_distance2(&self, p: [f64; 3], c: [u32; 3]) -> f64 {
        let g = &self.grid;
        let mut d2 = 0.0;
        for k in 0..3 {
            let lo = g.origin[k] + c[k] as f64 * g.cell;
            let d = if p[k] < lo {
                lo - p[k]
            } else if p[k] > lo + g.cell {
                p[k] - lo - g.cell
            } else {
                0.0
            };
            d2 += d * d;
        }
        d2
    }

    /// The closest point over every triangle (brute force: the reference of the tests, O(triangles)).
    pub fn nearest_brute(&self, p: [f64; 3]) -> Option<Nearest> {
        let mut best = None;
        for t in 0..self.n_tri {
            best = closer(best, self.nearest_on(p, t));
        }
        best
    }

    /// The closest point of p on triangle t.
    #[inline(always)]
    pub fn nearest_on(&self, p: [f64; 3], t: u32) -> Nearest {
        let [a, b, c] = self.triangle(t);
        let (point, feature) = closest_on_triangle(p, a, b, c);
        let d = sub(p, point);
        Nearest { d2: dot(d, d), point, triangle: t, feature }
    }

    /// Whether p is inside by ray parity: the crossings of the ray p + s·`grid.ray`, s > 0, with every triangle
    /// (Möller–Trumbore), odd meaning inside. O(triangles).
    pub fn inside_by_parity(&self, p: [f64; 3]) -> bool {
        let mut odd = false;
        for t in 0..self.n_tri {
            let [a, b, c] = self.triangle(t);
            if ray_hits_triangle(p, self.grid.ray, a, b, c) {
                odd = !odd;
            }
        }
        odd
    }

    /// The answer from a closest point: the sign from the pseudo-normal or, in safe mode, from parity.
    #[inline(always)]
    pub fn answer(&self, p: [f64; 3], n: Nearest) -> SurfacePoint {
        let d = sub(p, n.point);
        let len = <f64 as Real>::sqrt(n.d2);
        let inside = if self.grid.safe != 0 {
            self.inside_by_parity(p)
        } else {
            dot(d, self.pseudo_normal(n.triangle, n.feature)) < 0.0
        };
        let normal = if len > 0.0 {
            let s = if inside { -1.0 / len } else { 1.0 / len };
            [d[0] * s, d[1] * s, d[2] * s]
        } else {
            self.pseudo_normal(n.triangle, n.feature)
        };
        SurfacePoint { distance: if inside { -len } else { len }, normal, point: n.point }
    }

    /// The "far" answer (module doc): |distance| = cutoff, the sign from the grid's cell sides where they decide it.
    #[inline(always)]
    fn far(&self, p: [f64; 3]) -> SurfacePoint {
        let g = &self.grid;
        let inside = if g.safe != 0 {
            self.inside_by_parity(p)
        } else {
            match self.cell_of(p) {
                None => false,
                Some(c) => match read(self.cell_side, g.dims[0] * g.dims[1] * g.dims[2], c) {
                    Some(CELL_OUT) => false,
                    Some(CELL_IN) => true,
                    _ => match self.nearest_in_grid(p, g.cell) {
                        Some(n) if n.d2 <= g.cell * g.cell => self.answer(p, n).distance < 0.0,
                        _ => self.inside_by_parity(p),
                    },
                },
            }
        };
        SurfacePoint { distance: if inside { -g.cutoff } else { g.cutoff }, normal: [0.0; 3], point: p }
    }

    /// The index of the cell holding p (None: outside the grid).
    #[inline(always)]
    fn cell_of(&self, p: [f64; 3]) -> Option<u32> {
        let g = &self.grid;
        let mut c = [0u32; 3];
        for k in 0..3 {
            let i = floor((p[k] - g.origin[k]) * g.inv_cell);
            if !(i >= 0.0 && i < g.dims[k] as f64) {
                return None;
            }
            c[k] = i as u32;
        }
        Some((c[2] * g.dims[1] + c[1]) * g.dims[0] + c[0])
    }

    /// The exact answer over every triangle, with no cut-off (brute force; tests).
    pub fn query_brute(&self, p: [f64; 3]) -> SurfacePoint {
        match self.nearest_brute(p) {
            Some(n) => self.answer(p, n),
            None => self.far(p),
        }
    }
}

impl ToolGeometry for MeshTool<'_> {
    /// Exact within `grid.cutoff` of the surface; "far" beyond it (module doc).
    #[inline(always)]
    fn query(&self, p: [f64; 3]) -> SurfacePoint {
        let c = self.grid.cutoff;
        match self.nearest_in_grid(p, c) {
            Some(n) if n.d2 <= c * c => self.answer(p, n),
            _ => self.far(p),
        }
    }
}

/// The nearer of two candidates; the first wins a tie, so the answer does not depend on the cell order of equal
/// distances beyond which triangle names them.
#[inline(always)]
fn closer(best: Option<Nearest>, n: Nearest) -> Option<Nearest> {
    match best {
        Some(b) if b.d2 <= n.d2 => Some(b),
        _ => Some(n),
    }
}

/// Ericson's closest point on triangle abc (Real-Time Collision Detection §5.1.5): the Voronoi region of p among
/// the vertices, edges and face, from the signs of dot products, and the point and feature of that region.
#[inline(always)]
pub fn closest_on_triangle(p: [f64; 3], a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> ([f64; 3], Feature) {
    let ab = sub(b, a);
    let ac = sub(c, a);
    let ap = sub(p, a);
    let d1 = dot(ab, ap);
    let d2 = dot(ac, ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, Feature::Vertex(0));
    }
    let bp = sub(p, b);
    let d3 = dot(ab, bp);
    let d4 = dot(ac, bp);
    if d3 >= 0.0 && d4 <= d3 {
        return (b, Feature::Vertex(1));
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (axpy(a, v, ab), Feature::Edge(0));
    }
    let cp = sub(p, c);
    let d5 = dot(ab, cp);
    let d6 = dot(ac, cp);
    if d6 >= 0.0 && d5 <= d6 {
        return (c, Feature::Vertex(2));
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (axpy(a, w, ac), Feature::Edge(2));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (axpy(b, w, sub(c, b)), Feature::Edge(1));
    }
    let denom = 1.0 / (va + vb + vc);
    let v = vb * denom;
    let w = vc * denom;
    (axpy(axpy(a, v, ab), w, ac), Feature::Face)
}

/// Möller–Trumbore: whether the ray o + s·d, s > 0, crosses triangle abc (a ray in the triangle's plane does not).
#[inline(always)]
pub fn ray_hits_triangle(o: [f64; 3], d: [f64; 3], a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> bool {
    let e1 = sub(b, a);
    let e2 = sub(c, a);
    let h = cross(d, e2);
    let det = dot(e1, h);
    if det == 0.0 {
        return false;
    }
    let f = 1.0 / det;
    let s = sub(o, a);
    let u = f * dot(s, h);
    if !(0.0..=1.0).contains(&u) {
        return false;
    }
    let q = cross(s, e1);
    let v = f * dot(d, q);
    if v < 0.0 || u + v > 1.0 {
        return false;
    }
    f * dot(e2, q) > 0.0
}

/// Explicit, so that the host build with std (tests) and the no_std builds call the same function.
#[inline(always)]
fn floor(x: f64) -> f64 {
    <f64 as Real>::floor(x)
}

#[inline(always)]
fn read<T: Copy>(p: *const T, len: u32, i: u32) -> Option<T> {
    // SAFETY: the constructor's contract: p holds len entries.
    if i < len { Some(unsafe { *p.add(i as usize) }) } else { None }
}

#[inline(always)]
fn read3(p: *const [f64; 3], len: u32, i: u32) -> [f64; 3] {
    read(p, len, i).unwrap_or([0.0; 3])
}

#[inline(always)]
fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline(always)]
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline(always)]
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// a + s·b.
#[inline(always)]
fn axpy(a: [f64; 3], s: f64, b: [f64; 3]) -> [f64; 3] {
    [a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]]
}
