//! What the terminal shows of runs: an indicatif progress bar on a terminal, silence (or one
//! log line per run) when piped, snapshots and checkpoints passed on to files.

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use packbench_core::Packing;
use packbench_core::run::{Observer, Progress};

use crate::interrupt::interrupt_flag;
use crate::records::RunRecord;

/// Progress over the runs of `compare` or `sweep`: a bar counting finished runs on a terminal,
/// and one line per finished run on stderr when it is not a terminal (a batch job's log, e.g. a
/// Slurm shard), where indicatif draws nothing. `quiet` silences both.
pub struct RunsProgress {
    bar: ProgressBar,
    command: &'static str,
    log_lines: bool,
}

impl RunsProgress {
    pub fn new(command: &'static str, runs: usize, quiet: bool) -> Self {
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
        let log_lines = !quiet && bar.is_hidden();
        RunsProgress {
            bar,
            command,
            log_lines,
        }
    }

    /// Counts one finished run, described by its row.
    pub fn done(&self, r: &RunRecord) {
        self.bar.inc(1);
        let knob = r.knob_value.map_or(String::new(), |v| format!(" at {v}"));
        self.bar
            .set_message(format!("last: {}{knob} seed {}", r.method, r.seed));
        if self.log_lines {
            let phi = r.phi.map_or("—".into(), |p| format!("{p:.6}"));
            let refined = r
                .delta_phi
                .map_or(String::new(), |d| format!(", refined Δφ {d:+.2e}"));
            // The refinement is part of the run's work: its seconds are shown beside the method's.
            let seconds = match r.refined_runtime_s {
                Some(t) => format!("{:.1} s + {t:.1} s refining", r.runtime_s),
                None => format!("{:.1} s", r.runtime_s),
            };
            eprintln!(
                "{} run {}/{}: {}{knob} seed {}: φ {phi}{refined}, {seconds}, {}",
                self.command,
                self.bar.position(),
                self.bar.length().unwrap_or(0),
                r.method,
                r.seed,
                r.termination
            );
        }
    }

    /// Removes the bar.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// Snapshot sink: called with (step, packing) every `--save-interval` steps.
pub type SnapshotSink = Box<dyn FnMut(u64, &Packing) + Send>;

/// A progress bar (hidden unless stderr is a terminal, or when `quiet`).
pub struct TerminalObserver {
    bar: ProgressBar,
    last: Instant,
    verbose: bool,
    snapshots: Option<SnapshotSink>,
    /// Where checkpoints go (`NAME.checkpoint.json`), and whether one was written.
    checkpoint_path: Option<PathBuf>,
    pub wrote_checkpoint: bool,
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
            checkpoint_path: None,
            wrote_checkpoint: false,
        }
    }

    /// Writes the checkpoints a method passes to `path` (each replacing the last).
    pub fn with_checkpoints(mut self, path: PathBuf) -> Self {
        self.checkpoint_path = Some(path);
        self
    }

    /// Removes the bar.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// A progress value: counts (bonds, n_dof) as integers, anything else in scientific notation.
fn number(v: f64, digits: usize) -> String {
    if v.fract() == 0.0 && v.abs() < 1e15 {
        format!("{v:.0}")
    } else {
        format!("{v:.digits$e}")
    }
}

/// `label{sep}value` for the method's quantity and each further one, joined by `join`.
fn named_values(p: &Progress, sep: &str, join: &str, digits: usize) -> String {
    std::iter::once((p.label, p.value))
        .chain(p.more.iter().copied())
        .map(|(label, v)| format!("{label}{sep}{}", number(v, digits)))
        .collect::<Vec<_>>()
        .join(join)
}

impl Observer for TerminalObserver {
    fn progress(&mut self, p: &Progress) {
        if let Some(f) = p.fraction {
            self.bar.set_position((f.clamp(0.0, 1.0) * 1000.0) as u64);
        }
        self.bar.set_message(format!(
            "step {}  φ = {:.6}  {}",
            p.step,
            p.phi,
            named_values(p, " = ", "  ", 3)
        ));
        if self.verbose && self.last.elapsed() > Duration::from_secs(2) {
            self.last = Instant::now();
            let line = format!(
                "step {} phi {:.8} {}",
                p.step,
                p.phi,
                named_values(p, " ", " ", 6)
            );
            // A hidden bar (stderr not a terminal, e.g. a batch job's log) drops its printlns.
            if self.bar.is_hidden() {
                eprintln!("{line}");
            } else {
                self.bar.println(line);
            }
        }
    }

    fn snapshot(&mut self, step: u64, packing: &Packing) {
        if let Some(f) = &mut self.snapshots {
            f(step, packing);
        }
    }

    fn checkpoint(&mut self, state: &serde_json::Value) {
        if let Some(path) = &self.checkpoint_path {
            // A failed checkpoint must not kill a long run; it is reported as not written.
            self.wrote_checkpoint = serde_json::to_vec(state)
                .ok()
                .is_some_and(|bytes| packbench_core::format::write_atomic(path, &bytes).is_ok());
        }
    }

    fn stop_flag(&self) -> Option<&'static AtomicBool> {
        Some(interrupt_flag())
    }
}
