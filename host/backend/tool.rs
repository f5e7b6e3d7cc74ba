//! A rigid tool's shape in the backend's memory, as the contact pass reads it: the parametric tool as one
//! `Tool2d` (its outline in 2D, the prism of the outline along z in 3D), or a triangle-mesh tool as its grid's
//! flat arrays (`swarf::mesh::MeshGridData`), from which each launch builds the kernels' `MeshTool` by value over
//! the buffers' addresses (roethlin-solver.md §5.5).

use super::{Backend, Buffer};
use crate::Result;
use crate::kernels::contact::mesh::MeshGrid;
use crate::kernels::contact::{MeshTool, Tool2d};
use crate::mesh::MeshGridData;

/// The mesh tool's arrays in the backend's memory (lengths as `MeshGridData`'s).
pub struct DeviceMesh<B: Backend> {
    pub grid: MeshGrid,
    verts: B::Buf<[f64; 3]>,
    face_n: B::Buf<[f64; 3]>,
    edge_n: B::Buf<[f64; 3]>,
    vert_n: B::Buf<[f64; 3]>,
    cell_start: B::Buf<u32>,
    cell_tri: B::Buf<u32>,
    cell_side: B::Buf<u32>,
    /// Entries of the cell lists (`cell_tri` holds one unused element when this is 0).
    n_cell_tri: u32,
}

impl<B: Backend> DeviceMesh<B> {
    /// Copies a mesh tool's grid and arrays to the backend. An empty array (a grid with no triangle list) is
    /// uploaded as one unused element, so that every buffer has an address.
    pub fn upload(b: &B, m: &MeshGridData) -> Result<Self> {
        let list: &[u32] = if m.cell_tri.is_empty() { &[0] } else { &m.cell_tri };
        Ok(DeviceMesh {
            grid: m.params,
            verts: b.upload(&m.verts, "mesh tool vertices")?,
            face_n: b.upload(&m.face_n, "mesh tool face normals")?,
            edge_n: b.upload(&m.edge_n, "mesh tool edge normals")?,
            vert_n: b.upload(&m.vert_n, "mesh tool vertex normals")?,
            cell_start: b.upload(&m.cell_start, "mesh tool cell starts")?,
            cell_tri: b.upload(list, "mesh tool cell triangles")?,
            cell_side: b.upload(&m.cell_side, "mesh tool cell sides")?,
            n_cell_tri: m.cell_tri.len() as u32,
        })
    }

    /// The kernels' tool over these buffers (valid while they live; the contact pass reads it by value).
    pub fn tool(&self, b: &B) -> MeshTool<'static> {
        let v = |buf: &B::Buf<[f64; 3]>| b.address(buf) as *const [f64; 3];
        let u = |buf: &B::Buf<u32>| b.address(buf) as *const u32;
        let n_tri = self.face_n.len() as u32;
        // SAFETY: the buffers hold what `MeshGridData::build` made, whose lengths agree with the grid (the
        // kernels' `from_slices` check on the host copy); they outlive every launch that reads this tool.
        unsafe {
            MeshTool::from_raw(
                self.grid,
                v(&self.verts),
                v(&self.face_n),
                v(&self.edge_n),
                v(&self.vert_n),
                u(&self.cell_start),
                u(&self.cell_tri),
                u(&self.cell_side),
                n_tri,
                self.n_cell_tri,
            )
        }
    }
}

/// A tool's shape on the backend.
pub enum DeviceTool<B: Backend> {
    /// The parametric tool (one element).
    Prism(B::Buf<Tool2d>),
    Mesh(DeviceMesh<B>),
}
