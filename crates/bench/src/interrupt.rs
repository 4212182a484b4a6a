//! Stop requests: Ctrl-C, SIGTERM (`kill`, `timeout`, Slurm at the time limit) and SIGHUP
//! become one flag that every running method polls, so it returns its best packing so far.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Instant;

/// Set by the interrupt handler.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// When the first stop request arrived, in milliseconds (plus one, so 0 means "none yet")
/// since the handler was installed.
static FIRST_SIGNAL_MS: AtomicU64 = AtomicU64::new(0);

/// A second request sooner than this after the first is the same request delivered twice
/// (GNU `timeout` outside the foreground signals the child and then its whole process group),
/// not an impatient user.
const REPEAT_WINDOW_MS: u64 = 1000;

/// Installs the handler of SIGINT (Ctrl-C), SIGTERM (Slurm, `kill`, `timeout`) and SIGHUP once:
/// the first request asks the method to stop and return its best packing; a second one at
/// least `REPEAT_WINDOW_MS` later exits at once.
pub fn install_interrupt_handler() {
    let epoch = Instant::now();
    let _ = ctrlc::set_handler(move || {
        let now = epoch.elapsed().as_millis() as u64 + 1;
        match FIRST_SIGNAL_MS.compare_exchange(0, now, Ordering::SeqCst, Ordering::SeqCst) {
            Ok(_) => INTERRUPTED.store(true, Ordering::SeqCst),
            Err(first) if now.saturating_sub(first) >= REPEAT_WINDOW_MS => std::process::exit(130),
            Err(_) => {}
        }
    });
}

/// True once a stop was requested (Ctrl-C, SIGTERM or SIGHUP).
pub fn interrupted() -> bool {
    INTERRUPTED.load(Ordering::SeqCst)
}

/// The flag behind [`interrupted`], for methods that poll it inside a solver.
pub fn interrupt_flag() -> &'static AtomicBool {
    &INTERRUPTED
}
