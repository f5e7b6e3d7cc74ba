//! The Material Point Method (issue 26; docs/mpm.md): Nairn's 2D cutting as ductile fracture on the same
//! backends, cell lists and output as SPH. `setup` turns an MPM scene into particles, a grid, a crack and motions;
//! `solver` holds the state on a backend and steps it with the kernels' gathers (`kernels::mpm`); `run` drives a
//! run and writes its output; `checkpoint` saves and restores a run's state; `coverage` draws the particles'
//! deformed domains (the glyph test of the position update).

pub mod checkpoint;
pub mod coverage;
pub mod output;
pub mod run;
pub mod setup;
pub mod solver;
