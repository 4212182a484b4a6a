//! `packbench merge`: joins shard folders of a comparison, and reruns of some of its runs,
//! into the outputs of one unsharded run. Rows are tied to runs by `(method, seed)`
//! ([`crate::shards`]), so a folder may hold any subset of the runs.

use std::path::{Path, PathBuf};

use clap::Args;

use super::Printed;
use crate::error::{BenchError, usage};
use crate::outputs::{load_packing, save_packing};
use crate::records::{NOT_RUN, RunRecord, RunsFile, run_list};
use crate::report;
use crate::shards::{index_of, is_finished, read_runs_file, run_index};

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
pub fn run(args: &MergeArgs) -> Result<Printed, BenchError> {
    if crate::design::history::is_design_dir(&args.dirs[0]) {
        return super::design::merge(&args.dirs, &args.out);
    }
    if crate::reproduce::rows::is_reproduce_dir(&args.dirs[0]) {
        return super::reproduce::merge(&args.dirs, &args.out);
    }
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
            save_packing(&args.out, c.row, &p)?;
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
    super::view::write_compare_page(&args.out)?;
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
    use crate::shards::INTERRUPTED;

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
