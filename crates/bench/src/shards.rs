//! A comparison run in pieces on a batch cluster: how many runs at once an allocation allows
//! (`SLURM_CPUS_PER_TASK`), finishing what a stopped shard left (`compare --resume-missing`),
//! and joining shard folders, reruns included, into the outputs of one run (`packbench merge`).
//!
//! A row is tied to its run by `(method, seed)`, not by its place in a file, so a folder may
//! hold any subset of a comparison's runs and the same run may come from several folders.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use clap::Args;

use crate::commands::Printed;
use crate::compare::{CompareConfig, RunsFile, load_packing, run_list, save_packing};
use crate::error::{BenchError, usage};
use crate::report;
use crate::runs::{NOT_RUN, RunRecord};

/// Termination of a run (or of its refinement) stopped by Ctrl-C or SIGTERM.
const INTERRUPTED: &str = "interrupted";

/// Runs at once for `compare`: `--jobs` when given, else the CPUs Slurm gave each task
/// (`SLURM_CPUS_PER_TASK`, set by `--cpus-per-task`), else 0, which rayon reads as every core.
///
/// Errors: a usage error when `SLURM_CPUS_PER_TASK` is set but not a positive integer.
pub fn jobs(flag: Option<usize>) -> Result<usize, BenchError> {
    jobs_from(flag, std::env::var("SLURM_CPUS_PER_TASK").ok().as_deref())
}

/// [`jobs`] with the environment variable's value passed in.
pub fn jobs_from(flag: Option<usize>, cpus_per_task: Option<&str>) -> Result<usize, BenchError> {
    if let Some(k) = flag {
        return Ok(k);
    }
    match cpus_per_task {
        None => Ok(0),
        Some(v) => match v.trim().parse::<usize>() {
            Ok(k) if k > 0 => Ok(k),
            _ => Err(usage(format!(
                "SLURM_CPUS_PER_TASK=`{v}` is not a CPU count; give --jobs instead"
            ))),
        },
    }
}

/// Whether a row is a result to keep: everything but a run that never started (`not_run`) or
/// that a signal stopped, itself or its refinement (`interrupted`).
pub fn is_finished(r: &RunRecord) -> bool {
    r.termination != NOT_RUN
        && r.termination != INTERRUPTED
        && r.refined_termination.as_deref() != Some(INTERRUPTED)
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
fn run_index(config: &CompareConfig) -> HashMap<(u64, String), usize> {
    run_list(config)
        .into_iter()
        .map(|(i, seed, method)| ((seed, method), i))
        .collect()
}

/// The index of the run behind `row` in `config`'s run list.
///
/// Errors: a usage error when no run of the comparison has that method and seed.
fn index_of(
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
            remove_packing(out, &row)?;
        }
    }
    Ok(kept)
}

/// Removes the saved packing of `row` (and its container), if any.
fn remove_packing(dir: &Path, row: &RunRecord) -> Result<(), BenchError> {
    let txt = dir
        .join("packings")
        .join(format!("{}_seed{}.txt", row.method, row.seed));
    for path in [txt.with_extension("container.json"), txt] {
        match std::fs::remove_file(&path) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                return Err(BenchError::Run(format!(
                    "cannot remove {}: {e}",
                    path.display()
                )));
            }
            _ => {}
        }
    }
    Ok(())
}

/// Flags of `packbench merge`.
#[derive(Args, Debug)]
pub struct MergeArgs {
    /// Output folders of one comparison: its shards, and reruns of some of its runs (e.g. a
    /// shard stopped by a time limit, run again into another folder).
    #[arg(required = true)]
    pub dirs: Vec<PathBuf>,
    /// Folder for the merged outputs.
    #[arg(long, default_value = "packbench-out")]
    pub out: PathBuf,
}

/// The row chosen for one run, and the folder it (and its packing) comes from.
struct Chosen<'a> {
    dir: &'a Path,
    row: &'a RunRecord,
}

/// Picks between two rows of the same run: a finished row over an unfinished one, an
/// interrupted run (which left a packing) over one never started.
///
/// Errors: a usage error when both are finished with different results, i.e. they are not
/// runs of the same comparison by the same build.
fn choose<'a>(held: Chosen<'a>, new: Chosen<'a>) -> Result<Chosen<'a>, BenchError> {
    match (is_finished(held.row), is_finished(new.row)) {
        (true, true) => {
            let (a, b) = (held.row, new.row);
            if a.phi.map(f64::to_bits) != b.phi.map(f64::to_bits)
                || a.termination != b.termination
                || a.refined_phi.map(f64::to_bits) != b.refined_phi.map(f64::to_bits)
            {
                return Err(usage(format!(
                    "{} and {} hold different results for {} seed {} (φ {:?} vs {:?}, {} vs {}): \
                     the same run gives the same result, so they are not one comparison",
                    held.dir.display(),
                    new.dir.display(),
                    a.method,
                    a.seed,
                    a.phi,
                    b.phi,
                    a.termination,
                    b.termination
                )));
            }
            Ok(held)
        }
        (true, false) => Ok(held),
        (false, true) => Ok(new),
        (false, false) if held.row.termination == NOT_RUN => Ok(new),
        (false, false) => Ok(held),
    }
}

/// `packbench merge`: joins the folders of one comparison into the outputs of one unsharded
/// run. Each run of the comparison must be in at least one folder; where several hold it, a
/// finished row wins over a stopped or unstarted one (a rerun replaces what a time limit
/// stopped), and two finished rows must agree.
///
/// Errors: usage errors for unreadable folders, folders of different comparisons (scene,
/// methods, seeds, refinement or `--set` differ), runs held by no folder, and finished rows
/// that disagree; run errors for outputs that cannot be written.
pub fn merge(args: &MergeArgs) -> Result<Printed, BenchError> {
    let files = args
        .dirs
        .iter()
        .map(|d| Ok((d.as_path(), read_runs_file(d)?)))
        .collect::<Result<Vec<_>, BenchError>>()?;
    let config = files[0].1.config.clone();
    if let Some((d, _)) = files.iter().find(|(_, f)| f.config != config) {
        return Err(usage(format!(
            "{} and {} come from different comparisons (their scene, methods, seeds or options \
             differ)",
            files[0].0.display(),
            d.display()
        )));
    }
    let index = run_index(&config);
    let mut chosen: Vec<Option<Chosen>> = (0..index.len()).map(|_| None).collect();
    for (dir, f) in &files {
        for row in &f.runs {
            let i = index_of(&index, row, dir)?;
            let new = Chosen { dir, row };
            chosen[i] = Some(match chosen[i].take() {
                None => new,
                Some(held) => choose(held, new)?,
            });
        }
    }
    let mut runs = Vec::with_capacity(chosen.len());
    for ((_, seed, method), c) in run_list(&config).into_iter().zip(&chosen) {
        let c = c.as_ref().ok_or_else(|| {
            usage(format!(
                "no folder holds the run of {method} seed {seed}: every run of the comparison \
                 (every shard) is needed"
            ))
        })?;
        if let Some(p) = load_packing(c.dir, &c.row.method, c.row.seed) {
            save_packing(&args.out.join("packings"), c.row, &p)?;
        }
        runs.push(c.row.clone());
    }
    let unfinished = runs.iter().filter(|r| !is_finished(r)).count();
    let merged = RunsFile {
        config,
        shard: (1, 1),
        runs,
    };
    report::write_all(&args.out, &merged)?;
    let mut stderr = vec![format!(
        "packbench merge: {} runs from {} folders -> {}/",
        merged.runs.len(),
        files.len(),
        args.out.display()
    )];
    if unfinished > 0 {
        stderr.push(format!(
            "packbench merge: {unfinished} run(s) unfinished (not_run or interrupted): run their \
             shards again with --resume-missing and merge again"
        ));
    }
    Ok(Printed {
        stdout: String::new(),
        stderr,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jobs_come_from_the_flag_then_the_allocation_then_every_core() {
        assert_eq!(jobs_from(Some(3), Some("8")).unwrap(), 3);
        assert_eq!(jobs_from(None, Some("4")).unwrap(), 4);
        assert_eq!(jobs_from(None, Some(" 2\n")).unwrap(), 2);
        assert_eq!(jobs_from(None, None).unwrap(), 0);
        for bad in ["0", "", "two", "-1", "2.5"] {
            let e = jobs_from(None, Some(bad)).unwrap_err();
            assert_eq!(e.exit_code(), 2, "{bad}");
            assert!(e.to_string().contains("SLURM_CPUS_PER_TASK"), "{e}");
        }
    }

    fn row(termination: &str, phi: Option<f64>) -> RunRecord {
        RunRecord {
            method: "mls".into(),
            seed: 3,
            termination: termination.into(),
            phi,
            ..RunRecord::default()
        }
    }

    #[test]
    fn only_unstarted_and_interrupted_runs_are_unfinished() {
        assert!(is_finished(&row("converged", Some(0.84))));
        assert!(is_finished(&row("max_steps", Some(0.8))));
        assert!(is_finished(&row("failed", None)));
        assert!(!is_finished(&row(NOT_RUN, None)));
        assert!(!is_finished(&row(INTERRUPTED, Some(0.7))));
        let mut refined = row("converged", Some(0.84));
        refined.refined_termination = Some(INTERRUPTED.into());
        assert!(!is_finished(&refined));
    }

    #[test]
    fn a_finished_row_replaces_a_stopped_one_and_finished_rows_must_agree() {
        let (a, b) = (Path::new("a"), Path::new("b"));
        let done = row("converged", Some(0.84));
        let stopped = row(INTERRUPTED, Some(0.7));
        let unstarted = row(NOT_RUN, None);
        let pick = |x: &RunRecord, y: &RunRecord| {
            choose(Chosen { dir: a, row: x }, Chosen { dir: b, row: y }).map(|c| c.row.clone())
        };
        assert_eq!(pick(&stopped, &done).unwrap(), done);
        assert_eq!(pick(&done, &unstarted).unwrap(), done);
        assert_eq!(pick(&unstarted, &stopped).unwrap(), stopped);
        assert_eq!(pick(&stopped, &unstarted).unwrap(), stopped);
        let mut again = done.clone();
        again.runtime_s = 9.0;
        assert_eq!(pick(&done, &again).unwrap(), done);
        let other = row("converged", Some(0.841));
        assert_eq!(pick(&done, &other).unwrap_err().exit_code(), 2);
    }
}
