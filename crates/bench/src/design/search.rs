//! The search: an optimiser (IPOP-CMA-ES over the `cmaes` crate by default, [`super::cma`];
//! see [`super::optimizer`]) over a family's free parameters, generation by generation. Each
//! generation's candidates are made (an invalid one is scored infeasible, not fatal), screened
//! by the predictor, packed with the search's common seeds, and scored; then the incumbent (the
//! best candidate so far) is packed once more with a fresh seed, so that one lucky seed does not
//! win. Every evaluation is a row handed on as it finishes.
//!
//! Fidelities: the screen predicts φ_J from the diameters for free; the search packs at
//! `search_n` (the scene's N unless smaller is asked); the confirmation repacks the best at the
//! scene's N. Each level's packings and time are in the rows (`kind`, `runtime_s`).

use packbench_core::Scene;
use packbench_core::distribution::Moments;
use packbench_core::run::Observer;
use rayon::ThreadPool;
use rayon::prelude::*;

use super::DesignConfig;
use super::family::Family;
use super::history::{
    DesignRow, INVALID, NOT_PACKED, PACKED, RowKey, RowKind, SKIPPED_PREDICTED, SKIPPED_RATIO,
};
use super::objective::{INFEASIBLE, SizeMeasures};
use super::optimizer::Optimizer;
use super::screen::{Calibration, Predictions, Verdict, predictions, verdict};
use crate::comparison_runs::execute;
use crate::error::BenchError;
use crate::methods;
use crate::records::{CompareConfig, RunRecord, mean_std};
use crate::shards::is_finished;

/// Weight of the squared distance outside the unit cube in a candidate's fitness.
pub const BOUNDARY_WEIGHT: f64 = 1e-3;

/// First seed of the confirmation reruns: far from the search's seeds, so they are fresh.
pub const CONFIRM_SEED_OFFSET: u64 = 1_000_000;

/// Most extra packings of one incumbent: past these its mean φ_J is known well enough, and
/// further packings would only take budget from the search.
pub const MAX_REEVALUATIONS: usize = 4;

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
    pub predictions: Predictions,
    /// Why its values make no distribution (it is then scored infeasible, not packed).
    pub invalid: Option<String>,
}

impl Candidate {
    /// A candidate at `point` (search coordinates) of `family`, its diameters drawn for `n`
    /// particles with `seed`. Values that make no distribution (a mixture whose weights are
    /// all zero) give an invalid candidate, which the search scores infeasible.
    pub fn new(
        family: &Family,
        dim: usize,
        n: usize,
        seed: u64,
        (generation, index): (usize, usize),
        point: &[f64],
    ) -> Candidate {
        let unit: Vec<f64> = point.iter().map(|x| x.clamp(0.0, 1.0)).collect();
        let penalty = BOUNDARY_WEIGHT
            * point
                .iter()
                .zip(&unit)
                .map(|(x, u)| (x - u) * (x - u))
                .sum::<f64>();
        let values = family.values_from_unit(&unit);
        let mut c = Candidate {
            generation,
            index,
            values,
            penalty,
            measures: SizeMeasures::default(),
            predictions: Predictions::default(),
            invalid: None,
        };
        match family.diameters(&c.values, n, seed) {
            Ok(d) => {
                c.measures = measures_of(&d);
                c.predictions = predictions(dim, &d);
            }
            Err(e) => c.invalid = Some(e.to_string()),
        }
        c
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

/// D_max/D_min and std/mean of `d`.
fn measures_of(d: &[f64]) -> SizeMeasures {
    let m = Moments::of(d);
    SizeMeasures {
        size_ratio: m.max / m.min,
        polydispersity: m.polydispersity,
    }
}

/// N of the search's packings: `search_n` when given (a cheaper fidelity), else the scene's.
pub fn search_n(config: &DesignConfig) -> usize {
    config.search_n.unwrap_or(config.scene.n)
}

/// The comparison of one method on one candidate: the search's scene with `n` particles and the
/// candidate's distribution (for a mixture, its diameters for `seed`).
pub fn candidate_comparison(
    config: &DesignConfig,
    values: &[f64],
    seed: u64,
    n: usize,
) -> Result<CompareConfig, BenchError> {
    let mut scene: Scene = config.scene.clone();
    scene.n = n;
    scene.distribution = config.family.scene_distribution(values, n, seed)?;
    Ok(CompareConfig {
        scene,
        methods: vec![config.method.clone()],
        seeds: 1,
        base_seed: seed,
        refine: config.refine.clone(),
        overrides: config.overrides.clone(),
    })
}

/// Packs candidate values with `seed` and `n` particles and returns the row of `compare`'s
/// runs.csv.
///
/// Errors: a scene or parameter the method cannot use (a failed run is a row, not an error).
pub fn pack(
    config: &DesignConfig,
    values: &[f64],
    seed: u64,
    n: usize,
    observer: &mut dyn Observer,
) -> Result<RunRecord, BenchError> {
    let cmp = candidate_comparison(config, values, seed, n)?;
    let method = methods::find(&config.method)?;
    Ok(execute(&cmp, seed, method, observer)?.record)
}

/// The row of a candidate not packed (`error`: why, for an invalid one).
fn unpacked_record(config: &DesignConfig, seed: u64, error: Option<String>) -> RunRecord {
    RunRecord {
        method: config.method.clone(),
        seed,
        d: config.scene.dim(),
        n: search_n(config),
        termination: NOT_PACKED.into(),
        error,
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

/// A candidate's mean φ_J and fitness from its packed rows: the objective on the mean φ_J and
/// the size measures of its first row, plus the penalty of a broken constraint (the mean
/// fraction of rattlers above `--max-rattlers`). `None` when no packing of it succeeded.
pub fn candidate_fitness(config: &DesignConfig, rows: &[&DesignRow]) -> Option<(f64, f64)> {
    let refined = config.refine.is_some();
    let phi = candidate_phi(rows, refined)?;
    let first = rows.first()?;
    let m = SizeMeasures {
        size_ratio: first.size_ratio,
        polydispersity: first.polydispersity,
    };
    let fractions: Vec<f64> = rows
        .iter()
        .filter(|r| r.phi_j(refined).is_some())
        .filter_map(|r| Some(r.record.rattlers? as f64 / r.record.n.max(1) as f64))
        .collect();
    let rattlers = mean_std(&fractions).map(|(m, _)| m);
    let f = config.objective.fitness(Some(phi), &m) + config.constraints.penalty(rattlers);
    Some((phi, f))
}

/// What the search has learnt so far: everything the optimiser's next ask and the screen's
/// next verdicts depend on, rebuilt the same way from kept rows on `--resume`.
#[derive(Default)]
struct SearchState {
    rows: Vec<DesignRow>,
    /// The points asked for and the fitness told back, generation by generation.
    asked: Vec<Vec<Vec<f64>>>,
    told: Vec<Vec<f64>>,
    /// Each candidate's mean φ_J − target (`None`: not packed, or no target).
    residuals: Vec<Vec<Option<f64>>>,
    calibration: Calibration,
    /// Best fitness of a packed candidate.
    best: Option<f64>,
    packings: usize,
}

/// What a search's steps share: the search, its island, the rows of an earlier run, the thread
/// pool, and the callbacks for observers and finished rows.
struct Context<'a> {
    config: &'a DesignConfig,
    island: usize,
    seeds: Vec<u64>,
    kept: &'a std::collections::BTreeMap<RowKey, DesignRow>,
    pool: ThreadPool,
    observer: &'a (dyn Fn() -> Box<dyn Observer> + Sync),
    done: &'a (dyn Fn(&DesignRow) -> Result<(), BenchError> + Sync),
}

/// Runs the search of island `island` with `budget` packings: generation after generation
/// while the next one fits in the budget. Rows in `kept` (an earlier run's, for `--resume`)
/// are used instead of packing again when finished; `done` receives every new row as it
/// finishes, from the worker threads.
///
/// Errors: a run error when the optimiser refuses its options or a thread pool cannot be
/// built; a usage error when a kept row disagrees with the candidate this search makes at its
/// place (it comes from another search).
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
    let ctx = Context {
        config,
        island,
        seeds: search_seeds(config),
        kept,
        pool: thread_pool(jobs)?,
        observer: &observer,
        done: &done,
    };
    let k = ctx.seeds.len();
    let max_generations = 4 * budget.div_ceil(lambda * k).max(1);
    let mut state = SearchState::default();
    let stop = loop {
        let g = state.told.len();
        if crate::interrupt::interrupted() {
            break "interrupted".to_string();
        }
        if g >= max_generations {
            break format!("{g} generations, most candidates screened out");
        }
        let seed = cma_seed(config.base_seed, island);
        let Some(points) = config.optimizer.ask(
            free,
            lambda,
            seed,
            &state.asked,
            &state.told,
            &state.residuals,
        )?
        else {
            break match config.optimizer {
                Optimizer::Cmaes => "CMA-ES converged in its last restart".into(),
                Optimizer::Ego => "EGO suggested no new point".into(),
                Optimizer::Bracket => "the target lies beyond a bound of the range".into(),
            };
        };
        if g > 0 && state.packings + points.len() * k > budget {
            break format!("budget of {budget} packings reached");
        }
        let (fitness, residuals) = run_generation(&ctx, &mut state, g, &points)?;
        let next = points.len() * k;
        state.asked.push(points);
        state.told.push(fitness);
        state.residuals.push(residuals);
        // The incumbent is packed again when that leaves room for the next generation, and
        // with whatever is left once no further generation fits. Not in a bracketing search:
        // its answer rests on the line through every packing, which more generations feed.
        if config.optimizer == Optimizer::Bracket {
            continue;
        }
        if state.packings + next > budget {
            while state.packings < budget && reevaluate_incumbent(&ctx, &mut state)? {}
        } else if state.packings + 1 + next <= budget {
            reevaluate_incumbent(&ctx, &mut state)?;
        }
    };
    let mut rows = state.rows;
    rows.sort_by_key(|r| r.key());
    Ok(SearchOutcome {
        rows,
        generations: state.told.len(),
        packings: state.packings,
        stop,
    })
}

/// A pool of `jobs` threads (`None`: every core).
fn thread_pool(jobs: Option<usize>) -> Result<ThreadPool, BenchError> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(jobs.unwrap_or(0))
        .build()
        .map_err(|e| BenchError::Run(format!("thread pool: {e}")))
}

/// Generation `g` at `points`: makes the candidates, screens them, packs the others with the
/// search's seeds, and returns every candidate's fitness and residual φ_J − target for the
/// optimiser.
fn run_generation(
    ctx: &Context,
    state: &mut SearchState,
    g: usize,
    points: &[Vec<f64>],
) -> Result<(Vec<f64>, Vec<Option<f64>>), BenchError> {
    let config = ctx.config;
    let (dim, n) = (config.scene.dim(), search_n(config));
    let candidates: Vec<Candidate> = points
        .iter()
        .enumerate()
        .map(|(i, p)| Candidate::new(&config.family, dim, n, ctx.seeds[0], (g, i), p))
        .collect();
    let screened: Vec<Option<(&str, f64)>> = candidates
        .iter()
        .map(|c| screen(config, state, c))
        .collect();
    let list: Vec<(&Candidate, u64)> = candidates
        .iter()
        .zip(&screened)
        .filter(|(_, s)| s.is_none())
        .flat_map(|(c, _)| candidate_seeds(ctx, c).map(move |seed| (c, seed)))
        .collect();
    state.packings += list.len();
    let new_rows = pack_all(ctx, &list)?;
    for (c, s) in candidates.iter().zip(&screened) {
        if let Some((why, _)) = s {
            state.rows.push(unpacked_row(ctx, c, why)?);
        }
    }
    let (mut fitness, mut residuals) = (Vec::new(), Vec::new());
    for (c, s) in candidates.iter().zip(&screened) {
        let (f, residual) = match s {
            Some((_, f)) => (*f, None),
            None => {
                let mine: Vec<&DesignRow> =
                    new_rows.iter().filter(|r| r.candidate == c.index).collect();
                let (f, phi) = score_packed(config, state, c, &mine);
                let residual = phi.zip(config.objective.target()).map(|(phi, t)| phi - t);
                (f, residual)
            }
        };
        fitness.push(f + c.penalty);
        residuals.push(residual);
    }
    state.rows.extend(new_rows);
    Ok((fitness, residuals))
}

/// The seeds candidate `c` is packed with: the search's common seeds, or in a bracketing search
/// seeds of its own (the line through every packing then averages over every seed's draw,
/// where common seeds shift the whole line, and its root, by their own mean's offset: 0.002
/// in φ_J with two seeds at N = 10³, docs/notes/design-search.md).
fn candidate_seeds<'a>(ctx: &'a Context, c: &Candidate) -> impl Iterator<Item = u64> + 'a {
    let k = ctx.seeds.len() as u64;
    let own = ctx.config.optimizer == Optimizer::Bracket;
    // Generations of at most 1000 candidates keep every candidate's seeds apart.
    let offset = if own {
        k * (1000 * c.generation as u64 + c.index as u64)
    } else {
        0
    };
    ctx.seeds.iter().map(move |s| s + offset)
}

/// Why candidate `c` is not packed, with the fitness it is told instead: invalid values, a
/// size ratio above `--max-ratio`, or a prediction that cannot win. `None`: pack it. The
/// screen's verdicts use only earlier generations, so they do not depend on the order in
/// which this generation's packings finish.
fn screen(
    config: &DesignConfig,
    state: &SearchState,
    c: &Candidate,
) -> Option<(&'static str, f64)> {
    if c.invalid.is_some() {
        return Some((INVALID, INFEASIBLE));
    }
    if let Some(r) = config.max_ratio
        && c.measures.size_ratio > r * (1.0 + 1e-12)
    {
        return Some((SKIPPED_RATIO, INFEASIBLE + (c.measures.size_ratio - r)));
    }
    match verdict(
        &config.objective,
        config.screen.pick(&c.predictions),
        &c.measures,
        &state.calibration,
        state.best,
        config.screen_margin,
    ) {
        Verdict::Pack => None,
        Verdict::Skip { corrected } => Some((
            SKIPPED_PREDICTED,
            config.objective.fitness(Some(corrected), &c.measures),
        )),
    }
}

/// Packs every `(candidate, seed)` of `list` at the search's N on the pool (kept rows reused).
fn pack_all(ctx: &Context, list: &[(&Candidate, u64)]) -> Result<Vec<DesignRow>, BenchError> {
    let n = search_n(ctx.config);
    ctx.pool.install(|| {
        list.par_iter()
            .map(|(c, seed)| {
                let key = (RowKind::Search, ctx.island, c.generation, c.index, *seed);
                if let Some(r) = ctx.kept.get(&key).filter(|r| is_finished(&r.record)) {
                    check_kept(r, c)?;
                    return Ok(r.clone());
                }
                let record = pack(ctx.config, &c.values, *seed, n, &mut *(ctx.observer)())?;
                let row = c.row(RowKind::Search, ctx.island, PACKED, record);
                (ctx.done)(&row)?;
                Ok(row)
            })
            .collect()
    })
}

/// The row of a candidate that was not packed, `why` (kept from an earlier run, or new).
fn unpacked_row(ctx: &Context, c: &Candidate, why: &str) -> Result<DesignRow, BenchError> {
    let key = (
        RowKind::Search,
        ctx.island,
        c.generation,
        c.index,
        ctx.seeds[0],
    );
    if let Some(r) = ctx.kept.get(&key) {
        check_kept(r, c)?;
        return Ok(r.clone());
    }
    let record = unpacked_record(ctx.config, ctx.seeds[0], c.invalid.clone());
    let row = c.row(RowKind::Search, ctx.island, why, record);
    (ctx.done)(&row)?;
    Ok(row)
}

/// The fitness of packed candidate `c` from its rows `mine`, with its mean φ_J (`None`: no
/// packing of it succeeded); updates the screen's calibration and the best fitness.
fn score_packed(
    config: &DesignConfig,
    state: &mut SearchState,
    c: &Candidate,
    mine: &[&DesignRow],
) -> (f64, Option<f64>) {
    let Some((phi, f)) = candidate_fitness(config, mine) else {
        return (INFEASIBLE, None);
    };
    if let Some(pred) = config.screen.pick(&c.predictions) {
        state.calibration.add(pred, phi);
    }
    state.best = Some(state.best.map_or(f, |b: f64| b.min(f)));
    (f, Some(phi))
}

/// Packs the incumbent (the best candidate so far) once more with a fresh seed, up to
/// [`MAX_REEVALUATIONS`] times: its mean φ_J then rests on more packings than any challenger's,
/// so a candidate that won on one lucky seed falls back when the next seed is ordinary.
/// Returns whether it packed.
fn reevaluate_incumbent(ctx: &Context, state: &mut SearchState) -> Result<bool, BenchError> {
    let Some((g, c, _, _)) = best_candidate(ctx.config, &state.rows) else {
        return Ok(false);
    };
    let mine: Vec<&DesignRow> = state
        .rows
        .iter()
        .filter(|r| r.kind == RowKind::Search && r.generation == g && r.candidate == c)
        .collect();
    let extra = mine.len().saturating_sub(ctx.seeds.len());
    if extra >= MAX_REEVALUATIONS {
        return Ok(false);
    }
    let seed = ctx.config.base_seed + mine.len() as u64;
    let first = mine[0];
    let cand = Candidate {
        generation: g,
        index: c,
        values: first.params.clone(),
        penalty: 0.0,
        measures: SizeMeasures {
            size_ratio: first.size_ratio,
            polydispersity: first.polydispersity,
        },
        predictions: Predictions {
            desmond_weeks: first.predicted_dw,
            farr_groot: first.predicted_fg,
        },
        invalid: None,
    };
    state.packings += 1;
    let row = pack_all(ctx, &[(&cand, seed)])?;
    state.rows.extend(row);
    Ok(true)
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
/// earliest), as `(generation, candidate, mean φ_J, fitness)`; in a bracketing search, the
/// packed candidate nearest the root of its line ([`super::bracket::root`]).
pub fn best_candidate(
    config: &DesignConfig,
    rows: &[DesignRow],
) -> Option<(usize, usize, f64, f64)> {
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
    let scored: Vec<((usize, usize), f64, f64, f64)> = groups
        .into_iter()
        .filter_map(|(key, rs)| {
            let (phi, f) = candidate_fitness(config, &rs)?;
            Some((key, phi, f, free_unit(config, &rs[0].params)))
        })
        .collect();
    let root = (config.optimizer == Optimizer::Bracket)
        .then(|| {
            let target = config.objective.target()?;
            let data: Vec<(f64, f64)> = scored.iter().map(|s| (s.3, s.1 - target)).collect();
            super::bracket::root(&data)
        })
        .flatten();
    // Smallest fitness, or distance to the root (ties: the earliest).
    let rank = |s: &((usize, usize), f64, f64, f64)| root.map_or(s.2, |x| (s.3 - x).abs());
    let mut best: Option<&((usize, usize), f64, f64, f64)> = None;
    for s in &scored {
        if best.is_none_or(|b| rank(s) < rank(b)) {
            best = Some(s);
        }
    }
    best.map(|&((g, c), phi, f, _)| (g, c, phi, f))
}

/// The first free parameter of `params` in the unit range of its bounds (0.5 when there is
/// none).
fn free_unit(config: &DesignConfig, params: &[f64]) -> f64 {
    let family = &config.family;
    let free = (family.params.iter().enumerate()).find(|(_, p)| p.is_free());
    match free {
        Some((i, p)) if p.hi > p.lo => params.get(i).map_or(0.5, |v| (v - p.lo) / (p.hi - p.lo)),
        _ => 0.5,
    }
}

/// The confirmation reruns of candidate `(generation, index)` with `values` at the scene's N:
/// one row per fresh seed, kept rows reused.
///
/// Errors: as [`run_search`], and a run error when the values make no distribution.
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
    let pool = thread_pool(jobs)?;
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
                let c = Candidate {
                    generation,
                    index,
                    values: values.to_vec(),
                    penalty: 0.0,
                    measures: measures_of(&d),
                    predictions: predictions(dim, &d),
                    invalid: None,
                };
                let record = pack(config, values, seed, n, &mut *observer())?;
                let row = c.row(RowKind::Confirm, island, PACKED, record);
                done(&row)?;
                Ok(row)
            })
            .collect()
    })
}
