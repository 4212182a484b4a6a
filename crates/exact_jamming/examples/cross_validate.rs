//! Cross-validation of the three exact-jamming methods on the same starting packings, with
//! timings and the core's metrics of every output.
//!
//! Usage: `cross_validate N DIM STARTS [methods] [start]`, e.g.
//! `cross_validate 1000 3 5 cj,qp,calippso random` (methods: `cj`, `cj-open` with App. B's
//! active set, `cj-most-tensile` with the most tensile release rule, `qp`, `calippso`). `start` is
//! `random` (RCPGenerator's initializer at φ = 0.3, shrunk to be overlap-free) or `poisson`
//! (the same at φ = 0.05, a nearly ideal-gas start), optionally suffixed `:lognormal0.3` for a lognormal mean-1
//! distribution of standard deviation 0.3, or `:bidisperse` for a 50:50 mixture of diameters
//! 1 and 1.4. An optional sixth argument is a wall-clock budget in seconds per run: the run then
//! stops (termination `interrupted`, its packing so far analysed like the others) when the budget
//! is spent, and progress goes to stderr every minute. Prints one Markdown table row per run.

use std::time::Instant;

use packbench_core::analysis::{AnalysisOptions, analyze};
use packbench_core::init::initial_packing;
use packbench_core::run::{Observer, Outcome, Progress};
use packbench_core::scene::{Placement, Scene};
use packbench_core::{Container, SizeDistribution};
use packbench_exact_jamming::{
    calippso, closest_jammed, closest_jammed_qp, shrink_to_overlap_free,
};

/// Stops a run after `budget` seconds and reports progress to stderr every minute.
struct Budget {
    start: Instant,
    last: Instant,
    budget: f64,
}

impl Budget {
    fn new(budget: f64) -> Self {
        Budget {
            start: Instant::now(),
            last: Instant::now(),
            budget,
        }
    }
}

impl Observer for Budget {
    fn progress(&mut self, p: &Progress) {
        if self.last.elapsed().as_secs_f64() >= 60.0 {
            self.last = Instant::now();
            eprintln!(
                "  {:.0} s: step {} phi {:.6} {} {}",
                self.start.elapsed().as_secs_f64(),
                p.step,
                p.phi,
                p.label,
                p.value
            );
        }
    }
    fn should_stop(&self) -> bool {
        self.start.elapsed().as_secs_f64() > self.budget
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).map_or(100, |s| s.parse().expect("N"));
    let dim: usize = args.get(2).map_or(3, |s| s.parse().expect("DIM"));
    let starts: u64 = args.get(3).map_or(1, |s| s.parse().expect("STARTS"));
    let methods = args
        .get(4)
        .cloned()
        .unwrap_or_else(|| "cj,qp,calippso".into());
    let start_kind = args.get(5).cloned().unwrap_or_else(|| "random".into());
    let budget: f64 = args
        .get(6)
        .map_or(f64::INFINITY, |s| s.parse().expect("BUDGET"));
    let (kind, dist) = match start_kind.split_once(':') {
        Some((k, "bidisperse")) => (
            k.to_string(),
            SizeDistribution::Bidisperse {
                d1: 1.0,
                d2: 1.4,
                p: 0.5,
            },
        ),
        Some((k, d)) => {
            let sigma: f64 = d
                .trim_start_matches("lognormal")
                .parse()
                .expect("lognormalS");
            (k.to_string(), SizeDistribution::LognormalMean1 { sigma })
        }
        None => (start_kind.clone(), SizeDistribution::Mono { d: 1.0 }),
    };
    let phi = if kind == "poisson" { 0.05 } else { 0.3 };
    println!(
        "| start | seed | method | φ_J | time (s) | steps | z' | rattlers | iso_gap | max_overlap | force_balance | termination |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for seed in 1..=starts {
        let scene = Scene {
            n,
            distribution: dist.clone(),
            container: Container::periodic_box(&vec![1.0; dim]).unwrap(),
            phi,
            seed: Some(seed),
            placement: Placement::Random,
        };
        let p = initial_packing(&scene, seed).unwrap();
        let start = shrink_to_overlap_free(&p, 1e-3).unwrap();
        for m in methods.split(',') {
            let clock = Instant::now();
            let obs = &mut Budget::new(budget);
            let out: Result<Outcome, _> = match m {
                "cj" => closest_jammed::run(&start, &Default::default(), obs),
                "cj-open" => closest_jammed::run(
                    &start,
                    &closest_jammed::Params {
                        open_tensile_bonds: true,
                        ..Default::default()
                    },
                    obs,
                ),
                "cj-most-tensile" => closest_jammed::run(
                    &start,
                    &closest_jammed::Params {
                        release_rule: closest_jammed::ReleaseRule::MostTensile,
                        ..Default::default()
                    },
                    obs,
                ),
                "qp" => closest_jammed_qp::run(&start, &Default::default(), obs),
                "calippso" => calippso::run(&start, &Default::default(), obs),
                other => panic!("unknown method {other}"),
            };
            let secs = clock.elapsed().as_secs_f64();
            match out {
                Ok(out) => {
                    let mt = analyze(&out.packing, &AnalysisOptions::default()).unwrap();
                    println!(
                        "| {start_kind} | {seed} | {m} | {:.6} | {secs:.2} | {} | {:.4} | {} | {} | {:.1e} | {:.1e} | {} |",
                        mt.phi,
                        out.steps,
                        mt.z_nonrattler,
                        mt.rattlers,
                        mt.iso_gap,
                        mt.max_overlap,
                        mt.force_balance.unwrap_or(f64::NAN),
                        out.termination
                    );
                    eprintln!("{m} seed {seed}: {:?}", out.extra);
                }
                Err(e) => println!(
                    "| {start_kind} | {seed} | {m} | error: {e} | {secs:.2} | | | | | | | |"
                ),
            }
        }
    }
}
