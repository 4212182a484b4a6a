//! Packings in every kind of container: nothing ends up outside its walls.

mod common;
use common::*;

use packbench_adam::Params;
use packbench_core::{Container, SizeDistribution};

/// Jams `n` equal spheres from a φ = 0.05 start in `c` with FIRE and asserts φ in `band`.
///
/// Walls cost density at these N (a layer of spheres ordered against each wall), so each
/// container has its own band, measured as φ of this start over seeds 1–10 (min–max, mean ± sd)
/// and set a few spreads wide; every 3D band stays below random close packing (φ ≈ 0.64) and the
/// 2D one well below the hexagonal crystal (0.9069).
fn jam_inside(c: Container, n: usize, band: (f64, f64)) {
    let out = pack(&start(n, mono(), c, 0.05, 7), &fire()).unwrap();
    assert_eq!(
        out.termination,
        "converged",
        "{}",
        out.packing.container.describe()
    );
    let m = metrics(&out.packing);
    assert!(
        m.phi > band.0 && m.phi < band.1,
        "phi {} outside {band:?} in {}",
        m.phi,
        out.packing.container.describe()
    );
    // FIRE stops when the overlaps fall under its tolerance (1.3e-4 to 3.0e-4 over those runs).
    assert!(m.max_overlap <= 1e-3, "overlap {}", m.max_overlap);
    assert_inside(&out.packing, 1e-3);
}

/// 120 disks in a circle: 0.793–0.812 (0.804 ± 0.005).
#[test]
fn disk() {
    jam_inside(
        Container::from_rcp_flags(&[1.0, 1.0], &[-2, 0]).unwrap(),
        120,
        (0.78, 0.83),
    );
}

/// 150 spheres in a cylinder with walled ends: 0.542–0.554 (0.548 ± 0.004).
#[test]
fn cylinder_with_walls_on_its_axis() {
    jam_inside(
        Container::from_rcp_flags(&[1.0, 1.0, 1.0], &[-2, 0, 1]).unwrap(),
        150,
        (0.53, 0.57),
    );
}

/// 150 spheres in a sphere: 0.550–0.563 (0.557 ± 0.004).
#[test]
fn sphere() {
    jam_inside(
        Container::from_rcp_flags(&[1.0, 1.0, 1.0], &[-3, 0, 0]).unwrap(),
        150,
        (0.54, 0.58),
    );
}

/// 150 spheres between two walls 3.2 diameters apart: 0.565–0.578, and 0.609 for one seed
/// (0.574 ± 0.012).
#[test]
fn box_with_walls_on_y_only() {
    jam_inside(
        Container::with_flags(&[1.0, 0.5, 1.0], &[false, true, false]).unwrap(),
        150,
        (0.55, 0.63),
    );
}

/// 150 spheres in a cylindrical shell: 0.517–0.539 (0.527 ± 0.006).
#[test]
fn cylindrical_shell() {
    jam_inside(
        Container::cylindrical_shell(0.15, 0.5, &[1.0], &[true]).unwrap(),
        150,
        (0.50, 0.555),
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
    // Jammed, not stopped short: 100 equal spheres under FIRE jam at 0.626–0.639 (seeds 1–10).
    let m = metrics(&out.packing);
    assert!((0.61..0.66).contains(&m.phi), "phi {}", m.phi);
    assert!(m.max_overlap <= 1e-3, "overlap {}", m.max_overlap);
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
