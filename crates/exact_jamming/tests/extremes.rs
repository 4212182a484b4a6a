//! Stability at the extremes: a slab thinner than two diameters, size ratios near five, boxes
//! shorter than two diameters, a crystal in six dimensions, and eight dimensions (periodic and
//! walled). Every output is judged by the core's analysis.

mod common;

use packbench_core::run::NullObserver;
use packbench_core::{Container, Packing, SizeDistribution};
use packbench_exact_jamming::{calippso, closest_jammed};

fn equality_and_active_set() -> [(&'static str, closest_jammed::Params); 2] {
    [
        ("closest-jammed", closest_jammed::Params::default()),
        (
            "active-set QP form",
            closest_jammed::Params {
                open_tensile_bonds: true,
                ..Default::default()
            },
        ),
    ]
}

/// Both forms of closest-jammed and calippso from `start`: every output jammed, overlap-free
/// to 1e-9 and force-balanced to 1e-8 by the core's analysis at contact tolerance 1e-9, with
/// the iso_gap over non-rattlers checked by `iso_gap_ok` (0 unless the test says why not). Returns the outputs by method.
fn every_method_jams(
    start: &Packing,
    what: &str,
    iso_gap_ok: impl Fn(i64) -> bool,
) -> Vec<(&'static str, Packing)> {
    let mut outputs = Vec::new();
    for (name, params) in equality_and_active_set() {
        let out = closest_jammed::run(start, &params, &mut NullObserver).unwrap();
        assert_eq!(out.termination, "jammed", "{what}, {name}");
        outputs.push((name, out.packing));
    }
    let out = calippso::run(start, &Default::default(), &mut NullObserver).unwrap();
    assert_eq!(out.termination, "converged", "{what}, calippso");
    // Its own force check from the LP duals (with walls it once scaled the wall forces by
    // 1/t and reported imbalances of 4 to 18); 1.4e-8 on the hyperstatic monodisperse slab.
    let imbalance = out.extra["force_imbalance"].as_f64().unwrap();
    assert!(
        imbalance < 1e-6,
        "{what}: calippso's own imbalance {imbalance}"
    );
    outputs.push(("calippso", out.packing));
    for (name, p) in &outputs {
        let m = common::strict_metrics(p);
        assert!(m.max_overlap <= 1e-9, "{what}, {name}: overlap {m:?}");
        let fb = m.force_balance.unwrap();
        assert!(fb <= 1e-8, "{what}, {name}: force balance {fb}");
        assert!(iso_gap_ok(m.iso_gap), "{what}, {name}: iso_gap {m:?}");
    }
    outputs
}

/// A slab 0.28 thick between walls, periodic in x and y: the spheres (D ≈ 0.16 at jamming)
/// form two layers, each on a wall. Equal spheres order into hexagonal patches within a layer,
/// whose contacts are redundant (hyperstatic, iso_gap > 0 for every method). A redundant bond
/// of closest-jammed is held in contact only by the basis bonds it depends on; it was once
/// kept redundant after one of those was released at a dependent admission, drifted into
/// overlap, and two spheres ended at the same place (max_overlap 1.0). With two sizes the
/// layers stay disordered and the packings isostatic.
#[test]
fn a_thin_slab_jams_with_every_pair_apart() {
    let slab = || Container::with_flags(&[1.0, 1.0, 0.28], &[false, false, true]).unwrap();
    let mono = common::start_in(slab(), 60, 0.3, 1, SizeDistribution::Mono { d: 1.0 });
    every_method_jams(&mono, "monodisperse slab", |gap| gap >= 0);
    let two_sizes = SizeDistribution::Bidisperse {
        d1: 1.0,
        d2: 1.4,
        p: 0.5,
    };
    let bidisperse = common::start_in(slab(), 60, 0.3, 1, two_sizes);
    every_method_jams(&bidisperse, "bidisperse slab", |gap| gap == 0);
}

/// Size ratios of about five: disks 1:5 (nine small to one large), and a 3D log-normal
/// σ = 0.3 sample (ratio 4.6 over 150 spheres).
#[test]
fn a_size_ratio_of_five_jams_exactly() {
    let disks = SizeDistribution::Bidisperse {
        d1: 1.0,
        d2: 5.0,
        p: 0.9,
    };
    let start = common::random_start(60, 2, 0.3, 1, disks);
    every_method_jams(&start, "disks 1:5", |gap| gap == 0);
    let lognormal = SizeDistribution::Lognormal {
        mu: 0.0,
        sigma: 0.3,
    };
    let start = common::random_start(150, 3, 0.3, 1, lognormal);
    let ratio = start.max_diameter() / start.min_diameter();
    assert!(ratio > 4.0, "size ratio {ratio}");
    every_method_jams(&start, "log-normal σ = 0.3", |gap| gap == 0);
}

/// Boxes shorter than two of the largest diameters, where a pair touches through more than one
/// periodic image: 60 log-normal σ = 0.5 spheres in 3D, and 30 equal spheres in 6D. The core
/// once counted the minimum image only and saw iso_gap −3 to −29 and force balance ~1e-2 for
/// packings every method had jammed exactly.
#[test]
fn a_box_shorter_than_two_diameters_jams_exactly() {
    let lognormal = SizeDistribution::Lognormal {
        mu: 0.0,
        sigma: 0.5,
    };
    let start = common::random_start(60, 3, 0.3, 1, lognormal);
    every_method_jams(&start, "log-normal σ = 0.5, N = 60", |gap| gap == 0);
    let start = common::random_start(30, 6, 0.05, 2, SizeDistribution::Mono { d: 1.0 });
    every_method_jams(&start, "6D, N = 30", |gap| gap == 0);
}

/// 30 equal spheres in a 6D box (side 1.45 D at jamming) that order into a defective crystal,
/// hyperstatic by 30 to 50 contacts (2 of 24 starts). Its bond basis grows ill-conditioned,
/// and a row in its span once looked independent (1.2e-6 from it by the Gram solve,
/// tolerance 1e-6): the basis grew past the rank d·N − d and the run stalled for good (the
/// equality form from seed 1, the QP form from seed 4). With that fixed, the equality form
/// then cycled at a fold: each bond released there was replaced by a redundant partner that
/// the motion was opening. Each now jams, with a basis no larger than that rank.
#[test]
fn a_crystal_in_six_dimensions_jams() {
    let (n, d) = (30, 6);
    for (seed, (name, params)) in [1, 4].into_iter().zip(equality_and_active_set()) {
        let start = common::random_start(n, d, 0.05, seed, SizeDistribution::Mono { d: 1.0 });
        let out = closest_jammed::run(&start, &params, &mut NullObserver).unwrap();
        assert_eq!(out.termination, "jammed", "seed {seed}, {name}");
        let basis =
            out.extra["bonds"].as_u64().unwrap() - out.extra["bonds_redundant"].as_u64().unwrap();
        // The basis and the dependent bond that jammed it.
        assert!(
            basis as usize <= d * n - d + 1,
            "seed {seed}, {name}: {basis} bonds"
        );
        let m = common::strict_metrics(&out.packing);
        assert!(m.max_overlap <= 1e-9, "seed {seed}, {name}: {m:?}");
        assert!(
            m.force_balance.unwrap() <= 1e-8,
            "seed {seed}, {name}: {m:?}"
        );
        // Thirty spheres in 6D jam on either side of 0.25 depending on the path (0.2412 for
        // seed 1 with the sequential dense solve); far above the start's 0.05 either way, and
        // below the densest known 6D packing, the E6 lattice's 0.3729 (a defective crystal in
        // a box of 1.45 D is far from it). Not iso_gap == 0: the crystal is hyperstatic.
        assert!(
            m.iso_gap > 0 && m.phi > 0.2 && m.phi < 0.3729,
            "seed {seed}, {name}: {m:?}"
        );
    }
}

/// Twenty spheres in an 8D periodic box, where D ≈ 0.84 L at jamming: every pair touches
/// through several images, so the packings are far above isostatic (iso_gap 14 to 28). Listing
/// the images took a cube of 7⁸ shifts per pair, and no method finished in two minutes; it now
/// takes a few seconds.
#[test]
fn eight_dimensions_in_a_periodic_box() {
    let start = common::random_start(20, 8, 0.005, 1, SizeDistribution::Mono { d: 1.0 });
    every_method_jams(&start, "8D periodic, N = 20", |gap| gap >= 0);
}

/// Twenty spheres in an 8D box with hard walls (φ_J ≈ 0.006, with two rattlers): every
/// method exact to the core's analysis. Calippso once converged here with three contacts of a
/// corner particle at relative gaps of 1e-9 to 1e-7 and duals of 1e-10 to 1e-7, which the core
/// does not count (docs/notes/calippso-lp-solver.md): the interior-point solution of the
/// degenerate LP left that particle inside its allowed region. With lazy rows its
/// LPs list fewer rows, their centred solutions differ, and it jams exactly on this start,
/// with every contact closed to 1e-9 (before: iso_gap −1 and force balance 2e-4 at 1e-9).
#[test]
fn eight_dimensions_in_a_walled_box() {
    let start = common::walled_start(20, 8, 0.01, 1);
    // Not iso_gap == 0: the active-set QP form ends with one contact more than n_dof at
    // contact tolerance 1e-9 (measured iso_gap 1, force balance 6e-17, six rattlers), a
    // redundant contact closed exactly, so every method is held to ≥ 0 here.
    every_method_jams(&start, "8D walled, N = 20", |gap| gap >= 0);
}
