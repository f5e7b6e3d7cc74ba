//! Closed-form models that predict what a simulation should give, for comparison beside its results.

pub mod nairn;
