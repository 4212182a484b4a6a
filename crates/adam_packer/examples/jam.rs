//! Jams one packing and prints φ, steps, time and the core's analysis.
//!
//! Usage: `jam N d dist seed [key=value ...]`
//! - dist: `mono`, `bi` (50:50, diameter ratio 1.4), `lognormal:σ` (mean 1), `powerlaw`
//!   (1–15, exponent −3), `ratio20` (bidisperse 1:20, 3% large);
//! - keys: `container=periodic|walls|disk|cylinder|sphere|ywalls|shell|slab|seed000`, `phi0=0.05`,
//!   `fix_height=k`, `analysis=full|quick|none`, and any `Params` field as JSON
//!   (`minimizer="fire"`, `protocol="pressure"`, `target_phi=0.5`, …).

use std::time::Instant;

use packbench_adam::{Params, run};
use packbench_core::analysis::{AnalysisOptions, analyze};
use packbench_core::init::initial_packing;
use packbench_core::run::NullObserver;
use packbench_core::scene::{Placement, Scene};
use packbench_core::{Container, SizeDistribution};
use serde_json::{Map, Value};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() < 5 {
        eprintln!("usage: jam N d dist seed [key=value ...]");
        std::process::exit(2);
    }
    let n: usize = args[1].parse().expect("N");
    let d: usize = args[2].parse().expect("d");
    let dist = match args[3].as_str() {
        "mono" => SizeDistribution::Mono { d: 1.0 },
        "bi" => SizeDistribution::Bidisperse {
            d1: 1.0,
            d2: 1.4,
            p: 0.5,
        },
        "powerlaw" => SizeDistribution::power_law_1_to_15(),
        "ratio20" => SizeDistribution::Bidisperse {
            d1: 1.0,
            d2: 20.0,
            p: 0.97,
        },
        s if s.starts_with("lognormal:") => SizeDistribution::LognormalMean1 {
            sigma: s[10..].parse().expect("sigma"),
        },
        s => panic!("unknown dist {s}"),
    };
    let seed: u64 = args[4].parse().expect("seed");
    let mut container = "periodic".to_string();
    let mut phi0 = 0.05;
    let mut fix_height = None;
    let mut analysis = "full".to_string();
    let mut show_trace = false;
    let mut overrides = Map::new();
    for a in &args[5..] {
        let (k, v) = a.split_once('=').expect("key=value");
        match k {
            "container" => container = v.to_string(),
            "phi0" => phi0 = v.parse().expect("phi0"),
            "fix_height" => fix_height = Some(v.parse::<f64>().expect("fix_height")),
            "analysis" => analysis = v.to_string(),
            "trace" => show_trace = v == "1",
            _ => {
                let value = serde_json::from_str(v).unwrap_or(Value::String(v.to_string()));
                overrides.insert(k.to_string(), value);
            }
        }
    }
    let ones = vec![1.0; d];
    let mut c = match container.as_str() {
        "periodic" => Container::periodic_box(&ones).unwrap(),
        "walls" => Container::with_flags(&ones, &vec![true; d]).unwrap(),
        "disk" => Container::from_rcp_flags(&[1.0, 1.0], &[-2, 0]).unwrap(),
        "cylinder" => Container::from_rcp_flags(&[1.0, 1.0, 1.0], &[-2, 0, 1]).unwrap(),
        "sphere" => Container::from_rcp_flags(&[1.0, 1.0, 1.0], &[-3, 0, 0]).unwrap(),
        "ywalls" | "seed000" => {
            Container::with_flags(&[1.0, 0.5, 1.0], &[false, true, false]).unwrap()
        }
        "shell" => Container::cylindrical_shell(0.2, 0.5, &[1.0], &[true]).unwrap(),
        "slab" => {
            let mut l = ones.clone();
            l[d - 1] = 0.05;
            let mut w = vec![false; d];
            w[d - 1] = true;
            Container::with_flags(&l, &w).unwrap()
        }
        s => panic!("unknown container {s}"),
    };
    c.fix_height = fix_height;
    let scene = Scene {
        n,
        distribution: dist,
        container: c,
        phi: phi0,
        seed: Some(seed),
        placement: Placement::Random,
    };
    let start = initial_packing(&scene, seed).expect("initial packing");
    let params: Params = serde_json::from_value(Value::Object(overrides)).expect("params");
    let t = Instant::now();
    let out = run(&start, &params, &mut NullObserver).expect("run");
    let secs = t.elapsed().as_secs_f64();
    let p = &out.packing;
    if show_trace {
        for row in &out.trace {
            let vals: Vec<String> = row
                .values
                .iter()
                .map(|(k, v)| format!("{k}={v:.3e}"))
                .collect();
            eprintln!(
                "step={} t={:.3} phi={:.6} {}",
                row.step,
                row.time_s,
                row.phi,
                vals.join(" ")
            );
        }
    }
    print!(
        "N={n} d={d} dist={} seed={seed} container={container} phi={:.6} steps={} time_s={secs:.3} termination={}",
        args[3],
        p.phi(),
        out.steps,
        out.termination
    );
    for key in [
        "neighbor_builds",
        "neighbor_pairs",
        "reversals",
        "final_stage",
    ] {
        if let Some(v) = out.extra.get(key) {
            print!(" {key}={v}");
        }
    }
    if analysis != "none" {
        let opts = AnalysisOptions {
            force_balance: analysis == "full",
            ..AnalysisOptions::default()
        };
        let m = analyze(p, &opts).expect("analysis");
        print!(
            " z_nonrattler={:.4} rattlers={} n_dof={} iso_gap={} max_overlap={:.3e}",
            m.z_nonrattler, m.rattlers, m.n_dof, m.iso_gap, m.max_overlap
        );
        if let Some(fb) = m.force_balance {
            print!(" force_balance={fb:.3e}");
        }
    }
    if let Some(h) = fix_height {
        print!(
            " height/D_max={:.12}",
            p.container.lengths[d - 1] / p.max_diameter()
        );
        let _ = h;
    }
    println!();
}
