//! The types a packer reports through: progress events to an [`Observer`], a trace of its
//! run, and its [`Outcome`]. Packers never compute headline metrics themselves; the bench
//! analyses `Outcome::packing` with [`crate::analysis`].

use std::sync::atomic::{AtomicBool, Ordering};

use serde::{Deserialize, Serialize};

use crate::packing::Packing;

/// One progress report from a running method.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Progress {
    /// Steps, iterations or collisions so far (the method's own unit).
    pub step: u64,
    /// Current packing fraction.
    pub phi: f64,
    /// Method-specific scalar: energy, reduced pressure, inflation Γ − 1, … (named in `label`).
    pub value: f64,
    /// What `value` is.
    pub label: &'static str,
    /// Fraction of the budget used, in [0, 1], when the method can tell.
    pub fraction: Option<f64>,
    /// Further named scalars worth watching (MLS: the compression rate γ and collisions per
    /// second).
    #[serde(default)]
    pub more: Vec<(&'static str, f64)>,
}

/// Receives progress and may ask a run to stop early (for Ctrl-C). Implementations must be
/// cheap: methods call `progress` a few times per second at most.
pub trait Observer: Send {
    /// A progress report.
    fn progress(&mut self, _p: &Progress) {}
    /// A snapshot the user asked for (`--save-interval`): the method passes its current packing.
    fn snapshot(&mut self, _step: u64, _packing: &Packing) {}
    /// An exact resume point in the method's own format (MLS: `packbench_mls::Checkpoint`),
    /// passed with each snapshot and when an interrupted run returns; the bench writes it
    /// beside the output for `pack --resume`.
    fn checkpoint(&mut self, _state: &serde_json::Value) {}
    /// True when the run should stop and return its best packing so far (by default: when
    /// `stop_flag` is set).
    fn should_stop(&self) -> bool {
        self.stop_flag().is_some_and(|f| f.load(Ordering::SeqCst))
    }
    /// A flag that asks the run to stop, for a method to poll where it cannot reach the
    /// observer: inside a library solver's callback (calippso's LPs at large N take minutes
    /// each).
    fn stop_flag(&self) -> Option<&'static AtomicBool> {
        None
    }
}

/// An observer that ignores everything.
pub struct NullObserver;
impl Observer for NullObserver {}

/// One row of a method's trace: a point of φ and the method's scalar over its run.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct TraceRow {
    /// Step, iteration or collision count.
    pub step: u64,
    /// Seconds since the start of the run.
    pub time_s: f64,
    /// Packing fraction.
    pub phi: f64,
    /// Named method quantities at this point (energy, pressure, rate, Γ…).
    pub values: Vec<(String, f64)>,
}

/// What a method returns.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Outcome {
    /// The final packing.
    pub packing: Packing,
    /// Steps, iterations or collisions performed.
    pub steps: u64,
    /// Why the run stopped, as a short snake_case tag (`converged`, `max_steps`, `interrupted`,
    /// `jammed`, `pressure_cap`, …).
    pub termination: String,
    /// The method's trace over time.
    pub trace: Vec<TraceRow>,
    /// Method-specific extra results (e.g. collisions, bonds opened, LP count), for the JSON.
    pub extra: serde_json::Map<String, serde_json::Value>,
}

/// How a method's error is reported: as bad input (the binary exits 2) or as a run that failed
/// (exit 1). Every packer crate's error type implements it, so the bench keeps the error typed
/// instead of matching on messages.
pub trait MethodError: std::error::Error {
    /// True when the input was at fault — a parameter, the starting packing, the container or
    /// the dimension — and the run did no work; false when a valid run failed on its way.
    fn is_input_error(&self) -> bool;
}

impl MethodError for crate::CoreError {
    fn is_input_error(&self) -> bool {
        !matches!(
            self,
            crate::CoreError::Io { .. } | crate::CoreError::Solver(_)
        )
    }
}
