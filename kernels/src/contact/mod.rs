//! Contact with a rigid tool: the seam between the contact law and the tool's shape ([`ToolGeometry`]), the 2D
//! parametric tool (segments and the edge arc), the tool's rigid motion at a step ([`ToolState`]: translation and
//! rotation) and the penalty contact with LS-DYNA friction (roethlin-solver.md §5.4; klippel-constitutive.md §1.3).

pub mod geometry;
pub mod mesh;
pub mod motion;
pub mod penalty;
pub mod tool2d;

pub use geometry::{SurfacePoint, ToolArg, ToolGeometry};
pub use mesh::{MeshGrid, MeshTool};
pub use motion::ToolState;
pub use penalty::ContactParams;
pub use tool2d::{Tool2d, ToolShape};
