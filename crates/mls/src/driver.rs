//! What LS and MLS share around the event loop: one pressure window with its trace row,
//! progress, snapshots, interruption and budget, and the final [`Outcome`].

use std::time::Instant;

use packbench_core::Packing;
use packbench_core::run::{Observer, Outcome, Progress, TraceRow};
use serde_json::{Map, Value, json};

use crate::params::Dynamics;
use crate::system::{System, WindowEnd};

/// Seconds between two progress reports.
const PROGRESS_PERIOD_S: f64 = 0.25;

/// Observer, clock, trace and budget of one run.
pub(crate) struct Driver<'a> {
    observer: &'a mut dyn Observer,
    dynamics: &'a Dynamics,
    template: &'a Packing,
    start: Instant,
    last_progress: f64,
    next_snapshot: u64,
    trace: Vec<TraceRow>,
    /// Reduced pressure of the last completed window.
    pub pressure: f64,
    /// Completed windows.
    pub windows: u64,
    /// Compression rate of the current window, and collisions at the last progress report.
    rate: f64,
    last_collisions: u64,
    /// The last compression rate (γ > 0) a progress report carried. A window at another one
    /// (a new stage) is reported at its first poll, before the period: the progress towards the
    /// final rate moves only there, and a run shorter than the period would report nothing.
    reported_stage: f64,
    /// Whether the last window ended with a snapshot (a checkpoint then goes with it).
    pub snapshot_taken: bool,
    /// Run time of earlier legs of a resumed run, and the collisions they made.
    pub earlier_runtime_s: f64,
    earlier_collisions: u64,
    stop: Option<&'static str>,
}

impl<'a> Driver<'a> {
    pub fn new(
        observer: &'a mut dyn Observer,
        dynamics: &'a Dynamics,
        template: &'a Packing,
    ) -> Self {
        Driver {
            observer,
            dynamics,
            template,
            start: Instant::now(),
            last_progress: 0.0,
            next_snapshot: dynamics.save_interval,
            trace: Vec::new(),
            pressure: f64::NAN,
            windows: 0,
            rate: 0.0,
            last_collisions: 0,
            reported_stage: 0.0,
            snapshot_taken: false,
            earlier_runtime_s: 0.0,
            earlier_collisions: 0,
            stop: None,
        }
    }

    /// A driver continuing a run at a checkpoint: its window count, run time and the next
    /// snapshot after its collisions.
    pub fn resumed(
        observer: &'a mut dyn Observer,
        dynamics: &'a Dynamics,
        template: &'a Packing,
        c: &crate::Checkpoint,
    ) -> Self {
        let mut d = Driver::new(observer, dynamics, template);
        d.windows = c.windows;
        d.earlier_runtime_s = c.runtime_s;
        d.earlier_collisions = c.collisions;
        d.last_collisions = c.collisions;
        d.pressure = c.pressure.unwrap_or(f64::NAN);
        if let Some(done) = c.collisions.checked_div(dynamics.save_interval) {
            d.next_snapshot = (done + 1) * dynamics.save_interval;
        }
        d
    }

    /// Run time of the whole run so far (earlier legs included).
    pub fn runtime_s(&self) -> f64 {
        self.earlier_runtime_s + self.start.elapsed().as_secs_f64()
    }

    /// Passes a checkpoint to the observer.
    pub fn checkpoint(&mut self, c: &crate::Checkpoint) {
        if let Ok(value) = serde_json::to_value(c) {
            self.observer.checkpoint(&value);
        }
    }

    /// Called from inside the event loop: reports progress at most a few times per second (and
    /// at each new compression stage) and says whether to stop (observer request or collision
    /// budget).
    fn poll(&mut self, collisions: u64, phi: f64) -> bool {
        let elapsed = self.start.elapsed().as_secs_f64();
        let since = elapsed - self.last_progress;
        let new_stage = self.rate > 0.0 && self.rate != self.reported_stage;
        if new_stage || since >= PROGRESS_PERIOD_S {
            let speed = match since > 0.0 {
                true => (collisions - self.last_collisions) as f64 / since,
                false => 0.0,
            };
            if new_stage {
                self.reported_stage = self.rate;
            }
            self.last_progress = elapsed;
            self.last_collisions = collisions;
            self.observer.progress(&Progress {
                step: collisions,
                phi,
                value: self.pressure,
                label: "reduced_pressure",
                fraction: None,
                more: vec![("rate", self.rate), ("collisions_per_s", speed)],
            });
        }
        if self.observer.should_stop() {
            self.stop = Some("interrupted");
        } else if self.dynamics.max_collisions > 0 && collisions >= self.dynamics.max_collisions {
            self.stop = Some("max_steps");
        }
        self.stop.is_some()
    }

    /// Runs one pressure window of `collisions_per_particle·N` collisions at compression rate
    /// `rate` (Baranau & Tallarek 2014 §III.B) and returns its reduced pressure, or the termination tag that
    /// ends the run.
    pub fn window<const D: usize, const P: bool>(
        &mut self,
        sys: &mut System<D, P>,
        rate: f64,
    ) -> Result<f64, &'static str> {
        self.rate = rate;
        sys.begin_window(rate);
        let target = self.dynamics.collisions_per_particle * sys.n() as u64;
        let end = sys.run_window(target, &mut |c, phi| self.poll(c, phi));
        let pressure = match end {
            WindowEnd::Completed { pressure } => pressure,
            WindowEnd::BoxLimit => return Err("box_limit"),
            WindowEnd::Idle => return Err("no_collisions"),
            WindowEnd::Stopped => return Err(self.stop.unwrap_or("interrupted")),
        };
        self.pressure = pressure;
        self.windows += 1;
        let time_s = self.start.elapsed().as_secs_f64();
        self.trace.push(TraceRow {
            step: sys.collisions,
            time_s,
            phi: sys.phi(),
            values: vec![("reduced_pressure".into(), pressure), ("rate".into(), rate)],
        });
        self.snapshot_taken = false;
        if self.dynamics.save_interval > 0 && sys.collisions >= self.next_snapshot {
            self.snapshot_taken = true;
            self.observer
                .snapshot(sys.collisions, &sys.packing(self.template));
            while self.next_snapshot <= sys.collisions {
                self.next_snapshot += self.dynamics.save_interval;
            }
        }
        if self.poll(sys.collisions, sys.phi()) {
            return Err(self.stop.unwrap_or("interrupted"));
        }
        Ok(pressure)
    }

    /// The run's outcome: the packing now, the trace, and `collisions`, `runtime_s`,
    /// `collisions_per_s`, `windows`, `final_rate`, `final_pressure`, `length_unit`,
    /// `cell_rebuilds`, `events` plus `more` in `extra`.
    pub fn finish<const D: usize, const P: bool>(
        self,
        sys: &System<D, P>,
        termination: &str,
        final_rate: f64,
        more: Map<String, Value>,
    ) -> Outcome {
        // Of this leg, and of the whole run when it was resumed from a checkpoint.
        let leg_s = self.start.elapsed().as_secs_f64();
        let runtime_s = self.earlier_runtime_s + leg_s;
        let mut extra = Map::new();
        extra.insert("collisions".into(), json!(sys.collisions));
        extra.insert("runtime_s".into(), json!(runtime_s));
        let rate = if leg_s > 0.0 {
            (sys.collisions - self.earlier_collisions) as f64 / leg_s
        } else {
            0.0
        };
        extra.insert("collisions_per_s".into(), json!(rate));
        if self.earlier_collisions > 0 || self.earlier_runtime_s > 0.0 {
            extra.insert(
                "resumed_at_collisions".into(),
                json!(self.earlier_collisions),
            );
            extra.insert("this_leg_runtime_s".into(), json!(leg_s));
        }
        extra.insert("windows".into(), json!(self.windows));
        extra.insert("final_rate".into(), json!(final_rate));
        extra.insert("final_pressure".into(), finite_or_null(self.pressure));
        extra.insert("length_unit".into(), json!(sys.length_unit));
        extra.insert("cell_rebuilds".into(), json!(sys.rebuilds));
        extra.insert("events".into(), json!(sys.events));
        extra.extend(more);
        Outcome {
            packing: sys.packing(self.template),
            steps: sys.collisions,
            termination: termination.into(),
            trace: self.trace,
            extra,
        }
    }
}

/// JSON has no NaN or ∞: those become null.
fn finite_or_null(x: f64) -> Value {
    if x.is_finite() { json!(x) } else { Value::Null }
}
