//! Ctrl-C and SIGTERM for the commands that run until their source ends (`run`, `ros2`,
//! `localise`): a flag they poll, so that they stop after the current frame and write what
//! they have; a live source waiting for packets ends its stream (the frame in progress is
//! kept).

use std::sync::atomic::{AtomicBool, Ordering};

/// Set once Ctrl-C or SIGTERM arrives.
pub static STOP: AtomicBool = AtomicBool::new(false);

/// Installs the handler; `without` says what the command loses if it cannot be installed
/// (logged as a warning, with the reason).
pub fn install(without: &str) {
    if let Err(e) = ctrlc::set_handler(|| {
        STOP.store(true, Ordering::SeqCst);
        keylo::io::ouster::stop_live_sources();
    }) {
        tracing::warn!("{without}: {e}");
    }
}

/// Whether Ctrl-C or SIGTERM has arrived.
pub fn requested() -> bool {
    STOP.load(Ordering::SeqCst)
}
