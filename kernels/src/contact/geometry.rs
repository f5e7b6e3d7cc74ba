//! The seam between the contact law and the tool's shape: a rigid tool answers, for a point of its own frame, the
//! signed distance to its surface, the outward normal and the closest surface point (roethlin-solver.md §5.4;
//! §3.2 for the triangle-mesh tools of 3D). The contact pass is generic over it and monomorphised (no `dyn`: it
//! runs on the GPU), so a new shape is a new implementation, not a new pass.
//!
//! Points are 3-component in every dimension: a 2D run passes z = 0 and reads only x and y of the answer. The
//! tool's rigid motion (where its frame is, how fast a point of it moves) is the step's [`super::ToolState`].

use super::mesh::MeshTool;
use super::tool2d::Tool2d;

/// The closest surface point of a query point, in the tool's frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SurfacePoint {
    /// Signed distance to the surface: negative inside the tool.
    pub distance: f64,
    /// Outward unit normal of the surface at `point` (for an outside point, the direction from `point` to the query).
    pub normal: [f64; 3],
    /// The closest point on the surface.
    pub point: [f64; 3],
}

/// A rigid tool's shape in its own frame. Implementations are plain data (or plain data with device pointers,
/// for a mesh read through them) and must not panic: they run inside the GPU's contact pass.
pub trait ToolGeometry {
    /// The signed distance, outward normal and closest surface point of `p` (tool frame).
    fn query(&self, p: [f64; 3]) -> SurfacePoint;

    /// Whether `p` (tool frame) lies inside the tool or on its surface.
    #[inline(always)]
    fn contains(&self, p: [f64; 3]) -> bool {
        self.query(p).distance <= 0.0
    }
}

/// The 2D parametric tool; in 3D the prism of its outline along z (the extruded orthogonal cut). The answers are
/// [`Tool2d::closest`] and [`Tool2d::contains`] of (x, y), bit for bit, with z = 0 in the normal and z kept in the
/// closest point.
impl ToolGeometry for Tool2d {
    #[inline(always)]
    fn query(&self, p: [f64; 3]) -> SurfacePoint {
        let c = self.closest([p[0], p[1]]);
        SurfacePoint {
            distance: c.distance,
            normal: [c.normal[0], c.normal[1], 0.0],
            point: [c.point[0], c.point[1], p[2]],
        }
    }

    #[inline(always)]
    fn contains(&self, p: [f64; 3]) -> bool {
        Tool2d::contains(self, [p[0], p[1]])
    }
}

/// How a contact pass receives its tools: a pointer to an array of `count` tools in device (or host) memory, the
/// parametric tools' `Tool2d`s or the mesh tools' `MeshTool`s (each its grid's scalars and the addresses of its
/// arrays). `VARIANT` is the pass table's variant number of the contact entry (kernels/src/pass/table.rs): 0 the
/// parametric tool, 1 the mesh.
pub trait ToolArg: Copy {
    type Geometry: ToolGeometry;
    const VARIANT: u32;
    /// Tool k's shape.
    ///
    /// # Safety
    /// The pointer points at an array of live tools longer than k.
    unsafe fn geometry(&self, k: usize) -> &Self::Geometry;
}

impl ToolArg for *const Tool2d {
    type Geometry = Tool2d;
    const VARIANT: u32 = 0;
    #[inline(always)]
    unsafe fn geometry(&self, k: usize) -> &Tool2d {
        unsafe { &*self.add(k) }
    }
}

impl ToolArg for *const MeshTool<'static> {
    type Geometry = MeshTool<'static>;
    const VARIANT: u32 = 1;
    #[inline(always)]
    unsafe fn geometry(&self, k: usize) -> &MeshTool<'static> {
        unsafe { &*self.add(k) }
    }
}
