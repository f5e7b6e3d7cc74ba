//! The signal handler's decision (issue 27 #6), in a test binary of its own: it sets the process-wide
//! `run::INTERRUPTED`, which any run in the same process would read.

/// A second Ctrl-C forces the exit however soon it follows the first: before, a second signal within a second of
/// the first was ignored (main.rs's handler kept a one-second window), so pressing Ctrl-C twice did not stop a run.
/// The handler's decision (`run::on_signal`): the first asks for a checkpoint, every later one for the exit.
#[test]
fn a_second_interrupt_forces_the_exit_at_once() {
    use swarf::run::{INTERRUPTED, SignalAction, on_signal};
    INTERRUPTED.store(false, std::sync::atomic::Ordering::Relaxed);
    assert_eq!(on_signal(), SignalAction::Checkpoint);
    assert!(INTERRUPTED.load(std::sync::atomic::Ordering::Relaxed));
    assert_eq!(on_signal(), SignalAction::Exit, "the second signal, at once");
    assert_eq!(on_signal(), SignalAction::Exit);
    INTERRUPTED.store(false, std::sync::atomic::Ordering::Relaxed);
}
