//! The Material Point Method of Nairn's cutting simulations (nairn-mpm.md §1; docs/mpm.md): 2D plane strain,
//! uGIMP shape functions, two specimen fields per node across a cohesive crack on the cut plane, a rigid tool
//! of particles with prescribed contact normals and Coulomb friction, PIC damping with the second-order position
//! update, and neo-Hookean J2 plasticity. Every step is a sequence of gathers (`step`), so that the GPU and the
//! CPU sum the same terms in the same order.

pub mod grid;
pub mod hyperelastic;
pub mod shape;
pub mod step;
