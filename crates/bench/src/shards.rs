//! A comparison run in pieces on a batch cluster: finishing what a stopped shard left
//! (`compare --resume-missing`), and which rows of shard folders, reruns included, stand for which runs (`packbench merge`).
//!
//! A row is tied to its run by `(method, seed)`, not by its place in a file, so a folder may
//! hold any subset of a comparison's runs and the same run may come from several folders.

use std::collections::HashMap;
use std::path::Path;

use crate::error::{BenchError, usage};
use crate::outputs::remove_packing;
use crate::records::{CompareConfig, NOT_RUN, RunRecord, RunsFile, run_list};

/// Termination of a run (or of its refinement) stopped by Ctrl-C or SIGTERM.
pub const INTERRUPTED: &str = "interrupted";

/// Whether a row is a result to keep: everything but a run that never started (`not_run`) or
/// that a signal stopped, itself or its refinement (`interrupted`).
pub fn is_finished(r: &RunRecord) -> bool {
    r.termination != NOT_RUN
        && r.termination != INTERRUPTED
        && r.refined_termination.as_deref() != Some(INTERRUPTED)
}

/// The end of a batch command's last line for runs a stop request (Ctrl-C, SIGTERM, a Slurm
/// time limit) left unfinished: ", K of them interrupted or not run (continue with
/// `--flag`)"; empty when every run finished.
pub fn unfinished_note<'a>(records: impl IntoIterator<Item = &'a RunRecord>, flag: &str) -> String {
    match records.into_iter().filter(|r| !is_finished(r)).count() {
        0 => String::new(),
        k => format!(", {k} of them interrupted or not run (continue with {flag})"),
    }
}

/// Reads `DIR/runs.json`.
///
/// Errors: a usage error naming the file when it cannot be read or is not a `runs.json`.
pub fn read_runs_file(dir: &Path) -> Result<RunsFile, BenchError> {
    let path = dir.join("runs.json");
    let text = std::fs::read_to_string(&path)
        .map_err(|e| usage(format!("cannot read {}: {e}", path.display())))?;
    serde_json::from_str(&text)
        .map_err(|e| usage(format!("{}: not a runs.json: {e}", path.display())))
}

/// Index of every run of a comparison in its canonical order, by `(seed, method)`.
pub fn run_index(config: &CompareConfig) -> HashMap<(u64, String), usize> {
    run_list(config)
        .into_iter()
        .map(|(i, seed, method)| ((seed, method), i))
        .collect()
}

/// The index of the run behind `row` in `config`'s run list.
///
/// Errors: a usage error when no run of the comparison has that method and seed.
pub fn index_of(
    index: &HashMap<(u64, String), usize>,
    row: &RunRecord,
    dir: &Path,
) -> Result<usize, BenchError> {
    index
        .get(&(row.seed, row.method.clone()))
        .copied()
        .ok_or_else(|| {
            usage(format!(
                "{} holds a run ({} seed {}) that is not part of its comparison",
                dir.display(),
                row.method,
                row.seed
            ))
        })
}

/// `compare --resume-missing`: the finished rows, with their run indices, of an earlier run of
/// the same comparison and shard in `out`, which the new run keeps (their packings stay in
/// place); the packings of the rows it does not keep are removed, since those runs start over.
/// A folder without `runs.json` (a job killed before it wrote one) keeps nothing.
///
/// Errors: a usage error when `out/runs.json` is unreadable or holds another comparison or
/// another shard.
pub fn resume_missing(
    out: &Path,
    config: &CompareConfig,
    shard: (usize, usize),
) -> Result<Vec<(usize, RunRecord)>, BenchError> {
    if !out.join("runs.json").exists() {
        return Ok(Vec::new());
    }
    let earlier = read_runs_file(out)?;
    if earlier.config != *config || earlier.shard != shard {
        return Err(usage(format!(
            "{} holds another comparison or shard ({}/{}); --resume-missing continues only the \
             same one (same scene, methods, seeds, --set and --shard)",
            out.display(),
            earlier.shard.0,
            earlier.shard.1
        )));
    }
    let index = run_index(config);
    let mut kept = Vec::new();
    for row in earlier.runs {
        let i = index_of(&index, &row, out)?;
        if is_finished(&row) {
            kept.push((i, row));
        } else {
            remove_packing(out, &row.method, row.seed)?;
        }
    }
    Ok(kept)
}
