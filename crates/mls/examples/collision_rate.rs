//! Measures collisions per second of the event-driven core for 3D monodisperse spheres:
//! an LS compression at rate 1 from a Poisson start to the pressure cap (the reference run
//! of issue 4), then the same packing shrunk to φ = 0.55 and run at (nearly) zero growth.
//!
//! ```text
//! cargo build --release -p packbench-mls --examples
//! nice -n 10 target/release/examples/collision_rate 10000
//! ```

use std::error::Error;

use packbench_core::init::initial_packing;
use packbench_core::run::NullObserver;
use packbench_core::scene::{Placement, Scene};
use packbench_core::{Container, SizeDistribution};
use packbench_mls::{LsParams, MlsParams, run_ls, run_mls};

fn main() -> Result<(), Box<dyn Error>> {
    let n: usize = std::env::args().nth(1).map_or(Ok(10_000), |s| s.parse())?;
    let scene = Scene {
        n,
        distribution: SizeDistribution::Mono { d: 1.0 },
        container: Container::periodic_box(&[1.0, 1.0, 1.0])?,
        phi: 0.01,
        seed: Some(1),
        placement: Placement::Poisson,
    };
    let start = initial_packing(&scene, 1)?;
    let ls = run_ls(&start, &LsParams::default(), &mut NullObserver)?;
    let e = &ls.extra;
    println!(
        "ls rate 1: phi {:.4} collisions {} windows {} runtime_s {:.2} collisions_per_s {:.3e}",
        ls.packing.phi(),
        e["collisions"],
        e["windows"],
        e["runtime_s"].as_f64().unwrap_or(0.0),
        e["collisions_per_s"].as_f64().unwrap_or(0.0)
    );
    let mut fluid = ls.packing.clone();
    fluid.scale_diameters((0.55 / fluid.phi()).cbrt());
    let mut params = MlsParams {
        rate_initial: 1e-9,
        rate_final: 1e-10,
        ..MlsParams::default()
    };
    params.dynamics.max_collisions = 100 * n as u64;
    let eq = run_mls(&fluid, &params, &mut NullObserver)?;
    let e = &eq.extra;
    println!(
        "equilibrium phi {:.4}: collisions {} runtime_s {:.2} collisions_per_s {:.3e} pressure {}",
        eq.packing.phi(),
        e["collisions"],
        e["runtime_s"].as_f64().unwrap_or(0.0),
        e["collisions_per_s"].as_f64().unwrap_or(0.0),
        e["final_pressure"]
    );
    Ok(())
}
