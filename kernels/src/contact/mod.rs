//! Contact with a rigid tool: the tool's geometry (2D: segments and the edge arc) and the penalty contact with
//! LS-DYNA friction (roethlin-solver.md §5.4; klippel-constitutive.md §1.3).

pub mod penalty;
pub mod tool2d;

pub use penalty::{ContactParams, ToolState};
pub use tool2d::{Tool2d, ToolShape};
