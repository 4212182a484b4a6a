//! Extremes: a clear result or a clear error, never NaN, a hang or a panic.

mod common;
use common::*;

use packbench_adam::{AdamError, Params};
use packbench_core::{Container, Packing, SizeDistribution};

#[test]
fn one_sphere_in_a_periodic_box_is_a_clear_error() {
    let err = pack(&start(1, mono(), periodic(3), 0.05, 1), &fire()).unwrap_err();
    assert!(matches!(err, AdamError::BoxTooSmall { .. }), "{err}");
    assert!(err.to_string().contains("its own image"), "{err}");
}

/// Diameters spanning more than adam resolves are refused before the first step, down to a
/// subnormal one (the file that found it: 1e-320 beside 0.02, whose overlaps underflowed into a
/// non-finite energy once the large disk could pass half the box).
#[test]
fn a_size_ratio_beyond_resolution_is_a_clear_error() {
    for tiny in [1e-15, 1e-320] {
        let p = Packing::new(vec![0.05, 0.05, 0.5, 0.4], vec![0.02, tiny], periodic(2)).unwrap();
        let err = pack(&p, &Params::default()).unwrap_err();
        assert!(matches!(err, AdamError::SizeRatio { .. }), "{err}");
    }
    let p = Packing::new(vec![0.05, 0.05, 0.5, 0.4], vec![0.02, 1e-12], periodic(2)).unwrap();
    assert!(!matches!(
        pack(&p, &Params::default()),
        Err(AdamError::SizeRatio { .. })
    ));
}

/// A periodic slab thinner than two diameters makes every sphere touch others through further
/// images; past 128 of them adam refuses (their pairs would cost N² per step) with a sentence,
/// where a few are summed (the two-sphere test below).
#[test]
fn a_thin_periodic_slab_of_many_spheres_is_a_clear_error() {
    // Jammed at φ ≈ 0.63 the 400 spheres would be 0.65 wide, above half the 0.9 height.
    let slab = Container::periodic_box(&[10.0, 10.0, 0.9]).unwrap();
    let out = pack(&start(400, mono(), slab, 0.05, 7), &fire());
    let Err(err) = out else {
        panic!("packed, phi {}", out.unwrap().packing.phi());
    };
    assert!(matches!(err, AdamError::TooManyWide { .. }), "{err}");
    assert!(err.to_string().contains("larger box"), "{err}");
}

/// Two equal spheres in a periodic box touch each other only through several images, and the
/// one jammed arrangement is the centred lattice: the square one of φ = π/4 for disks, body-
/// centred cubic of φ = π√3/8 for spheres (every other arrangement can still grow). Bands,
/// fixed before the run: 0.003, several times the φ the stopping overlap leaves.
#[test]
fn two_spheres_in_a_periodic_box_jam_in_the_centred_lattice() {
    use std::f64::consts::PI;
    for (d, phi) in [(2, PI / 4.0), (3, PI * 3f64.sqrt() / 8.0)] {
        let out = pack(&start(2, mono(), periodic(d), 0.05, 2), &fire()).unwrap();
        let p = &out.packing;
        assert!(
            (p.phi() - phi).abs() < 3e-3,
            "{d}D: phi {} against {phi}",
            p.phi()
        );
        let m = metrics(p);
        assert!(m.max_overlap < 1e-3, "{d}D: overlap {}", m.max_overlap);
    }
}

#[test]
fn one_sphere_in_a_walled_box_fills_its_narrowest_width() {
    let c = Container::with_flags(&[1.0, 2.0], &[true, true]).unwrap();
    let out = pack(&start(1, mono(), c, 0.05, 3), &fire()).unwrap();
    let p = &out.packing;
    assert!((p.diameters[0] - 1.0).abs() < 1e-3, "{}", p.diameters[0]);
    assert_inside(p, 1e-3);
}

#[test]
fn size_ratio_twenty() {
    let dist = SizeDistribution::Bidisperse {
        d1: 1.0,
        d2: 20.0,
        p: 0.97,
    };
    let c = Container::with_flags(&[1.0, 1.0], &[true, true]).unwrap();
    let out = pack(&start(250, dist, c, 0.05, 4), &fire()).unwrap();
    assert!(["converged", "max_steps"].contains(&out.termination.as_str()));
    let m = metrics(&out.packing);
    // About seven large disks carry the packing (92 % of the volume), so φ is set by how they
    // fit the square: 0.67–0.84 over seeds 1–10 (0.75 ± 0.055), none of them loose (a
    // packing stopped before jamming sits far lower) or overlapping into a higher φ.
    assert!((0.6..0.9).contains(&m.phi), "phi {}", m.phi);
    assert!(m.max_overlap <= 1e-3, "overlap {}", m.max_overlap);
    assert_inside(&out.packing, 1e-3);
}

/// RCPGenerator 1.0's power law (diameters 1–15, density D⁻³) between walls: large spheres touched by
/// many small ones and small spheres pressed on walls, the stiffness contrasts the Jacobi
/// length scales are there for. The pressure protocol measures overlaps in the mean diameter
/// here (ratio 15 > `ABSOLUTE_OVERLAP_SIZE_RATIO`); ADAM (whose stall tolerance is then 3e-5)
/// and FIRE (1e-6) both jam it with most small spheres rattling in the voids of a skeleton of
/// large ones.
#[test]
fn power_law_one_to_fifteen_between_walls() {
    let dist = SizeDistribution::power_law_1_to_15();
    let c = Container::with_flags(&[1.0, 1.0, 1.0], &[true, true, true]).unwrap();
    let begin = start(400, dist, c, 0.05, 2);
    let pressure = Params {
        protocol: packbench_adam::Protocol::Pressure,
        ..Params::default()
    };
    for params in [pressure, fire()] {
        let out = pack(&begin, &params).unwrap();
        let name = format!("{:?}", params.minimizer);
        assert_eq!(out.termination, "converged", "{name}");
        assert_eq!(out.extra["protocol"], "pressure", "{name}: {:?}", out.extra);
        // The stall tolerance the run resolved: 3e-5 for absolute overlaps unless set (FIRE's).
        let tol = params.rung_phi_tol.unwrap_or(3e-5);
        assert_eq!(out.extra["rung_phi_tol"], tol, "{name}: {:?}", out.extra);
        let m = metrics(&out.packing);
        // Walls cost density at this small N (the largest spheres span a good part of the box).
        assert!(m.phi > 0.52 && m.phi < 0.65, "{name}: phi {}", m.phi);
        assert!(m.max_overlap <= 1e-3, "{name}: overlap {}", m.max_overlap);
        assert!(
            m.rattlers > m.n / 2,
            "{name}: rattlers {} of {}",
            m.rattlers,
            m.n
        );
        assert_inside(&out.packing, 1e-3);
    }
}

/// The same power law under the default RCPGenerator schedule (energy harmonic in the
/// absolute overlap, as RCPGenerator's): it ends near its 5e-4 overlap tolerance, inside the
/// walls, with most small spheres rattling.
#[test]
fn power_law_one_to_fifteen_under_the_rcpgenerator_schedule() {
    let dist = SizeDistribution::power_law_1_to_15();
    let c = Container::with_flags(&[1.0, 1.0, 1.0], &[true, true, true]).unwrap();
    let out = pack(&start(400, dist, c, 0.05, 2), &Params::default()).unwrap();
    assert_eq!(out.termination, "converged");
    assert_eq!(out.extra["protocol"], "rcpgenerator");
    let m = metrics(&out.packing);
    assert!(m.phi > 0.52 && m.phi < 0.65, "phi {}", m.phi);
    // The stop test saw < 5e-4 one ADAM step (≤ α_max/100) before the returned positions.
    assert!(m.max_overlap < 1e-3, "overlap {}", m.max_overlap);
    assert!(m.rattlers > m.n / 2, "rattlers {} of {}", m.rattlers, m.n);
    assert_inside(&out.packing, 1e-3);
}

/// A slab about one diameter thick (fix-height 1.05 holds it at that multiple of D_max).
#[test]
fn slab_one_diameter_thick() {
    let mut c = Container::with_flags(&[6.0, 6.0, 1.05], &[false, false, true]).unwrap();
    c.fix_height = Some(1.05);
    let out = pack(&start(60, mono(), c, 0.05, 5), &fire()).unwrap();
    let p = &out.packing;
    assert!((p.container.lengths[2] / p.max_diameter() - 1.05).abs() < 1e-12);
    assert!(metrics(p).max_overlap <= 1e-3);
    assert_inside(p, 1e-3);
}

#[test]
fn coincident_spheres_are_separated() {
    let c = Container::periodic_box(&[4.0, 4.0]).unwrap();
    let mut x = Vec::new();
    for k in 0..8 {
        x.extend_from_slice(&[1.0 + 0.25 * k as f64, 2.0]);
    }
    x.extend_from_slice(&[3.0, 3.0, 3.0, 3.0]);
    let p = Packing::new(x, vec![0.3; 10], c).unwrap();
    let out = pack(&p, &fire()).unwrap();
    assert!(out.packing.positions.iter().all(|v| v.is_finite()));
    assert!(metrics(&out.packing).max_overlap <= 1e-3);
}

#[test]
fn eight_dimensions_run() {
    let params = Params {
        max_steps: 3000,
        ..fire()
    };
    let out = pack(&start(60, mono(), periodic(8), 0.001, 6), &params);
    // Either a packing or the own-image refusal: never NaN or a panic.
    match out {
        Ok(o) => assert!(o.packing.phi().is_finite()),
        Err(e) => assert!(matches!(e, AdamError::BoxTooSmall { .. }), "{e}"),
    }
}
