//! Smoothed-particle hydrodynamics for solids (roethlin-solver.md §3–§5).

pub mod density;
pub mod kernel;

pub use kernel::CubicSpline;
