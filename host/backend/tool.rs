//! A run's rigid tools in the backend's memory, as the contact pass reads them: their contact constants, one
//! `ContactParams` each, and their shapes: parametric tools as an array of `Tool2d` (the outline in 2D, the prism
//! of the outline along z in 3D), or triangle-mesh tools, each as its grid's flat arrays
//! (`swarf::mesh::MeshGridData`) with an array of the kernels' `MeshTool`s over the buffers' addresses
//! (roethlin-solver.md §5.5).

use super::{Backend, Buffer};
use crate::Result;
use crate::kernels::contact::mesh::MeshGrid;
use crate::kernels::contact::{ContactParams, MeshTool, Tool2d};
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

/// The tools' shapes on the backend, all of one kind.
pub enum DeviceShapes<B: Backend> {
    /// Parametric tools (one element each).
    Prism(B::Buf<Tool2d>),
    /// Mesh tools: their arrays, and the kernels' `MeshTool`s over them as raw words (a `MeshTool` holds device
    /// addresses, so it is not `Pod`; the contact pass reads the array as `*const MeshTool`).
    Mesh { meshes: Vec<DeviceMesh<B>>, views: B::Buf<u64> },
}

/// A run's tools on the backend: their contact constants and shapes, one of each per tool.
pub struct DeviceTools<B: Backend> {
    pub params: B::Buf<ContactParams>,
    pub shapes: DeviceShapes<B>,
}

// The `MeshTool` array is uploaded as whole 8-byte words.
const _: () = assert!(size_of::<MeshTool<'static>>().is_multiple_of(8) && align_of::<MeshTool<'static>>() <= 8);

impl<B: Backend> DeviceTools<B> {
    /// Uploads the tools (`params[k]` with `shapes[k]`; all parametric or all meshes).
    pub fn upload(b: &B, params: &[ContactParams], shapes: &[&crate::tool::Shape]) -> Result<Self> {
        use crate::tool::Shape;
        if params.len() != shapes.len() || params.is_empty() {
            return Err(crate::Error::Length {
                op: "tools (constants and shapes)",
                expected: params.len(),
                got: shapes.len(),
            });
        }
        let prisms: Option<Vec<Tool2d>> = shapes.iter().map(|s| s.parametric().copied()).collect();
        let shapes = match prisms {
            Some(p) => DeviceShapes::Prism(b.upload(&p, "tool shapes")?),
            None => {
                let meshes = shapes
                    .iter()
                    .map(|s| match s {
                        Shape::Mesh(m) => DeviceMesh::upload(b, m),
                        Shape::Parametric(_) => {
                            Err(crate::Error::Scene("the tools of a run must be all meshes or all parametric".into()))
                        }
                    })
                    .collect::<Result<Vec<_>>>()?;
                let views: Vec<MeshTool<'static>> = meshes.iter().map(|m| m.tool(b)).collect();
                // SAFETY: `MeshTool` is `repr(C)`, a whole number of words (asserted above) with no padding (its
                // fields are words and u32 pairs), so its bytes read as u64 words.
                let words = unsafe {
                    std::slice::from_raw_parts(views.as_ptr() as *const u64, views.len() * size_of::<MeshTool>() / 8)
                };
                DeviceShapes::Mesh { views: b.upload(words, "mesh tools")?, meshes }
            }
        };
        Ok(DeviceTools { params: b.upload(params, "contact parameters")?, shapes })
    }

    /// How many tools.
    pub fn count(&self) -> usize {
        self.params.len()
    }

    /// The parametric tools' array, if the tools are parametric.
    pub fn prisms(&self) -> Option<&B::Buf<Tool2d>> {
        match &self.shapes {
            DeviceShapes::Prism(t) => Some(t),
            DeviceShapes::Mesh { .. } => None,
        }
    }
}
