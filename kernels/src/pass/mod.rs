//! One argument struct per pass: the pass's particle count, its buffers as raw pointers (null where a buffer is
//! off) and its by-value parameter blocks, `#[repr(C)]` so that the host (x86-64) and the device (nvptx64) lay it
//! out alike. The PTX entry takes the struct by value as its single parameter (`.param .align N .b8 a[size]`:
//! the launch copies it into the constant bank with the launch, as `SphParams` was before) and the CPU backend
//! builds the same struct with host pointers, so a swapped pointer no longer compiles and both backends share
//! the per-particle loads and stores. tests/ptx.rs checks each entry's parameter block against
//! `size_of`/`align_of` of its struct.

pub mod correction;
pub mod finish;
pub mod launch;
pub mod models;
pub mod mpm;
pub mod neighbour;
pub mod predict;
pub mod rates;
pub mod sph;
pub mod table;

pub use correction::{CorrectionArgs, CorrectionPass};
pub use finish::{Finish, FinishArgs, FinishPlastic, FinishPlasticArgs, StepPtrs};
pub use launch::{Grid, Particles, Pass, Span};
pub use models::{FLOW_MODEL_TAGS, ModelEntry};
pub use neighbour::{
    GatherArgs, GatherFieldsArgs, Hash, HashArgs, HashCountArgs, NeighbourList, NeighbourListArgs, ScanApplyArgs,
    ScanReduceArgs, ScatterArgs, SortArgs, Verlet, VerletArgs, ZeroArgs,
};
pub use predict::{Predict, PredictArgs};
pub use rates::{RatesArgs, RatesPass};
pub use sph::{
    Bond, BondArgs, BondIndex, BondIndexArgs, BondOpen, BondOpenArgs, Contact, ContactArgs, Density, DensityArgs, Heat,
    HeatArgs, Plastic, PlasticArgs, Prepare, PrepareArgs,
};
pub use table::{ENTRY_COUNT, ENTRY_KEYS, ENTRY_NAMES, EntryKey, entry_index, single_index};
