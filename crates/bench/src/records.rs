//! The records of runs, the bottom layer of the bench: one row per run (`runs.csv`), the
//! comparison that made them (`runs.json`), how a comparison is split into shards, and the
//! statistics reports take over rows. Nothing here runs a method or draws.

use packbench_core::Scene;
use serde::{Deserialize, Serialize};

use crate::error::{BenchError, usage};

/// One row of `runs.csv`. The first fourteen columns are the documented ones; the rest
/// describe a refinement (`--refine`) and failures.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RunRecord {
    pub method: String,
    pub seed: u64,
    pub d: usize,
    pub n: usize,
    pub phi: Option<f64>,
    pub z_nonrattler: Option<f64>,
    pub rattlers: Option<usize>,
    pub iso_gap: Option<i64>,
    pub isostatic: Option<bool>,
    pub max_overlap: Option<f64>,
    pub force_balance: Option<f64>,
    pub runtime_s: f64,
    pub steps: u64,
    pub termination: String,
    /// The knob value of a sweep row (empty in comparisons).
    pub knob_value: Option<f64>,
    /// φ after `--refine`.
    pub refined_phi: Option<f64>,
    /// φ_refined − φ.
    pub delta_phi: Option<f64>,
    /// Why the refinement stopped (`jammed`, `converged`, `max_steps`, …): a Δφ means φ_J
    /// only if the refiner jammed. Absent in outputs written before it was recorded.
    #[serde(default)]
    pub refined_termination: Option<String>,
    /// The refined packing's isostaticity gap over non-rattlers (core analysis).
    #[serde(default)]
    pub refined_iso_gap: Option<i64>,
    /// The refined packing's force-balance residual (core analysis).
    #[serde(default)]
    pub refined_force_balance: Option<f64>,
    /// The methods that refined the packing, in order (`calippso`, `mls → calippso`).
    #[serde(default)]
    pub refined_by: Option<String>,
    /// The refinement's wall time in seconds, its legs summed (without the analyses).
    #[serde(default)]
    pub refined_runtime_s: Option<f64>,
    /// Whether the refined packing is jammed: the exact refiner claimed it and the core's
    /// analysis agrees (no overlap, iso_gap ≥ 0, force balance; the rule of `pack`). `None`
    /// when the refiner makes no such claim (mls) or the output predates the column. The
    /// report counts this column; it does not judge again.
    #[serde(default)]
    pub refined_jammed: Option<bool>,
    /// The error message of a failed run.
    pub error: Option<String>,
}

impl RunRecord {
    /// Whether the run made a packing: it has one, was not left at its step budget with
    /// overlaps above `OVERLAP_AT_BUDGET`, and is not an exact method's jammed packing that the
    /// analysis contradicts (those packings are kept for inspection, not results).
    pub fn made_packing(&self) -> bool {
        self.phi.is_some()
            && self.termination != BUDGET_WITH_OVERLAPS
            && self.termination != NOT_JAMMED
    }
}

/// Termination of a run that was not started because a stop request came first.
pub const NOT_RUN: &str = "not_run";

/// Termination of a run that used its whole step budget and still overlaps by more than
/// `OVERLAP_AT_BUDGET`: a failed run whose packing is kept for inspection.
pub const BUDGET_WITH_OVERLAPS: &str = "max_steps_with_overlaps";

/// Termination of a run whose method claimed an exactly jammed packing that the core's
/// analysis contradicts ([`packbench_core::analysis::not_jammed_because`]).
pub const NOT_JAMMED: &str = "not_jammed";

/// Everything that defines a comparison; stored with its results so shards can be merged.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct CompareConfig {
    pub scene: Scene,
    pub methods: Vec<String>,
    pub seeds: u64,
    pub base_seed: u64,
    pub refine: Option<String>,
    pub overrides: Vec<(String, String, serde_json::Value)>,
}

/// The contents of `runs.json`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RunsFile {
    pub config: CompareConfig,
    /// `(i, n)` for a shard, `(1, 1)` for a whole run.
    pub shard: (usize, usize),
    pub runs: Vec<RunRecord>,
}

/// Parses `i/n`.
pub fn parse_shard(s: &str) -> Result<(usize, usize), BenchError> {
    let bad = || {
        usage(format!(
            "--shard `{s}` must be i/n with 1 ≤ i ≤ n, e.g. 2/8"
        ))
    };
    let (i, n) = s.split_once('/').ok_or_else(bad)?;
    let (i, n): (usize, usize) = (
        i.trim().parse().map_err(|_| bad())?,
        n.trim().parse().map_err(|_| bad())?,
    );
    if i == 0 || n == 0 || i > n {
        return Err(bad());
    }
    Ok((i, n))
}

/// The runs of a comparison in canonical order: seed-major, then method.
pub fn run_list(config: &CompareConfig) -> Vec<(usize, u64, String)> {
    let mut list = Vec::new();
    for k in 0..config.seeds {
        for m in &config.methods {
            list.push((list.len(), config.base_seed + k, m.clone()));
        }
    }
    list
}

/// Mean and (sample) standard deviation.
pub fn mean_std(v: &[f64]) -> Option<(f64, f64)> {
    if v.is_empty() {
        return None;
    }
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let var = if v.len() > 1 {
        v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)
    } else {
        0.0
    };
    Some((mean, var.sqrt()))
}
