//! Published tables recomputed: each table of [`tables`] names its source, the protocol the
//! publication used and the packbench method that follows it, and turns an N into cases (one
//! scene and method each, packed once per seed) and cells (a published number beside the
//! statistic of the case's runs that recomputes it) — the library behind `packbench reproduce`.
//!
//! What it is made of: [`published`] (the numbers, kept in `crates/bench/data/published/`
//! with their citations), [`tables`] (one file per publication), [`rows`] (`runs.csv`, one
//! row per run appended as it finishes, and `reproduce.json`) and [`report`] (report.md and
//! the figure). Every run is a `compare` row made by [`crate::comparison_runs::execute`];
//! nothing here packs or analyses.
//!
//! What it is not: no published value is computed from packbench's own runs; a value the
//! publication has but packbench cannot recompute (a method it lacks, a protocol too long for
//! the machine) is a cell marked not run, with why.

pub mod published;
pub mod report;
pub mod rows;
pub mod tables;

use packbench_core::Scene;
use serde::{Deserialize, Serialize};
use serde_json::Value;

use crate::comparison_runs::execute;
use crate::error::{BenchError, usage};
use crate::methods;
use crate::records::{CompareConfig, RunRecord, mean_std};
use crate::runs::QuietObserver;
use published::Band;
use rayon::prelude::*;
use rows::ReproduceRow;

/// One published table and how packbench recomputes it.
pub struct Table {
    /// The name on the command line (`baranau2014-table4`).
    pub name: &'static str,
    /// Authors, year, journal and the table or figure.
    pub source: &'static str,
    /// What is run, in one or two sentences: the publication's protocol and packbench's method.
    pub protocol: &'static str,
    /// The publication's N, when it gives one; `--N` may only go below it.
    pub published_n: Option<usize>,
    /// The N run when `--N` is not given; `None` when the table's cases fix their own size
    /// (3DRSP's bricks) and `--N` does not apply.
    pub default_n: Option<usize>,
    /// The smallest N the table's scenes hold (below it the largest sphere outgrows the box).
    pub min_n: usize,
    /// Label of the cases' axis in the figure.
    pub axis: &'static str,
    /// The cases at `n` particles.
    pub cases: fn(usize) -> Result<Vec<Case>, BenchError>,
}

/// A row of a table: one scene packed by one method (or nothing packed), and its cells.
pub struct Case {
    /// Its label in the report, the figure and `runs.csv` (`σ = 0.10`).
    pub label: String,
    /// What is packed once per seed; `None` when every cell is predicted or not run.
    pub run: Option<CaseRun>,
    /// The published values of this case and how each is recomputed.
    pub cells: Vec<Cell>,
}

/// The packing behind a case: a scene, a method, an optional method chained after it, and
/// method parameters (`(method, key, value)` as `compare --set`).
pub struct CaseRun {
    pub scene: Scene,
    pub method: &'static str,
    pub refine: Option<&'static str>,
    pub overrides: Vec<(String, String, Value)>,
}

impl CaseRun {
    /// The comparison whose runs these are, over `seeds` seeds from `base_seed`.
    pub fn comparison(&self, seeds: u64, base_seed: u64) -> CompareConfig {
        CompareConfig {
            scene: self.scene.clone(),
            methods: vec![self.method.to_string()],
            seeds,
            base_seed,
            refine: self.refine.map(str::to_string),
            overrides: self.overrides.clone(),
        }
    }
}

/// A published value and its recomputation.
pub struct Cell {
    /// What it is (`φ_RCP`, `z`, `N per unit cube`).
    pub quantity: &'static str,
    /// The published value (`None`: the publication gives none; shown beside for context).
    pub published: Option<f64>,
    /// How packbench recomputes it.
    pub recompute: Recompute,
    /// A note for the report (what the published value is, when it is not a measurement).
    pub note: Option<&'static str>,
    /// The band the recomputed value must fall in, from the published file alone (its
    /// uncertainty and finite-size allowance at the N run); `None`: the value has no band.
    pub band: Option<Band>,
    /// Why the recomputation is known to fall outside the band (from the published file);
    /// `None`: it is expected inside.
    pub disagrees: Option<String>,
}

impl Cell {
    /// A cell without band (context, or a value the publication states no uncertainty for).
    pub fn unbanded(quantity: &'static str, published: Option<f64>, recompute: Recompute) -> Cell {
        Cell {
            quantity,
            published,
            recompute,
            note: None,
            band: None,
            disagrees: None,
        }
    }

    /// A cell for column `col` of a published row, with its band at `n` particles and its
    /// known disagreement.
    pub fn of_row(
        quantity: &'static str,
        row: &published::Row,
        col: &str,
        n: Option<usize>,
        recompute: Recompute,
    ) -> Cell {
        Cell {
            quantity,
            published: row.num(col),
            recompute,
            note: None,
            band: row.band(col, n),
            disagrees: row.disagreement(col),
        }
    }
}

/// How a cell is recomputed.
pub enum Recompute {
    /// A statistic of a field over the case's runs that made a packing.
    Runs(Statistic, Field),
    /// A value computed without packing (a predictor).
    Value(f64),
    /// Not recomputed, and why.
    NotRun(&'static str),
}

/// A statistic over the runs of a case.
#[derive(Clone, Copy)]
pub enum Statistic {
    /// Mean ± standard error of the mean.
    Mean,
    /// The lowest of the seeds ± its bootstrap standard error (an estimate of a lower edge).
    Lowest,
    /// The highest of the seeds ± its bootstrap standard error (an estimate of an upper edge).
    Highest,
}

/// A column of a run's row.
#[derive(Clone, Copy)]
pub enum Field {
    /// φ of the method's packing.
    Phi,
    /// φ after the chained method (MLS after LS).
    RefinedPhi,
    /// Mean contact number over non-rattlers.
    ZNonrattler,
    /// Number of spheres placed (seq-fill).
    N,
}

impl Field {
    /// The field of `r`, when the run made what the field needs.
    pub fn of(self, r: &RunRecord) -> Option<f64> {
        if !r.made_packing() {
            return None;
        }
        match self {
            Field::Phi => r.phi,
            Field::RefinedPhi if r.error.is_none() => r.refined_phi,
            Field::RefinedPhi => None,
            Field::ZNonrattler => r.z_nonrattler,
            Field::N => Some(r.n as f64),
        }
    }
}

/// A recomputed value: the estimate, its standard error (none from fewer than 2 runs) and the
/// number of runs it comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    pub value: f64,
    pub std_error: Option<f64>,
    pub runs: usize,
}

impl Statistic {
    /// The statistic of `values`; `None` without values.
    pub fn estimate(self, values: &[f64]) -> Option<Estimate> {
        let (mean, std) = mean_std(values)?;
        let k = values.len();
        let (value, std_error) = match self {
            Statistic::Mean => (mean, std / (k as f64).sqrt()),
            Statistic::Lowest | Statistic::Highest => {
                let mut sorted = values.to_vec();
                sorted.sort_by(f64::total_cmp);
                if let Statistic::Highest = self {
                    sorted.reverse();
                }
                (sorted[0], bootstrap_extreme_se(&sorted))
            }
        };
        Some(Estimate {
            value,
            std_error: (k > 1).then_some(std_error),
            runs: k,
        })
    }
}

/// Standard error of the extreme of `k` values by the exact bootstrap: the extreme of `k`
/// draws with replacement from `sorted` (ordered from the extreme inwards) is `sorted[i]` with
/// probability ((k − i)/k)^k − ((k − i − 1)/k)^k (Efron & Tibshirani 1993, §7.3, for the
/// minimum), so no random resampling is needed.
fn bootstrap_extreme_se(sorted: &[f64]) -> f64 {
    let k = sorted.len() as f64;
    let p = |i: usize| ((k - i as f64) / k).powf(k) - ((k - i as f64 - 1.0) / k).powf(k);
    let mean: f64 = sorted.iter().enumerate().map(|(i, x)| p(i) * x).sum();
    let var: f64 = sorted
        .iter()
        .enumerate()
        .map(|(i, x)| p(i) * (x - mean).powi(2))
        .sum();
    var.sqrt()
}

/// Everything that defines a reproduction; stored in `reproduce.json` so that `--resume` and
/// `merge` continue or join only the same one.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReproduceConfig {
    pub table: String,
    /// Particles per packing (`None` for tables whose cases fix their own size).
    pub n: Option<usize>,
    pub seeds: u64,
    pub base_seed: u64,
    /// The rows of the table run (1-based); empty for all.
    #[serde(default)]
    pub rows: Vec<usize>,
}

/// The table named `name`.
///
/// Errors: a usage error naming the tables there are.
pub fn find(name: &str) -> Result<&'static Table, BenchError> {
    tables::TABLES
        .iter()
        .find(|t| t.name == name)
        .ok_or_else(|| {
            usage(format!(
                "unknown table `{name}`; `packbench reproduce --list` names them: {}",
                tables::TABLES
                    .iter()
                    .map(|t| t.name)
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
        })
}

impl Table {
    /// The N to run: `n` when given and allowed, else the default.
    ///
    /// Errors: a usage error for an N the table does not take (below its smallest scene, above
    /// the publication's, or any N for a table whose cases fix their size).
    pub fn n(&self, n: Option<usize>) -> Result<Option<usize>, BenchError> {
        let Some(default) = self.default_n else {
            return match n {
                None => Ok(None),
                Some(_) => Err(usage(format!(
                    "--N does not apply to {}: its cases fix their own size (the publication's \
                     bricks), so drop --N",
                    self.name
                ))),
            };
        };
        let n = n.unwrap_or(default);
        if n < self.min_n {
            return Err(usage(format!(
                "--N {n} is too small for {}: its scenes need at least {} spheres",
                self.name, self.min_n
            )));
        }
        if let Some(p) = self.published_n
            && n > p
        {
            return Err(usage(format!(
                "--N {n} is above the publication's N = {p} for {}; give N ≤ {p}",
                self.name
            )));
        }
        Ok(Some(n))
    }
}

impl ReproduceConfig {
    /// The cases of `table` this reproduction runs: its rows at its N, or those of `rows`.
    ///
    /// Errors: a usage error for a row the table does not have; errors of the table's cases.
    pub fn cases(&self, table: &Table) -> Result<Vec<Case>, BenchError> {
        let all = (table.cases)(self.n.unwrap_or(0))?;
        if let Some(&bad) = self.rows.iter().find(|&&r| r == 0 || r > all.len()) {
            return Err(usage(format!(
                "--rows {bad}: {} has rows 1 to {}",
                table.name,
                all.len()
            )));
        }
        Ok(all
            .into_iter()
            .enumerate()
            .filter(|(i, _)| self.rows.is_empty() || self.rows.contains(&(i + 1)))
            .map(|(_, c)| c)
            .collect())
    }
}

/// The runs of a reproduction in canonical order, case-major then seed: `(index, case,
/// seed)` for every case that packs.
pub fn run_list(cases: &[Case], config: &ReproduceConfig) -> Vec<(usize, usize, u64)> {
    let mut list = Vec::new();
    for (c, case) in cases.iter().enumerate() {
        if case.run.is_some() {
            for k in 0..config.seeds {
                list.push((list.len(), c, config.base_seed + k));
            }
        }
    }
    list
}

/// Runs the entries `(index, case, seed)` of a run list on `jobs` threads (0: every core),
/// each with [`execute`] as `compare` runs it, telling `done` each finished row (a failed run
/// is a row). Returns the rows with their indices.
///
/// Errors: a scene or parameter a case cannot use, a thread pool that cannot be built, or an
/// error of `done`.
pub fn run_cases(
    cases: &[Case],
    config: &ReproduceConfig,
    list: &[(usize, usize, u64)],
    jobs: usize,
    done: impl Fn(&ReproduceRow) -> Result<(), BenchError> + Sync,
) -> Result<Vec<(usize, ReproduceRow)>, BenchError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .build()
        .map_err(|e| BenchError::Run(format!("thread pool: {e}")))?;
    pool.install(|| {
        list.par_iter()
            .map(|&(idx, c, seed)| {
                let case = &cases[c];
                let Some(run) = &case.run else {
                    return Err(BenchError::Run(format!("{} packs nothing", case.label)));
                };
                let comparison = run.comparison(config.seeds, config.base_seed);
                let method = methods::find(run.method)?;
                let t0 = std::time::Instant::now();
                let result = execute(&comparison, seed, method, &mut QuietObserver)?;
                let row = ReproduceRow {
                    case: case.label.clone(),
                    record: result.record,
                    total_s: t0.elapsed().as_secs_f64(),
                };
                done(&row)?;
                Ok((idx, row))
            })
            .collect()
    })
}

/// Checks every case's method parameters before the first run starts.
///
/// Errors: a usage error for a parameter a method refuses.
pub fn check_cases(cases: &[Case]) -> Result<(), BenchError> {
    for run in cases.iter().filter_map(|c| c.run.as_ref()) {
        crate::comparison_runs::check_comparison(&run.comparison(1, 1))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extremes_and_their_bootstrap_errors() {
        let v = [0.64, 0.63, 0.65];
        let lo = Statistic::Lowest.estimate(&v).unwrap();
        let hi = Statistic::Highest.estimate(&v).unwrap();
        assert_eq!((lo.value, hi.value, lo.runs), (0.63, 0.65, 3));
        // Bootstrap minimum of 3: 0.63 with 19/27, 0.64 with 7/27, 0.65 with 1/27.
        let m = (19.0 * 0.63 + 7.0 * 0.64 + 0.65) / 27.0;
        let var =
            (19.0 * (0.63f64 - m).powi(2) + 7.0 * (0.64f64 - m).powi(2) + (0.65f64 - m).powi(2))
                / 27.0;
        assert!((lo.std_error.unwrap() - var.sqrt()).abs() < 1e-15);
        assert!((hi.std_error.unwrap() - var.sqrt()).abs() < 1e-15);
        let one = Statistic::Mean.estimate(&[0.64]).unwrap();
        assert_eq!((one.value, one.std_error), (0.64, None));
        assert!(Statistic::Mean.estimate(&[]).is_none());
    }

    #[test]
    fn every_table_builds_its_cases_at_its_smallest_n() {
        for t in tables::TABLES {
            let n = t.n(t.default_n.map(|_| t.min_n)).unwrap();
            let cases = (t.cases)(n.unwrap_or(0)).unwrap();
            assert!(!cases.is_empty(), "{}", t.name);
            for c in &cases {
                assert!(!c.cells.is_empty(), "{} {}", t.name, c.label);
                if let Some(r) = &c.run {
                    crate::methods::find(r.method).unwrap();
                }
            }
        }
    }
}
