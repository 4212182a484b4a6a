//! One method on one starting packing (or from its checkpoint) as a library call: the parameters
//! a run gets from a seed and a step budget, and the timed run through an observer followed by
//! the core's analysis.
//! `packbench pack` and the Python module's `pack` are both made of it.

use std::time::Instant;

use packbench_core::Packing;
use packbench_core::analysis::{AnalysisOptions, Metrics, analyze};
use packbench_core::run::{Observer, Outcome};
use serde_json::{Map, Value};

use crate::error::{BenchError, usage};
use crate::methods::{Method, Product};
use crate::runs::judged_termination;

/// Overrides for the run's seed (methods that take one) and its step budget in the method's own
/// unit. A budget for a method that takes none is a usage error.
pub fn budget_overrides(
    method: &dyn Method,
    seed: u64,
    max_steps: Option<u64>,
) -> Result<Vec<(String, Value)>, BenchError> {
    let defaults = method.default_params();
    let mut out = Vec::new();
    if defaults.contains_key("seed") {
        out.push(("seed".to_string(), Value::from(seed)));
    }
    if let Some(m) = max_steps {
        let key = method
            .budget_key()
            .ok_or_else(|| usage(format!("method {} takes no step budget", method.name())))?;
        out.push((key.to_string(), Value::from(m)));
    }
    Ok(out)
}

/// Where a run begins: a starting packing, or a checkpoint the method wrote (`pack --resume`).
pub enum RunFrom<'a> {
    Start(&'a Packing),
    Checkpoint(&'a Value),
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
/// a checkpoint has none), and analyses the final packing with `analysis`. Errors: the
/// method's (a usage error for bad parameters, a run error otherwise) and the analysis'.
/// A termination the analysis contradicts is replaced, and the reason kept in `overruled`.
pub fn pack_run(
    method: &dyn Method,
    from: RunFrom,
    params: &Map<String, Value>,
    observer: &mut dyn Observer,
    with_products: bool,
    analysis: &AnalysisOptions,
) -> Result<PackRun, BenchError> {
    let t0 = Instant::now();
    let (outcome, products) = match from {
        RunFrom::Start(start) if with_products => {
            method.run_with_products(start, params, observer)?
        }
        RunFrom::Start(start) => (method.run(start, params, observer)?, Vec::new()),
        RunFrom::Checkpoint(c) => (method.resume(c, params, observer)?, Vec::new()),
    };
    let runtime_s = t0.elapsed().as_secs_f64();
    let metrics = analyze(&outcome.packing, analysis)?;
    let (termination, overruled) = judged_termination(method, &outcome.termination, &metrics);
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
