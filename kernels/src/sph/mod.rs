//! Smoothed-particle hydrodynamics for solids: updated-Lagrangian "Algorithm 1" (roethlin-solver.md §3–§5).

pub mod bond;
pub mod correction;
pub mod density;
pub mod eigen;
pub mod energy;
pub mod heat;
pub mod integrate;
pub mod interact;
pub mod kernel;
pub mod lanes;
pub mod params;
pub mod plastic;
pub mod step;
pub mod tensor;

pub use kernel::CubicSpline;
pub use params::{SphParams, Stabilisers};
pub use tensor::TensorOps;
