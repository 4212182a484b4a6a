//! Runs `ls` or `mls` (or `ls+mls`: LS then MLS on its result) on a generated scene and prints
//! φ, reduced pressure, collisions, collisions per second and the core's analysis.
//!
//! ```text
//! cargo run --release -p packbench-mls --example pack -- \
//!     --method ls+mls --n 10000 --dim 3 --dist mono --rate 1 --seed 1
//! ```
//! Options: `--method ls|mls|ls+mls`, `--n N`, `--dim d`, `--dist mono|lognormal:σ|bidisperse:ratio`,
//! `--rate γ` (LS), `--rate-initial γ0`, `--rate-final γ_end` (MLS), `--walls` (hard walls on every axis),
//! `--seed s`, `--max-collisions c`, `--no-force-balance`.

use std::error::Error;

use packbench_core::analysis::{AnalysisOptions, analyze};
use packbench_core::run::{NullObserver, Outcome};
use packbench_core::scene::{Placement, Scene};
use packbench_core::{Container, Packing, SizeDistribution, init::initial_packing};
use packbench_mls::{LsParams, MlsParams, run_ls, run_mls};

fn main() -> Result<(), Box<dyn Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let get = |name: &str| {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1).cloned())
    };
    let method = get("--method").unwrap_or_else(|| "ls".into());
    let n: usize = get("--n").map_or(Ok(1000), |s| s.parse())?;
    let dim: usize = get("--dim").map_or(Ok(3), |s| s.parse())?;
    let seed: u64 = get("--seed").map_or(Ok(1), |s| s.parse())?;
    let dist = get("--dist").unwrap_or_else(|| "mono".into());
    let distribution = match dist.split_once(':') {
        None if dist == "mono" => SizeDistribution::Mono { d: 1.0 },
        Some(("lognormal", s)) => SizeDistribution::LognormalMean1 { sigma: s.parse()? },
        Some(("bidisperse", r)) => SizeDistribution::Bidisperse {
            d1: 1.0,
            d2: r.parse()?,
            p: 0.5,
        },
        _ => return Err(format!("unknown --dist {dist}").into()),
    };
    let walls = args.iter().any(|a| a == "--walls");
    let container = Container::with_flags(&vec![1.0; dim], &vec![walls; dim])?;
    let scene = Scene {
        n,
        distribution,
        container,
        phi: 0.01,
        seed: Some(seed),
        placement: Placement::Poisson,
    };
    let start = initial_packing(&scene, seed)?;
    let mut ls = LsParams::default();
    let mut mls = MlsParams::default();
    if let Some(r) = get("--rate") {
        ls.rate = r.parse()?;
    }
    if let Some(r) = get("--rate-initial") {
        mls.rate_initial = r.parse()?;
    }
    if let Some(r) = get("--rate-final") {
        mls.rate_final = r.parse()?;
    }
    for d in [&mut ls.dynamics, &mut mls.dynamics] {
        d.seed = seed;
        if let Some(c) = get("--max-collisions") {
            d.max_collisions = c.parse()?;
        }
    }
    let force_balance = !args.iter().any(|a| a == "--no-force-balance");
    println!("scene: d={dim} N={n} dist={dist} walls={walls} seed={seed}");
    let report = |label: &str, o: &Outcome| -> Result<Packing, Box<dyn Error>> {
        let e = &o.extra;
        println!(
            "{label}: termination={} phi={:.6} pressure={} collisions={} runtime_s={:.2} collisions_per_s={:.3e} windows={} events={} rebuilds={}",
            o.termination,
            o.packing.phi(),
            e["final_pressure"],
            e["collisions"],
            e["runtime_s"].as_f64().unwrap_or(0.0),
            e["collisions_per_s"].as_f64().unwrap_or(0.0),
            e["windows"],
            e["events"],
            e["cell_rebuilds"],
        );
        let m = analyze(
            &o.packing,
            &AnalysisOptions {
                contact_tol: 1e-6,
                force_balance,
            },
        )?;
        println!("{label} analysis: {}", serde_json::to_string(&m)?);
        Ok(o.packing.clone())
    };
    match method.as_str() {
        "ls" => {
            report("ls", &run_ls(&start, &ls, &mut NullObserver)?)?;
        }
        "mls" => {
            report("mls", &run_mls(&start, &mls, &mut NullObserver)?)?;
        }
        "ls+mls" => {
            let p = report("ls", &run_ls(&start, &ls, &mut NullObserver)?)?;
            report("mls", &run_mls(&p, &mls, &mut NullObserver)?)?;
        }
        _ => return Err(format!("unknown --method {method}").into()),
    }
    Ok(())
}
