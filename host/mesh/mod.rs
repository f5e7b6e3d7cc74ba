//! Triangle-mesh tools of 3D (roethlin-solver.md §5.5): reading a tool's surface (STL, OBJ, LS-DYNA keyword),
//! checking it is a closed, consistently and outward oriented 2-manifold, placing it (scale, rotation, translation)
//! and building the uniform triangle grid that `swarf_kernels::contact::MeshTool` queries.

pub mod check;
pub mod dyna;
pub mod grid;
pub mod obj;
pub mod place;
pub mod read;
pub mod stl;

pub use check::{CheckReport, check, prepare, weld};
pub use grid::{GridOptions, MeshGridData};
pub use place::Placement;
pub use read::read;

use thiserror::Error;

/// A triangle soup or mesh: vertex positions and triangles as vertex indices, counter-clockwise seen from outside.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriMesh {
    /// Where it came from (a file name, or a label), for messages.
    pub source: String,
    pub vertices: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
}

impl TriMesh {
    /// The lowest and highest corner of the vertices' bounding box (zeros for an empty mesh).
    pub fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for v in &self.vertices {
            for k in 0..3 {
                lo[k] = lo[k].min(v[k]);
                hi[k] = hi[k].max(v[k]);
            }
        }
        if self.vertices.is_empty() { ([0.0; 3], [0.0; 3]) } else { (lo, hi) }
    }

    /// The enclosed volume, Σ a·(b × c)/6 over the triangles (divergence theorem): positive for an outward
    /// oriented closed mesh.
    pub fn signed_volume(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = self.corners(t);
                a[0] * (b[1] * c[2] - b[2] * c[1])
                    + a[1] * (b[2] * c[0] - b[0] * c[2])
                    + a[2] * (b[0] * c[1] - b[1] * c[0])
            })
            .sum::<f64>()
            / 6.0
    }

    /// A triangle's three vertex positions.
    pub fn corners(&self, t: &[u32; 3]) -> [[f64; 3]; 3] {
        t.map(|i| self.vertices[i as usize])
    }

    /// The centroid of triangle t (a location for messages).
    pub fn centroid(&self, t: usize) -> [f64; 3] {
        let [a, b, c] = self.corners(&self.triangles[t]);
        [(a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0, (a[2] + b[2] + c[2]) / 3.0]
    }
}

/// Why a mesh cannot be read, placed or used; each names the file and where.
#[derive(Debug, Error)]
pub enum MeshError {
    #[error("{file}: {source}")]
    Io {
        file: String,
        #[source]
        source: std::io::Error,
    },
    /// A line that does not parse: its number (1-based) and what was expected there.
    #[error("{file}, line {line}: expected {expected}, found `{found}`")]
    Parse { file: String, line: usize, expected: String, found: String },
    /// A file that is not of the format (or holds no triangles).
    #[error("{file}: {what}")]
    Format { file: String, what: String },
    /// A mesh the checks refuse: what is wrong and where (triangle indices and a coordinate).
    #[error("{file}: mesh refused: {what}")]
    Broken { file: String, what: String },
    /// A placement that is not a similarity (non-positive scale, non-rotation matrix, zero axis, NaN).
    #[error("mesh placement: {0}")]
    Placement(String),
    /// A grid that cannot be built (the message says which option).
    #[error("{file}: mesh grid: {what}")]
    Grid { file: String, what: String },
}

impl From<MeshError> for crate::Error {
    fn from(e: MeshError) -> Self {
        crate::Error::Scene(e.to_string())
    }
}

/// A coordinate for messages.
pub(crate) fn at(p: [f64; 3]) -> String {
    format!("({:.6e}, {:.6e}, {:.6e})", p[0], p[1], p[2])
}
