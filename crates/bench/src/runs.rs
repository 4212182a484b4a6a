//! One method on one start (or from its checkpoint), timed and analysed by the core: the one
//! path every run takes. [`pack_run`] returns its errors (`packbench pack`, Python's `pack`);
//! [`run_one`] records every outcome as a row, failures too, the unit that `compare`, `sweep`,
//! `reproduce`, `design` and `merge` are made of.

use std::sync::atomic::AtomicBool;
use std::time::Instant;

use packbench_core::Packing;
use packbench_core::analysis::{AnalysisOptions, Metrics, analyze, not_jammed_because};
use packbench_core::run::{Observer, Outcome};
use serde_json::{Map, Value};

use crate::error::BenchError;
use crate::interrupt::interrupt_flag;
use crate::methods::{Method, Product};
use crate::records::{BUDGET_WITH_OVERLAPS, NOT_JAMMED, NOT_RUN, RunRecord};

/// Largest relative overlap `1 − r/σ` a run may leave when it stops at its step budget and
/// still count as a packing; soft-sphere methods end near 1e-4 (RCPGenerator: 4.9e-4).
pub const OVERLAP_AT_BUDGET: f64 = 1e-3;

/// The termination to record for `method`'s own `termination`, judged by the core's
/// `metrics`, and the reason when the bench overrules the method: a run stopped by its budget
/// with overlaps says so, and an exact method's claim of a jammed packing stands only when
/// the analysis agrees.
pub fn judged_termination(
    method: &dyn Method,
    termination: &str,
    metrics: &Metrics,
) -> (String, Option<String>) {
    if termination == "max_steps" && metrics.max_overlap > OVERLAP_AT_BUDGET {
        return (BUDGET_WITH_OVERLAPS.to_string(), None);
    }
    if method.jammed_terminations().contains(&termination)
        && let Some(why) = not_jammed_because(metrics)
    {
        let reason = format!(
            "{} ended `{termination}`, but the packing is not jammed: {why}",
            method.name()
        );
        return (NOT_JAMMED.to_string(), Some(reason));
    }
    (termination.to_string(), None)
}

/// Where a run begins: a starting packing, or a checkpoint the method wrote (`pack --resume`).
pub enum RunFrom<'a> {
    Start(&'a Packing),
    Checkpoint(&'a Value),
}

/// A method's outcome and products (when asked for), and its wall time in seconds (the method
/// alone, without the analysis), also when it failed.
pub fn timed_run(
    method: &dyn Method,
    from: RunFrom,
    params: &Map<String, Value>,
    observer: &mut dyn Observer,
    with_products: bool,
) -> (Result<(Outcome, Vec<Product>), BenchError>, f64) {
    let t0 = Instant::now();
    let ran = match from {
        RunFrom::Start(start) if with_products => method.run_with_products(start, params, observer),
        RunFrom::Start(start) => method.run(start, params, observer).map(|o| (o, Vec::new())),
        RunFrom::Checkpoint(c) => method.resume(c, params, observer).map(|o| (o, Vec::new())),
    };
    (ran, t0.elapsed().as_secs_f64())
}

/// The run time of the whole run: a resumed run's method counts its earlier legs in
/// `extra.runtime_s` (MLS's checkpoints carry them); otherwise this leg's `leg_s`.
fn whole_run_s(outcome: &Outcome, leg_s: f64) -> f64 {
    outcome
        .extra
        .get("runtime_s")
        .and_then(Value::as_f64)
        .filter(|&t| t >= leg_s)
        .unwrap_or(leg_s)
}

/// The core's verdict on a run's packing: its metrics, the termination to record
/// ([`judged_termination`]) and why the bench overruled the method, when it did.
pub struct Judgement {
    pub metrics: Metrics,
    pub termination: String,
    pub overruled: Option<String>,
}

/// Analyses the packing of `outcome` with `analysis` and judges the method's termination by
/// the metrics. Errors: the analysis'.
pub fn judge(
    method: &dyn Method,
    outcome: &Outcome,
    analysis: &AnalysisOptions,
) -> Result<Judgement, BenchError> {
    let metrics = analyze(&outcome.packing, analysis)?;
    let (termination, overruled) = judged_termination(method, &outcome.termination, &metrics);
    Ok(Judgement {
        metrics,
        termination,
        overruled,
    })
}

/// A finished run: what the method returned (its termination judged by the core's metrics,
/// [`judged_termination`]), its extra products (when asked for), the core's metrics of its
/// packing, its wall time in seconds (the method alone, without the analysis), and why the
/// bench overruled the method's termination, when it did.
#[derive(Clone, Debug)]
pub struct PackRun {
    pub outcome: Outcome,
    pub products: Vec<Product>,
    pub metrics: Metrics,
    pub runtime_s: f64,
    pub overruled: Option<String>,
}

/// Runs `method` from `from` with `params` (a complete parameter object), reporting to
/// `observer`, keeps the method's products when `with_products` (seq-fill's tables; a run from
/// a checkpoint has none), and analyses the final packing with `analysis` ([`timed_run`], then
/// [`judge`]). Errors: the method's (a usage error for bad parameters, a run error otherwise)
/// and the analysis'.
pub fn pack_run(
    method: &dyn Method,
    from: RunFrom,
    params: &Map<String, Value>,
    observer: &mut dyn Observer,
    with_products: bool,
    analysis: &AnalysisOptions,
) -> Result<PackRun, BenchError> {
    let (ran, leg_s) = timed_run(method, from, params, observer, with_products);
    let (outcome, products) = ran?;
    let runtime_s = whole_run_s(&outcome, leg_s);
    let Judgement {
        metrics,
        termination,
        overruled,
    } = judge(method, &outcome, analysis)?;
    Ok(PackRun {
        outcome: Outcome {
            termination,
            ..outcome
        },
        products,
        metrics,
        runtime_s,
        overruled,
    })
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
    let (ran, runtime_s) = timed_run(method, RunFrom::Start(start), params, observer, false);
    record.runtime_s = runtime_s;
    let outcome = match ran {
        Ok((o, _)) => o,
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
    record.n = outcome.packing.n();
    match judge(method, &outcome, &AnalysisOptions::default()) {
        Ok(Judgement {
            metrics: m,
            termination,
            overruled,
        }) => {
            record.termination = termination;
            record.error = overruled;
            record.phi = Some(m.phi);
            record.z_nonrattler = m.defined_z_nonrattler();
            record.rattlers = Some(m.rattlers);
            record.iso_gap = m.defined_iso_gap();
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
            // The packing is kept: a failed analysis says nothing against the run.
            record.termination = outcome.termination;
            record.error = Some(format!("analysis failed: {e}"));
            RunResult {
                record,
                packing: Some(outcome.packing),
                metrics: None,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::methods::find;
    use packbench_core::{Container, Packing};

    /// Two spheres overlapping by half a diameter in a periodic box: what the 6D closest-jammed
    /// run once returned as `jammed` (its largest overlap 0.76).
    fn overlapping_pair() -> Metrics {
        let container = Container::periodic_box(&[4.0, 4.0]).unwrap();
        let p = Packing::new(vec![1.0, 1.0, 1.5, 1.0], vec![1.0, 1.0], container).unwrap();
        analyze(&p, &AnalysisOptions::default()).unwrap()
    }

    #[test]
    fn an_exact_method_claiming_an_overlapping_packing_jammed_is_overruled() {
        let m = overlapping_pair();
        for (name, claim) in [
            ("closest-jammed", "jammed"),
            ("closest-jammed-qp", "jammed"),
            ("calippso", "converged"),
        ] {
            let (termination, why) = judged_termination(find(name).unwrap(), claim, &m);
            assert_eq!(termination, NOT_JAMMED, "{name}");
            let why = why.expect("a reason");
            assert!(why.contains("overlap") && why.contains(name), "{why}");
        }
    }

    #[test]
    fn other_terminations_and_compression_methods_keep_their_word() {
        let m = overlapping_pair();
        // An exact method stopped by its budget claims nothing.
        let (t, why) = judged_termination(find("calippso").unwrap(), "max_iters", &m);
        assert_eq!((t.as_str(), why), ("max_iters", None));
        // adam's overlaps are soft-sphere overlaps; its `converged` claims no hard-sphere jam.
        let (t, why) = judged_termination(find("adam").unwrap(), "converged", &m);
        assert_eq!((t.as_str(), why), ("converged", None));
        // A budget run with overlaps is marked as such.
        let (t, _) = judged_termination(find("adam").unwrap(), "max_steps", &m);
        assert_eq!(t, BUDGET_WITH_OVERLAPS);
    }
}
