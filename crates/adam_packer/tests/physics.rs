//! Jamming physics at small N, judged by the core's analysis.

mod common;
use common::*;

use packbench_adam::{Params, Protocol};
use packbench_core::{Container, SizeDistribution};

/// 3D monodisperse spheres jam near φ_J ≈ 0.64, isostatic after rattler removal.
#[test]
fn fire_jams_3d_monodisperse_isostatically() {
    let out = pack(&start(200, mono(), periodic(3), 0.05, 1), &fire()).unwrap();
    assert_eq!(out.termination, "converged");
    let m = metrics(&out.packing);
    assert!((0.62..0.65).contains(&m.phi), "phi {}", m.phi);
    assert!(m.max_overlap <= 1e-3, "overlap {}", m.max_overlap);
    assert!((m.z_nonrattler - 6.0).abs() <= 0.15, "z {}", m.z_nonrattler);
    assert!(
        m.iso_gap.unsigned_abs() as f64 <= 0.02 * m.n_dof as f64,
        "{m:?}"
    );
    assert!(
        m.force_balance.unwrap() < 1e-2,
        "force balance {:?}",
        m.force_balance
    );
}

/// The seed's own chain (ADAM → AMSGrad → overdamped Verlet) under the pressure protocol jams
/// near isostatic, with overlaps of the last rung's scale.
#[test]
fn adam_chain_jams_3d_monodisperse() {
    let params = Params {
        protocol: Protocol::Pressure,
        ..Params::default()
    };
    let out = pack(&start(150, mono(), periodic(3), 0.05, 3), &params).unwrap();
    assert_eq!(out.termination, "converged");
    assert_eq!(out.extra["final_stage"], "verlet");
    // The defaults left open in the parameters, as the run resolved them.
    assert_eq!(out.extra["rung_phi_tol"], 1e-5);
    assert_eq!(out.extra["verlet_damping"], 0.01);
    assert_eq!(out.extra["amsgrad_steps"], 1000);
    let m = metrics(&out.packing);
    assert!((0.61..0.65).contains(&m.phi), "phi {}", m.phi);
    assert!(m.max_overlap <= 1e-3, "overlap {}", m.max_overlap);
    assert!((m.z_nonrattler - 6.0).abs() <= 0.2, "z {}", m.z_nonrattler);
    assert!(
        m.iso_gap.unsigned_abs() as f64 <= 0.03 * m.n_dof as f64,
        "{m:?}"
    );
}

/// The default, RCPGenerator 1.0's schedule: ADAM throughout, a first rung of 6000 + 9√(Nd)
/// steps, then the decay and the oscillation of μ; it stops in the oscillation's last quarter
/// period once the largest overlap stayed below 5e-4, near isostatic, at the φ_J of
/// RCPGenerator at this N (0.63–0.64 for N = 150 in 3D).
#[test]
fn rcpgenerator_schedule_jams_3d_monodisperse() {
    let out = pack(
        &start(150, mono(), periodic(3), 0.05, 3),
        &Params::default(),
    )
    .unwrap();
    assert_eq!(out.termination, "converged");
    assert_eq!(out.extra["protocol"], "rcpgenerator");
    assert_eq!(out.extra["final_stage"], "adam");
    let first_rung = (6000.0 + 9.0 * 450f64.sqrt()) as u64;
    assert_eq!(out.extra["first_rung_steps"], first_rung);
    // The decay takes about 15 ticks of 250 steps and the oscillation 1.75 to 2 periods of
    // half the first rung.
    assert!(
        out.steps > first_rung + 3000 + first_rung * 7 / 8,
        "{} steps",
        out.steps
    );
    assert!(
        ["oscillation", "final_descent"].contains(&out.extra["phase"].as_str().unwrap()),
        "{:?}",
        out.extra
    );
    let m = metrics(&out.packing);
    assert!((0.625..0.645).contains(&m.phi), "phi {}", m.phi);
    // The stop test saw < 5e-4 one ADAM step (≤ α_max/100) before the returned positions.
    assert!(m.max_overlap < 1e-3, "overlap {}", m.max_overlap);
    assert!((m.z_nonrattler - 6.0).abs() <= 0.2, "z {}", m.z_nonrattler);
    assert!(
        m.iso_gap.unsigned_abs() as f64 <= 0.03 * m.n_dof as f64,
        "{m:?}"
    );
}

/// 2D bidisperse 50:50 disks with diameter ratio 1.4 jam at φ_J ≈ 0.84 with Z → 4.
#[test]
fn bidisperse_disks_jam_near_0_84() {
    let dist = SizeDistribution::Bidisperse {
        d1: 1.0,
        d2: 1.4,
        p: 0.5,
    };
    let out = pack(&start(200, dist, periodic(2), 0.05, 2), &fire()).unwrap();
    let m = metrics(&out.packing);
    assert!((0.82..0.855).contains(&m.phi), "phi {}", m.phi);
    assert!((m.z_nonrattler - 4.0).abs() <= 0.12, "z {}", m.z_nonrattler);
    assert!(m.max_overlap <= 1e-3);
}

/// RCPGenerator 1.0's threshold loop (inflate below the energy threshold, deflate when balanced),
/// still available by name, ends jammed as well.
#[test]
fn threshold_protocol_jams() {
    let params = Params {
        protocol: Protocol::Threshold,
        ..fire()
    };
    let out = pack(&start(150, mono(), periodic(3), 0.05, 4), &params).unwrap();
    assert_eq!(out.termination, "converged");
    let m = metrics(&out.packing);
    assert!((0.60..0.65).contains(&m.phi), "phi {}", m.phi);
    assert!(m.max_overlap <= 1e-3, "overlap {}", m.max_overlap);
    assert!(m.z_nonrattler > 5.7, "z {}", m.z_nonrattler);
}

/// φ_J falls with dimension (Skoge et al. 2006: ≈ 0.46 in 4D).
#[test]
fn four_dimensional_packing_jams_lower() {
    let out = pack(&start(150, mono(), periodic(4), 0.02, 5), &fire()).unwrap();
    let m = metrics(&out.packing);
    assert!((0.40..0.50).contains(&m.phi), "phi {}", m.phi);
    assert!(m.max_overlap <= 1e-3);
}

/// Same input, same parameters: bit-identical output whether the force loop runs on the
/// calling thread or on one or two rayon threads, for ADAM's chain and for FIRE, in a periodic
/// box and between walls.
#[test]
fn runs_are_bit_identical_at_any_thread_count() {
    let pool = |t| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build()
            .unwrap()
    };
    let starts = [
        start(300, mono(), periodic(3), 0.05, 6),
        start(
            300,
            mono(),
            Container::with_flags(&[1.0, 1.0, 1.0], &[false, true, false]).unwrap(),
            0.05,
            7,
        ),
    ];
    for s in &starts {
        let pressure = Params {
            protocol: Protocol::Pressure,
            ..Params::default()
        };
        for base in [Params::default(), pressure, fire()] {
            let serial = pack(s, &base).unwrap();
            let par = Params {
                parallel_min_particles: 1,
                ..base
            };
            let one = pool(1).install(|| pack(s, &par).unwrap());
            let two = pool(2).install(|| pack(s, &par).unwrap());
            assert!(serial.steps > 100, "a real run: {} steps", serial.steps);
            for other in [&one, &two] {
                assert_eq!(other.steps, serial.steps);
                assert_eq!(other.packing.positions, serial.packing.positions);
                assert_eq!(other.packing.diameters, serial.packing.diameters);
            }
        }
    }
}

/// Refreshing only the rows of the particles that moved lists other pairs apart than whole
/// builds do, and the same pairs in contact: the default protocol's path is the same to the
/// bit with and without it, on one and two threads, for equal spheres in a periodic box, a
/// power law 1–15 between walls on y (small spheres searching for large partners) and a
/// fix-height slab.
#[test]
fn refreshing_movers_rows_keeps_the_path_to_the_bit() {
    let power_law = SizeDistribution::power_law_1_to_15();
    let walls_on_y = Container::with_flags(&[1.0, 0.5, 1.0], &[false, true, false]).unwrap();
    let mut slab = Container::with_flags(&[6.0, 6.0, 1.5], &[false, false, true]).unwrap();
    slab.fix_height = Some(1.5);
    let starts = [
        start(400, mono(), periodic(3), 0.05, 8),
        start(400, power_law, walls_on_y, 0.05, 9),
        start(120, mono(), slab, 0.05, 10),
    ];
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    for s in &starts {
        let whole = Params {
            neighbor_refresh_min_ratio: 1e300,
            ..Params::default()
        };
        let always = Params {
            neighbor_refresh_min_ratio: 0.0,
            ..Params::default()
        };
        let built = pack(s, &whole).unwrap();
        let refreshed = pack(s, &always).unwrap();
        let two_threads = Params {
            parallel_min_particles: 1,
            ..always
        };
        let refreshed_two = pool.install(|| pack(s, &two_threads).unwrap());
        assert!(built.steps > 100, "a real run: {} steps", built.steps);
        let count = |o: &packbench_core::run::Outcome, key: &str| o.extra[key].as_u64().unwrap();
        assert!(
            count(&refreshed, "neighbor_refreshes") > 0
                && count(&refreshed, "neighbor_builds") < count(&built, "neighbor_builds"),
            "refreshes {} and builds {} against {}",
            refreshed.extra["neighbor_refreshes"],
            refreshed.extra["neighbor_builds"],
            built.extra["neighbor_builds"]
        );
        for other in [&refreshed, &refreshed_two] {
            assert_eq!(other.steps, built.steps);
            assert_eq!(other.packing.positions, built.packing.positions);
            assert_eq!(other.packing.diameters, built.packing.diameters);
        }
    }
}

/// Spheres whose diameters are held (`fixed_diameters`) keep them to the bit while the others
/// grow with one common scale and jam around them, under ADAM's default schedule and under
/// FIRE's pressure protocol; the pressure acts on the growing spheres only, and the packing is
/// jammed by the core's analysis.
#[test]
fn held_diameters_stay_while_the_others_jam_around_them() {
    let dist = SizeDistribution::Bidisperse {
        d1: 1.0,
        d2: 3.0,
        p: 0.9,
    };
    let s = start(240, dist, periodic(3), 0.3, 8);
    // The start is scaled to its φ: the large spheres are those three times the smallest.
    let small = s.diameters.iter().fold(f64::INFINITY, |m, &v| m.min(v));
    let held: Vec<usize> = (0..s.n())
        .filter(|&i| s.diameters[i] > 2.0 * small)
        .collect();
    assert!((5..60).contains(&held.len()), "{} held", held.len());
    for base in [Params::default(), fire()] {
        let params = Params {
            fixed_diameters: held.clone(),
            ..base
        };
        let out = pack(&s, &params).unwrap();
        assert_eq!(out.termination, "converged");
        let d = &out.packing.diameters;
        let first_growing = (0..s.n()).find(|i| !held.contains(i)).unwrap();
        let scale = d[first_growing] / s.diameters[first_growing];
        for (i, (&now, &was)) in d.iter().zip(&s.diameters).enumerate() {
            if held.contains(&i) {
                assert_eq!(now, was, "held sphere {i}");
            } else {
                assert!((now / was / scale - 1.0).abs() < 1e-12, "sphere {i}");
            }
        }
        // The small spheres grew (φ 0.3 → jammed) while the held ones did not: the size ratio
        // is no longer 3.
        assert!(scale > 1.1, "growing scale {scale}");
        let m = metrics(&out.packing);
        assert!((0.60..0.72).contains(&m.phi), "phi {}", m.phi);
        assert!(m.max_overlap < 1e-3, "overlap {}", m.max_overlap);
        assert!(
            m.iso_gap.unsigned_abs() as f64 <= 0.03 * m.n_dof as f64,
            "{m:?}"
        );
    }
}
