//! swarf: a GPU meshless (SPH) simulator for metal cutting.
//!
//! The host crate orchestrates: it owns device memory, launches kernels on a [`backend::Backend`] (the CPU, or
//! an NVIDIA GPU through CUDA) and never re-implements physics, which lives once in `swarf_kernels`.

pub mod analysis;
pub mod analytic;
pub mod backend;
pub mod bench;
pub mod check;
pub mod checkpoint;
pub mod cutting;
pub mod ensemble;
pub mod error;
pub mod grid;
pub mod hash;
pub mod identify;
pub mod info;
pub mod material;
pub mod mesh;
pub mod method;
pub mod mpm;
pub mod neighbour;
pub mod output;
pub mod plot;
pub mod provenance;
pub mod ptx;
pub mod render;
pub mod resume;
pub mod rng;
pub mod run;
pub mod run_folder;
pub mod scene;
pub mod solver;
pub mod state;
pub mod state_table;
pub mod study;
pub mod sweep;
pub mod tool;
pub mod tuning;

pub use error::{Error, Result};
pub use swarf_kernels as kernels;
