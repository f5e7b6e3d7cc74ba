//! The triangle grid of a mesh tool, built once on the host (roethlin-solver.md §5.5): a uniform grid of cubic
//! cells over the mesh's bounding box grown by a margin, each cell listing the triangles that overlap it (the
//! Akenine-Möller separating-axis test of a box and a triangle: the 3 box axes, the triangle's normal and the 9
//! cross products of the box axes with the triangle's edges), in CSR form (cell starts + triangle indices). With
//! it, flat arrays of the triangles' vertices, unit face normals and angle-weighted pseudo-normals per edge and per
//! vertex (Bærentzen & Aanæs 2005: an edge's is the sum of its two face normals, a vertex's the sum of its faces'
//! normals weighted by the angle each face makes at it, normalised), and each cell's side: overlapped by triangles,
//! or wholly inside or outside the mesh by the ray parity of its centre (so that a query far from the surface
//! needs no ray). `swarf_kernels::contact::MeshTool` reads them.

use super::check::{cross, dist, dot, sub};
use super::{MeshError, TriMesh};
use crate::kernels::contact::mesh::{
    CELL_IN, CELL_MIXED, CELL_OUT, MeshArrays, MeshGrid, MeshTool, RAY_DIR, ray_hits_triangle,
};
use std::collections::HashMap;

/// How to build the grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridOptions {
    /// Cell edge length; None: the mean edge length of the mesh (Röthlin's choice, §5.5).
    pub cell: Option<f64>,
    /// How far the grid reaches beyond the mesh's bounding box on every side.
    pub margin: f64,
    /// The query's cut-off distance (`MeshGrid::cutoff`): beyond it a point reports "far".
    pub cutoff: f64,
    /// Safe mode: the sign of every query from ray parity.
    pub safe: bool,
    /// The most cells the grid may have.
    pub max_cells: usize,
}

impl GridOptions {
    /// Cells of the mean edge length, a margin of one cut-off, pseudo-normal signs, at most 2²⁴ cells.
    pub fn new(cutoff: f64) -> Self {
        GridOptions { cell: None, margin: cutoff, cutoff, safe: false, max_cells: 1 << 24 }
    }
}

/// The grid and arrays of a mesh tool, owned on the host (copy them to the device for a GPU tool).
#[derive(Clone, Debug, PartialEq)]
pub struct MeshGridData {
    pub params: MeshGrid,
    pub verts: Vec<[f64; 3]>,
    pub face_n: Vec<[f64; 3]>,
    pub edge_n: Vec<[f64; 3]>,
    pub vert_n: Vec<[f64; 3]>,
    pub cell_start: Vec<u32>,
    pub cell_tri: Vec<u32>,
    pub cell_side: Vec<u32>,
}

impl MeshGridData {
    /// Builds the grid of a mesh that passed [`super::prepare`] (closed, manifold, outward oriented).
    pub fn build(m: &TriMesh, o: &GridOptions) -> Result<Self, MeshError> {
        let err = |what: String| MeshError::Grid { file: m.source.clone(), what };
        let report = super::check(m)?;
        let cell = o.cell.unwrap_or(report.mean_edge);
        if !(cell > 0.0
            && cell.is_finite()
            && o.margin >= 0.0
            && o.margin.is_finite()
            && o.cutoff > 0.0
            && o.cutoff.is_finite())
        {
            return Err(err(format!(
                "cell = {cell}, margin = {}, cutoff = {}: expected cell > 0, margin ≥ 0, cutoff > 0, all finite",
                o.margin, o.cutoff
            )));
        }
        let (lo, hi) = report.bounds;
        let origin = lo.map(|x| x - o.margin);
        let dims = [0, 1, 2].map(|k| (((hi[k] - lo[k] + 2.0 * o.margin) / cell).ceil() as u64).max(1));
        let cells = dims.iter().product::<u64>();
        if cells > o.max_cells as u64 || cells >= u32::MAX as u64 {
            return Err(err(format!("{cells} cells of {cell:e}: expected at most {}; use larger cells", o.max_cells)));
        }
        let params = MeshGrid {
            origin,
            cell,
            inv_cell: 1.0 / cell,
            cutoff: o.cutoff,
            ray: RAY_DIR,
            dims: dims.map(|d| d as u32),
            safe: o.safe as u32,
        };
        let verts: Vec<[f64; 3]> = m.triangles.iter().flat_map(|t| m.corners(t)).collect();
        let (face_n, edge_n, vert_n) = pseudo_normals(m);
        let (cell_start, cell_tri) = bin(m, &params);
        if cell_tri.len() >= u32::MAX as usize {
            return Err(err(format!("{} cell entries: expected fewer than 2³²; use larger cells", cell_tri.len())));
        }
        let cell_side = sides(m, &params, &cell_start);
        Ok(MeshGridData { params, verts, face_n, edge_n, vert_n, cell_start, cell_tri, cell_side })
    }

    /// The arrays as slices.
    pub fn arrays(&self) -> MeshArrays<'_> {
        MeshArrays {
            verts: &self.verts,
            face_n: &self.face_n,
            edge_n: &self.edge_n,
            vert_n: &self.vert_n,
            cell_start: &self.cell_start,
            cell_tri: &self.cell_tri,
            cell_side: &self.cell_side,
        }
    }

    /// The tool over these host arrays (the CPU's; lengths agree by construction).
    pub fn tool(&self) -> MeshTool<'_> {
        match MeshTool::from_slices(self.params, self.arrays()) {
            Ok(t) => t,
            Err(_) => unreachable!("build() makes arrays of agreeing lengths"),
        }
    }
}

fn unit(v: [f64; 3]) -> [f64; 3] {
    let l = dot(v, v).sqrt();
    v.map(|x| x / l)
}

/// Face, edge and vertex normals, flat.
type Normals = (Vec<[f64; 3]>, Vec<[f64; 3]>, Vec<[f64; 3]>);

/// Face normals and the edge and vertex pseudo-normals, per triangle slot (each edge's and vertex's computed once,
/// so every triangle sharing it stores the same bits).
fn pseudo_normals(m: &TriMesh) -> Normals {
    let face: Vec<[f64; 3]> = m
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = m.corners(t);
            unit(cross(sub(b, a), sub(c, a)))
        })
        .collect();
    let mut edge: HashMap<(u32, u32), [f64; 3]> = HashMap::new();
    let mut vert = vec![[0.0; 3]; m.vertices.len()];
    for (t, tri) in m.triangles.iter().enumerate() {
        let c = m.corners(tri);
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            let e = edge.entry((a.min(b), a.max(b))).or_insert([0.0; 3]);
            *e = [0, 1, 2].map(|i| e[i] + face[t][i]);
            // The face's angle at corner k.
            let (u, w) = (sub(c[(k + 1) % 3], c[k]), sub(c[(k + 2) % 3], c[k]));
            let angle = (dot(u, w) / (dist(u, [0.0; 3]) * dist(w, [0.0; 3]))).clamp(-1.0, 1.0).acos();
            let v = &mut vert[tri[k] as usize];
            *v = [0, 1, 2].map(|i| v[i] + angle * face[t][i]);
        }
    }
    let mut edge_n = Vec::with_capacity(3 * m.triangles.len());
    let mut vert_n = Vec::with_capacity(3 * m.triangles.len());
    for tri in &m.triangles {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            edge_n.push(unit(edge[&(a.min(b), a.max(b))]));
            vert_n.push(unit(vert[tri[k] as usize]));
        }
    }
    (face, edge_n, vert_n)
}

/// The CSR lists: for each cell (x fastest), the triangles whose surface overlaps the cell's box.
fn bin(m: &TriMesh, g: &MeshGrid) -> (Vec<u32>, Vec<u32>) {
    let cells = g.dims.iter().map(|&d| d as usize).product::<usize>();
    let mut pairs: Vec<(u32, u32)> = Vec::new();
    for (t, tri) in m.triangles.iter().enumerate() {
        let c = m.corners(tri);
        let range = [0, 1, 2].map(|k| {
            let cell_of = |x: f64| (((x - g.origin[k]) * g.inv_cell).floor().max(0.0) as u32).min(g.dims[k] - 1);
            let (lo, hi) = (c[0][k].min(c[1][k]).min(c[2][k]), c[0][k].max(c[1][k]).max(c[2][k]));
            (cell_of(lo), cell_of(hi))
        });
        for z in range[2].0..=range[2].1 {
            for y in range[1].0..=range[1].1 {
                for x in range[0].0..=range[0].1 {
                    let centre = [x, y, z].map(|i| i as f64 + 0.5);
                    let centre = [0, 1, 2].map(|k| g.origin[k] + centre[k] * g.cell);
                    // Grown by a hair so that a triangle on a cell face is listed in both cells.
                    if box_overlaps_triangle(centre, 0.5 * g.cell * (1.0 + 1e-9), c) {
                        pairs.push(((z * g.dims[1] + y) * g.dims[0] + x, t as u32));
                    }
                }
            }
        }
    }
    pairs.sort_unstable();
    let mut start = vec![0u32; cells + 1];
    for &(c, _) in &pairs {
        start[c as usize + 1] += 1;
    }
    for i in 0..cells {
        start[i + 1] += start[i];
    }
    (start, pairs.into_iter().map(|p| p.1).collect())
}

/// Each cell's side: [`CELL_MIXED`] where triangles overlap it, else the ray parity of its centre (a cell no
/// triangle touches is wholly on one side). O(empty cells × triangles), once per tool.
fn sides(m: &TriMesh, g: &MeshGrid, start: &[u32]) -> Vec<u32> {
    let tris: Vec<[[f64; 3]; 3]> = m.triangles.iter().map(|t| m.corners(t)).collect();
    let [nx, ny, _] = g.dims.map(|d| d as usize);
    (0..start.len() - 1)
        .map(|c| {
            if start[c + 1] > start[c] {
                return CELL_MIXED;
            }
            let i = [c % nx, c / nx % ny, c / (nx * ny)];
            let p = [0, 1, 2].map(|k| g.origin[k] + (i[k] as f64 + 0.5) * g.cell);
            let hits = tris.iter().filter(|t| ray_hits_triangle(p, g.ray, t[0], t[1], t[2])).count();
            if hits % 2 == 1 { CELL_IN } else { CELL_OUT }
        })
        .collect()
}

/// Akenine-Möller's box–triangle overlap by separating axes (the module doc): a cube of centre `c` and half-width `h`.
fn box_overlaps_triangle(c: [f64; 3], h: f64, tri: [[f64; 3]; 3]) -> bool {
    let v = tri.map(|p| sub(p, c));
    let f = [sub(v[1], v[0]), sub(v[2], v[1]), sub(v[0], v[2])];
    let e = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let mut axes = vec![e[0], e[1], e[2], cross(f[0], f[1])];
    for ek in e {
        for fj in f {
            axes.push(cross(ek, fj));
        }
    }
    axes.iter().all(|a| {
        let p = v.map(|x| dot(*a, x));
        let r = h * (a[0].abs() + a[1].abs() + a[2].abs());
        !(p[0].min(p[1]).min(p[2]) > r || p[0].max(p[1]).max(p[2]) < -r)
    })
}
