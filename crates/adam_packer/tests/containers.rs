//! Packings in every kind of container: nothing ends up outside its walls.

mod common;
use common::*;

use packbench_adam::Params;
use packbench_core::{Container, SizeDistribution};

fn jam_inside(c: Container, n: usize, lo: f64) {
    let out = pack(&start(n, mono(), c, 0.05, 7), &fire()).unwrap();
    assert_eq!(
        out.termination,
        "converged",
        "{}",
        out.packing.container.describe()
    );
    let m = metrics(&out.packing);
    assert!(
        m.phi > lo && m.phi < 0.9,
        "phi {} in {}",
        m.phi,
        out.packing.container.describe()
    );
    assert!(m.max_overlap <= 1e-3);
    assert_inside(&out.packing, 1e-3);
}

#[test]
fn disk() {
    jam_inside(
        Container::from_rcp_flags(&[1.0, 1.0], &[-2, 0]).unwrap(),
        120,
        0.75,
    );
}

#[test]
fn cylinder_with_walls_on_its_axis() {
    jam_inside(
        Container::from_rcp_flags(&[1.0, 1.0, 1.0], &[-2, 0, 1]).unwrap(),
        150,
        0.5,
    );
}

#[test]
fn sphere() {
    jam_inside(
        Container::from_rcp_flags(&[1.0, 1.0, 1.0], &[-3, 0, 0]).unwrap(),
        150,
        0.5,
    );
}

#[test]
fn box_with_walls_on_y_only() {
    jam_inside(
        Container::with_flags(&[1.0, 0.5, 1.0], &[false, true, false]).unwrap(),
        150,
        0.55,
    );
}

#[test]
fn cylindrical_shell() {
    jam_inside(
        Container::cylindrical_shell(0.15, 0.5, &[1.0], &[true]).unwrap(),
        150,
        0.45,
    );
}

/// Particle Assembler's use: grow to φ = 0.3 in a cylindrical shell and stop overlap-free.
#[test]
fn target_phi_in_a_cylindrical_shell() {
    let c = Container::cylindrical_shell(0.2, 0.5, &[1.0], &[true]).unwrap();
    let params = Params {
        target_phi: Some(0.3),
        ..fire()
    };
    let out = pack(&start(300, mono(), c, 0.05, 8), &params).unwrap();
    assert_eq!(out.termination, "target_reached");
    assert!(
        (out.packing.phi() - 0.3).abs() < 1e-9,
        "{}",
        out.packing.phi()
    );
    let m = metrics(&out.packing);
    assert!(
        m.max_overlap <= params.target_overlap_tol,
        "{}",
        m.max_overlap
    );
    assert_inside(&out.packing, 1e-6);
}

/// A target above jamming cannot be reached: the run says so and returns the jammed packing.
#[test]
fn target_above_jamming_is_reported() {
    let params = Params {
        target_phi: Some(0.9),
        ..fire()
    };
    let out = pack(&start(100, mono(), periodic(3), 0.05, 9), &params).unwrap();
    assert_eq!(out.termination, "jammed_below_target");
    assert!(out.packing.phi() < 0.66);
}

/// `--fix-height 4`: the final height is exactly four largest diameters.
#[test]
fn fix_height_holds_four_largest_diameters() {
    let mut c = Container::with_flags(&[1.0, 0.5, 4.0], &[false, true, false]).unwrap();
    c.fix_height = Some(4.0);
    let dist = SizeDistribution::Powerlaw {
        d_min: 1.0,
        d_max: 4.0,
        exponent: -3.0,
    };
    let out = pack(&start(200, dist, c, 0.05, 10), &fire()).unwrap();
    let p = &out.packing;
    let ratio = p.container.lengths[2] / p.max_diameter();
    assert!((ratio - 4.0).abs() < 1e-12, "height / D_max = {ratio}");
    assert!(metrics(p).max_overlap <= 1e-3);
    assert_inside(p, 1e-3);
}
