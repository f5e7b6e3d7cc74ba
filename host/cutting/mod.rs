//! Orthogonal cutting's analyses: the force series and the end-of-run analysis (steady state, chip thickness,
//! segmentation), and the chip geometry of one frame along the whole chip (`chip_frame`). The tool's motion and
//! set-up live below the solver, in [`crate::tool`]; they are re-exported here under their former paths.

pub mod autocorr;
pub mod cells;
pub mod chip;
pub mod chip_axis;
pub mod chip_frame;
pub mod chip_profile;
pub mod chip_report;
pub mod chip_run;
pub mod curl;
pub mod early_stop;
pub mod energy_audit;
pub mod record;
pub mod segments;
pub mod shear_band;
pub mod steady;
pub mod tool_wear;
pub mod window;

pub use crate::tool::{motion, setup};
