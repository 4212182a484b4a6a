//! One method on one starting packing as a library call: the parameters a run gets from a seed
//! and a step budget, and the timed run through an observer followed by the core's analysis.
//! `packbench pack` and the Python module's `pack` are both made of it.

use std::time::Instant;

use packbench_core::Packing;
use packbench_core::analysis::{AnalysisOptions, Metrics, analyze};
use packbench_core::run::{Observer, Outcome};
use serde_json::{Map, Value};

use crate::error::{BenchError, usage};
use crate::methods::Method;

/// The parameter keys a step budget (`--max-steps`) sets, in the order they are looked for:
/// each method has at most one of them.
const BUDGET_KEYS: [&str; 3] = ["max_steps", "max_iters", "max_collisions"];

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
        let key = BUDGET_KEYS
            .into_iter()
            .find(|k| defaults.contains_key(*k))
            .ok_or_else(|| usage(format!("method {} takes no step budget", method.name())))?;
        out.push((key.to_string(), Value::from(m)));
    }
    Ok(out)
}

/// A finished run: what the method returned, the core's metrics of its packing, and its wall
/// time in seconds (the method alone, without the analysis).
#[derive(Clone, Debug)]
pub struct PackRun {
    pub outcome: Outcome,
    pub metrics: Metrics,
    pub runtime_s: f64,
}

/// Runs `method` from `start` with `params` (a complete parameter object), reporting to
/// `observer`, and analyses the final packing with `analysis`. Errors: the method's (a usage
/// error for bad parameters, a run error otherwise) and the analysis'.
pub fn pack_run(
    method: &dyn Method,
    start: &Packing,
    params: &Map<String, Value>,
    observer: &mut dyn Observer,
    analysis: &AnalysisOptions,
) -> Result<PackRun, BenchError> {
    let t0 = Instant::now();
    let outcome = method.run(start, params, observer)?;
    let runtime_s = t0.elapsed().as_secs_f64();
    let metrics = analyze(&outcome.packing, analysis)?;
    Ok(PackRun {
        outcome,
        metrics,
        runtime_s,
    })
}
