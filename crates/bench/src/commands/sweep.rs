//! `packbench sweep`: one method over its accuracy knob — the speed–accuracy curve.
//!
//! Values are listed from fast to accurate; the last one is the best-converged run of each
//! start and gives φ_ref, against which |φ_J − φ_ref| is measured.

use std::fmt::Write as _;
use std::path::PathBuf;

use clap::Args;
use packbench_core::Scene;
use packbench_core::format::write_atomic;
use packbench_core::init::initial_packing;
use rayon::prelude::*;
use serde_json::{Map, Value};

use super::Printed;
use crate::args::{BatchArgs, SceneArgs, default_compare_scene};
use crate::error::{BenchError, usage};
use crate::figures;
use crate::methods::run_params::parse_overrides;
use crate::methods::{self, ParamSources};
use crate::records::RunRecord;
use crate::refinement::{self, chain_label, refine};
use crate::report::{fmt_ms, runs_csv};
use crate::runs::run_one;

/// Flags of `packbench sweep`.
#[derive(Args, Debug)]
pub struct SweepArgs {
    /// The method.
    #[arg(long)]
    pub method: String,
    /// The parameter to vary (default: the method's accuracy knob).
    #[arg(long)]
    pub knob: Option<String>,
    /// Comma-separated values, from fast to accurate (the last is the reference).
    #[arg(
        long,
        value_delimiter = ',',
        required = true,
        allow_hyphen_values = true
    )]
    pub values: Vec<f64>,
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Number of starting packings.
    #[arg(long, default_value_t = 2)]
    pub seeds: u64,
    /// First seed.
    #[arg(long = "seed", default_value_t = 1)]
    pub base_seed: u64,
    /// Chain every result into this method and report its φ too (e.g. `--method ls --refine
    /// mls`: the LS packing of each rate and its MLS φ_J, Baranau & Tallarek 2014 Fig. 2a–b); `exact`: the
    /// fastest exact chain at the scene's N (calippso, after MLS above N = 12 000).
    #[arg(long)]
    pub refine: Option<String>,
    /// Other method parameters, KEY=VALUE (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Output folder.
    #[arg(long, default_value = "packbench-sweep")]
    pub out: PathBuf,
    #[command(flatten)]
    pub batch: BatchArgs,
}

/// Runs the sweep and writes `sweep.csv`, `sweep.md` and the figures.
pub fn run(args: &SweepArgs) -> Result<Printed, BenchError> {
    let method = methods::find(&args.method)?;
    let knob = args
        .knob
        .clone()
        .unwrap_or_else(|| method.accuracy_knob().to_string());
    let scene = args.scene.scene_or(default_compare_scene(), None)?;
    let base = parse_overrides(&args.set)?;
    // The knob's value comes after the other `--set` values.
    let params = |value: f64, seed: Option<u64>| {
        let mut set = base.clone();
        set.push((knob.clone(), Value::from(value)));
        ParamSources {
            set,
            seed,
            ..Default::default()
        }
        .resolve(method)
    };
    // Every value is checked before the first run starts: a refused value is bad input.
    for &value in &args.values {
        method.check(&params(value, None)?)?;
    }
    // Every start of a sweep has the scene's N, so one chain refines them all.
    let refined_by = args
        .refine
        .as_deref()
        .map(|r| refinement::legs(r, method.name(), scene.n).map(|l| chain_label(&l)))
        .transpose()?;
    crate::interrupt::install_interrupt_handler();
    let runs = run_all(args, method, &scene, &params)?;
    let points = sweep_points(&runs, args.values.last().copied());
    std::fs::create_dir_all(&args.out)
        .map_err(|e| BenchError::Run(format!("creating {}: {e}", args.out.display())))?;
    write_atomic(&args.out.join("sweep.csv"), runs_csv(&runs)?.as_bytes())?;
    let figs = figures::sweep(
        &args.out,
        method.name(),
        &knob,
        refined_by.as_deref(),
        &points,
    )?;
    let table = SweepTable {
        method: method.name(),
        knob: &knob,
        scene: &scene,
        seeds: args.seeds,
        values: &args.values,
        refined_by: refined_by.as_deref(),
    };
    let md = table.markdown(&runs, &points, &figs);
    write_atomic(&args.out.join("sweep.md"), md.as_bytes())?;
    Ok(Printed {
        stdout: md,
        stderr: vec![format!(
            "packbench sweep: {} runs -> {}/",
            runs.len(),
            args.out.display()
        )],
    })
}

/// Runs every (seed, value) of the sweep on `--jobs` threads, each refined by `--refine`
/// when asked, and returns their rows. Errors: a start that cannot be drawn, bad parameters.
fn run_all(
    args: &SweepArgs,
    method: &'static dyn methods::Method,
    scene: &Scene,
    params: &(dyn Fn(f64, Option<u64>) -> Result<Map<String, Value>, BenchError> + Sync),
) -> Result<Vec<RunRecord>, BenchError> {
    let list: Vec<(u64, f64)> = (0..args.seeds)
        .flat_map(|k| args.values.iter().map(move |&v| (args.base_seed + k, v)))
        .collect();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.batch.jobs()?)
        .build()
        .map_err(|e| BenchError::Run(format!("thread pool: {e}")))?;
    let progress = crate::progress::RunsProgress::new("sweep", list.len(), args.batch.quiet);
    let runs: Vec<RunRecord> = pool.install(|| {
        list.par_iter()
            .map(|&(seed, value)| {
                let start = initial_packing(scene, seed)?;
                let mut result = run_one(method, &params(value, Some(seed))?, &start, seed);
                if let Some(r) = &args.refine {
                    let sources = ParamSources {
                        seed: Some(seed),
                        ..Default::default()
                    };
                    let legs = refinement::legs_with_params(r, method.name(), start.n(), |m| {
                        sources.resolve(m)
                    })?;
                    refine(&mut result, &legs, seed);
                }
                let mut r = result.record;
                r.knob_value = Some(value);
                progress.done(&r);
                Ok(r)
            })
            .collect::<Result<Vec<_>, BenchError>>()
    })?;
    progress.finish();
    if runs.is_empty() {
        return Err(usage("nothing to sweep"));
    }
    Ok(runs)
}

/// The figures' points: one per run that made a packing, with |φ_J − φ_ref| against its
/// start's run at the `reference` value (the last, most accurate one).
fn sweep_points(runs: &[RunRecord], reference: Option<f64>) -> Vec<figures::SweepPoint> {
    let phi_ref = |seed: u64| {
        runs.iter()
            .find(|r| r.seed == seed && r.knob_value == reference)
            .and_then(|r| r.phi)
    };
    runs.iter()
        .filter_map(|r| {
            Some(figures::SweepPoint {
                value: r.knob_value?,
                runtime_s: r.runtime_s,
                phi: r.phi?,
                error: (r.phi? - phi_ref(r.seed)?).abs(),
                iso_gap: r.iso_gap.map(|g| g as f64),
                refined_phi: r.refined_phi,
            })
        })
        .collect()
}

/// What `sweep.md` describes: the method, its knob and values, the scene and the refinement.
struct SweepTable<'a> {
    method: &'a str,
    knob: &'a str,
    scene: &'a Scene,
    seeds: u64,
    values: &'a [f64],
    refined_by: Option<&'a str>,
}

impl SweepTable<'_> {
    /// `sweep.md`: the scene, one row per knob value (mean ± std over starts; "—" where a
    /// quantity is undefined for every run, with a note), and the figures.
    fn markdown(
        &self,
        runs: &[RunRecord],
        points: &[figures::SweepPoint],
        figs: &[(String, String)],
    ) -> String {
        let (knob, scene) = (self.knob, self.scene);
        let mut md = String::new();
        let _ = writeln!(md, "# packbench sweep: {} over `{knob}`\n", self.method);
        let _ = writeln!(
            md,
            "Scene: d = {}, N = {}, {}, {}; {} starting packings. φ_ref of each start is its run at `{knob}` = {}.\n",
            scene.dim(),
            scene.n,
            scene.distribution.name(),
            scene.container.describe(),
            self.seeds,
            self.values.last().copied().unwrap_or(f64::NAN)
        );
        let refined_col = self.refined_by.map(|c| format!(" φ after {c} |"));
        let _ = writeln!(
            md,
            "| {knob} | φ_J | \\|φ_J − φ_ref\\| | iso_gap | runtime (s) | failed |{}",
            refined_col.as_deref().unwrap_or_default()
        );
        let _ = writeln!(
            md,
            "|---|---|---|---|---|---|{}",
            if self.refined_by.is_some() {
                "---|"
            } else {
                ""
            }
        );
        for &v in self.values {
            let _ = writeln!(md, "{}", self.row(v, runs, points));
        }
        if points.iter().any(|p| p.iso_gap.is_none()) {
            let _ = writeln!(
                md,
                "\niso_gap is undefined (—, and empty in sweep.csv) for a packing whose every particle is a rattler: it has no contact network. Such runs are left out of the iso_gap column."
            );
        }
        for (path, caption) in figs {
            let _ = writeln!(md, "\n![{caption}]({path})\n\n*{caption}*");
        }
        md
    }

    /// The table row of knob value `v`.
    fn row(&self, v: f64, runs: &[RunRecord], points: &[figures::SweepPoint]) -> String {
        let pts: Vec<&figures::SweepPoint> = points.iter().filter(|p| p.value == v).collect();
        let f = |g: &dyn Fn(&figures::SweepPoint) -> Option<f64>, digits: usize| {
            fmt_ms(&pts.iter().filter_map(|p| g(p)).collect::<Vec<_>>(), digits)
        };
        let failed = runs
            .iter()
            .filter(|r| r.knob_value == Some(v) && !r.made_packing())
            .count();
        let refined = match self.refined_by {
            Some(_) => format!(" {} |", f(&|p| p.refined_phi, 5)),
            None => String::new(),
        };
        format!(
            "| {v:e} | {} | {} | {} | {} | {failed} |{refined}",
            f(&|p| Some(p.phi), 5),
            f(&|p| Some(p.error), 6),
            f(&|p| p.iso_gap, 1),
            f(&|p| Some(p.runtime_s), 3)
        )
    }
}
