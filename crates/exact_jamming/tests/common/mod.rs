//! Shared helpers of the integration tests.
#![allow(dead_code)]

use packbench_core::analysis::{AnalysisOptions, Metrics, analyze};
use packbench_core::init::initial_packing;
use packbench_core::scene::{Placement, Scene};
use packbench_core::{Container, Packing, SizeDistribution};
use packbench_exact_jamming::shrink_to_overlap_free;

/// A random overlap-free start of `n` particles at about `phi` in a periodic cube.
pub fn random_start(n: usize, d: usize, phi: f64, seed: u64, dist: SizeDistribution) -> Packing {
    start_in(
        Container::periodic_box(&vec![1.0; d]).unwrap(),
        n,
        phi,
        seed,
        dist,
    )
}

/// The same in a box with hard walls on every axis.
pub fn walled_start(n: usize, d: usize, phi: f64, seed: u64) -> Packing {
    let walled = Container::with_flags(&vec![1.0; d], &vec![true; d]).unwrap();
    start_in(walled, n, phi, seed, SizeDistribution::Mono { d: 1.0 })
}

/// A random overlap-free start of `n` particles at about `phi` in `container`.
pub fn start_in(
    container: Container,
    n: usize,
    phi: f64,
    seed: u64,
    dist: SizeDistribution,
) -> Packing {
    let scene = Scene {
        n,
        distribution: dist,
        container,
        phi,
        seed: Some(seed),
        placement: Placement::Random,
    };
    let p = initial_packing(&scene, seed).unwrap();
    shrink_to_overlap_free(&p, 1e-3).unwrap()
}

/// The core's metrics, with force balance.
pub fn metrics(p: &Packing) -> Metrics {
    analyze(p, &AnalysisOptions::default()).unwrap()
}

/// The core's metrics at contact tolerance 1e-9 (the tolerance at which an exact method's
/// `jammed` must stand), with force balance.
pub fn strict_metrics(p: &Packing) -> Metrics {
    let strict = AnalysisOptions {
        contact_tol: 1e-9,
        force_balance: true,
    };
    analyze(p, &strict).unwrap()
}

/// Asserts an exactly jammed packing by the core's analysis at contact tolerance 1e-9:
/// isostatic (iso_gap 0), overlaps ≤ 1e-9, force balance ≤ 1e-8.
pub fn assert_exactly_jammed(p: &Packing, what: &str) -> Metrics {
    let m = strict_metrics(p);
    assert_eq!(m.iso_gap, 0, "{what}: not isostatic: {m:?}");
    assert!(m.max_overlap <= 1e-9, "{what}: overlap {}", m.max_overlap);
    let fb = m.force_balance.unwrap();
    assert!(fb <= 1e-8, "{what}: force balance {fb}");
    m
}
