//! CALiPPSO's unit tests: exact jamming from small starts, the LP against a dense solve,
//! walls, curved walls, warm starts and the bound schedules.

use super::lp::*;
use super::network::CLOSE_TOL;
use super::*;
use packbench_core::init::initial_packing;
use packbench_core::scene::{Placement, Scene};
use packbench_core::{Container, SizeDistribution};

/// Asserts that the core finds `p` exactly jammed at contact tolerance 1e-9: isostatic, no
/// overlap above 1e-9, force balance within 1e-8.
fn assert_exactly_jammed(p: &Packing, what: &str) {
    use packbench_core::analysis::{AnalysisOptions, analyze};
    let m = analyze(
        p,
        &AnalysisOptions {
            contact_tol: 1e-9,
            force_balance: true,
        },
    )
    .unwrap();
    assert!(m.max_overlap <= 1e-9, "{what}: {m:?}");
    assert_eq!(m.iso_gap, 0, "{what}: {m:?}");
    assert!(m.force_balance.unwrap() <= 1e-8, "{what}: {m:?}");
}

/// A random placement (the core's initializer, which lets spheres overlap) of `n`
/// monodisperse spheres at packing fraction `phi` in `container`.
fn random_mono(container: Container, n: usize, phi: f64, seed: u64) -> Packing {
    let scene = Scene {
        n,
        distribution: SizeDistribution::Mono { d: 1.0 },
        container,
        phi,
        seed: Some(seed),
        placement: Placement::Random,
    };
    initial_packing(&scene, seed).unwrap()
}

/// [`random_mono`] shrunk until overlap-free (relative clearance 1e-3).
fn overlap_free_mono(container: Container, n: usize, phi: f64, seed: u64) -> Packing {
    crate::shrink_to_overlap_free(&random_mono(container, n, phi, seed), 1e-3).unwrap()
}

fn unit_cube() -> Container {
    Container::periodic_box(&[1.0; 3]).unwrap()
}

/// The state after `max_iters` LPs from a random start of `n` monodisperse spheres
/// (φ 0.3, shrunk until overlap-free) in a periodic unit cube.
fn after_lps(n: usize, seed: u64, max_iters: u64) -> Growth {
    let start = overlap_free_mono(unit_cube(), n, 0.3, seed);
    let few = Params {
        max_iters,
        ..Params::default()
    };
    let out = run(&start, &few, &mut packbench_core::run::NullObserver).unwrap();
    Growth::new(&out.packing, 0.5, 1e-9).unwrap()
}

fn solve(g: &Growth, scope: &LpScope) -> LpStep {
    solve_lp(g, scope, &[0, 1, 2], &Params::default(), None, None)
        .unwrap()
        .unwrap()
}

fn assert_same_gamma(step: &LpStep, full: &LpStep) {
    assert!(
        (step.g - full.g).abs() <= 1e-9 * full.g.abs().max(1e-3),
        "{} vs {}",
        step.g,
        full.g
    );
}

/// Curved walls: in a cylinder periodic along its axis and in a sphere the run
/// converges to a packing the core finds jammed, with every sphere inside the wall.
#[test]
fn jams_inside_a_cylinder_and_a_sphere() {
    for walls in [[-2, 0, 0], [-3, 0, 0]] {
        let container = Container::from_rcp_flags(&[1.0; 3], &walls).unwrap();
        let start = overlap_free_mono(container.clone(), 50, 0.3, 1);
        let out = run(
            &start,
            &Params::default(),
            &mut packbench_core::run::NullObserver,
        )
        .unwrap();
        assert_eq!(out.termination, "converged", "walls {walls:?}");
        let p = &out.packing;
        for (x, dia) in p.positions.chunks_exact(3).zip(&p.diameters) {
            assert!(
                container.contains(x, 0.5 * dia, 1e-9 * dia),
                "walls {walls:?}: outside"
            );
        }
        assert_exactly_jammed(p, &format!("walls {walls:?}"));
    }
}

/// `pack --method calippso --N 200 --Ndim 3 --seed 5`: an LP of this
/// start met a negative pivot in its normal equations and the run failed. It converges, and
/// the core finds its output exactly jammed.
#[test]
fn a_start_with_a_negative_pivot_converges_jammed() {
    use packbench_core::analysis::contact_network;
    let raw = random_mono(unit_cube(), 200, 0.05, 5);
    let start = if contact_network(&raw, 0.0).max_overlap > 1e-12 {
        crate::shrink_to_overlap_free(&raw, 1e-3).unwrap()
    } else {
        raw
    };
    let out = run(
        &start,
        &Params::default(),
        &mut packbench_core::run::NullObserver,
    )
    .unwrap();
    assert_eq!(out.termination, "converged");
    assert_exactly_jammed(&out.packing, "N = 200, seed 5");
}

/// The final network is closed to rounding: every contact of the output touches to 1e-13
/// and no other pair comes within 1e-9, so the core counts the same isostatic network at
/// any contact tolerance between. The same run left open (`close_network = false`) ends at
/// the same φ to 1e-12, with contacts open by more than that.
#[test]
fn the_final_network_is_closed_to_rounding() {
    use packbench_core::analysis::{AnalysisOptions, analyze, contact_network};
    let start = overlap_free_mono(unit_cube(), 300, 0.5, 2);
    let jam = |close_network| {
        let params = Params {
            close_network,
            ..Params::default()
        };
        let out = run(&start, &params, &mut packbench_core::run::NullObserver).unwrap();
        assert_eq!(out.termination, "converged");
        out
    };
    let (closed, open) = (jam(true), jam(false));
    let gap = closed.extra["closed_gap"].as_f64().unwrap();
    assert!(gap <= CLOSE_TOL, "closed to {gap}");
    assert!(open.extra["closed_gap"].is_null());
    let iso_gap = |p: &Packing, contact_tol| {
        let options = AnalysisOptions {
            contact_tol,
            force_balance: false,
        };
        analyze(p, &options).unwrap().iso_gap
    };
    for tol in [1e-13, 1e-11, 1e-9] {
        assert_eq!(iso_gap(&closed.packing, tol), 0, "contact tolerance {tol}");
    }
    assert!(contact_network(&closed.packing, 0.0).max_overlap <= 1e-13);
    let widest = |p: &Packing| {
        contact_network(p, 1e-9)
            .contacts
            .iter()
            .map(|c| c.gap.abs())
            .fold(0.0, f64::max)
    };
    assert!(widest(&closed.packing) <= 1e-13);
    assert!(widest(&open.packing) > 1e-13, "{}", widest(&open.packing));
    assert!((closed.packing.phi() - open.packing.phi()).abs() <= 1e-12);
    // The reported network is the better balanced of the last LP's and the fine-tuning's.
    let imbalance = |key: &str| closed.extra[key].as_f64().unwrap();
    assert!(imbalance("force_imbalance") <= imbalance("force_imbalance_lp"));
}

/// from a random start of 300 spheres (φ 0.5, seed 1) the seed's schedule has
/// the bound binding and not binding in turn (15 switches); the trust region grows the
/// bound while it binds and the model agrees, and switches far less (1). Both outputs are
/// exactly jammed. The LP counts are not compared: the seed schedule's path here is
/// chaotic in rounding (130 LPs on one machine, 87 on the CI machine, against the trust
/// region's 100 on both), and at N = 1000 the trust region takes more LPs (BENCHMARKS).
#[test]
fn the_trust_region_switches_less_than_the_seed_schedule() {
    let start = overlap_free_mono(unit_cube(), 300, 0.5, 1);
    let [seed, trust] = [BoundSchedule::Seed, BoundSchedule::TrustRegion].map(|schedule| {
        let p = Params {
            bound_schedule: schedule,
            ..Params::default()
        };
        let out = run(&start, &p, &mut packbench_core::run::NullObserver).unwrap();
        assert_eq!(out.termination, "converged", "{schedule:?}");
        assert_exactly_jammed(&out.packing, &format!("{schedule:?}"));
        out.extra["bound_switches"].as_u64().unwrap()
    });
    assert!(trust < seed, "switches: trust region {trust}, seed {seed}");
}

/// near jamming, an LP warm-started from the previous LP's duals reaches the
/// optimum the cold start reaches, in far fewer interior-point iterations. The start is
/// near-jammed as an ADAM packing is: a jammed packing of 200 spheres with every centre
/// moved by up to 2·10⁻³ D, shrunk until overlap-free; two LPs bring it to the creep.
#[test]
fn a_warm_started_lp_reaches_the_cold_optimum_in_fewer_iterations() {
    use rand::rngs::StdRng;
    use rand::{RngExt, SeedableRng};
    let jammed = run(
        &overlap_free_mono(unit_cube(), 200, 0.55, 4),
        &Params::default(),
        &mut packbench_core::run::NullObserver,
    )
    .unwrap()
    .packing;
    let mut moved = jammed.clone();
    let step = 2e-3 * jammed.diameters[0];
    let mut rng = StdRng::seed_from_u64(4);
    moved
        .positions
        .iter_mut()
        .for_each(|x| *x += rng.random_range(-step..step));
    let start = crate::shrink_to_overlap_free(&moved, 1e-3).unwrap();
    let mut g = Growth::new(&start, 0.5, 1e-9).unwrap();
    let r = 0.5 * g.t * g.diameters[0];
    let scope = LpScope {
        cutoff_gap: 0.5 * r,
        s_bound: Some(0.01 * r),
        excess_cap: None,
        working_gap: LAZY_GAP,
        clarabel_fallback: true,
    };
    let p = Params::default();
    let lp = |g: &Growth, warm: Option<&LpStep>| {
        solve_lp(g, &scope, &[0, 1, 2], &p, None, warm)
            .unwrap()
            .unwrap()
    };
    let mut last = lp(&g, None);
    for _ in 0..2 {
        g.x.iter_mut().zip(&last.s).for_each(|(x, s)| *x += s);
        g.t *= (1.0 + last.g).sqrt();
        last = lp(&g, Some(&last));
    }
    g.x.iter_mut().zip(&last.s).for_each(|(x, s)| *x += s);
    g.t *= (1.0 + last.g).sqrt();
    let (cold, warm) = (lp(&g, None), lp(&g, Some(&last)));
    assert_same_gamma(&warm, &cold);
    assert!(
        f64::from(warm.iterations) <= 0.7 * f64::from(cold.iterations),
        "iterations: warm {}, cold {}",
        warm.iterations,
        cold.iterations
    );
}

/// Leaving out rows that cannot bind, and a Γ cap that does not bind, change no LP optimum.
#[test]
fn dropping_rows_that_cannot_bind_keeps_the_lp_optimum() {
    // A few LPs in, near jamming, where the cap drops most of the shell.
    let g = after_lps(40, 7, 8);
    let r = 0.5 * g.diameters[0];
    let every_row = LpScope {
        cutoff_gap: r,
        s_bound: Some(0.02 * r),
        excess_cap: None,
        working_gap: f64::INFINITY,
        clarabel_fallback: true,
    };
    let full = solve(&g, &every_row);
    let capped = solve(
        &g,
        &LpScope {
            excess_cap: Some(4.0 * full.g),
            ..every_row
        },
    );
    assert!(capped.links.len() < full.links.len());
    assert_same_gamma(&capped, &full);
}

/// Lazy rows: an LP started from the nearest rows, with the rows its solutions violate
/// added, reaches the optimum of the LP over every row, in the wide first shell (ℓ0 = 4R,
/// free to move far) as near jamming.
#[test]
fn lazy_rows_reach_the_optimum_of_every_row() {
    // After 14 LPs (√Γ − 1 ≈ 5e-2, where the rows must be added in several rounds) and
    // after 25 (√Γ − 1 ≈ 2e-3).
    for max_iters in [14, 25] {
        let g = after_lps(60, 3, max_iters);
        let r = 0.5 * g.diameters[0];
        let every_row = LpScope {
            cutoff_gap: 2.0 * r,
            s_bound: Some(2.0 * r / (4.0 * 3f64.sqrt())),
            excess_cap: None,
            working_gap: f64::INFINITY,
            clarabel_fallback: true,
        };
        let full = solve(&g, &every_row);
        let lazy = solve(
            &g,
            &LpScope {
                working_gap: LAZY_GAP,
                ..every_row
            },
        );
        assert!(lazy.links.len() < full.links.len());
        assert_same_gamma(&lazy, &full);
        // The lazy solution satisfies every row of the full LP.
        let rows = full
            .keys
            .iter()
            .zip(&full.links)
            .map(|(&k, &l)| Row::new(k, l, g.t, r));
        let u: Vec<f64> = lazy.s.iter().map(|v| v / r).collect();
        let worst = rows
            .map(|row| row.slack(&u, lazy.g, 3))
            .fold(f64::INFINITY, f64::min);
        assert!(worst >= -1e-9, "a left-out row is violated by {worst:e}");
    }
}

/// An overlap check that finds pairs overlapping beyond `tol_overlap` (what an LP solved only
/// to its tolerance can leave) clears them by shrinking every diameter, and counts the repair,
/// instead of ending the run with an error.
#[test]
fn an_overlap_check_clears_overlaps_by_shrinking_the_diameters() {
    let params = Params::default();
    // A converged packing: its contacts are closed exactly.
    let g = after_lps(60, 4, 1000);
    let mut it = iteration::Iteration::new(g, &params);
    // Grown by 3e-8, every contact overlaps by about that.
    it.g.t *= 1.0 + 3e-8;
    let (before, _, _) = worst_overlap(&it.g);
    assert!(before > params.tol_overlap, "{before}");
    let t = it.g.t;
    it.clear_overlaps();
    let (after, _, _) = worst_overlap(&it.g);
    assert!(after <= 1e-15, "overlap left: {after}");
    assert!(
        it.g.t < t && it.g.t > t * (1.0 - 1e-7),
        "{} against {t}",
        it.g.t
    );
    let mut extra = serde_json::Map::new();
    it.counts.insert_into(&mut extra);
    assert_eq!(extra["overlap_repairs"], 1);
    assert_eq!(extra["largest_repaired_overlap"], before);
    // Within the tolerance nothing changes.
    let t = it.g.t;
    it.clear_overlaps();
    assert_eq!(it.g.t, t);
}

/// The fine-tuning LP only offers a better balanced network for a packing that is final, so
/// when it does not converge within its iterations it is skipped, with the reason, and the
/// last LP's network is reported; it never ends the run with an error.
#[test]
fn a_fine_tuning_lp_that_does_not_converge_leaves_the_last_lps_network() {
    // Two interior-point iterations per solve, and the fine-tuning asked for whatever the
    // balance: neither the last LP nor the fine-tuning can converge.
    let params = Params {
        lp_max_iter: 2,
        tol_mechanical_equilibrium: 0.0,
        ..Params::default()
    };
    let g = after_lps(60, 4, 1000);
    let mut it = iteration::Iteration::new(g, &params);
    it.lp(None).unwrap().unwrap();
    let mut extra = serde_json::Map::new();
    it.final_network(None, &mut extra);
    let skipped = extra["fine_tuning_skipped"].as_str().unwrap();
    assert!(skipped.starts_with("no convergence"), "{skipped}");
    assert_eq!(extra["fine_tuned"], false);
    assert_eq!(extra["force_imbalance"], extra["force_imbalance_lp"]);
}

/// The Newton finish ends the run on the packing the LPs reach: from the start of
/// `the_final_network_is_closed_to_rounding`, with the finish and without it (every LP to
/// √Γ − 1 < 1e-12, then the closure), the same φ to 1e-9, both exactly jammed, and the finish
/// with fewer LPs. On this start the network changes by tens of contacts per LP until the end,
/// so the earlier tries find tensile contacts and no overlap and fall back to the LPs.
#[test]
fn the_newton_finish_reaches_the_packing_of_the_lp_path() {
    let start = overlap_free_mono(unit_cube(), 300, 0.5, 2);
    let jam = |newton_finish_below| {
        let params = Params {
            newton_finish_below,
            ..Params::default()
        };
        let out = run(&start, &params, &mut packbench_core::run::NullObserver).unwrap();
        assert_eq!(out.termination, "converged", "{:?}", out.extra);
        assert_exactly_jammed(&out.packing, "newton finish");
        out
    };
    let (newton, lps) = (jam(1e-5), jam(0.0));
    let finish = &newton.extra["newton_finish"];
    assert!(finish["batches"].is_u64(), "no finish: {finish}");
    assert!(lps.extra["newton_finish"]["attempts"] == 0);
    let count = |o: &Outcome| o.extra["lp_count"].as_u64().unwrap();
    assert!(
        count(&newton) < count(&lps),
        "{} LPs against {}",
        count(&newton),
        count(&lps)
    );
    let (a, b) = (newton.packing.phi(), lps.packing.phi());
    assert!((a - b).abs() <= 1e-9, "φ {a} with the finish, {b} without");
}

/// A finish tried from the first LP, on networks that are still rearranging, fails (a batch
/// that cannot keep its network square, or a Newton solve that diverges) and the LPs go on:
/// the run still converges, exactly jammed.
#[test]
fn a_failed_newton_finish_falls_back_to_the_lps() {
    let start = overlap_free_mono(unit_cube(), 300, 0.5, 1);
    let params = Params {
        newton_finish_below: 1.0,
        ..Params::default()
    };
    let out = run(&start, &params, &mut packbench_core::run::NullObserver).unwrap();
    assert_eq!(out.termination, "converged", "{:?}", out.extra);
    assert_exactly_jammed(&out.packing, "after failed finishes");
    let finish = &out.extra["newton_finish"];
    let failed: u64 = [
        "failed_diverged",
        "failed_unbalanced",
        "failed_batches",
        "failed_analysis",
    ]
    .iter()
    .map(|k| finish[*k].as_u64().unwrap())
    .sum();
    assert!(failed >= 1, "{finish}");
    assert!(out.extra["lp_count"].as_u64().unwrap() > 1);
}
