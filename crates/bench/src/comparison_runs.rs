//! The runs of a comparison as data: each method on each seed's starting packing (refined when
//! asked), in parallel, as [`RunResult`]s whose rows are those of `runs.csv`. `packbench
//! compare` writes them to files; the Python module's `compare` returns them as dicts.

use packbench_core::init::initial_packing;
use packbench_core::run::Observer;
use rayon::prelude::*;
use serde_json::{Map, Value};

use crate::error::BenchError;
use crate::methods::{self, Method};
use crate::records::{CompareConfig, RunRecord};
use crate::runs::{RunResult, refine_observed, run_one_observed, with_seed};

/// The parameters of `method` in a comparison: its defaults with the comparison's overrides
/// for it. An unknown key is a usage error.
pub fn comparison_params(
    config: &CompareConfig,
    method: &dyn Method,
) -> Result<Map<String, Value>, BenchError> {
    let ov: Vec<(String, Value)> = config
        .overrides
        .iter()
        .filter(|(m, _, _)| m == method.name())
        .map(|(_, k, v)| (k.clone(), v.clone()))
        .collect();
    methods::params_with(method, &ov)
}

/// Runs `method` on the starting packing of `seed`, refining it when the comparison asks;
/// both runs report to `observer`. Errors: a scene or parameter the comparison cannot use (a
/// failed run is a row, not an error).
pub fn execute(
    config: &CompareConfig,
    seed: u64,
    method: &dyn Method,
    observer: &mut dyn Observer,
) -> Result<RunResult, BenchError> {
    let start = initial_packing(&config.scene, seed)?;
    let params = with_seed(comparison_params(config, method)?, seed);
    let mut result = run_one_observed(method, &params, &start, seed, observer);
    if let Some(refiner) = &config.refine {
        let refiner = methods::find(refiner)?;
        let params = with_seed(comparison_params(config, refiner)?, seed);
        refine_observed(&mut result, refiner, &params, seed, observer);
    }
    Ok(result)
}

/// Runs the entries `(index, seed, method)` of a run list (see [`crate::records::run_list`]) on `jobs`
/// threads (`None`: all cores). Each run gets its own observer from `observer`, and `done` is
/// told each finished row. Returns the results with their indices, in the list's order.
pub fn run_comparison<O: Observer>(
    config: &CompareConfig,
    list: &[(usize, u64, String)],
    jobs: Option<usize>,
    observer: impl Fn() -> O + Sync,
    done: impl Fn(&RunRecord) + Sync,
) -> Result<Vec<(usize, RunResult)>, BenchError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs.unwrap_or(0))
        .build()
        .map_err(|e| BenchError::Run(format!("thread pool: {e}")))?;
    pool.install(|| {
        list.par_iter()
            .map(|(idx, seed, name)| {
                let method = methods::find(name)?;
                let r = execute(config, *seed, method, &mut observer())?;
                done(&r.record);
                Ok((*idx, r))
            })
            .collect::<Result<Vec<_>, BenchError>>()
    })
}
