//! Orthogonal cutting: the tool's motion, the force series and the end-of-run analysis (steady state, chip
//! thickness, segmentation).

pub mod chip;
pub mod motion;
pub mod record;
pub mod setup;
pub mod steady;
