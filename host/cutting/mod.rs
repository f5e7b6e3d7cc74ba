//! Orthogonal cutting's analyses: the force series and the end-of-run analysis (steady state, chip thickness,
//! segmentation). The tool's motion and set-up live below the solver, in [`crate::tool`]; they are re-exported here
//! under their former paths.

pub mod chip;
pub mod record;
pub mod steady;

pub use crate::tool::{motion, setup};
