//! `packbench merge`: joins the shard folders of a comparison into the outputs of one
//! unsharded run.

use std::path::PathBuf;

use clap::Args;

use super::Printed;
use crate::error::{BenchError, usage};
use crate::outputs::{load_packing, save_packing};
use crate::records::{RunRecord, RunsFile, run_list};
use crate::report;

/// Flags of `packbench merge`.
#[derive(Args, Debug)]
pub struct MergeArgs {
    /// Shard output folders.
    #[arg(required = true)]
    pub dirs: Vec<PathBuf>,
    /// Folder for the merged outputs.
    #[arg(long, default_value = "packbench-out")]
    pub out: PathBuf,
}

/// `packbench merge`: joins shards into the outputs of one unsharded run.
pub fn run(args: &MergeArgs) -> Result<Printed, BenchError> {
    let mut files = Vec::new();
    for d in &args.dirs {
        let path = d.join("runs.json");
        let text = std::fs::read_to_string(&path)
            .map_err(|e| usage(format!("cannot read {}: {e}", path.display())))?;
        let f: RunsFile = serde_json::from_str(&text)
            .map_err(|e| usage(format!("{}: not a runs.json: {e}", path.display())))?;
        files.push((d.clone(), f));
    }
    let config = files[0].1.config.clone();
    let n = files[0].1.shard.1;
    if files
        .iter()
        .any(|(_, f)| f.config != config || f.shard.1 != n)
    {
        return Err(usage(
            "the shards come from different comparisons (their configurations differ)",
        ));
    }
    let mut seen: Vec<usize> = files.iter().map(|(_, f)| f.shard.0).collect();
    seen.sort();
    seen.dedup();
    if seen.len() != n {
        return Err(usage(format!(
            "{} distinct shards of {n} given; every shard 1..{n} is needed once",
            seen.len()
        )));
    }
    let list = run_list(&config);
    let mut runs: Vec<(usize, RunRecord)> = Vec::new();
    for (dir, f) in &files {
        let mine: Vec<usize> = list
            .iter()
            .filter(|(i, _, _)| i % n == f.shard.0 - 1)
            .map(|(i, _, _)| *i)
            .collect();
        if mine.len() != f.runs.len() {
            return Err(usage(format!(
                "{} holds {} runs but its shard has {}",
                dir.display(),
                f.runs.len(),
                mine.len()
            )));
        }
        for (i, r) in mine.into_iter().zip(&f.runs) {
            runs.push((i, r.clone()));
            if let Some(p) = load_packing(dir, &r.method, r.seed) {
                save_packing(&args.out, r, &p)?;
            }
        }
    }
    runs.sort_by_key(|(i, _)| *i);
    let merged = RunsFile {
        config,
        shard: (1, 1),
        runs: runs.into_iter().map(|(_, r)| r).collect(),
    };
    report::write_all(&args.out, &merged)?;
    Ok(Printed {
        stdout: String::new(),
        stderr: vec![format!(
            "packbench merge: {} runs from {} shards -> {}/",
            merged.runs.len(),
            n,
            args.out.display()
        )],
    })
}
