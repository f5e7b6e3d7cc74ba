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

/// The particles a per-particle pass covers: the first `n`, or with blanking only the first `*active` of them,
/// the unblanked particles, which the cell list sorts before the blanked ones (`active` points at the cell starts'
/// entry `n_cells`, docs/3d.md "Blanking"). The count is read where the pass runs (in every GPU thread, by the CPU
/// before its loop), so that a captured step needs no read by the host. Null `active`: all `n`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct Span {
    pub n: u32,
    pub _pad: u32,
    pub active: *const u32,
}

impl Span {
    /// All n particles.
    pub const fn all(n: u32) -> Self {
        Span { n, _pad: 0, active: core::ptr::null() }
    }

    /// Whether particle i is one the pass runs: i < n and, with blanking, i < *active.
    ///
    /// # Safety
    /// A non-null `active` points at a live count.
    #[inline(always)]
    pub unsafe fn live(&self, i: u32) -> bool {
        i < self.n && (self.active.is_null() || i < unsafe { *self.active })
    }

    /// How many particles the pass runs: min(n, *active), n without blanking.
    ///
    /// # Safety
    /// As [`Span::live`].
    #[inline(always)]
    pub unsafe fn limit(&self) -> u32 {
        if self.active.is_null() { self.n } else { unsafe { (*self.active).min(self.n) } }
    }
}

/// A pass's particle count: a plain count (every particle: the hash, the gathers) or a [`Span`].
pub trait Particles {
    /// The upper bound: the launch's particle count.
    fn upper(&self) -> usize;
    /// The blanking's count of active particles (null: none).
    fn active(&self) -> *const u32;
}

impl Particles for u32 {
    fn upper(&self) -> usize {
        *self as usize
    }
    fn active(&self) -> *const u32 {
        core::ptr::null()
    }
}

impl Particles for Span {
    fn upper(&self) -> usize {
        self.n as usize
    }
    fn active(&self) -> *const u32 {
        self.active
    }
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

    /// The blanking's count of active particles, a bound below [`Pass::particles`] that the pass reads where it
    /// runs (null: none; [`Span`]). The CPU reads it once before the loop, the GPU in every thread.
    fn active(_a: &Self::Args) -> *const u32 {
        core::ptr::null()
    }

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
                $crate::pass::launch::Particles::upper(&a.n)
            }
            fn active(a: &Self::Args) -> *const u32 {
                $crate::pass::launch::Particles::active(&a.n)
            }
            unsafe fn particle(a: &Self::Args, i: usize) -> u32 {
                unsafe { a.particle(i) };
                0
            }
        }
    };
}
