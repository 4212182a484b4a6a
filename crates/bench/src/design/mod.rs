//! Designing a size distribution: which member of a family (or which mixture) reaches the
//! highest φ_J, a target φ_J, or a target with the smallest size ratio — the search behind
//! `packbench design`.
//!
//! What it is made of, one file a job: [`family`] (distributions with named, bounded
//! parameters), [`objective`] (one number to minimise per candidate, and the constraints on
//! the packed structure), [`screen`] (the Desmond–Weeks or Farr–Groot prediction that skips
//! hopeless candidates), [`optimizer`] (which optimiser proposes the candidates: IPOP-CMA-ES of
//! [`cma`] over the `cmaes` crate, the bisection with a line fit of [`bracket`] for one
//! parameter and a target, or with the `ego` cargo feature the Kriging surrogate of
//! `surrogate`), [`search`] (the generations, packings by any
//! registered method through `compare`'s own [`crate::comparison_runs::execute`]), [`history`]
//! (the rows, `evaluations.csv`, and `design.json`) and [`report`] (best distribution, figures,
//! report.md).
//!
//! What it is not: no packing or analysis lives here; every φ_J is a comparison row made by the
//! same code as `packbench compare`'s.
//!
//! A search split with `--shard i/n` runs n independent searches (islands) with
//! different optimiser seeds and the same packing seeds, each with 1/n of the budget and its
//! own confirmation; `packbench merge` joins their rows and picks the best confirmed
//! candidate. Island 1 of any split is the prefix of the unsplit search with the same seed.

pub mod bracket;
pub mod cma;
pub mod family;
pub mod history;
pub mod objective;
pub mod optimizer;
#[cfg(test)]
mod random_searches;
pub mod report;
pub mod screen;
pub mod search;
#[cfg(feature = "ego")]
pub mod surrogate;

use std::collections::BTreeMap;

use packbench_core::run::Observer;
use packbench_core::{Scene, SizeDistribution};
use serde::{Deserialize, Serialize};

use crate::error::{BenchError, usage};
use crate::records::mean_std;
use family::Family;
use history::{DesignRow, RowKey, RowKind};
use objective::{Constraints, Objective};
use optimizer::Optimizer;
use screen::Screen;

/// Everything that defines a design search; stored in `design.json` so that `--resume` and
/// `merge` continue or join only the same search.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DesignConfig {
    /// The family searched and the bounds of its parameters.
    pub family: Family,
    /// What is optimised.
    pub objective: Objective,
    /// Constraints on the packed structure (none in searches written before there were any).
    #[serde(default)]
    pub constraints: Constraints,
    /// Largest D_max/D_min a candidate's packed diameters may have (a mixture's support is
    /// bounded by its own `max_ratio` instead).
    pub max_ratio: Option<f64>,
    /// The scene every candidate is packed in (N, dimension, container, initial φ); its
    /// distribution is replaced by each candidate's.
    pub scene: Scene,
    /// N of the search's packings when smaller than the scene's (a cheaper fidelity); the
    /// confirmation packs at the scene's N.
    #[serde(default)]
    pub search_n: Option<usize>,
    /// The method that packs candidates.
    pub method: String,
    /// The exact-jamming method chained after it (`compare --refine`); φ_J is then the refined
    /// φ.
    pub refine: Option<String>,
    /// Method parameters, `(method, key, value)` as `compare --set`.
    pub overrides: Vec<(String, String, serde_json::Value)>,
    /// Packings of each candidate (seeds `base_seed`, `base_seed + 1`, …).
    pub seeds_per_candidate: u64,
    /// First packing seed and the seed of the optimiser.
    pub base_seed: u64,
    /// Packings the search may use (confirmations not counted), over all islands.
    pub budget: usize,
    /// Candidates per generation λ: CMA-ES's population, EGO's batch (default 4 + ⌊3 ln dim⌋).
    pub population: Option<usize>,
    /// The optimiser that proposes the candidates (absent in searches written before there
    /// was a choice: CMA-ES).
    #[serde(default)]
    pub optimizer: Optimizer,
    /// The predictor that screens candidates.
    pub screen: Screen,
    /// Margin in φ the screen leaves before skipping a candidate.
    pub screen_margin: f64,
    /// Confirmation reruns of the best candidate with fresh seeds.
    pub confirm: u64,
}

impl DesignConfig {
    /// Every check of the search that needs no packing, for a search split into `shards`
    /// islands: a family with something to search, a non-negative screen margin, at least one
    /// seed per candidate, methods that exist, an optimiser this build has, a population the
    /// optimiser can use (CMA-ES: at least 2), a budget for at least one generation per island,
    /// and method parameters the methods accept (checked on the middle of the family).
    ///
    /// Errors: a usage error saying which, in the command line's flags.
    pub fn check(&self, shards: usize) -> Result<(), BenchError> {
        self.family.validate()?;
        if !(self.screen_margin.is_finite() && self.screen_margin >= 0.0) {
            return Err(usage(format!(
                "--screen-margin {} must be a non-negative number",
                self.screen_margin
            )));
        }
        if self.seeds_per_candidate == 0 {
            return Err(usage("--seeds-per-candidate must be at least 1"));
        }
        crate::methods::find(&self.method)?;
        if let Some(refine) = &self.refine {
            crate::refinement::possible_legs(refine, false)?;
        }
        self.optimizer.check()?;
        let free = self.family.free().len();
        if self.optimizer == Optimizer::Bracket && (free != 1 || self.objective.target().is_none())
        {
            return Err(usage(format!(
                "--optimizer bracket searches one free parameter for a target φ_J (--objective \
                 target, min-ratio or min-polydispersity); this search has {free} free \
                 parameters and {}",
                if self.objective.target().is_some() {
                    "a target"
                } else {
                    "no target"
                }
            )));
        }
        let lambda = search::population(self, free);
        let least = self.optimizer.min_population();
        if lambda < least {
            return Err(usage(format!(
                "--population {lambda}: --optimizer {} needs at least {least} candidates per \
                 generation",
                self.optimizer.name()
            )));
        }
        let per_generation = lambda * self.seeds_per_candidate as usize;
        if island_budget(self, shards) < per_generation {
            return Err(usage(format!(
                "--budget {} is too small: one generation packs {lambda} candidates × {} seeds = \
                 {per_generation}{}",
                self.budget,
                self.seeds_per_candidate,
                if shards > 1 {
                    format!(" in each of {shards} shards")
                } else {
                    String::new()
                }
            )));
        }
        if let Some(n) = self.search_n
            && !(2..=self.scene.n).contains(&n)
        {
            return Err(usage(format!(
                "--search-N {n} must be between 2 and --N {} (the search's packings are the \
                 cheaper fidelity; the confirmation packs at --N)",
                self.scene.n
            )));
        }
        let mid = self.family.values_from_unit(&vec![0.5; free]);
        let cmp = search::candidate_comparison(self, &mid, self.base_seed, search::search_n(self))?;
        crate::comparison_runs::check_comparison(&cmp)
    }
}

/// The best distribution found, with its confirmation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BestDistribution {
    pub island: usize,
    pub generation: usize,
    pub candidate: usize,
    /// The family's parameter names, in order.
    pub names: Vec<String>,
    /// Their values.
    pub values: Vec<f64>,
    /// The core's distribution of these values (`None` for a mixture: see `diameters`).
    pub distribution: Option<SizeDistribution>,
    /// Mean φ_J over the search's seeds.
    pub search_phi: f64,
    /// φ_J of each confirmation rerun that made a packing.
    pub confirm_phi: Vec<f64>,
    /// Mean and sample standard deviation of `confirm_phi`.
    pub confirm_mean: Option<f64>,
    pub confirm_std: Option<f64>,
    /// D_max/D_min and std/mean of `diameters`.
    pub size_ratio: f64,
    pub polydispersity: f64,
    /// The N diameters of its first confirmation packing (of its first search packing when
    /// there was no confirmation), in units of the family (smallest or scale 1).
    pub diameters: Vec<f64>,
}

/// What a design search produced.
#[derive(Clone, Debug)]
pub struct DesignOutcome {
    /// Every evaluation, in key order.
    pub rows: Vec<DesignRow>,
    /// The best distribution (`None` when no candidate made a packing).
    pub best: Option<BestDistribution>,
    /// Generations run by this island.
    pub generations: usize,
    /// Packings made by the search of this island (confirmations excluded).
    pub packings: usize,
    /// Why the search stopped.
    pub stop: String,
}

/// The packing budget of island `i` of `n`.
pub fn island_budget(config: &DesignConfig, n: usize) -> usize {
    config.budget.div_ceil(n.max(1))
}

/// Runs island `shard.0` of `shard.1` of the search `config`: the optimiser's generations within its
/// budget, then `config.confirm` reruns of its best candidate. `kept` are rows of an earlier
/// run of the same search and island (`--resume`), reused where finished; `done` receives each
/// new row as it finishes. Returns the rows and the best distribution.
///
/// Errors: a usage error when a kept row comes from another search; run errors when a
/// candidate makes no distribution, a thread pool cannot be built, or `done` fails. A stop
/// request (Ctrl-C, SIGTERM) ends the search after the generation under way, without
/// confirmation; its rows say which runs were not finished.
pub fn design_island(
    config: &DesignConfig,
    shard: (usize, usize),
    kept: Vec<DesignRow>,
    jobs: Option<usize>,
    observer: impl Fn() -> Box<dyn Observer> + Sync,
    done: impl Fn(&DesignRow) -> Result<(), BenchError> + Sync,
) -> Result<DesignOutcome, BenchError> {
    let kept: BTreeMap<RowKey, DesignRow> = history::by_key(kept);
    let island = shard.0;
    let budget = island_budget(config, shard.1);
    let out = search::run_search(config, island, budget, &kept, jobs, &observer, &done)?;
    let mut rows = out.rows;
    let mut stop = out.stop;
    if crate::interrupt::interrupted() {
        stop = "interrupted: run again with --resume to finish".into();
    } else if let Some((g, c, _, _)) = search::best_candidate(config, &rows) {
        let values = rows
            .iter()
            .find(|r| r.generation == g && r.candidate == c)
            .map(|r| r.params.clone())
            .unwrap_or_default();
        rows.extend(search::confirm(
            config,
            island,
            (g, c),
            &values,
            &kept,
            jobs,
            &observer,
            &done,
        )?);
    }
    rows.sort_by_key(|r| r.key());
    let best = best_distribution(config, &rows)?;
    Ok(DesignOutcome {
        rows,
        best,
        generations: out.generations,
        packings: out.packings,
        stop,
    })
}

/// A whole search in memory, on `jobs` threads (`None`: every core), nothing written: the
/// library call behind the Python module's `design`. Each packing reports to an observer from
/// `observer` (whose stop flag ends it early), and `done` is told each row as it finishes; an
/// error from `done` ends the search with that error.
///
/// Errors: as [`design_island`].
pub fn design(
    config: &DesignConfig,
    jobs: Option<usize>,
    observer: impl Fn() -> Box<dyn Observer> + Sync,
    done: impl Fn(&DesignRow) -> Result<(), BenchError> + Sync,
) -> Result<DesignOutcome, BenchError> {
    design_island(config, (1, 1), Vec::new(), jobs, observer, done)
}

/// The best distribution of `rows` (one island or several): each island's best candidate with
/// its confirmation; across islands the one whose confirmed mean (search mean when it has no
/// confirmation) has the best fitness.
///
/// Errors: a run error when the best values make no distribution.
pub fn best_distribution(
    config: &DesignConfig,
    rows: &[DesignRow],
) -> Result<Option<BestDistribution>, BenchError> {
    let refined = config.refine.is_some();
    let islands: std::collections::BTreeSet<usize> = rows.iter().map(|r| r.island).collect();
    let mut best: Option<(f64, BestDistribution)> = None;
    for island in islands {
        let mine: Vec<DesignRow> = rows
            .iter()
            .filter(|r| r.island == island)
            .cloned()
            .collect();
        let Some((g, c, search_phi, _)) = search::best_candidate(config, &mine) else {
            continue;
        };
        let values = mine
            .iter()
            .find(|r| r.generation == g && r.candidate == c)
            .map(|r| r.params.clone())
            .unwrap_or_default();
        let confirm_rows: Vec<&DesignRow> = mine
            .iter()
            .filter(|r| r.kind == RowKind::Confirm && r.generation == g && r.candidate == c)
            .collect();
        let confirm_phi: Vec<f64> = confirm_rows
            .iter()
            .filter_map(|r| r.phi_j(refined))
            .collect();
        let stats = mean_std(&confirm_phi);
        let seed = confirm_rows
            .first()
            .map_or(config.base_seed, |r| r.record.seed);
        let diameters = config.family.diameters(&values, config.scene.n, seed)?;
        let m = packbench_core::distribution::Moments::of(&diameters);
        // Judged on its confirmation when it has one, else on its search rows.
        let judged_rows: Vec<&DesignRow> = if stats.is_some() {
            confirm_rows.clone()
        } else {
            mine.iter()
                .filter(|r| r.kind == RowKind::Search && r.generation == g && r.candidate == c)
                .collect()
        };
        let f = search::candidate_fitness(config, &judged_rows).map_or(f64::INFINITY, |x| x.1);
        let candidate = BestDistribution {
            island,
            generation: g,
            candidate: c,
            names: config
                .family
                .params
                .iter()
                .map(|p| p.name.clone())
                .collect(),
            distribution: config.family.distribution(&values),
            values,
            search_phi,
            confirm_mean: stats.map(|s| s.0),
            confirm_std: stats.map(|s| s.1),
            confirm_phi,
            size_ratio: m.max / m.min,
            polydispersity: m.polydispersity,
            diameters,
        };
        if best.as_ref().is_none_or(|(bf, _)| f < *bf) {
            best = Some((f, candidate));
        }
    }
    Ok(best.map(|(_, b)| b))
}
