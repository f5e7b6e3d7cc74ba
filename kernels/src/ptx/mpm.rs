//! MPM entry points (`mpm::step`): one thread per node, crack point, tile of nodes or particle.

use super::global_index;
use crate::pass::mpm::{CrackArgs, FeedbackArgs, G2pArgs, KeArgs, NodesArgs, P2gArgs};

/// The MPM entries of the pass table (pass::table), each in its own anonymous scope.
macro_rules! mpm_entry {
    (mpm_g2p, $sym:expr, $r:ident, $d:ident) => {
        const _: () = {
            /// Particle i's update; a flagged particle sets its flag word.
            #[unsafe(export_name = $sym)]
            pub unsafe extern "ptx-kernel" fn entry(args: G2pArgs<$r>) {
                let i = global_index();
                if i < args.n {
                    unsafe { args.store(args.particle(i as usize)) };
                }
            }
        };
    };
    ($kind:ident, $sym:expr, $r:ident, $d:ident) => {
        mpm_entry!(@simple $kind, $sym, $r);
    };
    (@simple mpm_p2g, $sym:expr, $r:ident) => {
        mpm_entry!(@item P2gArgs, $sym, $r);
    };
    (@simple mpm_crack, $sym:expr, $r:ident) => {
        mpm_entry!(@item CrackArgs, $sym, $r);
    };
    (@simple mpm_nodes, $sym:expr, $r:ident) => {
        mpm_entry!(@item NodesArgs, $sym, $r);
    };
    (@simple mpm_ke, $sym:expr, $r:ident) => {
        mpm_entry!(@item KeArgs, $sym, $r);
    };
    (@simple mpm_feedback, $sym:expr, $r:ident) => {
        mpm_entry!(@item FeedbackArgs, $sym, $r);
    };
    (@simple $kind:ident, $sym:expr, $r:ident) => {};
    (@item $args:ident, $sym:expr, $r:ident) => {
        const _: () = {
            /// Item i's work (node or crack point).
            #[unsafe(export_name = $sym)]
            pub unsafe extern "ptx-kernel" fn entry(args: $args<$r>) {
                let i = global_index();
                if i < args.n {
                    unsafe { args.particle(i as usize) };
                }
            }
        };
    };
    ($kind:ident, $($rest:tt)*) => {};
}

crate::for_each_entry!(mpm_entry);
