//! The arguments of the MPM passes (`mpm::step`): the node gather, the crack points, the node update, the
//! start-up damping (the kinetic energy's tile sums and the update) and the particle update, one struct each,
//! taken by value.

use super::launch::{Grid, Pass};
use super::table::entry_index;
use crate::mpm::grid::{MpmParams, MpmStep};
use crate::mpm::step::{
    Cells, Crack, ESCAPED, NON_FINITE, Nodes, Particles, crack_point, feedback, g2p_particle, ke_tile, node_update,
    p2g_node,
};
use crate::real::Real;
use core::marker::PhantomData;

/// The node gather (`mpm::step::p2g_node`): one item per node.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct P2gArgs<R: Real> {
    pub n: u32,
    pub _pad: u32,
    pub params: MpmParams,
    pub parts: Particles<R>,
    pub cells: Cells,
    pub nodes: Nodes<R>,
}

impl<R: Real> P2gArgs<R> {
    /// # Safety
    /// i < n; the pointers name live arrays of the grid's nodes and the run's particles.
    #[inline(always)]
    pub unsafe fn particle(&self, i: usize) {
        unsafe { p2g_node(&self.params, &self.parts, &self.cells, &self.nodes, i) }
    }
}

/// The node gather pass (`swarf_mpm_p2g_*`).
pub struct P2g<R>(PhantomData<R>);
crate::simple_pass!(P2g<R>, P2gArgs<R>, entry_index("mpm_p2g", 2, size_of::<R>(), 0), Grid::Particles, [R: Real]);

/// The crack points (`mpm::step::crack_point`): one item per point.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct CrackArgs<R: Real> {
    pub n: u32,
    pub _pad: u32,
    pub params: MpmParams,
    pub parts: Particles<R>,
    pub crack: Crack<R>,
}

impl<R: Real> CrackArgs<R> {
    /// # Safety
    /// i < n; the crack's arrays hold n points whose pairs name live particles.
    #[inline(always)]
    pub unsafe fn particle(&self, i: usize) {
        unsafe { crack_point(&self.params, &self.parts, &self.crack, i) }
    }
}

/// The crack pass (`swarf_mpm_crack_*`).
pub struct CrackPass<R>(PhantomData<R>);
crate::simple_pass!(CrackPass<R>, CrackArgs<R>, entry_index("mpm_crack", 2, size_of::<R>(), 0), Grid::Particles,
    [R: Real]);

/// The node update (`mpm::step::node_update`): one item per node.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct NodesArgs<R: Real> {
    pub n: u32,
    pub _pad: u32,
    pub params: MpmParams,
    /// The step's motions: an entry of a device table, so that a captured batch of steps reads each step's own.
    pub step: *const MpmStep,
    pub nodes: Nodes<R>,
}

impl<R: Real> NodesArgs<R> {
    /// # Safety
    /// i < n; the pointers name live arrays of the grid's nodes.
    #[inline(always)]
    pub unsafe fn particle(&self, i: usize) {
        unsafe { node_update(&self.params, &*self.step, &self.nodes, i) }
    }
}

/// The node update pass (`swarf_mpm_nodes_*`).
pub struct NodesPass<R>(PhantomData<R>);
crate::simple_pass!(NodesPass<R>, NodesArgs<R>, entry_index("mpm_nodes", 2, size_of::<R>(), 0), Grid::Particles,
    [R: Real]);

/// The kinetic energy's tile sums (`mpm::step::ke_tile`): one item per tile of `KE_TILE` nodes.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct KeArgs<R: Real> {
    pub n: u32,
    /// The grid's nodes.
    pub nodes_n: u32,
    pub nodes: Nodes<R>,
}

impl<R: Real> KeArgs<R> {
    /// # Safety
    /// i < n tiles of the grid's `nodes_n` nodes; the pointers name live arrays.
    #[inline(always)]
    pub unsafe fn particle(&self, i: usize) {
        unsafe { ke_tile(&self.nodes, self.nodes_n as usize, i) }
    }
}

/// The tile-sum pass (`swarf_mpm_ke_*`).
pub struct KePass<R>(PhantomData<R>);
crate::simple_pass!(KePass<R>, KeArgs<R>, entry_index("mpm_ke", 2, size_of::<R>(), 0), Grid::Particles, [R: Real]);

/// The start-up damping's update (`mpm::step::feedback`): one item (n = 1).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct FeedbackArgs<R: Real> {
    pub n: u32,
    /// The tiles of [`KeArgs`].
    pub tiles: u32,
    /// As [`NodesArgs::step`].
    pub step: *const MpmStep,
    pub nodes: Nodes<R>,
}

impl<R: Real> FeedbackArgs<R> {
    /// # Safety
    /// i = 0; the pointers name live arrays.
    #[inline(always)]
    pub unsafe fn particle(&self, _i: usize) {
        unsafe { feedback(&*self.step, &self.nodes, self.tiles as usize) }
    }
}

/// The damping update pass (`swarf_mpm_feedback_*`).
pub struct FeedbackPass<R>(PhantomData<R>);
crate::simple_pass!(FeedbackPass<R>, FeedbackArgs<R>, entry_index("mpm_feedback", 2, size_of::<R>(), 0),
    Grid::Particles, [R: Real]);

/// The particle update (`mpm::step::g2p_particle`): one item per particle; `flags[0]` is set when a particle
/// went non-finite, `flags[1]` when one left the grid.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct G2pArgs<R: Real> {
    pub n: u32,
    pub _pad: u32,
    pub params: MpmParams,
    /// As [`NodesArgs::step`].
    pub step: *const MpmStep,
    pub parts: Particles<R>,
    pub nodes: Nodes<R>,
    pub flags: *mut u32,
}

impl<R: Real> G2pArgs<R> {
    /// # Safety
    /// i < n; the pointers name live arrays of the run's particles and the grid's nodes.
    #[inline(always)]
    pub unsafe fn particle(&self, i: usize) -> u32 {
        unsafe { g2p_particle(&self.params, &*self.step, &self.parts, &self.nodes, i) }
    }

    /// Stores particle flags in `flags` (each word only ever set to 1, so that threads may race on it).
    ///
    /// # Safety
    /// `flags` points at two live words.
    #[inline(always)]
    pub unsafe fn store(&self, flags: u32) {
        unsafe {
            if flags & NON_FINITE != 0 {
                core::ptr::write_volatile(self.flags, 1);
            }
            if flags & ESCAPED != 0 {
                core::ptr::write_volatile(self.flags.add(1), 1);
            }
        }
    }
}

/// The particle update pass (`swarf_mpm_g2p_*`).
pub struct G2p<R>(PhantomData<R>);

impl<R: Real> Pass for G2p<R> {
    type Args = G2pArgs<R>;
    const ENTRY: usize = entry_index("mpm_g2p", 2, size_of::<R>(), 0);
    const GRID: Grid = Grid::Particles;
    fn particles(a: &Self::Args) -> usize {
        a.n as usize
    }
    unsafe fn particle(a: &Self::Args, i: usize) -> u32 {
        unsafe { a.particle(i) }
    }
    unsafe fn finish(a: &Self::Args, flags: u32) {
        unsafe { a.store(flags) }
    }
}
