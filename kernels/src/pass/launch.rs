//! What a backend needs to launch a pass: [`Pass`] ties an argument struct to its entry in the pass table and
//! gives the CPU twin of one particle's work. The host's `Backend::launch` is generic over it: the CUDA backend
//! launches entry [`Pass::ENTRY`] with the struct by value, the CPU backend runs [`Pass::particle`] over the
//! particles in parallel. A pass's variant (stabilisers, flow model, fused conduction) is a type parameter of its
//! marker type, and its entry is found in the table at compile time ([`super::table::entry_index`]): a variant
//! the table does not list does not compile.

/// How a pass's GPU threads map onto its particles: the launch's thread count, block size and block order.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Grid {
    /// One thread per particle, blocks of the default size.
    Particles,
    /// [`Pass::lanes`] threads per particle, blocks of the neighbour passes' size and order (`SWARF_PAIR_*`).
    Pair,
    /// One thread per particle, blocks of the plastic corrector's size and order (`SWARF_PLASTIC_*`).
    Plastic,
    /// A grid-stride loop over the particles on a capped grid (the gated passes of a rebuild: a step that does
    /// not rebuild pays only for the blocks that read the gate).
    Strided,
}

/// A pass of the table: its argument struct, its entry, its thread layout and its CPU twin.
pub trait Pass {
    /// The argument struct, passed by value to the entry.
    type Args: Copy;
    /// The entry's position in the table (`ENTRY_NAMES`).
    const ENTRY: usize;
    const GRID: Grid;

    /// The particles the launch covers.
    fn particles(a: &Self::Args) -> usize;

    /// Threads per particle ([`Grid::Pair`]).
    fn lanes(_a: &Self::Args) -> u32 {
        1
    }

    /// The struct's block-order field ([`Grid::Pair`], [`Grid::Plastic`]), which the GPU backend sets.
    fn order(_a: &mut Self::Args) -> Option<&mut u32> {
        None
    }

    /// The step's rebuild flag the pass is gated on (null: always runs). The CPU reads it once before the loop,
    /// the GPU in every thread.
    fn gate(_a: &Self::Args) -> *const u32 {
        core::ptr::null()
    }

    /// The CPU twin of particle i's work; returns flags that the CPU ORs over every particle and hands to
    /// [`Pass::finish`] (where the GPU's threads store a flag themselves).
    ///
    /// # Safety
    /// i < [`Pass::particles`]; the struct's pointers name live host buffers as long as the pass reads or writes,
    /// and no other particle's call writes what particle i's reads or writes.
    unsafe fn particle(a: &Self::Args, i: usize) -> u32;

    /// The CPU's end of the pass, with the OR of every particle's flags.
    ///
    /// # Safety
    /// As [`Pass::particle`], after every particle's call has returned.
    unsafe fn finish(_a: &Self::Args, _flags: u32) {}
}

/// Implements [`Pass`] for a marker whose CPU twin calls `particle(i)` on its struct, one thread per particle.
#[macro_export]
#[doc(hidden)]
macro_rules! simple_pass {
    ($marker:ty, $args:ty, $entry:expr, $grid:expr, [$($gen:tt)*]) => {
        impl<$($gen)*> $crate::pass::launch::Pass for $marker {
            type Args = $args;
            const ENTRY: usize = $entry;
            const GRID: $crate::pass::launch::Grid = $grid;
            fn particles(a: &Self::Args) -> usize {
                a.n as usize
            }
            unsafe fn particle(a: &Self::Args, i: usize) -> u32 {
                unsafe { a.particle(i) };
                0
            }
        }
    };
}
