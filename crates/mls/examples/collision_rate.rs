//! Measures collisions per second of the event-driven core for 3D monodisperse spheres:
//! an LS compression at rate 1 from a Poisson start to the pressure cap (the reference run
//! of), then the same packing shrunk to φ = 0.55 and run at (nearly) zero growth.
//!
//! With `dense` as second argument it also runs a slow LS compression (γ = 0.03) to the
//! pressure cap and reports the rate over its windows at φ ≥ 0.62 (the dense regime MLS spends
//! its time in).
//!
//! Rates are collisions per wall-clock second; `cpu_s` is the process' user+system CPU time
//! of the phase (from /proc, Linux only), which is what to compare on a loaded machine.
//!
//! ```text
//! cargo build --release -p packbench-mls --examples
//! nice -n 10 target/release/examples/collision_rate 10000 [dense]
//! ```

use std::error::Error;

use packbench_core::init::initial_packing;
use packbench_core::run::NullObserver;
use packbench_core::scene::{Placement, Scene};
use packbench_core::{Container, SizeDistribution};
use packbench_mls::{LsParams, MlsParams, run_ls, run_mls};

/// CPU seconds (user + system) of this process so far, NaN where /proc is unavailable.
fn cpu_seconds() -> f64 {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else {
        return f64::NAN;
    };
    // Fields after the parenthesised command name; utime and stime are fields 14 and 15.
    let rest = stat.rsplit_once(')').map_or("", |(_, r)| r);
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks = |k: usize| f.get(k - 3).and_then(|x| x.parse::<f64>().ok());
    match (ticks(14), ticks(15)) {
        // Linux reports in USER_HZ, 100 on every common configuration.
        (Some(u), Some(s)) => (u + s) / 100.0,
        _ => f64::NAN,
    }
}

fn main() -> Result<(), Box<dyn Error>> {
    let n: usize = std::env::args().nth(1).map_or(Ok(10_000), |s| s.parse())?;
    let dense = std::env::args().nth(2).is_some_and(|a| a == "dense");
    let scene = Scene {
        n,
        distribution: SizeDistribution::Mono { d: 1.0 },
        container: Container::periodic_box(&[1.0, 1.0, 1.0])?,
        phi: 0.01,
        seed: Some(1),
        placement: Placement::Poisson,
    };
    let start = initial_packing(&scene, 1)?;
    let cpu0 = cpu_seconds();
    let ls = run_ls(&start, &LsParams::default(), &mut NullObserver)?;
    let cpu1 = cpu_seconds();
    let e = &ls.extra;
    println!(
        "ls rate 1: phi {:.4} events {} collisions {} windows {} runtime_s {:.2} collisions_per_s {:.3e} cpu_s {:.2} collisions_per_cpu_s {:.3e}",
        ls.packing.phi(),
        e["events"],
        e["collisions"],
        e["windows"],
        e["runtime_s"].as_f64().unwrap_or(0.0),
        e["collisions_per_s"].as_f64().unwrap_or(0.0),
        cpu1 - cpu0,
        ls.steps as f64 / (cpu1 - cpu0)
    );
    let mut fluid = ls.packing.clone();
    fluid.scale_diameters((0.55 / fluid.phi()).cbrt());
    let mut params = MlsParams {
        rate_initial: 1e-9,
        rate_final: 1e-10,
        ..MlsParams::default()
    };
    params.dynamics.max_collisions = 100 * n as u64;
    let cpu0 = cpu_seconds();
    let eq = run_mls(&fluid, &params, &mut NullObserver)?;
    let cpu1 = cpu_seconds();
    let e = &eq.extra;
    println!(
        "equilibrium phi {:.4}: events {} collisions {} runtime_s {:.2} collisions_per_s {:.3e} pressure {} cpu_s {:.2} collisions_per_cpu_s {:.3e}",
        eq.packing.phi(),
        e["events"],
        e["collisions"],
        e["runtime_s"].as_f64().unwrap_or(0.0),
        e["collisions_per_s"].as_f64().unwrap_or(0.0),
        e["final_pressure"],
        cpu1 - cpu0,
        eq.steps as f64 / (cpu1 - cpu0)
    );
    if dense {
        let params = LsParams {
            rate: 0.03,
            ..LsParams::default()
        };
        let cpu0 = cpu_seconds();
        let slow = run_ls(&start, &params, &mut NullObserver)?;
        let cpu1 = cpu_seconds();
        // Rate over the windows that ended at φ ≥ 0.62 (each trace row closes one window).
        let rows = &slow.trace;
        let first = rows.iter().position(|r| r.phi >= 0.62);
        let (collisions, seconds) = match first {
            Some(k) if k > 0 => (
                rows[rows.len() - 1].step - rows[k - 1].step,
                rows[rows.len() - 1].time_s - rows[k - 1].time_s,
            ),
            _ => (0, 0.0),
        };
        println!(
            "ls rate 0.03: phi {:.4} windows {} collisions {} cpu_s {:.2} collisions_per_cpu_s {:.3e}; \
             windows at phi >= 0.62: collisions {} wall_s {:.2} collisions_per_s {:.3e}",
            slow.packing.phi(),
            rows.len(),
            slow.steps,
            cpu1 - cpu0,
            slow.steps as f64 / (cpu1 - cpu0),
            collisions,
            seconds,
            collisions as f64 / seconds
        );
    }
    Ok(())
}
