//! `packbench compare` and `packbench merge`: several methods on the same starting packings,
//! split into shards when one machine is not enough.

use std::path::{Path, PathBuf};

use clap::Args;
use packbench_core::{Packing, Scene};
use serde::{Deserialize, Serialize};

use crate::args::SceneArgs;
use crate::commands::Printed;
use crate::comparison_runs::run_comparison;
use crate::error::{BenchError, usage};
use crate::methods::{self, parse_override};
use crate::report;
use crate::runs::{QuietObserver, RunRecord};

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
    /// Chain every result into this exact-jamming method and report Δφ = φ_refined − φ.
    #[arg(long)]
    pub refine: Option<String>,
    /// Output folder.
    #[arg(long, default_value = "packbench-out")]
    pub out: PathBuf,
    /// Runs at once (default: all cores).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Run only the i-th of n slices of the runs (1-based, e.g. 2/8); join with `merge`.
    #[arg(long)]
    pub shard: Option<String>,
    /// Method parameter, METHOD.KEY=VALUE (repeatable).
    #[arg(long = "set", value_name = "METHOD.KEY=VALUE")]
    pub set: Vec<String>,
    /// No progress bar (nor the per-run log lines written when stderr is not a terminal).
    #[arg(long)]
    pub quiet: bool,
}

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

impl CompareArgs {
    /// The comparison these flags describe; errors for unknown methods, a bad scene or `--set`.
    pub fn config(&self) -> Result<CompareConfig, BenchError> {
        let scene = self.scene.scene_or(default_compare_scene(), None)?;
        let methods = match &self.methods {
            Some(m) => m.clone(),
            None => methods::registry()
                .iter()
                .map(|m| m.name().to_string())
                .collect(),
        };
        for m in &methods {
            methods::find(m)?;
        }
        if let Some(r) = &self.refine {
            methods::find(r)?;
        }
        let mut overrides = Vec::new();
        for s in &self.set {
            let (key, value) = parse_override(s)?;
            let (m, k) = key.split_once('.').ok_or_else(|| {
                usage(format!(
                    "--set `{s}` must name its method: METHOD.KEY=VALUE"
                ))
            })?;
            overrides.push((m.to_string(), k.to_string(), value));
        }
        if self.seeds == 0 {
            return Err(usage("--seeds must be at least 1"));
        }
        Ok(CompareConfig {
            scene,
            methods,
            seeds: self.seeds,
            base_seed: self.base_seed,
            refine: self.refine.clone(),
            overrides,
        })
    }
}

/// The default comparison: 2D bidisperse disks (diameters 1 and 1.4, equal numbers, the
/// classic glass-former), N = 40 in a periodic box, so that every method — including the slow
/// exact ones — finishes in about a minute on 2 cores, and the packings can be drawn to scale.
pub fn default_compare_scene() -> Scene {
    let mut s = crate::args::default_scene();
    s.n = 40;
    s.distribution = packbench_core::SizeDistribution::Bidisperse {
        d1: 1.0,
        d2: 1.4,
        p: 0.5,
    };
    s.container = packbench_core::Container::periodic_box(&[1.0, 1.0]).expect("valid box");
    s
}

/// `packbench compare`.
pub fn run(args: &CompareArgs) -> Result<Printed, BenchError> {
    let config = args.config()?;
    let shard = match &args.shard {
        Some(s) => parse_shard(s)?,
        None => (1, 1),
    };
    crate::progress::install_interrupt_handler();
    let list: Vec<_> = run_list(&config)
        .into_iter()
        .filter(|(idx, _, _)| idx % shard.1 == shard.0 - 1)
        .collect();
    let progress = crate::progress::RunsProgress::new("compare", list.len(), args.quiet);
    let results = run_comparison(
        &config,
        &list,
        args.jobs,
        || QuietObserver,
        |r| progress.done(r),
    )?;
    progress.finish();
    let packings_dir = args.out.join("packings");
    let mut runs = Vec::new();
    for (idx, r) in &results {
        let mut rec = r.record.clone();
        rec.knob_value = None;
        if let Some(p) = &r.packing {
            save_packing(&packings_dir, &rec, p)?;
        }
        runs.push((*idx, rec));
    }
    runs.sort_by_key(|(i, _)| *i);
    let file = RunsFile {
        config,
        shard,
        runs: runs.into_iter().map(|(_, r)| r).collect(),
    };
    report::write_all(&args.out, &file)?;
    Ok(Printed {
        stdout: String::new(),
        stderr: vec![format!(
            "packbench compare: {} runs{} -> {}/ (runs.csv, runs.json, report.md, figures/)",
            file.runs.len(),
            if shard.1 > 1 {
                format!(" (shard {}/{})", shard.0, shard.1)
            } else {
                String::new()
            },
            args.out.display()
        )],
    })
}

fn save_packing(dir: &Path, rec: &RunRecord, p: &Packing) -> Result<(), BenchError> {
    let path = dir.join(format!("{}_seed{}.txt", rec.method, rec.seed));
    packbench_core::format::write_atomic(&path, packbench_core::format::write_text(p).as_bytes())?;
    let json = serde_json::to_string(&p.container).map_err(|e| BenchError::Run(e.to_string()))?;
    packbench_core::format::write_atomic(&path.with_extension("container.json"), json.as_bytes())?;
    Ok(())
}

/// Reads a packing saved by a comparison.
pub fn load_packing(dir: &Path, method: &str, seed: u64) -> Option<Packing> {
    let path = dir
        .join("packings")
        .join(format!("{method}_seed{seed}.txt"));
    let text = std::fs::read_to_string(&path).ok()?;
    let container =
        serde_json::from_str(&std::fs::read_to_string(path.with_extension("container.json")).ok()?)
            .ok()?;
    packbench_core::format::read_packing(&path.display().to_string(), &text, &container).ok()
}

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
pub fn merge(args: &MergeArgs) -> Result<Printed, BenchError> {
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
                save_packing(&args.out.join("packings"), r, &p)?;
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
