//! Orthogonal cutting's analyses: the force series and the end-of-run analysis (steady state, chip thickness,
//! segmentation). The tool's motion and set-up live below the solver, in [`crate::tool`]; they are re-exported here
//! under their former paths.

pub mod autocorr;
pub mod chip;
pub mod chip_axis;
pub mod early_stop;
pub mod record;
pub mod segments;
pub mod steady;
pub mod window;

pub use crate::tool::{motion, setup};
