//! The signal handler's decision (issue 27 #6), in a test binary of its own: it sets the process-wide
//! `run::INTERRUPTED`, which any run in the same process would read.

use std::sync::atomic::{AtomicU64, Ordering};
use swarf::run::{INTERRUPTED, SIGNAL_ECHO_MS, SignalAction, on_signal};

/// A second Ctrl-C forces the exit: before, any signal within a second of the first was ignored, so pressing
/// Ctrl-C twice in quick succession (here 0.3 s apart) did not stop the run. A copy of the first signal that
/// arrives with it (`kill -INT` reaches a command and its process group; tests/checkpoint.rs sends two at once) is
/// still the same Ctrl-C.
#[test]
fn a_second_interrupt_forces_the_exit() {
    let first = AtomicU64::new(0);
    INTERRUPTED.store(false, Ordering::Relaxed);
    assert_eq!(on_signal(&first, 5_000), SignalAction::Checkpoint);
    assert!(INTERRUPTED.load(Ordering::Relaxed));
    assert_eq!(on_signal(&first, 5_000 + SIGNAL_ECHO_MS - 1), SignalAction::Echo, "the same Ctrl-C, delivered twice");
    assert_eq!(on_signal(&first, 5_300), SignalAction::Exit, "a second press 0.3 s later");
    assert_eq!(on_signal(&first, 9_000), SignalAction::Exit);
    INTERRUPTED.store(false, Ordering::Relaxed);
}
