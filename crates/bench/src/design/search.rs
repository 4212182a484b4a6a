//! The search: an optimiser (CMA-ES over the `cmaes` crate by default; see
//! [`super::optimizer`]) over a family's free parameters, each candidate screened by the
//! predictor and scored by packing it with the chosen method, generation by generation, every
//! evaluation a row handed on as it finishes. The CMA-ES ask step lives here; the surrogate's
//! (`--optimizer ego`) in `surrogate`.
//!
//! # Ask and tell over the `cmaes` crate
//!
//! `cmaes` drives the objective function itself (`CMAES::next` samples λ points and evaluates
//! them), which does not fit evaluations that are packings spread over threads, files and
//! restarts. Its state is a pure function of its seed and the objective values it has been
//! told, so [`ask`] rebuilds it: a fresh `CMAES` with the search's seed is told the recorded
//! values of every finished generation, in order, and the points it then asks for are the next
//! generation. Replaying is microseconds per generation for the few parameters a family has;
//! in exchange `--resume` needs nothing but the rows, and the same seed gives the same history.
//!
//! # Bounds
//!
//! CMA-ES searches the unit cube of the free parameters (0 = lower bound, 1 = upper). A point
//! outside is evaluated at its projection onto the cube, and its fitness is raised by
//! [`BOUNDARY_WEIGHT`] times the squared distance (Hansen's repair-and-penalise rule), so a
//! best candidate on a bound sits exactly on it.

use cmaes::{CMAESOptions, DVector, ObjectiveFunction};
use packbench_core::Scene;
use packbench_core::distribution::Moments;
use packbench_core::run::Observer;
use rayon::prelude::*;

use super::DesignConfig;
use super::family::Family;
use super::history::{
    DesignRow, NOT_PACKED, PACKED, RowKey, RowKind, SKIPPED_PREDICTED, SKIPPED_RATIO,
};
use super::objective::{INFEASIBLE, SizeMeasures};
use super::optimizer::Optimizer;
use super::screen::{Calibration, Verdict, predictions, verdict};
use crate::comparison_runs::execute;
use crate::error::BenchError;
use crate::methods;
use crate::records::{CompareConfig, RunRecord, mean_std};
use crate::shards::is_finished;

/// Weight of the squared distance outside the unit cube in a candidate's fitness.
pub const BOUNDARY_WEIGHT: f64 = 1e-3;

/// Initial step size of CMA-ES in the unit cube: a third of each interval.
pub const SIGMA0: f64 = 0.3;

/// First seed of the confirmation reruns: far from the search's seeds, so they are fresh.
pub const CONFIRM_SEED_OFFSET: u64 = 1_000_000;

/// An objective function for `cmaes` that returns recorded values in call order and, past
/// them, records the points it is asked about.
struct Replay {
    told: Vec<f64>,
    calls: usize,
    asked: Vec<Vec<f64>>,
}

impl ObjectiveFunction for Replay {
    fn evaluate(&mut self, x: &DVector<f64>) -> f64 {
        let v = self.told.get(self.calls).copied();
        self.calls += 1;
        match v {
            Some(v) => v,
            None => {
                self.asked.push(x.iter().copied().collect());
                0.0
            }
        }
    }
}

/// Population size λ for `dim` free parameters: the configured one, else CMA-ES's default
/// 4 + ⌊3 ln dim⌋.
pub fn population(config: &DesignConfig, dim: usize) -> usize {
    config
        .population
        .unwrap_or(4 + (3.0 * (dim as f64).ln()).floor() as usize)
}

/// The seed of island `island`'s optimiser: the search's seed for island 1, and well apart
/// for the others.
pub fn cma_seed(base_seed: u64, island: usize) -> u64 {
    base_seed.wrapping_add((island as u64 - 1).wrapping_mul(0x9E37_79B9_7F4A_7C15))
}

/// The points (in the search's coordinates) of the generation after `history`, the fitness
/// values of every earlier generation in the order they were asked; `None` when CMA-ES stopped
/// on one of its own criteria within the history (the search has converged).
///
/// Errors: a run error when `cmaes` refuses the options.
pub fn ask(
    dim: usize,
    lambda: usize,
    seed: u64,
    history: &[Vec<f64>],
) -> Result<Option<Vec<Vec<f64>>>, BenchError> {
    let replay = Replay {
        told: history.iter().flatten().copied().collect(),
        calls: 0,
        asked: Vec::new(),
    };
    let mut cma = CMAESOptions::new(vec![0.5; dim], SIGMA0)
        .population_size(lambda)
        .seed(seed)
        .build(replay)
        .map_err(|e| BenchError::Run(format!("CMA-ES options: {e:?}")))?;
    for _ in history {
        if cma.next().is_some() {
            return Ok(None);
        }
    }
    // The values of this last generation are placeholders; its state is thrown away.
    let _ = cma.next();
    let replay = cma.into_objective_function();
    Ok(Some(replay.asked))
}

/// A candidate of a generation: where the optimiser put it, where it is evaluated, and what is
/// known of it before packing.
#[derive(Clone, Debug)]
pub struct Candidate {
    pub generation: usize,
    pub index: usize,
    /// Every parameter's value (the point projected onto the bounds).
    pub values: Vec<f64>,
    /// [`BOUNDARY_WEIGHT`] × squared distance of the point outside the unit cube.
    pub penalty: f64,
    /// Size measures of its diameters at the first search seed.
    pub measures: SizeMeasures,
    /// Predictions from those diameters.
    pub predictions: super::screen::Predictions,
}

impl Candidate {
    /// A candidate at `point` (search coordinates) of `family`, its diameters drawn for `n`
    /// particles with `seed`.
    ///
    /// Errors: a run error when the values make no distribution.
    pub fn new(
        family: &Family,
        dim: usize,
        n: usize,
        seed: u64,
        (generation, index): (usize, usize),
        point: &[f64],
    ) -> Result<Candidate, BenchError> {
        let unit: Vec<f64> = point.iter().map(|x| x.clamp(0.0, 1.0)).collect();
        let penalty = BOUNDARY_WEIGHT
            * point
                .iter()
                .zip(&unit)
                .map(|(x, u)| (x - u) * (x - u))
                .sum::<f64>();
        let values = family.values_from_unit(&unit);
        let d = family.diameters(&values, n, seed)?;
        let m = Moments::of(&d);
        Ok(Candidate {
            generation,
            index,
            measures: SizeMeasures {
                size_ratio: m.max / m.min,
                polydispersity: m.polydispersity,
            },
            predictions: predictions(dim, &d),
            values,
            penalty,
        })
    }

    /// A row of this candidate for `seed` with `record` as its run columns.
    pub fn row(
        &self,
        kind: RowKind,
        island: usize,
        screened: &str,
        record: RunRecord,
    ) -> DesignRow {
        DesignRow {
            kind,
            island,
            generation: self.generation,
            candidate: self.index,
            params: self.values.clone(),
            size_ratio: self.measures.size_ratio,
            polydispersity: self.measures.polydispersity,
            predicted_dw: self.predictions.desmond_weeks,
            predicted_fg: self.predictions.farr_groot,
            screened: screened.to_string(),
            record,
        }
    }
}

/// The comparison of one method on one candidate: the search's scene with the candidate's
/// distribution (for a mixture, its diameters for `seed`).
pub fn candidate_comparison(
    config: &DesignConfig,
    values: &[f64],
    seed: u64,
) -> Result<CompareConfig, BenchError> {
    let mut scene: Scene = config.scene.clone();
    scene.distribution = config.family.scene_distribution(values, scene.n, seed)?;
    Ok(CompareConfig {
        scene,
        methods: vec![config.method.clone()],
        seeds: 1,
        base_seed: seed,
        refine: config.refine.clone(),
        overrides: config.overrides.clone(),
    })
}

/// Packs candidate values with `seed` and returns the row of `compare`'s runs.csv.
///
/// Errors: a scene or parameter the method cannot use (a failed run is a row, not an error).
pub fn pack(
    config: &DesignConfig,
    values: &[f64],
    seed: u64,
    observer: &mut dyn Observer,
) -> Result<RunRecord, BenchError> {
    let cmp = candidate_comparison(config, values, seed)?;
    let method = methods::find(&config.method)?;
    Ok(execute(&cmp, seed, method, observer)?.record)
}

/// The row of a candidate not packed.
fn unpacked_record(config: &DesignConfig, seed: u64) -> RunRecord {
    RunRecord {
        method: config.method.clone(),
        seed,
        d: config.scene.dim(),
        n: config.scene.n,
        termination: NOT_PACKED.into(),
        ..RunRecord::default()
    }
}

/// The seeds every candidate of the search is packed with (common random numbers: every
/// candidate starts from the same seeds, so differences between candidates are not seed noise).
pub fn search_seeds(config: &DesignConfig) -> Vec<u64> {
    (0..config.seeds_per_candidate)
        .map(|k| config.base_seed + k)
        .collect()
}

/// The fresh seeds of the confirmation reruns.
pub fn confirm_seeds(config: &DesignConfig) -> Vec<u64> {
    (0..config.confirm)
        .map(|k| config.base_seed + CONFIRM_SEED_OFFSET + k)
        .collect()
}

/// What a search produced.
#[derive(Clone, Debug)]
pub struct SearchOutcome {
    /// Every row, in key order.
    pub rows: Vec<DesignRow>,
    /// Generations run.
    pub generations: usize,
    /// Packings made by the search (confirmations excluded).
    pub packings: usize,
    /// Why the search stopped.
    pub stop: String,
}

/// The mean φ_J of a candidate's rows and whether any packing of it succeeded.
pub fn candidate_phi(rows: &[&DesignRow], refined: bool) -> Option<f64> {
    let v: Vec<f64> = rows.iter().filter_map(|r| r.phi_j(refined)).collect();
    mean_std(&v).map(|(m, _)| m)
}

/// Runs the search of island `island` with `budget` packings: generation after generation
/// while the next one fits in the budget, then the confirmation reruns of the best candidate.
/// Rows in `kept` (an earlier run's, for `--resume`) are used instead of packing again when
/// finished; `done` receives every new row as it finishes, from the worker threads.
///
/// Errors: a run error when a candidate makes no distribution or the optimiser refuses its
/// options;
/// a usage error when a kept row disagrees with the candidate this search makes at its place
/// (it comes from another search).
pub fn run_search(
    config: &DesignConfig,
    island: usize,
    budget: usize,
    kept: &std::collections::BTreeMap<RowKey, DesignRow>,
    jobs: Option<usize>,
    observer: impl Fn() -> Box<dyn Observer> + Sync,
    done: impl Fn(&DesignRow) -> Result<(), BenchError> + Sync,
) -> Result<SearchOutcome, BenchError> {
    let free = config.family.free().len();
    let lambda = population(config, free);
    let seeds = search_seeds(config);
    let k = seeds.len();
    let refined = config.refine.is_some();
    let dim = config.scene.dim();
    let n = config.scene.n;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs.unwrap_or(0))
        .build()
        .map_err(|e| BenchError::Run(format!("thread pool: {e}")))?;
    let max_generations = 4 * budget.div_ceil(lambda * k).max(1);
    let mut rows: Vec<DesignRow> = Vec::new();
    // The points asked for and the fitness told back, generation by generation: everything the
    // optimiser's next ask depends on, rebuilt the same way from kept rows on `--resume`.
    let mut asked: Vec<Vec<Vec<f64>>> = Vec::new();
    let mut told: Vec<Vec<f64>> = Vec::new();
    let mut calibration = Calibration::default();
    let mut best: Option<f64> = None;
    let mut packings = 0usize;
    let stop;
    loop {
        let g = told.len();
        if crate::interrupt::interrupted() {
            stop = "interrupted".into();
            break;
        }
        if g > 0 && packings + lambda * k > budget {
            stop = format!("budget of {budget} packings reached");
            break;
        }
        if g >= max_generations {
            stop = format!("{g} generations, most candidates screened out");
            break;
        }
        let seed = cma_seed(config.base_seed, island);
        let Some(points) = config.optimizer.ask(free, lambda, seed, &asked, &told)? else {
            stop = match config.optimizer {
                Optimizer::Cmaes => "CMA-ES converged".into(),
                Optimizer::Ego => "EGO suggested no new point".into(),
            };
            break;
        };
        let candidates = points
            .iter()
            .enumerate()
            .map(|(i, p)| Candidate::new(&config.family, dim, n, seeds[0], (g, i), p))
            .collect::<Result<Vec<_>, _>>()?;
        // The screen's verdicts use only earlier generations, so they do not depend on the
        // order in which this generation's packings finish.
        let mut screened: Vec<Option<(&str, f64)>> = Vec::with_capacity(lambda);
        for c in &candidates {
            let over_ratio = config
                .max_ratio
                .is_some_and(|r| c.measures.size_ratio > r * (1.0 + 1e-12));
            screened.push(if over_ratio {
                let r = config.max_ratio.unwrap_or(1.0);
                Some((SKIPPED_RATIO, INFEASIBLE + (c.measures.size_ratio - r)))
            } else {
                match verdict(
                    &config.objective,
                    config.screen.pick(&c.predictions),
                    &c.measures,
                    &calibration,
                    best,
                    config.screen_margin,
                ) {
                    Verdict::Pack => None,
                    Verdict::Skip { corrected } => Some((
                        SKIPPED_PREDICTED,
                        config.objective.fitness(Some(corrected), &c.measures),
                    )),
                }
            });
        }
        let mut list = Vec::new();
        for (c, s) in candidates.iter().zip(&screened) {
            if s.is_none() {
                for &seed in &seeds {
                    list.push((c, seed));
                }
            }
        }
        packings += list.len();
        let new_rows: Vec<DesignRow> = pool.install(|| {
            list.par_iter()
                .map(|(c, seed)| {
                    let key = (RowKind::Search, island, g, c.index, *seed);
                    if let Some(r) = kept.get(&key).filter(|r| is_finished(&r.record)) {
                        check_kept(r, c)?;
                        return Ok(r.clone());
                    }
                    let record = pack(config, &c.values, *seed, &mut *observer())?;
                    let row = c.row(RowKind::Search, island, PACKED, record);
                    done(&row)?;
                    Ok(row)
                })
                .collect::<Result<Vec<_>, BenchError>>()
        })?;
        for (c, s) in candidates.iter().zip(&screened) {
            if let Some((why, _)) = s {
                let key = (RowKind::Search, island, g, c.index, seeds[0]);
                let row = match kept.get(&key) {
                    Some(r) => {
                        check_kept(r, c)?;
                        r.clone()
                    }
                    None => {
                        let row = c.row(
                            RowKind::Search,
                            island,
                            why,
                            unpacked_record(config, seeds[0]),
                        );
                        done(&row)?;
                        row
                    }
                };
                rows.push(row);
            }
        }
        let mut fitness = Vec::with_capacity(lambda);
        for (c, s) in candidates.iter().zip(&screened) {
            let f = match s {
                Some((_, f)) => *f,
                None => {
                    let mine: Vec<&DesignRow> =
                        new_rows.iter().filter(|r| r.candidate == c.index).collect();
                    let phi = candidate_phi(&mine, refined);
                    if let (Some(p), Some(pred)) = (phi, config.screen.pick(&c.predictions)) {
                        calibration.add(pred, p);
                    }
                    let f = config.objective.fitness(phi, &c.measures);
                    if phi.is_some() {
                        best = Some(best.map_or(f, |b: f64| b.min(f)));
                    }
                    f
                }
            };
            fitness.push(f + c.penalty);
        }
        rows.extend(new_rows);
        asked.push(points);
        told.push(fitness);
    }
    rows.sort_by_key(|r| r.key());
    Ok(SearchOutcome {
        rows,
        generations: told.len(),
        packings,
        stop,
    })
}

/// Errors when a kept row is not of candidate `c` (another family's values at its place).
fn check_kept(r: &DesignRow, c: &Candidate) -> Result<(), BenchError> {
    let same = r.params.len() == c.values.len()
        && r.params
            .iter()
            .zip(&c.values)
            .all(|(a, b)| (a - b).abs() <= 1e-9 * b.abs().max(1.0));
    if same {
        Ok(())
    } else {
        Err(crate::error::usage(format!(
            "the earlier rows hold generation {} candidate {} with other values ({:?} against \
             {:?}): they come from another search; use another --out or drop --resume",
            c.generation, c.index, r.params, c.values
        )))
    }
}

/// The best candidate of the rows: the packed candidate with the smallest fitness (ties: the
/// earliest), as `(generation, candidate, mean φ_J, fitness)`.
pub fn best_candidate(
    config: &DesignConfig,
    rows: &[DesignRow],
) -> Option<(usize, usize, f64, f64)> {
    let refined = config.refine.is_some();
    let mut groups: std::collections::BTreeMap<(usize, usize), Vec<&DesignRow>> =
        Default::default();
    for r in rows
        .iter()
        .filter(|r| r.kind == RowKind::Search && r.screened.is_empty())
    {
        groups
            .entry((r.generation, r.candidate))
            .or_default()
            .push(r);
    }
    let mut best: Option<(usize, usize, f64, f64)> = None;
    for ((g, c), rs) in groups {
        let Some(phi) = candidate_phi(&rs, refined) else {
            continue;
        };
        let m = SizeMeasures {
            size_ratio: rs[0].size_ratio,
            polydispersity: rs[0].polydispersity,
        };
        let f = config.objective.fitness(Some(phi), &m);
        if best.is_none_or(|b| f < b.3) {
            best = Some((g, c, phi, f));
        }
    }
    best
}

/// The confirmation reruns of candidate `(generation, index)` with `values`: one row per fresh
/// seed, kept rows reused.
///
/// Errors: as [`run_search`].
#[allow(clippy::too_many_arguments)]
pub fn confirm(
    config: &DesignConfig,
    island: usize,
    (generation, index): (usize, usize),
    values: &[f64],
    kept: &std::collections::BTreeMap<RowKey, DesignRow>,
    jobs: Option<usize>,
    observer: impl Fn() -> Box<dyn Observer> + Sync,
    done: impl Fn(&DesignRow) -> Result<(), BenchError> + Sync,
) -> Result<Vec<DesignRow>, BenchError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs.unwrap_or(0))
        .build()
        .map_err(|e| BenchError::Run(format!("thread pool: {e}")))?;
    let dim = config.scene.dim();
    let n = config.scene.n;
    let seeds = confirm_seeds(config);
    pool.install(|| {
        seeds
            .par_iter()
            .map(|&seed| {
                let key = (RowKind::Confirm, island, generation, index, seed);
                if let Some(r) = kept.get(&key).filter(|r| is_finished(&r.record)) {
                    return Ok(r.clone());
                }
                let d = config.family.diameters(values, n, seed)?;
                let m = Moments::of(&d);
                let c = Candidate {
                    generation,
                    index,
                    values: values.to_vec(),
                    penalty: 0.0,
                    measures: SizeMeasures {
                        size_ratio: m.max / m.min,
                        polydispersity: m.polydispersity,
                    },
                    predictions: predictions(dim, &d),
                };
                let record = pack(config, values, seed, &mut *observer())?;
                let row = c.row(RowKind::Confirm, island, PACKED, record);
                done(&row)?;
                Ok(row)
            })
            .collect()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn asking_again_after_the_same_values_gives_the_same_points() {
        let first = ask(2, 6, 7, &[]).unwrap().unwrap();
        assert_eq!(first.len(), 6);
        assert_eq!(first, ask(2, 6, 7, &[]).unwrap().unwrap());
        assert_ne!(first, ask(2, 6, 8, &[]).unwrap().unwrap());
        // Told that the points near (1, 1) are better, the mean moves there.
        let told: Vec<f64> = first
            .iter()
            .map(|p| (p[0] - 1.0).powi(2) + (p[1] - 1.0).powi(2))
            .collect();
        let second = ask(2, 6, 7, std::slice::from_ref(&told)).unwrap().unwrap();
        assert_eq!(second, ask(2, 6, 7, &[told]).unwrap().unwrap());
        let mean = |ps: &[Vec<f64>]| ps.iter().map(|p| p[0] + p[1]).sum::<f64>() / 6.0;
        assert!(mean(&second) > mean(&first) - 0.5);
    }

    #[test]
    fn cma_es_in_the_unit_cube_finds_a_corner() {
        // φ rising with the one parameter: the best point sits on the upper bound.
        let mut told: Vec<Vec<f64>> = Vec::new();
        let mut best = f64::INFINITY;
        let mut best_u = 0.0;
        for _ in 0..15 {
            let pts = ask(1, 4, 3, &told).unwrap().unwrap();
            let f: Vec<f64> = pts
                .iter()
                .map(|p| {
                    let u = p[0].clamp(0.0, 1.0);
                    let v = -u + BOUNDARY_WEIGHT * (p[0] - u).powi(2);
                    if v < best {
                        best = v;
                        best_u = u;
                    }
                    v
                })
                .collect();
            told.push(f);
        }
        assert_eq!(best_u, 1.0);
    }
}
