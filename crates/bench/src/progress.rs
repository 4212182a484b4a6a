//! The terminal observer: an indicatif progress bar on a terminal, silence when piped, and
//! Ctrl-C turned into a polite stop request so the method returns its best packing so far.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use packbench_core::Packing;
use packbench_core::run::{Observer, Progress};

/// Set by the Ctrl-C handler.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Installs the Ctrl-C handler once; a second Ctrl-C exits at once.
pub fn install_interrupt_handler() {
    let _ = ctrlc::set_handler(|| {
        if INTERRUPTED.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
    });
}

/// True once Ctrl-C was pressed.
pub fn interrupted() -> bool {
    INTERRUPTED.load(Ordering::SeqCst)
}

/// A bar counting the finished runs of `compare` or `sweep` (hidden with `quiet`, and by
/// indicatif when stderr is not a terminal).
pub fn runs_bar(command: &str, runs: usize, quiet: bool) -> ProgressBar {
    let bar = if quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::with_draw_target(Some(runs as u64), ProgressDrawTarget::stderr())
    };
    bar.set_style(
        ProgressStyle::with_template(&format!(
            "{command} {{elapsed_precise}} [{{bar:30}}] {{pos}}/{{len}} runs {{msg}}"
        ))
        .expect("valid")
        .progress_chars("=> "),
    );
    bar
}

/// Snapshot sink: called with (step, packing) every `--save-interval` steps.
pub type SnapshotSink = Box<dyn FnMut(u64, &Packing) + Send>;

/// A progress bar (hidden unless stderr is a terminal, or when `quiet`).
pub struct TerminalObserver {
    bar: ProgressBar,
    last: Instant,
    verbose: bool,
    snapshots: Option<SnapshotSink>,
}

impl TerminalObserver {
    /// A bar labelled with the method name.
    pub fn new(method: &str, quiet: bool, verbose: bool, snapshots: Option<SnapshotSink>) -> Self {
        let bar = if quiet {
            ProgressBar::hidden()
        } else {
            let b = ProgressBar::with_draw_target(Some(1000), ProgressDrawTarget::stderr());
            b.set_style(
                ProgressStyle::with_template("{prefix:>8} {elapsed_precise} [{bar:30}] {msg}")
                    .expect("valid template")
                    .progress_chars("=> "),
            );
            b.set_prefix(method.to_string());
            b.enable_steady_tick(Duration::from_millis(250));
            b
        };
        TerminalObserver {
            bar,
            last: Instant::now(),
            verbose,
            snapshots,
        }
    }

    /// Removes the bar.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

impl Observer for TerminalObserver {
    fn progress(&mut self, p: &Progress) {
        if let Some(f) = p.fraction {
            self.bar.set_position((f.clamp(0.0, 1.0) * 1000.0) as u64);
        }
        self.bar.set_message(format!(
            "step {}  φ = {:.6}  {} = {:.3e}",
            p.step, p.phi, p.label, p.value
        ));
        if self.verbose && self.last.elapsed() > Duration::from_secs(2) {
            self.last = Instant::now();
            self.bar.println(format!(
                "step {} phi {:.8} {} {:.6e}",
                p.step, p.phi, p.label, p.value
            ));
        }
    }

    fn snapshot(&mut self, step: u64, packing: &Packing) {
        if let Some(f) = &mut self.snapshots {
            f(step, packing);
        }
    }

    fn should_stop(&self) -> bool {
        interrupted()
    }
}
