//! Cell-list neighbour search: a uniform grid over a bounding box, one cell key per particle, particles sorted by
//! key (counting sort), a prefix array of cell starts, and a gather over a fixed stencil of cells, or over the
//! Verlet list built on it (`verlet`).
//!
//! Roethlin's design (roethlin-solver.md §6.3–6.4): one thread per particle, gather only, no atomics in the
//! force loop. Differences from the original code are recorded in docs/neighbour-search.md.

pub mod grid;
pub mod reorder;
pub mod search;
pub mod sort;
pub mod verlet;

pub use grid::{BlankBox, GridParams};
pub use reorder::GatherField;
pub use search::{for_each_neighbour, for_each_neighbour_strided};
pub use verlet::{Neighbours, for_each_candidate, for_each_candidate_strided};
