//! `packbench pack`: one method on one starting packing; writes the packing and its sidecar.

use std::path::{Path, PathBuf};

use clap::Args;
use packbench_core::Packing;
use packbench_core::analysis::{AnalysisOptions, Metrics};
use packbench_core::format::{Sidecar, write_text};
use packbench_core::init::time_seed;
use serde_json::{Map, Value};

use super::Printed;
use crate::args::SceneArgs;
use crate::error::{BenchError, usage};
use crate::figures::radius_histogram;
use crate::interrupt::install_interrupt_handler;
use crate::methods::run_params::parse_overrides;
use crate::methods::{self, Method, ParamSources, Product, StopProgress, flags};
use crate::outputs::{output_path, start_packing, write_packing};
use crate::progress::TerminalObserver;
use crate::records::BUDGET_WITH_OVERLAPS;
use crate::runs::{OVERLAP_AT_BUDGET, PackRun, RunFrom, pack_run};

/// Flags of `packbench pack`.
#[derive(Args, Debug)]
pub struct PackArgs {
    /// The method (see `packbench methods`).
    #[arg(long)]
    pub method: String,
    /// Starting packing in plain text (`-` for standard input). Without it the start is built
    /// from the scene flags (`--scene` or the `init` flags), as `packbench init` would.
    #[arg(long, conflicts_with = "resume")]
    pub file: Option<String>,
    /// Continue a stopped run exactly (bit for bit) from the checkpoint it left,
    /// NAME.checkpoint.json (which methods write one, and when: their notes below). The run's
    /// own parameters are used; flags given now override them (e.g. a larger --max-steps).
    #[arg(long, value_name = "CHECKPOINT")]
    pub resume: Option<String>,
    #[command(flatten)]
    pub scene: SceneArgs,
    /// The method options given (`--rate 0.1` → `("rate", "0.1")`): each method declares its
    /// own (`methods::flags`), and `main` adds them to this command and fills this in.
    #[arg(skip)]
    pub method_flags: Vec<(String, String)>,
    /// Seed of every random choice (default: time-based, printed to stderr).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Output name: writes NAME.txt and NAME.json (default: the packing goes to standard output).
    #[arg(long)]
    pub output: Option<String>,
    /// Step budget of the method (its own unit: steps, iterations, collisions per particle…).
    #[arg(long = "max-steps", alias = "MaxSteps")]
    pub max_steps: Option<u64>,
    /// Save a snapshot every K steps as NAME_step<K>.txt (0 = off).
    #[arg(long = "save-interval", default_value_t = 0)]
    pub save_interval: u64,
    /// Print a progress line every 2 s as well as the bar (to stderr also when it is not a
    /// terminal, e.g. a batch job's log).
    #[arg(long)]
    pub verbose: bool,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Set a method parameter, KEY=VALUE (repeatable; `packbench methods` lists them); the method's
    /// own flags, --max-steps, --save-interval and --seed override a --set of the same key.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Largest relative gap counted as a contact in the analysis of the result.
    #[arg(long = "contact-tol", default_value_t = 1e-6)]
    pub contact_tol: f64,
    /// Skip the force-balance residual in the analysis (about 3 s at N = 10⁴ and 25 s at
    /// N = 10⁵ in 3D; `packbench analyze` can compute it later).
    #[arg(long = "no-force-balance")]
    pub no_force_balance: bool,
}

/// The sources of the run's parameters ([`ParamSources`]): the scene flags, `--set`, the
/// method flags, `--max-steps`, `--save-interval` and `seed`.
fn param_sources<'a>(
    method: &dyn Method,
    args: &'a PackArgs,
    seed: Option<u64>,
) -> Result<ParamSources<'a>, BenchError> {
    Ok(ParamSources {
        scene: Some(&args.scene),
        set: parse_overrides(&args.set)?,
        options: flags::overrides(method, &args.method_flags)?,
        max_steps: args.max_steps,
        save_interval: (args.save_interval > 0).then_some(args.save_interval),
        seed,
    })
}

/// What `pack` runs: a method from a start, or the continuation of a run from its checkpoint.
enum Job {
    Start(Packing),
    Resume(Value),
}

/// A run resolved from the flags, before it starts: the job, the scene the start was drawn
/// from (none for a file or a checkpoint), the complete parameters and the seed.
struct Resolved {
    job: Job,
    scene: Option<packbench_core::Scene>,
    params: Map<String, Value>,
    /// The seed of the run's random choices; `None` when nothing is random (a deterministic
    /// method from a file) and no --seed was given.
    seed: Option<u64>,
}

/// Resolves the flags into a run, checked by [`Method::check`] as `compare` and `sweep` check
/// theirs; a time-based seed is drawn, and named on stderr, only when something is random:
/// the start is drawn from the scene or the method draws numbers of its own.
fn resolve(
    method: &dyn Method,
    args: &PackArgs,
    printed: &mut Printed,
) -> Result<Resolved, BenchError> {
    let resolved = match &args.resume {
        None => {
            let random = args.file.is_none() || method.seed_key().is_some();
            let seed = args.seed.or_else(|| {
                random.then(|| {
                    let s = time_seed();
                    printed
                        .stderr
                        .push(format!("packbench pack: no --seed given, using --seed {s}"));
                    s
                })
            });
            let params = param_sources(method, args, seed)?.resolve(method)?;
            // A file start draws nothing, so its seed is only the method's.
            let (start, scene) =
                start_packing(args.file.as_deref(), &args.scene, seed.unwrap_or(0))?;
            Resolved {
                job: Job::Start(start),
                scene,
                params,
                seed,
            }
        }
        Some(file) => {
            // The run's own parameters (its seed too), with only the flags given now on top.
            let sources = param_sources(method, args, args.seed)?;
            let checkpoint = read_checkpoint(file)?;
            let base = match checkpoint.get("params") {
                Some(Value::Object(p)) => p.clone(),
                _ => {
                    return Err(usage(format!(
                        "{file} holds no run parameters: it is not a checkpoint written by `pack`"
                    )));
                }
            };
            let params = sources.resolve_over(method, base)?;
            let seed = method
                .seed_key()
                .and_then(|k| params.get(k))
                .and_then(Value::as_u64)
                .or(args.seed);
            Resolved {
                job: Job::Resume(checkpoint),
                scene: None,
                params,
                seed,
            }
        }
    };
    method.check(&resolved.params)?;
    Ok(resolved)
}

/// The progress display of the run: a bar, `--verbose` lines, snapshots and checkpoints
/// beside the output.
fn observer_for(
    method: &dyn Method,
    params: &Map<String, Value>,
    args: &PackArgs,
    out_name: Option<&Path>,
) -> TerminalObserver {
    let snapshots = match (out_name, args.save_interval) {
        (Some(path), k) if k > 0 => Some(snapshot_sink(path.to_path_buf())),
        _ => None,
    };
    let stop = StopProgress::new(method, params);
    let observer = TerminalObserver::new(method.name(), stop, args.quiet, args.verbose, snapshots);
    match out_name {
        Some(path) => observer.with_checkpoints(checkpoint_path(path)),
        None => observer,
    }
}

/// Runs the method and writes its outputs.
pub fn run(args: &PackArgs) -> Result<Printed, BenchError> {
    let mut printed = Printed::default();
    let method = methods::find(&flags::method_name(&args.method, &args.method_flags)?)?;
    let Resolved {
        job,
        scene,
        params,
        seed,
    } = resolve(method, args, &mut printed)?;
    install_interrupt_handler();
    let out_name = args.output.as_deref().map(output_path).transpose()?;
    let mut observer = observer_for(method, &params, args, out_name.as_deref());
    let from = match &job {
        Job::Start(start) => RunFrom::Start(start),
        Job::Resume(checkpoint) => RunFrom::Checkpoint(checkpoint),
    };
    let analysis = AnalysisOptions {
        contact_tol: args.contact_tol,
        force_balance: !args.no_force_balance,
    };
    let result = pack_run(
        method,
        from,
        &params,
        &mut observer,
        out_name.is_some(),
        &analysis,
    );
    observer.finish();
    let PackRun {
        outcome,
        products,
        metrics,
        runtime_s,
        overruled,
    } = result?;
    let sidecar = Sidecar {
        packbench_version: env!("CARGO_PKG_VERSION").to_string(),
        method: method.name().to_string(),
        scene,
        seed,
        parameters: Value::Object(params),
        metrics: Some(metrics.clone()),
        container: outcome.packing.container.clone(),
        runtime_s,
        steps: outcome.steps,
        termination: outcome.termination.clone(),
        extra: outcome.extra.clone(),
        trace: outcome.trace.clone(),
    };
    let summary = summary_line(method.name(), &metrics, &sidecar);
    if let Some(why) = failure(&outcome.termination, &metrics, overruled) {
        if let Some(path) = &out_name {
            write_packing(path, &outcome.packing, &sidecar)?;
        }
        let kept = out_name.as_ref().map_or(String::new(), |p| {
            format!(" (written to {} for inspection)", p.display())
        });
        return Err(BenchError::Run(format!("{summary}: {why}{kept}")));
    }
    match out_name {
        Some(path) => {
            write_packing(&path, &outcome.packing, &sidecar)?;
            printed
                .stderr
                .push(format!("{summary} -> {} (+ .json)", path.display()));
            for p in write_products(&path, products)? {
                printed.stderr.push(format!("  also wrote {}", p.display()));
            }
            let stopped = matches!(outcome.termination.as_str(), "interrupted" | "max_steps");
            if stopped && observer.wrote_checkpoint {
                let c = checkpoint_path(&path);
                printed.stderr.push(format!(
                    "  checkpoint {} (continue with: packbench pack --method {} --resume {} --output NAME)",
                    c.display(),
                    method.name(),
                    c.display()
                ));
            }
        }
        None => {
            printed.stdout = write_text(&outcome.packing);
            printed.stderr.push(summary);
        }
    }
    Ok(printed)
}

/// The one line `pack` prints about a run; an undefined z' and iso_gap (no non-rattlers)
/// print as "—".
fn summary_line(method: &str, metrics: &Metrics, sidecar: &Sidecar) -> String {
    let dash = |v: Option<String>| v.unwrap_or_else(|| "— (no non-rattlers)".into());
    format!(
        "packbench pack --method {method}: phi = {:.6}, z' = {}, rattlers = {}, iso_gap = {}, max_overlap = {:.2e}, {} steps, {:.2} s, {}",
        metrics.phi,
        dash(metrics.defined_z_nonrattler().map(|z| format!("{z:.3}"))),
        metrics.rattlers,
        dash(metrics.defined_iso_gap().map(|g| g.to_string())),
        metrics.max_overlap,
        sidecar.steps,
        sidecar.runtime_s,
        sidecar.termination
    )
}

/// Why the run made no packing, when it made none: its step budget ran out with overlaps, or
/// the analysis overruled its claim of a jammed packing (`overruled`). Either way the packing
/// is written for inspection and `pack` exits 1.
fn failure(termination: &str, metrics: &Metrics, overruled: Option<String>) -> Option<String> {
    if termination == BUDGET_WITH_OVERLAPS {
        return Some(format!(
            "the run used its whole step budget and its particles still overlap by up to {:.1e} (more than {OVERLAP_AT_BUDGET:.0e}), so it made no packing; raise --max-steps",
            metrics.max_overlap
        ));
    }
    overruled
}

/// Writes a method's products beside its packing `path` (NAME.txt → NAME<suffix>); returns
/// their paths.
fn write_products(path: &Path, products: Vec<Product>) -> Result<Vec<PathBuf>, BenchError> {
    let beside =
        |suffix: &str| PathBuf::from(format!("{}{suffix}", path.with_extension("").display()));
    let mut written = Vec::new();
    for product in products {
        match product {
            Product::Table { suffix, csv } => {
                let file = beside(suffix);
                packbench_core::format::write_atomic(&file, &csv)?;
                written.push(file);
            }
            Product::RadiusHistogram {
                placed,
                discarded,
                target,
            } => {
                let file = beside("_radii.png");
                radius_histogram(&file, &placed, &discarded, &target)?;
                written.push(file);
            }
        }
    }
    Ok(written)
}

/// Where the checkpoints of a run writing `path` (NAME.txt) go: NAME.checkpoint.json.
fn checkpoint_path(path: &Path) -> PathBuf {
    path.with_extension("checkpoint.json")
}

/// Reads a checkpoint file (JSON), with a usage error that names it.
fn read_checkpoint(file: &str) -> Result<Value, BenchError> {
    let text =
        std::fs::read_to_string(file).map_err(|e| usage(format!("cannot read {file}: {e}")))?;
    serde_json::from_str(&text).map_err(|e| usage(format!("{file} is not a checkpoint: {e}")))
}

fn snapshot_sink(path: PathBuf) -> crate::progress::SnapshotSink {
    Box::new(move |step, packing| {
        let stem = path.with_extension("");
        let snap = PathBuf::from(format!("{}_step{step}.txt", stem.display()));
        // A failed snapshot must not kill a long run; the final output reports real errors.
        let _ =
            packbench_core::format::write_atomic(Path::new(&snap), write_text(packing).as_bytes());
    })
}
