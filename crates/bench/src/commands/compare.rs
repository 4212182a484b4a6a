//! `packbench compare`: several methods on the same starting packings, split into shards
//! (`--shard i/n`) when one machine is not enough; `merge` joins the shards.

use std::path::PathBuf;

use clap::Args;

use super::Printed;
use crate::args::{BatchArgs, SceneArgs};
use crate::comparison_runs::{CompareOptions, run_comparison};
use crate::error::BenchError;
use crate::methods::run_params::method_overrides;
use crate::outputs::save_packing;
use crate::records::{CompareConfig, RunsFile, parse_shard, run_list};
use crate::report;
use crate::runs::QuietObserver;

/// Flags of `packbench compare`.
#[derive(Args, Debug)]
pub struct CompareArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Comma-separated methods (default: every registered method).
    #[arg(long, value_delimiter = ',')]
    pub methods: Option<Vec<String>>,
    /// Number of starting packings (seeds base, base+1, …).
    #[arg(long, default_value_t = 3)]
    pub seeds: u64,
    /// First seed.
    #[arg(long = "seed", default_value_t = 1)]
    pub base_seed: u64,
    /// Chain every result into this exact-jamming method (calippso, closest-jammed,
    /// closest-jammed-qp) and report Δφ = φ_refined − φ; `exact` picks the fastest exact chain
    /// at the scene's N: calippso directly up to N = 12 000, MLS then calippso above.
    #[arg(long)]
    pub refine: Option<String>,
    /// Output folder.
    #[arg(long, default_value = "packbench-out")]
    pub out: PathBuf,
    /// Run only the i-th of n slices of the runs (1-based, e.g. 2/8); join with `merge`.
    #[arg(long)]
    pub shard: Option<String>,
    /// Method parameter, METHOD.KEY=VALUE (repeatable).
    #[arg(long = "set", value_name = "METHOD.KEY=VALUE")]
    pub set: Vec<String>,
    /// Keep the finished runs an earlier run of this comparison and shard left in --out, and
    /// run only the others: those not started or stopped by a signal (e.g. a time limit).
    #[arg(long = "resume-missing")]
    pub resume_missing: bool,
    #[command(flatten)]
    pub batch: BatchArgs,
    /// Also measure the void space of every packing: pores.csv, a "Void space" section in
    /// report.md and its figures (radical Voronoi local φ, D_i, D_f, pore sizes, chords).
    #[arg(long)]
    pub pores: bool,
}

impl CompareArgs {
    /// The comparison these flags describe, checked ([`CompareOptions::config`]); errors for
    /// unknown methods, a bad scene or `--set`.
    pub fn config(&self) -> Result<CompareConfig, BenchError> {
        CompareOptions {
            scene: self.scene.clone(),
            methods: self.methods.clone(),
            seeds: self.seeds,
            base_seed: self.base_seed,
            refine: self.refine.clone(),
            overrides: method_overrides(&self.set)?,
        }
        .config()
    }
}

/// `packbench compare`.
pub fn run(args: &CompareArgs) -> Result<Printed, BenchError> {
    let config = args.config()?;
    let shard = match &args.shard {
        Some(s) => parse_shard(s)?,
        None => (1, 1),
    };
    let kept = if args.resume_missing {
        crate::shards::resume_missing(&args.out, &config, shard)?
    } else {
        Vec::new()
    };
    crate::interrupt::install_interrupt_handler();
    let list: Vec<_> = run_list(&config)
        .into_iter()
        .filter(|(idx, _, _)| idx % shard.1 == shard.0 - 1)
        .filter(|(idx, _, _)| kept.iter().all(|(k, _)| k != idx))
        .collect();
    let progress = crate::progress::RunsProgress::new("compare", list.len(), args.batch.quiet);
    let jobs = args.batch.jobs()?;
    let results = run_comparison(
        &config,
        &list,
        Some(jobs),
        || QuietObserver,
        |r| progress.done(r),
    )?;
    progress.finish();
    let mut runs = Vec::new();
    for (idx, r) in &results {
        let mut rec = r.record.clone();
        rec.knob_value = None;
        if let Some(p) = &r.packing {
            save_packing(&args.out, &rec, p)?;
        }
        runs.push((*idx, rec));
    }
    let kept_count = kept.len();
    runs.extend(kept);
    runs.sort_by_key(|(i, _)| *i);
    let file = RunsFile {
        config,
        shard,
        runs: runs.into_iter().map(|(_, r)| r).collect(),
    };
    report::write_all(&args.out, &file)?;
    if args.pores {
        crate::pore_comparison::write_pore_comparison(&args.out, &file)?;
    }
    super::view::write_compare_page(&args.out)?;
    Ok(Printed {
        stdout: String::new(),
        stderr: vec![format!(
            "packbench compare: {} runs{}{}{} -> {}/ (runs.csv, runs.json, report.md, figures/{})",
            file.runs.len(),
            crate::shards::unfinished_note(&file.runs, "--resume-missing"),
            if args.resume_missing {
                format!(" ({kept_count} kept from the earlier run)")
            } else {
                String::new()
            },
            if shard.1 > 1 {
                format!(" (shard {}/{})", shard.0, shard.1)
            } else {
                String::new()
            },
            args.out.display(),
            if args.pores { ", pores.csv" } else { "" }
        )],
    })
}
