//! The runs of a comparison as data: each method on each seed's starting packing (refined when
//! asked), in parallel, as [`RunResult`]s whose rows are those of `runs.csv`. `packbench
//! compare` writes them to files; the Python module's `compare` returns them as dicts.

use packbench_core::init::initial_packing;
use packbench_core::run::Observer;
use rayon::prelude::*;
use serde_json::{Map, Value};

use crate::args::{SceneArgs, default_compare_scene};
use crate::error::{BenchError, usage};
use crate::methods::run_params::set_for;
use crate::methods::{self, Method, ParamSources};
use crate::records::{CompareConfig, RunRecord};
use crate::refinement::{self, refine_observed};
use crate::runs::{RunResult, run_one_observed};

/// A comparison as asked for, by `packbench compare`'s flags or Python's `compare` keywords.
#[derive(Clone, Debug)]
pub struct CompareOptions {
    /// The scene of the starting packings (none given: [`default_compare_scene`]).
    pub scene: SceneArgs,
    /// The methods to run (`None`: every registered method).
    pub methods: Option<Vec<String>>,
    /// Starting packings, seeds `base_seed`, `base_seed + 1`, ….
    pub seeds: u64,
    /// The first seed.
    pub base_seed: u64,
    /// The exact-jamming method every result is chained into, or `exact` for the fastest
    /// exact chain at the scene's N ([`refinement::legs`]).
    pub refine: Option<String>,
    /// Method parameters, `(method, key, value)` (`--set METHOD.KEY=VALUE`).
    pub overrides: Vec<(String, String, Value)>,
}

impl CompareOptions {
    /// The comparison these options describe, with every method's parameters checked before
    /// the first run starts. Errors: usage errors for an unknown method or refiner, a bad
    /// scene, no seeds, and the parameters [`check_comparison`] refuses.
    pub fn config(&self) -> Result<CompareConfig, BenchError> {
        let scene = self.scene.scene_or(default_compare_scene(), None)?;
        let methods = match &self.methods {
            Some(m) => m.clone(),
            None => methods::registry()
                .iter()
                .map(|m| m.name().to_string())
                .collect(),
        };
        for m in &methods {
            methods::find(m)?;
        }
        if let Some(r) = &self.refine {
            refinement::possible_legs(r, true)?;
        }
        if self.seeds == 0 {
            return Err(usage("--seeds must be at least 1"));
        }
        let config = CompareConfig {
            scene,
            methods,
            seeds: self.seeds,
            base_seed: self.base_seed,
            refine: self.refine.clone(),
            overrides: self.overrides.clone(),
        };
        check_comparison(&config)?;
        Ok(config)
    }
}

/// The parameters of `method` in a comparison: its defaults with the comparison's `--set` for
/// it and the run's `seed` (none when the parameters are checked before the runs). An unknown
/// key is a usage error.
pub fn comparison_params(
    config: &CompareConfig,
    method: &dyn Method,
    seed: Option<u64>,
) -> Result<Map<String, Value>, BenchError> {
    ParamSources {
        set: set_for(&config.overrides, method.name()),
        seed,
        ..Default::default()
    }
    .resolve(method)
}

/// Checks the parameters of every method of a comparison (and its refiner) before the first
/// run starts. Errors: a usage error for an unknown method or key, or a parameter a method
/// refuses ([`Method::check`]).
pub fn check_comparison(config: &CompareConfig) -> Result<(), BenchError> {
    let refiners = match &config.refine {
        Some(r) => refinement::possible_legs(r, false)?,
        None => Vec::new(),
    };
    for name in &config.methods {
        let method = methods::find(name)?;
        method.check(&comparison_params(config, method, None)?)?;
    }
    for method in refiners {
        method.check(&comparison_params(config, method, None)?)?;
    }
    Ok(())
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
    let params = comparison_params(config, method, Some(seed))?;
    let mut result = run_one_observed(method, &params, &start, seed, observer);
    if let Some(refine) = &config.refine {
        let legs = refinement::legs_with_params(refine, method.name(), start.n(), |m| {
            comparison_params(config, m, Some(seed))
        })?;
        refine_observed(&mut result, &legs, seed, observer);
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
