//! Cases whose jamming point is known by hand.

mod common;

use packbench_core::run::NullObserver;
use packbench_core::{Container, Packing};
use packbench_exact_jamming::{calippso, closest_jammed, closest_jammed_qp};
use std::f64::consts::PI;

/// Two disks in a unit periodic square: the relative position that keeps them farthest apart
/// is the centre of the square, where each disk touches four images of the other at distance
/// 1/√2: φ_J = 2·π/4·(1/2) = π/4.
fn two_disks() -> Packing {
    let c = Container::periodic_box(&[1.0, 1.0]).unwrap();
    Packing::new(vec![0.1, 0.2, 0.45, 0.83], vec![0.2, 0.2], c).unwrap()
}

/// Two disks in a periodic 1 × √3 box: the deepest relative position is (1/2, √3/2), where
/// each disk touches four images of the other and its own image along x, all at distance 1:
/// the triangular crystal, φ_J = π/(2√3).
fn two_disks_triangular() -> Packing {
    let c = Container::periodic_box(&[1.0, 3f64.sqrt()]).unwrap();
    Packing::new(vec![0.2, 0.3, 0.9, 1.0], vec![0.3, 0.3], c).unwrap()
}

#[test]
fn two_disks_jam_at_pi_over_4() {
    let p = two_disks();
    let out = closest_jammed::run(&p, &Default::default(), &mut NullObserver).unwrap();
    assert_eq!(out.termination, "jammed");
    assert!(
        (out.packing.phi() - PI / 4.0).abs() < 1e-10,
        "{}",
        out.packing.phi()
    );
    let out = calippso::run(&p, &Default::default(), &mut NullObserver).unwrap();
    assert_eq!(out.termination, "converged", "{:?}", out.extra);
    assert!(
        (out.packing.phi() - PI / 4.0).abs() < 1e-9,
        "{}",
        out.packing.phi()
    );
    let out = closest_jammed_qp::run(&p, &Default::default(), &mut NullObserver).unwrap();
    assert_eq!(out.termination, "jammed");
    assert!(
        (out.packing.phi() - PI / 4.0).abs() < 1e-10,
        "{}",
        out.packing.phi()
    );
}

#[test]
fn two_disks_jam_into_the_triangular_crystal() {
    let p = two_disks_triangular();
    let phi_hex = PI / (2.0 * 3f64.sqrt());
    let out = closest_jammed::run(&p, &Default::default(), &mut NullObserver).unwrap();
    assert_eq!(out.termination, "jammed");
    assert!(
        (out.packing.phi() - phi_hex).abs() < 1e-10,
        "{}",
        out.packing.phi()
    );
    let out = calippso::run(&p, &Default::default(), &mut NullObserver).unwrap();
    assert!(
        (out.packing.phi() - phi_hex).abs() < 1e-9,
        "{}",
        out.packing.phi()
    );
}

#[test]
fn an_already_jammed_packing_returns_unchanged() {
    let start = common::random_start(
        30,
        2,
        0.3,
        1,
        packbench_core::SizeDistribution::Bidisperse {
            d1: 1.0,
            d2: 1.4,
            p: 0.5,
        },
    );
    let jammed = calippso::run(&start, &Default::default(), &mut NullObserver).unwrap();
    let again = calippso::run(&jammed.packing, &Default::default(), &mut NullObserver).unwrap();
    assert_eq!(again.termination, "converged");
    assert!((again.packing.phi() - jammed.packing.phi()).abs() < 1e-12);
    let again =
        closest_jammed::run(&jammed.packing, &Default::default(), &mut NullObserver).unwrap();
    assert_eq!(again.termination, "jammed");
    assert!((again.packing.phi() - jammed.packing.phi()).abs() < 1e-12);
    let moved = again
        .packing
        .positions
        .iter()
        .zip(&jammed.packing.positions)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(moved < 1e-9, "moved by {moved}");
}

#[test]
fn a_rattler_is_left_out_of_n_dof() {
    // Bidisperse disks, seed chosen so the jammed packing has rattlers.
    let start = common::random_start(
        40,
        2,
        0.3,
        1,
        packbench_core::SizeDistribution::Bidisperse {
            d1: 1.0,
            d2: 1.4,
            p: 0.5,
        },
    );
    let out = closest_jammed::run(&start, &Default::default(), &mut NullObserver).unwrap();
    let m = common::assert_exactly_jammed(&out.packing, "closest-jammed");
    assert!(m.rattlers > 0);
    let rattlers = out.extra["rattlers"].as_u64().unwrap() as usize;
    assert_eq!(rattlers, m.rattlers);
    let n_dof = out.extra["n_dof"].as_u64().unwrap() as usize;
    assert_eq!(n_dof, 2 * (40 - rattlers - 1) + 1);
    assert_eq!(n_dof, m.n_dof);
    assert_eq!(
        out.extra["non_rattler_bonds"].as_u64().unwrap() as usize,
        n_dof
    );
}
