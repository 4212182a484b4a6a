//! Small random packings: every method's output is exactly jammed by the core's analysis.

mod common;

use packbench_core::analysis::{AnalysisOptions, analyze};
use packbench_core::run::{NullObserver, Observer};
use packbench_core::{Container, Packing, SizeDistribution};
use packbench_exact_jamming::{JammingError, calippso, closest_jammed, closest_jammed_qp};
use std::sync::atomic::AtomicBool;

fn bidisperse() -> SizeDistribution {
    SizeDistribution::Bidisperse {
        d1: 1.0,
        d2: 1.4,
        p: 0.5,
    }
}

#[test]
fn closest_jammed_outputs_are_isostatic_and_force_balanced() {
    for seed in [1, 2] {
        let p = common::random_start(40, 2, 0.3, seed, bidisperse());
        let out = closest_jammed::run(&p, &Default::default(), &mut NullObserver).unwrap();
        assert_eq!(out.termination, "jammed");
        common::assert_exactly_jammed(&out.packing, "closest-jammed 2D");
        assert!(
            out.extra["total_velocity_max"].as_f64().unwrap() < 1e-10,
            "eqn 12"
        );
    }
    let p = common::random_start(30, 3, 0.3, 2, SizeDistribution::Mono { d: 1.0 });
    let out = closest_jammed::run(&p, &Default::default(), &mut NullObserver).unwrap();
    let m = common::assert_exactly_jammed(&out.packing, "closest-jammed 3D");
    // Thirty equal spheres jam below the large-N 0.64: the exact methods gave 0.603–0.641
    // (0.623 ± 0.010) from φ = 0.3 starts, seeds 1–12.
    assert!(m.phi > 0.59 && m.phi < 0.66, "{}", m.phi);
}

/// A jammed packing shrunk by 1e-3 in diameter, as a start made by compression: every contact
/// of its network is a near pair but none is a bond yet, so the factorisation's pattern holds
/// only the closest of them and is rebuilt as the bonds form. The packing jams again next to
/// where it was.
#[test]
fn a_shrunk_jammed_packing_jams_again_nearby() {
    let p = common::random_start(60, 3, 0.3, 2, SizeDistribution::Mono { d: 1.0 });
    let jammed = calippso::run(&p, &Default::default(), &mut NullObserver).unwrap();
    let phi_jammed = common::assert_exactly_jammed(&jammed.packing, "calippso").phi;
    let mut start = jammed.packing.clone();
    start.scale_diameters(1.0 - 1e-3);
    let out = closest_jammed::run(&start, &Default::default(), &mut NullObserver).unwrap();
    assert_eq!(out.termination, "jammed");
    let m = common::assert_exactly_jammed(&out.packing, "closest-jammed from a shrunk packing");
    assert!(
        (m.phi - phi_jammed).abs() < 1e-3,
        "{} against {phi_jammed}",
        m.phi
    );
    let patterns = out.extra["step_counts"]["patterns"].as_u64().unwrap();
    assert!(patterns > 1, "the pattern was never rebuilt ({patterns})");
}

/// Item 3's cross-validation where it is sharp: from a start next to a jammed packing (its
/// centres moved by up to 2e-5 diameters, as an energy minimiser leaves them, then shrunk to be
/// overlap-free, 1e-4 below in φ), every exact method comes back to that jammed state, φ_J equal
/// to 1e-9 relative: closest-jammed, its QP form solved by clarabel and as an active set
/// (`open_tensile_bonds`), and calippso. A jammed packing is an isolated maximum of φ, so any
/// exact method started in its basin should find it (at N = 1000 from an ADAM start the four
/// agree to 3e-10 where they finish, docs/BENCHMARKS.md#known-limits).
#[test]
fn every_exact_method_agrees_next_to_jamming() {
    let p = common::random_start(60, 3, 0.3, 2, SizeDistribution::Mono { d: 1.0 });
    let jammed = calippso::run(&p, &Default::default(), &mut NullObserver).unwrap();
    let phi_jammed = common::assert_exactly_jammed(&jammed.packing, "calippso").phi;
    let mut moved = jammed.packing.clone();
    let amplitude = 2e-5 * moved.diameters[0];
    // A deterministic scatter in [−1, 1) per coordinate (golden-ratio sequence).
    for (k, x) in moved.positions.iter_mut().enumerate() {
        let u = (k as f64 * 0.618_033_988_749_895).fract() * 2.0 - 1.0;
        *x += amplitude * u;
    }
    moved.wrap_positions();
    let start = packbench_exact_jamming::shrink_to_overlap_free(&moved, 1e-6).unwrap();
    assert!(start.phi() < phi_jammed - 5e-5, "start {}", start.phi());
    let open = closest_jammed::Params {
        open_tensile_bonds: true,
        ..Default::default()
    };
    let outputs = [
        (
            "closest-jammed",
            closest_jammed::run(&start, &Default::default(), &mut NullObserver),
        ),
        (
            "closest-jammed, QP form as an active set",
            closest_jammed::run(&start, &open, &mut NullObserver),
        ),
        (
            "closest-jammed, QP form by clarabel",
            closest_jammed_qp::run(&start, &Default::default(), &mut NullObserver),
        ),
        (
            "calippso",
            calippso::run(&start, &Default::default(), &mut NullObserver),
        ),
    ];
    for (what, out) in outputs {
        let out = out.unwrap_or_else(|e| panic!("{what}: {e}"));
        let phi = common::assert_exactly_jammed(&out.packing, what).phi;
        assert!(
            ((phi - phi_jammed) / phi_jammed).abs() < 1e-9,
            "{what} {phi} against the jammed {phi_jammed} (start {})",
            start.phi()
        );
    }
}

/// A run stopped early (step budget or interrupt) returns an overlap-free packing: it stops
/// between steps with every contact admitted, and its bonds are projected onto contact, so no
/// bond keeps the overshoot allowed to the contact that ended the last step (before, stops after
/// 200, 350 and 600 steps here left bonds at −4.5e-8, −9.9e-7 and −5.0e-7, and an interrupted
/// N = 2000 lognormal run a pair at −2.2e-7).
#[test]
fn closest_jammed_stopped_early_overlaps_nowhere() {
    let p = common::random_start(100, 3, 0.3, 2, SizeDistribution::Mono { d: 1.0 });
    let quick = AnalysisOptions {
        force_balance: false,
        ..Default::default()
    };
    let mut worst = (0.0, 0);
    for max_steps in (50..=600).step_by(50) {
        let params = closest_jammed::Params {
            max_steps,
            ..Default::default()
        };
        let out = closest_jammed::run(&p, &params, &mut NullObserver).unwrap();
        let overlap = analyze(&out.packing, &quick).unwrap().max_overlap;
        if overlap > worst.0 {
            worst = (overlap, max_steps);
        }
    }
    assert!(
        worst.0 <= 1e-12,
        "overlap {} after {} steps",
        worst.0,
        worst.1
    );
}

/// 3D starts whose bond manifold folds before jamming (the minimum-norm velocities diverge and
/// the bonds cannot all stay in contact): seeds 3 and 8 used to fail with "projection
/// diverged"; a tensile bond is now released at the fold.
#[test]
fn closest_jammed_passes_folds_of_the_bond_manifold() {
    for seed in [3, 8] {
        let p = common::random_start(30, 3, 0.3, seed, SizeDistribution::Mono { d: 1.0 });
        let out = closest_jammed::run(&p, &Default::default(), &mut NullObserver).unwrap();
        assert_eq!(out.termination, "jammed");
        assert!(out.extra["bonds_released"].as_u64().unwrap() > 0);
        common::assert_exactly_jammed(&out.packing, "closest-jammed 3D fold");
    }
}

/// The most tensile release rule, no longer the default, ends exactly jammed too (100 spheres
/// make about 300 bonds, so the solves run on a sparse factor).
#[test]
fn most_tensile_release_rule_jams() {
    let params = closest_jammed::Params {
        release_rule: closest_jammed::ReleaseRule::MostTensile,
        ..Default::default()
    };
    let p = common::random_start(100, 3, 0.3, 1, SizeDistribution::Mono { d: 1.0 });
    let out = closest_jammed::run(&p, &params, &mut NullObserver).unwrap();
    assert_eq!(out.termination, "jammed");
    assert!(out.extra["bonds_released"].as_u64().unwrap() > 0);
    let m = common::assert_exactly_jammed(&out.packing, "closest-jammed, most tensile release");
    // A hundred equal spheres under this rule: 0.627–0.646 (0.634 ± 0.006) from φ = 0.3
    // starts, seeds 1–8.
    assert!(m.phi > 0.61 && m.phi < 0.66, "{}", m.phi);
}

/// With factor updates (the preconditioning factor kept by CHOLMOD row updates, no border)
/// and the default refactorisation bound, the run takes the same path as with bordered
/// factors: the same steps and φ_J to the last digits, exactly jammed. With a looser bound
/// the path may differ, but the packing still jams exactly. Needs the `cholmod` feature.
#[cfg(feature = "cholmod")]
#[test]
fn factor_updates_keep_the_path_and_jam_exactly() {
    // Sixty spheres make about 180 bonds: the solves run on the sparse factor.
    let p = common::random_start(60, 3, 0.3, 1, SizeDistribution::Mono { d: 1.0 });
    let bordered = closest_jammed::run(&p, &Default::default(), &mut NullObserver).unwrap();
    let updates = closest_jammed::Params {
        factor_updates: true,
        ..Default::default()
    };
    let updated = closest_jammed::run(&p, &updates, &mut NullObserver).unwrap();
    assert_eq!(updated.termination, "jammed");
    assert_eq!(updated.steps, bordered.steps);
    let row_updates = |o: &packbench_core::run::Outcome| {
        o.extra["step_counts"]["factor_row_updates"]
            .as_u64()
            .unwrap()
    };
    assert!(row_updates(&updated) > 0, "the factor was never updated");
    assert_eq!(row_updates(&bordered), 0);
    let m = common::assert_exactly_jammed(&updated.packing, "closest-jammed, factor updates");
    let m0 = common::assert_exactly_jammed(&bordered.packing, "closest-jammed");
    assert!(
        (m.phi - m0.phi).abs() < 1e-12,
        "{} against {}",
        m.phi,
        m0.phi
    );
    let loose = closest_jammed::Params {
        refactor_iterations: 8,
        ..updates
    };
    let out = closest_jammed::run(&p, &loose, &mut NullObserver).unwrap();
    assert_eq!(out.termination, "jammed");
    let m1 = common::assert_exactly_jammed(&out.packing, "closest-jammed, factor updates, bound 8");
    // Restarted from its jammed packing, every contact waits to be admitted: each joins the
    // updated factor (in a slot kept for the waiting contacts), and the packing stays put.
    let again = closest_jammed::run(&out.packing, &loose, &mut NullObserver).unwrap();
    assert_eq!(again.termination, "jammed");
    assert!(row_updates(&again) > 0, "the factor was never updated");
    let m2 = common::assert_exactly_jammed(&again.packing, "closest-jammed restarted, updates");
    assert!(
        (m2.phi - m1.phi).abs() < 1e-9,
        "{} against {}",
        m2.phi,
        m1.phi
    );
}

/// Without the `cholmod` feature, factor updates are refused before the run with a sentence
/// that names the feature, instead of silently running without them.
#[cfg(not(feature = "cholmod"))]
#[test]
fn factor_updates_without_cholmod_are_refused() {
    let p = common::random_start(20, 3, 0.3, 1, SizeDistribution::Mono { d: 1.0 });
    let updates = closest_jammed::Params {
        factor_updates: true,
        ..Default::default()
    };
    let err = closest_jammed::run(&p, &updates, &mut NullObserver).unwrap_err();
    assert!(err.to_string().contains("--features cholmod"), "{err}");
}

#[test]
fn calippso_outputs_are_isostatic_and_force_balanced() {
    for (n, d, seed) in [(40, 2, 1), (60, 3, 1), (30, 3, 3)] {
        let dist = if d == 2 {
            bidisperse()
        } else {
            SizeDistribution::Mono { d: 1.0 }
        };
        let p = common::random_start(n, d, 0.3, seed, dist);
        let out = calippso::run(&p, &Default::default(), &mut NullObserver).unwrap();
        assert_eq!(out.termination, "converged", "{:?}", out.extra);
        common::assert_exactly_jammed(&out.packing, "calippso");
        // The first LP makes every contact; the run converges on a network that the last LP
        // no longer changes.
        let changed = |row: &packbench_core::run::TraceRow| {
            row.values
                .iter()
                .find(|(k, _)| k == "contacts_changed")
                .map(|&(_, v)| v)
                .unwrap()
        };
        let first = out.trace.first().unwrap();
        let contacts = first
            .values
            .iter()
            .find(|(k, _)| k == "contacts")
            .unwrap()
            .1;
        assert!(changed(first) >= contacts, "{:?}", first.values);
        assert_eq!(changed(out.trace.last().unwrap()), 0.0, "{n} {d} {seed}");
    }
}

#[test]
fn calippso_jams_against_hard_walls() {
    let p = common::walled_start(30, 2, 0.3, 4);
    let out = calippso::run(&p, &Default::default(), &mut NullObserver).unwrap();
    assert_eq!(out.termination, "converged", "{:?}", out.extra);
    // Isostatic with the wall contacts counted (n_dof of a walled box), overlap-free, balanced.
    common::assert_exactly_jammed(&out.packing, "calippso between hard walls");
}

#[test]
fn qp_form_jams_small_packings() {
    let p = common::random_start(20, 2, 0.3, 3, bidisperse());
    let out = closest_jammed_qp::run(&p, &Default::default(), &mut NullObserver).unwrap();
    assert_eq!(out.termination, "jammed");
    common::assert_exactly_jammed(&out.packing, "closest-jammed-qp 2D");
    assert!(out.extra.contains_key("bonds_opened"));
}

/// Records the largest overlap of every step's packing.
struct OverlapWatch(f64);
impl Observer for OverlapWatch {
    fn snapshot(&mut self, _step: u64, packing: &Packing) {
        let quick = AnalysisOptions {
            force_balance: false,
            ..Default::default()
        };
        self.0 = self.0.max(analyze(packing, &quick).unwrap().max_overlap);
    }
}

/// A pair that the projection of the bonds moves to contact between the QP and the step was
/// once left out of both, and overlapped freely (3D Poisson starts failed with "projection
/// diverged" at φ ≈ 0.98). Now such a pair touches at once and joins the next QP, so no step
/// overlaps by more than what one projection can push it in (~1e-9 relative; the jammed output
/// is checked at 1e-9 as before).
#[test]
fn qp_form_overlaps_at_no_step() {
    for seed in [1, 2] {
        let p = common::random_start(16, 3, 0.3, seed, SizeDistribution::Mono { d: 1.0 });
        let params = closest_jammed_qp::Params {
            save_interval: 1,
            ..Default::default()
        };
        let mut watch = OverlapWatch(0.0);
        let out = closest_jammed_qp::run(&p, &params, &mut watch).unwrap();
        assert_eq!(out.termination, "jammed");
        assert!(
            watch.0 <= 1e-8,
            "seed {seed}: overlap {} at some step",
            watch.0
        );
        common::assert_exactly_jammed(&out.packing, "qp 3D");
    }
}

/// A step's projection bends the path; it once pushed pairs that were no bonds into overlap
/// unchecked (up to 19 % at N = 1000 under the minimum-norm rule, and the run froze). Now such
/// a step is shortened, and a new bond still apart after an undone admission projection is not
/// admitted (closing it would push the released bond's pair in: 5 times, by up to 2e-4, on this
/// start). So every step's packing overlaps by no more than the overshoot allowed to the contact
/// that ends the step (1e-6 relative), under either release rule.
#[test]
fn closest_jammed_overlaps_at_no_step() {
    for rule in [
        closest_jammed::ReleaseRule::MostTensile,
        closest_jammed::ReleaseRule::MinimumNorm,
    ] {
        let params = closest_jammed::Params {
            release_rule: rule,
            save_interval: 1,
            ..Default::default()
        };
        let p = common::random_start(100, 3, 0.3, 2, SizeDistribution::Mono { d: 1.0 });
        let mut watch = OverlapWatch(0.0);
        let out = closest_jammed::run(&p, &params, &mut watch).unwrap();
        assert_eq!(out.termination, "jammed");
        assert!(
            watch.0 <= 1e-6,
            "{rule:?}: overlap {} at some step",
            watch.0
        );
        common::assert_exactly_jammed(&out.packing, "closest-jammed, every step");
    }
}

#[test]
fn runs_are_deterministic() {
    let p = common::random_start(30, 2, 0.3, 5, bidisperse());
    let a = closest_jammed::run(&p, &Default::default(), &mut NullObserver).unwrap();
    let b = closest_jammed::run(&p, &Default::default(), &mut NullObserver).unwrap();
    assert_eq!(a.packing, b.packing);
    let a = calippso::run(&p, &Default::default(), &mut NullObserver).unwrap();
    let b = calippso::run(&p, &Default::default(), &mut NullObserver).unwrap();
    assert_eq!(a.packing, b.packing);
}

/// The same start gives the same bytes whatever rayon's thread count (faer's dense SVD once
/// took its blocking from it;), on a 3D start whose first 48 bonds use the
/// dense pseudoinverse.
#[test]
fn runs_are_the_same_on_one_and_two_threads() {
    let p = common::random_start(60, 3, 0.3, 5, SizeDistribution::Mono { d: 1.0 });
    let run_on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let out = pool.install(|| closest_jammed::run(&p, &Default::default(), &mut NullObserver));
        let packing = out.unwrap().packing;
        let bits: Vec<u64> = packing
            .positions
            .iter()
            .chain(&packing.diameters)
            .map(|v| v.to_bits())
            .collect();
        bits
    };
    assert_eq!(run_on(1), run_on(2));
}

#[test]
fn a_single_particle_jams_against_its_own_images() {
    // One disk in a unit periodic square touches its own images at D = 1: φ = π/4.
    let c = Container::periodic_box(&[1.0, 1.0]).unwrap();
    let p = Packing::new(vec![0.3, 0.4], vec![0.1], c).unwrap();
    let out = closest_jammed::run(&p, &Default::default(), &mut NullObserver).unwrap();
    assert_eq!(out.termination, "jammed");
    assert!((out.packing.phi() - std::f64::consts::PI / 4.0).abs() < 1e-12);
    let out = calippso::run(&p, &Default::default(), &mut NullObserver).unwrap();
    assert!((out.packing.phi() - std::f64::consts::PI / 4.0).abs() < 1e-9);
}

#[test]
fn bad_input_gets_clear_errors() {
    let c = Container::periodic_box(&[4.0, 4.0]).unwrap();
    let overlapping = Packing::new(vec![1.0, 1.0, 1.5, 1.0], vec![1.0, 1.0], c).unwrap();
    let e = closest_jammed::run(&overlapping, &Default::default(), &mut NullObserver).unwrap_err();
    assert!(matches!(e, JammingError::Overlap { .. }), "{e}");
    let e = calippso::run(&overlapping, &Default::default(), &mut NullObserver).unwrap_err();
    assert!(matches!(e, JammingError::Overlap { .. }), "{e}");
    let p = common::random_start(5, 2, 0.2, 1, bidisperse());
    let params = closest_jammed::Params {
        max_growth_step: f64::NAN,
        ..Default::default()
    };
    let e = closest_jammed::run(&p, &params, &mut NullObserver).unwrap_err();
    assert!(e.to_string().contains("max_growth_step"), "{e}");
    let params = calippso::Params {
        ell0: 1.0,
        ..Default::default()
    };
    let e = calippso::run(&p, &params, &mut NullObserver).unwrap_err();
    assert!(e.to_string().contains("ell0"), "{e}");
}

/// A stop request raised while an LP is being solved: `should_stop` is never asked again, so
/// only clarabel's callback, polling the flag between interior-point iterations, can end the run
/// (at N = 10⁴ one LP takes minutes, and Ctrl-C used to wait for it).
struct StopInsideLp;
static STOP_INSIDE_LP: AtomicBool = AtomicBool::new(true);
impl Observer for StopInsideLp {
    fn stop_flag(&self) -> Option<&'static AtomicBool> {
        Some(&STOP_INSIDE_LP)
    }
    // `should_stop` is never true, so only clarabel's callback can see the flag.
    fn should_stop(&self) -> bool {
        false
    }
}

#[test]
fn calippso_stops_inside_an_lp() {
    let p = common::random_start(40, 3, 0.3, 1, SizeDistribution::Mono { d: 1.0 });
    let out = calippso::run(&p, &Default::default(), &mut StopInsideLp).unwrap();
    assert_eq!(out.termination, "interrupted");
    assert_eq!(out.extra["lp_count"], 0);
    // The packing is the start, still overlap-free.
    assert!(common::metrics(&out.packing).max_overlap <= 1e-12);
}

/// Asks the run to stop at every question after the first `after`.
struct StopAfter {
    asked: std::cell::Cell<u32>,
    after: u32,
}
impl Observer for StopAfter {
    fn should_stop(&self) -> bool {
        self.asked.set(self.asked.get() + 1);
        self.asked.get() > self.after
    }
}

/// From a start at contact every contact of the start waits for its admission before the first
/// step (at N = 10⁴ that took minutes, during which Ctrl-C, `timeout` and Slurm's SIGTERM went
/// unheeded): an interrupt there ends the run at once, with the start's packing overlap-free.
#[test]
fn closest_jammed_stops_while_admitting_the_start_contacts() {
    let p = common::random_start(60, 3, 0.3, 2, SizeDistribution::Mono { d: 1.0 });
    let start = calippso::run(&p, &Default::default(), &mut NullObserver)
        .unwrap()
        .packing;
    let contacts = common::assert_exactly_jammed(&start, "calippso").contacts;
    let mut stop = StopAfter {
        asked: Default::default(),
        after: 10,
    };
    let out = closest_jammed::run(&start, &Default::default(), &mut stop).unwrap();
    assert_eq!(out.termination, "interrupted");
    assert_eq!(out.steps, 0);
    let bonds = out.extra["bonds"].as_u64().unwrap() as usize;
    assert!(
        (1..contacts).contains(&bonds),
        "{bonds} bonds of {contacts} contacts"
    );
    assert!(common::metrics(&out.packing).max_overlap <= 1e-12);
}

/// The QP form solved as an active set (`open_tensile_bonds`: every bond whose multiplier turns
/// tensile opens) ends exactly jammed from far starts. Near a fold of the bond manifold a step's
/// projection can carry the contact that ended the step apart again; such a pair was once
/// admitted as a bond anyway, and the run ended at a false fold one or two bonds short, with the
/// final projection pushing other pairs into overlap (N = 1000: iso_gap −1, overlap 7e-6).
#[test]
fn qp_form_as_an_active_set_jams_exactly() {
    let open = closest_jammed::Params {
        open_tensile_bonds: true,
        ..Default::default()
    };
    for (n, seed) in (1..=10).map(|s| (30, s)).chain([(100, 1)]) {
        let p = common::random_start(n, 3, 0.3, seed, SizeDistribution::Mono { d: 1.0 });
        let out = closest_jammed::run(&p, &open, &mut NullObserver).unwrap();
        assert_eq!(out.termination, "jammed", "N = {n}, seed {seed}");
        common::assert_exactly_jammed(
            &out.packing,
            &format!("active-set QP form, N = {n}, seed {seed}"),
        );
    }
}

/// `packbench pack --method closest-jammed --N 100 --Ndim 2 --seed 1`'s start (the CLI's
/// default scene, φ = 0.05, shrunk free of overlaps by 1e-3): it once repeated a step of length
/// zero for 240 000 steps at 189 non-rattler bonds = n_dof, its conjugate-gradient velocities
/// closing a pair that the admission found separating. That start now jams by the core's
/// analysis after its growth stops (next test); seed 2 of the same scene jams on its own. The core counts more contacts than bonds:
/// monodisperse disks order into triangular
/// patches whose extra contacts are exact (the same count at a contact tolerance of 1e-12 as
/// at 1e-6), so the packing is hyperstatic, not short of contacts.
#[test]
fn the_100_disk_start_that_repeated_a_step_jams() {
    let p = common::random_start(100, 2, 0.05, 2, SizeDistribution::Mono { d: 1.0 });
    let out = closest_jammed::run(&p, &Default::default(), &mut NullObserver).unwrap();
    assert_eq!(out.termination, "jammed");
    assert!(out.steps < 10_000, "{} steps", out.steps);
    // Rigid: at least n_dof bonds among non-rattlers (more where disks order into patches).
    assert!(
        out.extra["non_rattler_bonds"]
            .as_u64()
            .expect("non_rattler_bonds")
            >= out.extra["n_dof"].as_u64().expect("n_dof"),
        "{:?}",
        out.extra
    );
    let m = common::strict_metrics(&out.packing);
    assert!(m.max_overlap <= 1e-9, "overlap {}", m.max_overlap);
    assert!(m.force_balance.unwrap() <= 1e-8, "{m:?}");
    // Not iso_gap == 0: equal disks order into triangular patches whose extra contacts are
    // exact, so the packing is hyperstatic (never short of contacts) at contact tolerance 1e-9.
    assert!(m.iso_gap >= 0, "{m:?}");
    let exact = AnalysisOptions {
        contact_tol: 1e-12,
        force_balance: false,
    };
    assert_eq!(analyze(&out.packing, &exact).unwrap().iso_gap, m.iso_gap);
}

/// The start that once repeated a step 240 000 times (seed 1 of the scene) ends jammed within
/// 20 000 steps, overlap-free. Its crystal-patched packing is rigid before the integrator's own
/// test can say so (an extra bond it cannot tell from a dependent one), so the growth stops;
/// after 10 000 steps without growth the core's analysis, force balance included, decides,
/// and finds it jammed (`extra.jammed_by_analysis`). Where rounding takes another path the
/// integrator's own test may jam it first; either way the core's verdict holds.
#[test]
fn the_start_that_repeated_a_step_jams() {
    let p = common::random_start(100, 2, 0.05, 1, SizeDistribution::Mono { d: 1.0 });
    let out = closest_jammed::run(&p, &Default::default(), &mut NullObserver).unwrap();
    assert!(out.steps < 20_000, "{} steps", out.steps);
    assert_eq!(out.termination, "jammed", "{:?}", out.extra);
    if let Some(why) = out.extra.get("jammed_by_analysis") {
        let why = why.as_str().unwrap();
        assert!(why.contains("force balance"), "{why}");
        assert!(out.extra["stall"].as_str().is_some(), "{:?}", out.extra);
    }
    let m = common::strict_metrics(&out.packing);
    assert!(m.max_overlap <= 1e-9, "overlap {}", m.max_overlap);
    // Not iso_gap == 0: the packing is crystal-patched and hyperstatic (above), at contact
    // tolerance 1e-9 as at 1e-12.
    assert!(m.iso_gap >= 0, "{m:?}");
    assert!(m.force_balance.unwrap() <= 1e-8, "{m:?}");
    // 2D monodisperse disks jam near φ ≈ 0.84–0.86 (crystal patches push it up).
    assert!((0.82..0.88).contains(&m.phi), "φ = {}", m.phi);
}

/// The start of `packbench pack --method closest-jammed --N 100 --Ndim 2 --seed 5` (written by
/// `packbench init` with those flags): its bonds once cycled through a degenerate
/// configuration, one release per step for 10 000 steps without growth, and the run ended
/// `stalled` with a force-balance residual of 3e-4. After `CYCLING_STEPS` steps without growth
/// one quadratic program over every contact now chooses the bonds, and it jams by the
/// integrator's own Farkas test, exactly, in about 3 000 steps.
#[test]
fn the_100_disk_start_whose_bonds_cycled_jams() {
    let p = disks_in_unit_box(
        "disks100_cli_seed5.txt",
        include_str!("data/disks100_cli_seed5.txt"),
    );
    let out = closest_jammed::run(&p, &Default::default(), &mut NullObserver).unwrap();
    assert_eq!(out.termination, "jammed", "{:?}", out.extra);
    assert!(
        out.extra.get("jammed_by_analysis").is_none(),
        "{:?}",
        out.extra
    );
    assert!(
        out.extra["step_counts"]["cycles_left"].as_u64().unwrap() >= 1,
        "{:?}",
        out.extra
    );
    assert!(
        out.extra["min_force_ratio"].as_f64().unwrap() > -1e-9,
        "{:?}",
        out.extra
    );
    // Not iso_gap == 0: equal disks order into triangular patches, and the jammed packing is
    // hyperstatic at contact tolerance 1e-9 (measured: iso_gap 36, force balance 7e-17).
    let m = common::strict_metrics(&out.packing);
    assert!(m.iso_gap >= 0, "{m:?}");
    assert!(m.max_overlap <= 1e-9, "overlap {}", m.max_overlap);
    assert!(m.force_balance.unwrap() <= 1e-8, "{m:?}");
    assert!((0.82..0.88).contains(&m.phi), "φ = {}", m.phi);
}

/// The start of `pack --method closest-jammed-qp --N 30 --Ndim 2 --seed 2` (equal disks, which
/// crystallise in patches) ended in an error, "projecting the bonds onto contact diverged":
/// twice on the way, the QP held bonds dependent more than once, whose gaps no correction
/// closes. Those steps go on unprojected (`projections_skipped`; the bonds are within the
/// contact tolerance and the next QP sees them). Since the steps' QPs are solved by an active
/// set first, whose held sets are independent, this start no longer meets such a set (0
/// skipped projections, with or without the hold band); the run must still jam exactly.
#[test]
fn the_30_disk_qp_start_that_failed_to_project_jams() {
    let p = disks_in_unit_box(
        "disks30_cli_seed2.txt",
        include_str!("data/disks30_cli_seed2.txt"),
    );
    let out = closest_jammed_qp::run(&p, &Default::default(), &mut NullObserver).unwrap();
    assert_eq!(out.termination, "jammed", "{:?}", out.extra);
    assert!(
        out.extra["final_bond_gap"].as_f64().unwrap() < 1e-12,
        "{:?}",
        out.extra
    );
    // Not iso_gap == 0: thirty equal disks jam as a nearly hexagonal crystal (φ 0.8901), one
    // contact above n_dof at contact tolerance 1e-9 (measured before and after the hold band
    // of the QP form; force balance 2e-17).
    let m = common::strict_metrics(&out.packing);
    assert!(m.iso_gap >= 0, "{m:?}");
    assert!(m.max_overlap <= 1e-9, "overlap {}", m.max_overlap);
    assert!(m.force_balance.unwrap() <= 1e-8, "{m:?}");
}

/// A 2D start written by `packbench init` (unit periodic box), kept under tests/data.
fn disks_in_unit_box(name: &str, text: &str) -> Packing {
    let box2 = Container::periodic_box(&[1.0, 1.0]).unwrap();
    packbench_core::format::read_packing(name, text, &box2).unwrap()
}

/// Two exact runs at once (as `compare --jobs 2` makes them) give the bytes each gives alone.
/// Their factorisations order the bond and LP matrices with METIS, whose random generator is
/// process-wide: before its calls were serialised, concurrent runs took each other's draws and
/// their paths (a 6D closest-jammed run once ended with an overlap of 0.76).
#[test]
fn concurrent_runs_equal_runs_made_alone() {
    let p = common::random_start(150, 3, 0.3, 7, SizeDistribution::Mono { d: 1.0 });
    let bits = |packing: &Packing| -> Vec<u64> {
        packing
            .positions
            .iter()
            .chain(&packing.diameters)
            .map(|v| v.to_bits())
            .collect()
    };
    let cj = || closest_jammed::run(&p, &Default::default(), &mut NullObserver).unwrap();
    let lp = || calippso::run(&p, &Default::default(), &mut NullObserver).unwrap();
    let (cj_alone, lp_alone) = (cj(), lp());
    assert_eq!(cj_alone.termination, "jammed");
    assert_eq!(lp_alone.termination, "converged");
    let (cj_together, lp_together) = std::thread::scope(|s| {
        let a = s.spawn(cj);
        let b = s.spawn(lp);
        (a.join().unwrap(), b.join().unwrap())
    });
    assert_eq!(bits(&cj_together.packing), bits(&cj_alone.packing));
    assert_eq!(bits(&lp_together.packing), bits(&lp_alone.packing));
}

/// The start of `pack --method adam --N 100 --Ndim 3 --seed 3` (3D, equal spheres, a few
/// overlaps of 5e-4 that `pack` shrinks away): the QP form cycled on it, opening and closing
/// the same bonds for 10 110 steps (25 584 bonds opened) where the equality form takes 356.
/// Near a fold of the contact network the QP's velocities grow to 10³ D per unit t, and a step
/// opened the contacts the QP left inactive far past `contact_tol`; they dropped out of the
/// next QP, whose velocities closed them again one step at a time. A pair constrained in the
/// last QP now stays constrained while its gap is within `hold_band`
/// (docs/notes/closest-jammed-qp-cycling.md). The bound of 2 000 QPs was set before any fix
/// was run; the packing must be exactly jammed at contact tolerance 1e-9 with the QP's own
/// certificate.
#[test]
fn the_qp_form_does_not_cycle_on_the_100_sphere_adam_start() {
    let cube = Container::periodic_box(&[1.0, 1.0, 1.0]).unwrap();
    let text = include_str!("data/adam100_3d_seed3.txt");
    let p = packbench_core::format::read_packing("adam100_3d_seed3.txt", text, &cube).unwrap();
    let p = packbench_exact_jamming::shrink_to_overlap_free(&p, 1e-3).unwrap();
    let out = closest_jammed_qp::run(&p, &Default::default(), &mut NullObserver).unwrap();
    assert_eq!(out.termination, "jammed", "{:?}", out.extra);
    assert!(
        out.extra.get("jammed_by_analysis").is_none(),
        "{:?}",
        out.extra
    );
    let qps = out.extra["qp_count"].as_u64().unwrap();
    assert!(qps <= 2000, "{qps} QPs: {:?}", out.extra);
    let m = common::assert_exactly_jammed(&out.packing, "closest-jammed-qp, adam start");
    assert_eq!(m.iso_gap, 0);
    assert!(m.max_overlap <= 1e-9, "overlap {}", m.max_overlap);
}
