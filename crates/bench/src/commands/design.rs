//! `packbench design`: searches a family of size distributions for the one that maximises or
//! reaches a φ_J, screened by `predict`'s relations and scored by packing; every evaluation a
//! row of `evaluations.csv` written as it finishes, `--resume` to continue a stopped search,
//! `--shard i/n` for independent islands that `merge` joins.

use std::path::{Path, PathBuf};

use clap::Args;
use packbench_core::run::Observer;

use super::Printed;
use crate::args::{BatchArgs, SceneArgs};
use crate::design::family::{Draw, FAMILY_NAMES, Family, Fractions, Shape, short};
use crate::design::history::{
    self, DESIGN_JSON, DesignFile, DesignRow, RowWriter, read_design_file, read_rows,
    write_design_file,
};
use crate::design::objective::{Constraints, Objective};
use crate::design::optimizer::Optimizer;
use crate::design::screen::Screen;
use crate::design::{DesignConfig, best_distribution, design_island, island_budget, report};
use crate::error::{BenchError, usage};
use crate::records::parse_shard;
use crate::runs::QuietObserver;
use crate::shards::is_finished;

/// Flags of `packbench design`.
#[derive(Args, Debug)]
#[command(
    after_help = "Families and their parameters (every size in units of the smallest \
diameter or of the scale):\n  lognormal  sigma (log-std of D; default 0:0.4)\n  powerlaw   ratio \
(d_max/d_min; 1:10), exponent (density ∝ D^exponent; -4:0)\n  bidisperse ratio (d2/d1; 1:2), p \
(number fraction of d1; 0:1)\n  weibull    shape (2:20)\n  gamma      shape (4:100)\n  mixture    \
w<i> (weight; 0:1), c<i> (centre of a Gaussian in ln D, 0 = ln 1, 1 = ln max-ratio; 0:1), s<i> \
(its width in units of ln max-ratio; 0.01:0.3), for i = 1..components, on the support [1, \
max-ratio]\n  discrete   d<i> (diameter of component i ≥ 2, d1 = 1; 1:max-ratio), x<i> (share \
of component i in what components 1..i-1 leave, i < components; 0:1): discrete sizes with \
volume (or --fractions number) fractions, as rcptools' delta components\nObjectives: max-phi; \
target (--target φ_J: closest φ_J); min-ratio and min-polydispersity (smallest D_max/D_min or \
std/mean with φ_J ≥ --target). φ_J is exact (the jamming point itself) with --refine \
calippso.\nConstraints: --max-rattlers F (mean rattler fraction of the packings ≤ F)."
)]
pub struct DesignArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// The family searched: lognormal, powerlaw, bidisperse, weibull, gamma, mixture or
    /// discrete.
    #[arg(long)]
    pub family: String,
    /// Bounds of a parameter, NAME=LO:HI, or NAME=VALUE to fix it (repeatable).
    #[arg(long = "param", value_name = "NAME=LO:HI")]
    pub params: Vec<String>,
    /// Components of a mixture or discrete mixture.
    #[arg(long, default_value_t = 2)]
    pub components: usize,
    /// What a discrete mixture's shares count: volume or number.
    #[arg(long, default_value = "volume")]
    pub fractions: String,
    /// How a packing's N diameters are drawn: quantile (the N mid-point quantiles, the same
    /// for every seed, as rcptools draws them) or random (N independent draws with the
    /// packing's seed). A discrete mixture's are the same either way.
    #[arg(long, default_value = "quantile")]
    pub draw: String,
    /// Largest D_max/D_min: the support of a mixture, a bound on the other families' packed
    /// diameters (candidates above it are not packed).
    #[arg(long = "max-ratio")]
    pub max_ratio: Option<f64>,
    /// max-phi, target, min-ratio or min-polydispersity.
    #[arg(long, default_value = "max-phi")]
    pub objective: String,
    /// The φ_J of `target`, `min-ratio` and `min-polydispersity`.
    #[arg(long)]
    pub target: Option<f64>,
    /// Largest mean fraction of rattlers in a candidate's packings: candidates above it rank
    /// behind every candidate within it.
    #[arg(long = "max-rattlers", value_name = "FRACTION")]
    pub max_rattlers: Option<f64>,
    /// N of the search's packings, below --N: search at this cheaper fidelity and confirm the
    /// best at --N.
    #[arg(long = "search-N", value_name = "N")]
    pub search_n: Option<usize>,
    /// The method that packs candidates.
    #[arg(long, default_value = "adam")]
    pub method: String,
    /// Chain every packing into this exact-jamming method (or `exact`, the fastest exact chain
    /// at the scene's N, as in `compare`); φ_J is then the refined φ.
    #[arg(long)]
    pub refine: Option<String>,
    /// Method parameter, METHOD.KEY=VALUE (repeatable).
    #[arg(long = "set", value_name = "METHOD.KEY=VALUE")]
    pub set: Vec<String>,
    /// Packings of each candidate (the same seeds for every candidate).
    #[arg(long = "seeds-per-candidate", default_value_t = 2)]
    pub seeds_per_candidate: u64,
    /// First packing seed, and the seed of the optimiser.
    #[arg(long = "seed", default_value_t = 1)]
    pub base_seed: u64,
    /// Packings the search may use (confirmations not counted), over all shards.
    #[arg(long, default_value_t = 60)]
    pub budget: usize,
    /// Candidates per generation: CMA-ES's population, EGO's batch (default 4 + ⌊3 ln(free
    /// parameters)⌋).
    #[arg(long)]
    pub population: Option<usize>,
    /// The optimiser: cmaes (CMA-ES with IPOP restarts); bracket (bisection with a local line
    /// fit on φ_J − target, for one free parameter and an objective with a target); ego (a
    /// Kriging surrogate with expected improvement, in builds with the `ego` cargo feature;
    /// docs/BENCHMARKS.md, Design, compares them); or auto: bracket where it applies, cmaes
    /// otherwise.
    #[arg(long, default_value = "auto")]
    pub optimizer: String,
    /// Predictor that skips hopeless candidates: dw (Desmond–Weeks), fg (Farr–Groot), none, or
    /// auto (fg for mixture and powerlaw, whose broad distributions leave Desmond–Weeks' range,
    /// dw otherwise; docs/BENCHMARKS.md, Design).
    #[arg(long, default_value = "auto")]
    pub screen: String,
    /// Margin in φ the screen leaves (added to twice its calibration's residual spread).
    #[arg(long = "screen-margin", default_value_t = 0.01)]
    pub screen_margin: f64,
    /// Confirmation reruns of the best candidate with fresh seeds.
    #[arg(long, default_value_t = 5)]
    pub confirm: u64,
    /// Output folder.
    #[arg(long, default_value = "design-out")]
    pub out: PathBuf,
    /// Run island i of n: an independent search with its own optimiser seed and 1/n of the budget;
    /// join the islands' folders with `merge`.
    #[arg(long)]
    pub shard: Option<String>,
    /// Continue the search an earlier run left in --out: finished rows are kept, the rest run.
    #[arg(long)]
    pub resume: bool,
    #[command(flatten)]
    pub batch: BatchArgs,
}

/// The default scene of a design: 3D, N = 1000, periodic unit box, initial φ = 0.05.
fn default_design_scene() -> packbench_core::Scene {
    crate::args::default_scene()
}

impl DesignArgs {
    /// The search these flags describe; every check that needs no packing.
    ///
    /// Errors: usage errors for an unknown family, parameter, objective, optimiser (or `ego` in
    /// a build without its feature), screen or method, bad
    /// bounds, an empty family, an impossible target, a budget too small for one generation,
    /// and flags that make no sense here (`--dist`).
    pub fn config(&self) -> Result<DesignConfig, BenchError> {
        // Any distribution flag (--dist, --sigma, …) would be silently replaced by the family's.
        let no_distribution = format!("{:?}", crate::args::DistributionArgs::default());
        if format!("{:?}", self.scene.distribution) != no_distribution {
            return Err(usage(
                "design searches the family given by --family and its --param bounds; drop \
                 --dist and the distribution's flags (--sigma, --d1, …)",
            ));
        }
        let scene = self.scene.scene_or(default_design_scene(), None)?;
        let shape = Shape {
            components: self.components,
            max_ratio: self.max_ratio,
            dim: scene.dim(),
            fractions: Fractions::parse(&self.fractions)?,
            draw: Draw::parse(&self.draw)?,
        };
        let mut family = Family::with_defaults(&self.family, &shape).map_err(|e| match e {
            BenchError::Usage(m) if m.starts_with("unknown family") => usage(format!(
                "unknown family `{}`; use {FAMILY_NAMES}",
                self.family
            )),
            e => e,
        })?;
        for p in &self.params {
            let (name, spec) = p
                .split_once('=')
                .ok_or_else(|| usage(format!("--param `{p}` must be NAME=LO:HI or NAME=VALUE")))?;
            family.set_bounds(name.trim(), spec)?;
        }
        family.validate()?;
        let objective = Objective::parse(&self.objective, self.target)?;
        let optimizer = Optimizer::for_search(
            &self.optimizer,
            family.free().len(),
            objective.target().is_some(),
        )?;
        let screen = Screen::for_family(&self.screen, &family)?;
        let overrides = crate::methods::run_params::method_overrides(&self.set)?;
        let max_ratio = family.ratio_constraint(self.max_ratio);
        let config = DesignConfig {
            family,
            objective,
            constraints: Constraints::new(self.max_rattlers)?,
            search_n: self.search_n,
            max_ratio,
            scene,
            method: self.method.clone(),
            refine: self.refine.clone(),
            overrides,
            seeds_per_candidate: self.seeds_per_candidate,
            base_seed: self.base_seed,
            budget: self.budget,
            population: self.population,
            optimizer,
            screen,
            screen_margin: self.screen_margin,
            confirm: self.confirm,
        };
        config.check(self.shard()?.1)?;
        Ok(config)
    }

    fn shard(&self) -> Result<(usize, usize), BenchError> {
        match &self.shard {
            Some(s) => parse_shard(s),
            None => Ok((1, 1)),
        }
    }
}

/// The finished rows an earlier run of the same search and shard left in `out`.
///
/// Errors: a usage error when `out` holds another search or shard, or unreadable rows.
fn resumed_rows(
    out: &Path,
    config: &DesignConfig,
    shard: (usize, usize),
) -> Result<Vec<DesignRow>, BenchError> {
    if !out.join(DESIGN_JSON).exists() {
        return Ok(Vec::new());
    }
    let earlier = read_design_file(out)?;
    if earlier.config != *config || earlier.shard != shard {
        return Err(usage(format!(
            "{} holds another design search or shard; --resume continues only the same one \
             (same family, bounds, objective, optimizer, scene, method, seeds, budget and --shard)",
            out.display()
        )));
    }
    Ok(read_rows(out, &config.family)?
        .into_iter()
        .filter(|r| is_finished(&r.record))
        .collect())
}

/// `packbench design`.
pub fn run(args: &DesignArgs) -> Result<Printed, BenchError> {
    let config = args.config()?;
    let shard = args.shard()?;
    if !args.resume && args.out.join(DESIGN_JSON).exists() {
        return Err(usage(format!(
            "{} already holds a design search: give --resume to continue it, or another --out",
            args.out.display()
        )));
    }
    let kept = if args.resume {
        resumed_rows(&args.out, &config, shard)?
    } else {
        Vec::new()
    };
    let jobs = args.batch.jobs()?;
    std::fs::create_dir_all(&args.out)
        .map_err(|e| BenchError::Run(format!("creating {}: {e}", args.out.display())))?;
    write_design_file(
        &args.out,
        &DesignFile {
            config: config.clone(),
            shard,
        },
    )?;
    let writer = RowWriter::start(&args.out, &config.family, &kept)?;
    crate::interrupt::install_interrupt_handler();
    let total = island_budget(&config, shard.1) + config.confirm as usize;
    let progress = crate::progress::RunsProgress::new("design", total, args.batch.quiet);
    let kept_count = kept.len();
    let outcome = design_island(
        &config,
        shard,
        kept,
        Some(jobs),
        || Box::new(QuietObserver) as Box<dyn Observer>,
        |row| {
            if row.screened.is_empty() {
                progress.done(&row.record);
            }
            writer.append(row)
        },
    )?;
    progress.finish();
    packbench_core::format::write_atomic(
        &args.out.join(history::EVALUATIONS),
        &history::csv_text(&config.family, &outcome.rows)?,
    )?;
    report::write_outputs(
        &args.out,
        &config,
        &outcome.rows,
        outcome.best.as_ref(),
        &outcome.stop,
    )?;
    let t = report::totals(&outcome.rows);
    let mut stderr = vec![format!(
        "packbench design: {} generations, {} candidates ({} screened out, {} invalid), {} \
         packings + {} confirmations{}{}, {:.1} s of packing; {} -> {}/ (evaluations.csv, \
         best.json, report.md, figures/)",
        outcome.generations,
        t.candidates,
        t.screened,
        t.invalid,
        t.packings,
        t.confirmations,
        if kept_count > 0 {
            format!(" ({kept_count} rows kept from the earlier run)")
        } else {
            String::new()
        },
        if shard.1 > 1 {
            format!(" (island {}/{})", shard.0, shard.1)
        } else {
            String::new()
        },
        t.packing_s,
        outcome.stop,
        args.out.display()
    )];
    if let Some(b) = &outcome.best {
        stderr.push(format!(
            "packbench design: best {}: φ_J {}{}",
            config.family.describe(&b.values),
            short(b.search_phi),
            match (b.confirm_mean, b.confirm_std) {
                (Some(m), Some(s)) => format!(
                    " (search), {m:.5} ± {s:.5} over {} fresh seeds",
                    b.confirm_phi.len()
                ),
                _ => String::new(),
            }
        ));
    }
    Ok(Printed {
        stdout: String::new(),
        stderr,
    })
}

/// `packbench merge` of design folders: joins the islands of one search (`--shard i/n` for
/// every i) into one folder with every row and the best confirmed candidate over the islands.
///
/// Errors: usage errors for folders of different searches, an island missing or held twice
/// with different rows; run errors for outputs that cannot be written.
pub fn merge(dirs: &[PathBuf], out: &Path) -> Result<Printed, BenchError> {
    let files = dirs
        .iter()
        .map(|d| Ok((d.as_path(), read_design_file(d)?)))
        .collect::<Result<Vec<_>, BenchError>>()?;
    let config = files[0].1.config.clone();
    let n = files[0].1.shard.1;
    let mut islands = std::collections::BTreeMap::new();
    for (d, f) in &files {
        if f.config != config || f.shard.1 != n {
            return Err(usage(format!(
                "{} and {} come from different design searches (family, objective, scene, \
                 method, seeds, budget or shard count differ)",
                files[0].0.display(),
                d.display()
            )));
        }
        let rows = read_rows(d, &config.family)?;
        if let Some(prev) = islands.insert(f.shard.0, (d, rows.clone()))
            && prev.1 != rows
        {
            return Err(usage(format!(
                "{} and {} both hold island {} with different rows",
                prev.0.display(),
                d.display(),
                f.shard.0
            )));
        }
    }
    if let Some(i) = (1..=n).find(|i| !islands.contains_key(i)) {
        return Err(usage(format!(
            "no folder holds island {i}/{n}: every island of the search is needed"
        )));
    }
    let rows: Vec<DesignRow> = islands.into_values().flat_map(|(_, r)| r).collect();
    std::fs::create_dir_all(out)
        .map_err(|e| BenchError::Run(format!("creating {}: {e}", out.display())))?;
    write_design_file(
        out,
        &DesignFile {
            config: config.clone(),
            shard: (0, n),
        },
    )?;
    packbench_core::format::write_atomic(
        &out.join(history::EVALUATIONS),
        &history::csv_text(&config.family, &rows)?,
    )?;
    let best = best_distribution(&config, &rows)?;
    report::write_outputs(
        out,
        &config,
        &rows,
        best.as_ref(),
        &format!("{n} islands merged"),
    )?;
    Ok(Printed {
        stdout: String::new(),
        stderr: vec![format!(
            "packbench merge: {} design rows from {n} islands -> {}/",
            rows.len(),
            out.display()
        )],
    })
}
