//! Running one method on one start and recording the result as a row: the unit that
//! `compare`, `sweep` and `merge` are made of.

use std::sync::atomic::AtomicBool;
use std::time::Instant;

use packbench_core::Packing;
use packbench_core::analysis::{AnalysisOptions, Metrics, analyze};
use packbench_core::run::Observer;
use serde_json::{Map, Value};

use crate::interrupt::interrupt_flag;
use crate::methods::Method;
use crate::records::{NOT_RUN, RunRecord};

/// Largest relative overlap `1 − r/σ` a run may leave when it stops at its step budget and
/// still count as a packing; soft-sphere methods end near 1e-4 (RCPGenerator: 4.9e-4).
pub const OVERLAP_AT_BUDGET: f64 = 1e-3;

/// Termination of a run that used its whole step budget and still overlaps by more than
/// [`OVERLAP_AT_BUDGET`]: a failed run whose packing is kept for inspection.
pub const BUDGET_WITH_OVERLAPS: &str = "max_steps_with_overlaps";

/// The termination to record for a method's own `termination` and the largest overlap the
/// core measured: a run stopped by its budget with overlaps says so.
pub fn judged_termination(termination: &str, max_overlap: f64) -> String {
    if termination == "max_steps" && max_overlap > OVERLAP_AT_BUDGET {
        BUDGET_WITH_OVERLAPS.to_string()
    } else {
        termination.to_string()
    }
}

/// Only honours Ctrl-C: runs in parallel draw no bars of their own.
pub struct QuietObserver;
impl Observer for QuietObserver {
    fn stop_flag(&self) -> Option<&'static AtomicBool> {
        Some(interrupt_flag())
    }
}

/// What one run produced: its row, and its packing when it succeeded.
pub struct RunResult {
    pub record: RunRecord,
    pub packing: Option<Packing>,
    pub metrics: Option<Metrics>,
}

/// `params` with the run's seed filled in, for methods that take one.
pub fn with_seed(mut params: Map<String, Value>, seed: u64) -> Map<String, Value> {
    if params.contains_key("seed") {
        params.insert("seed".into(), seed.into());
    }
    params
}

/// Chains the packing of `result` into `refiner` (`--refine`: an exact jamming method, or
/// MLS after LS) and records φ_refined and Δφ = φ_refined − φ in its row; a failed
/// refinement is the row's error.
pub fn refine(
    result: &mut RunResult,
    refiner: &dyn Method,
    params: &Map<String, Value>,
    seed: u64,
) {
    refine_observed(result, refiner, params, seed, &mut QuietObserver);
}

/// [`refine`] with the refinement reporting to `observer` (whose stop request it honours).
pub fn refine_observed(
    result: &mut RunResult,
    refiner: &dyn Method,
    params: &Map<String, Value>,
    seed: u64,
    observer: &mut dyn Observer,
) {
    let Some(packing) = &result.packing else {
        return;
    };
    let refined = run_one_observed(refiner, params, packing, seed, observer);
    let record = &mut result.record;
    record.refined_phi = refined.record.phi;
    record.refined_termination = Some(refined.record.termination);
    record.refined_iso_gap = refined.record.iso_gap;
    record.refined_force_balance = refined.record.force_balance;
    record.delta_phi = match (refined.record.phi, record.phi) {
        (Some(a), Some(b)) => Some(a - b),
        _ => None,
    };
    if let Some(e) = refined.record.error {
        record.error = Some(format!("refinement failed: {e}"));
    }
}

/// Runs `method` from `start`, analyses the result with the core, and never fails: a failed
/// run becomes a row with `termination = "failed"` and the error message, and a run not
/// started because of an earlier stop request (Ctrl-C, SIGTERM) a row with `termination =
/// "not_run"`, so it cannot pass for a result.
pub fn run_one(
    method: &dyn Method,
    params: &Map<String, Value>,
    start: &Packing,
    seed: u64,
) -> RunResult {
    run_one_observed(method, params, start, seed, &mut QuietObserver)
}

/// [`run_one`] with the run reporting to `observer`: a stop request of the observer before
/// the start makes the row `not_run`, one during the run stops it early.
pub fn run_one_observed(
    method: &dyn Method,
    params: &Map<String, Value>,
    start: &Packing,
    seed: u64,
    observer: &mut dyn Observer,
) -> RunResult {
    let mut record = RunRecord {
        method: method.name().to_string(),
        seed,
        d: start.dim,
        n: start.n(),
        ..RunRecord::default()
    };
    if observer.should_stop() {
        record.termination = NOT_RUN.into();
        record.error =
            Some("not run: interrupted (Ctrl-C or SIGTERM) before this run started".into());
        return RunResult {
            record,
            packing: None,
            metrics: None,
        };
    }
    let t0 = Instant::now();
    let outcome = method.run(start, params, observer);
    record.runtime_s = t0.elapsed().as_secs_f64();
    let outcome = match outcome {
        Ok(o) => o,
        Err(e) => {
            record.termination = "failed".into();
            record.error = Some(e.to_string());
            return RunResult {
                record,
                packing: None,
                metrics: None,
            };
        }
    };
    record.steps = outcome.steps;
    record.termination = outcome.termination.clone();
    record.n = outcome.packing.n();
    match analyze(&outcome.packing, &AnalysisOptions::default()) {
        Ok(m) => {
            record.termination = judged_termination(&record.termination, m.max_overlap);
            record.phi = Some(m.phi);
            record.z_nonrattler = Some(m.z_nonrattler);
            record.rattlers = Some(m.rattlers);
            record.iso_gap = Some(m.iso_gap);
            record.isostatic = Some(m.isostatic);
            record.max_overlap = Some(m.max_overlap);
            record.force_balance = m.force_balance;
            RunResult {
                record,
                packing: Some(outcome.packing),
                metrics: Some(m),
            }
        }
        Err(e) => {
            record.error = Some(format!("analysis failed: {e}"));
            RunResult {
                record,
                packing: Some(outcome.packing),
                metrics: None,
            }
        }
    }
}
