//! What the terminal shows of runs: an indicatif progress bar on a terminal, silence (or one
//! log line per run) when piped, snapshots and checkpoints passed on to files.

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use packbench_core::Packing;
use packbench_core::run::{Observer, Progress};

use crate::interrupt::interrupt_flag;
use crate::methods::StopProgress;
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

/// Seconds between the progress lines of a run whose stderr is not a terminal (a batch job's
/// log, a pipe), where the bar draws nothing: a long run still shows it is working.
const LOG_LINE_EVERY_S: u64 = 10;

/// A progress bar (hidden unless stderr is a terminal, or when `quiet`); without a terminal,
/// a progress line every [`LOG_LINE_EVERY_S`] seconds (every 2 s with `verbose`).
pub struct TerminalObserver {
    bar: ProgressBar,
    last: Instant,
    verbose: bool,
    quiet: bool,
    /// The way to the method's own stopping rule, for the bar's position.
    stop: StopProgress,
    snapshots: Option<SnapshotSink>,
    /// Where checkpoints go (`NAME.checkpoint.json`), and whether one was written.
    checkpoint_path: Option<PathBuf>,
    pub wrote_checkpoint: bool,
}

impl TerminalObserver {
    /// A bar labelled with the method name, filled by `stop` (the method's stopping rule).
    pub fn new(
        method: &str,
        stop: StopProgress,
        quiet: bool,
        verbose: bool,
        snapshots: Option<SnapshotSink>,
    ) -> Self {
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
            quiet,
            stop,
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

    /// The progress line to print now, if one is due: every 2 s with `--verbose`, every
    /// [`LOG_LINE_EVERY_S`] s when the bar draws nothing and the run is not quiet.
    fn due_line(&mut self, p: &Progress, fraction: Option<f64>) -> Option<String> {
        let every = if self.verbose { 2 } else { LOG_LINE_EVERY_S };
        let wanted = self.verbose || (self.bar.is_hidden() && !self.quiet);
        if !wanted || self.last.elapsed() <= Duration::from_secs(every) {
            return None;
        }
        self.last = Instant::now();
        let done = fraction.map_or(String::new(), |f| {
            format!(" ({:.0} % of the way to its stopping rule)", 100.0 * f)
        });
        // "step N phi …" at the start of the line: batch logs are searched for it.
        Some(format!(
            "step {} phi {:.8} {}{done}",
            p.step,
            p.phi,
            named_values(p, " ", " ", 6)
        ))
    }
}

/// A progress value: counts (bonds, n_dof) as integers, anything else in scientific notation;
/// "—" for a value not defined yet (MLS's pressure before its first window).
fn number(v: f64, digits: usize) -> String {
    if !v.is_finite() {
        "—".into()
    } else if v.fract() == 0.0 && v.abs() < 1e15 {
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
        let fraction = p.fraction.or_else(|| self.stop.fraction(p));
        if let Some(f) = fraction {
            self.bar.set_position((f.clamp(0.0, 1.0) * 1000.0) as u64);
        }
        self.bar.set_message(format!(
            "step {}  φ = {:.6}  {}",
            p.step,
            p.phi,
            named_values(p, " = ", "  ", 3)
        ));
        if let Some(line) = self.due_line(p, fraction) {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::methods::find;

    /// Without a terminal (a batch job's log, a pipe) a long run still prints a progress line every
    /// few seconds, with how far it is towards its stopping rule and no NaN; `--quiet` prints
    /// none.
    #[test]
    fn a_run_without_a_terminal_prints_progress_lines() {
        let mls = find("mls").unwrap();
        let params = mls.default_params();
        let report = Progress {
            step: 1000,
            phi: 0.6,
            label: "reduced_pressure",
            value: f64::NAN,
            fraction: None,
            more: vec![("rate", 1.0)],
        };
        let long_ago = Instant::now() - Duration::from_secs(LOG_LINE_EVERY_S + 1);
        let mut quiet =
            TerminalObserver::new("mls", StopProgress::new(mls, &params), true, false, None);
        quiet.last = long_ago;
        assert_eq!(quiet.due_line(&report, Some(0.5)), None);
        let mut o =
            TerminalObserver::new("mls", StopProgress::new(mls, &params), false, false, None);
        // As on a batch job's log, whatever the test's own stderr is.
        o.bar = ProgressBar::with_draw_target(Some(1000), ProgressDrawTarget::hidden());
        assert_eq!(o.due_line(&report, Some(0.5)), None, "not due yet");
        o.last = long_ago;
        let line = o.due_line(&report, Some(0.5)).expect("a line is due");
        assert!(line.starts_with("step 1000 phi 0.60000000"), "{line}");
        assert!(
            line.contains("reduced_pressure —") && !line.contains("NaN"),
            "{line}"
        );
        assert!(
            line.contains("(50 % of the way to its stopping rule)"),
            "{line}"
        );
        assert_eq!(
            o.due_line(&report, Some(0.5)),
            None,
            "one line per interval"
        );
    }
}
