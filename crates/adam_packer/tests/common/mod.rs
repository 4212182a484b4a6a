//! Shared helpers of the integration tests: scenes, runs and the core's analysis.
#![allow(dead_code)]

use packbench_adam::{AdamError, Params, run};
use packbench_core::analysis::{AnalysisOptions, Metrics, analyze};
use packbench_core::init::initial_packing;
use packbench_core::run::{NullObserver, Outcome};
use packbench_core::scene::{Placement, Scene};
use packbench_core::{Container, Packing, SizeDistribution};

/// A random starting packing at φ = `phi` (RCPGenerator `InitializeParticles` semantics).
pub fn start(
    n: usize,
    dist: SizeDistribution,
    container: Container,
    phi: f64,
    seed: u64,
) -> Packing {
    let scene = Scene {
        n,
        distribution: dist,
        container,
        phi,
        seed: Some(seed),
        placement: Placement::Random,
    };
    initial_packing(&scene, seed).expect("initial packing")
}

pub fn mono() -> SizeDistribution {
    SizeDistribution::Mono { d: 1.0 }
}

pub fn periodic(d: usize) -> Container {
    Container::periodic_box(&vec![1.0; d]).unwrap()
}

pub fn fire() -> Params {
    Params::fire()
}

pub fn pack(p: &Packing, params: &Params) -> Result<Outcome, AdamError> {
    run(p, params, &mut NullObserver)
}

pub fn metrics(p: &Packing) -> Metrics {
    analyze(p, &AnalysisOptions::default()).expect("analysis")
}

/// Every sphere inside its container up to `tol` of its diameter, and nothing non-finite.
pub fn assert_inside(p: &Packing, tol: f64) {
    for i in 0..p.n() {
        let x = p.position(i);
        assert!(x.iter().all(|v| v.is_finite()), "particle {i} at {x:?}");
        let r = 0.5 * p.diameters[i];
        let clearance = p.container.wall_clearance(x);
        assert!(
            clearance >= r - tol * p.diameters[i],
            "particle {i} pokes out of {}: clearance {clearance}, radius {r}",
            p.container.describe()
        );
    }
}
