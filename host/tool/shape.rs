//! A rigid tool's shape as the solver holds it: the parametric tool (its outline in 2D, the prism of the outline
//! along z in 3D) or a triangle-mesh tool (its placed, checked mesh hashed into a grid, docs/3d.md), and the
//! picture of it written beside each frame.

use std::sync::Arc;

use crate::kernels::contact::{SurfacePoint, Tool2d, ToolGeometry, ToolState};
use crate::mesh::MeshGridData;

/// The tool's shape in its own frame. (The parametric tool is held by value: one per run, and the kernels read it
/// as plain data.)
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug)]
pub enum Shape {
    Parametric(Tool2d),
    /// Shared: the grid is built once per scene and may be large.
    Mesh(Arc<MeshGridData>),
}

impl Shape {
    /// The signed distance, outward normal and closest point of a tool-frame point (the kernels' query, on the
    /// host: the engagement check).
    pub fn query(&self, p: [f64; 3]) -> SurfacePoint {
        match self {
            Shape::Parametric(t) => t.query(p),
            Shape::Mesh(m) => m.tool().query(p),
        }
    }

    /// The tool's picture in its frame: the outline (z = 0) or the triangles' corners (3 per triangle).
    pub fn picture(&self) -> Picture {
        match self {
            Shape::Parametric(t) => {
                Picture::Outline(super::outline::outline(t).into_iter().map(|p| [p[0], p[1], 0.0]).collect())
            }
            Shape::Mesh(m) => Picture::Surface(m.verts.clone()),
        }
    }

    /// Bytes of the shape in the backend's memory (`backend::DeviceTool`): one `Tool2d`, or the mesh's arrays.
    pub fn device_bytes(&self) -> usize {
        match self {
            Shape::Parametric(_) => size_of::<Tool2d>(),
            Shape::Mesh(m) => {
                24 * (m.verts.len() + m.face_n.len() + m.edge_n.len() + m.vert_n.len())
                    + 4 * (m.cell_start.len() + m.cell_tri.len().max(1) + m.cell_side.len())
            }
        }
    }

    /// The parametric tool, if this is one.
    pub fn parametric(&self) -> Option<&Tool2d> {
        match self {
            Shape::Parametric(t) => Some(t),
            Shape::Mesh(_) => None,
        }
    }
}

impl ToolGeometry for Shape {
    fn query(&self, p: [f64; 3]) -> SurfacePoint {
        Shape::query(self, p)
    }
}

/// The tool as drawn beside a frame (`tool_*.vtp`): a closed polyline, or a triangle surface (3 points per
/// triangle, counter-clockwise seen from outside).
#[derive(Clone, Debug, PartialEq)]
pub enum Picture {
    Outline(Vec<[f64; 3]>),
    Surface(Vec<[f64; 3]>),
}

impl Picture {
    /// The picture placed in the world at the state `s`.
    pub fn in_world(&self, s: &ToolState) -> Picture {
        let place = |pts: &[[f64; 3]]| pts.iter().map(|&p| s.point_to_world(p)).collect();
        match self {
            Picture::Outline(p) => Picture::Outline(place(p)),
            Picture::Surface(p) => Picture::Surface(place(p)),
        }
    }
}
