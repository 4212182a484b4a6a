//! Invariants and physics of LS and MLS at small N (each test well under a few seconds in
//! release). Large-N figures live in docs/BENCHMARKS.md.

use packbench_core::analysis::{AnalysisOptions, analyze};
use packbench_core::init::initial_packing;
use packbench_core::run::{NullObserver, Observer, Outcome};
use packbench_core::scene::{Placement, Scene};
use packbench_core::{Container, Packing, SizeDistribution};

use crate::system::{System, WindowEnd};
use crate::{LsParams, MlsError, MlsParams, run_ls, run_mls};

fn poisson(n: usize, container: Container, distribution: SizeDistribution, seed: u64) -> Packing {
    let scene = Scene {
        n,
        distribution,
        container,
        phi: 0.01,
        seed: Some(seed),
        placement: Placement::Poisson,
    };
    initial_packing(&scene, seed).unwrap()
}

fn cube(d: usize) -> Container {
    Container::periodic_box(&vec![1.0; d]).unwrap()
}

fn mono() -> SizeDistribution {
    SizeDistribution::Mono { d: 1.0 }
}

fn ls_params(rate: f64, cap: f64, seed: u64) -> LsParams {
    let mut p = LsParams {
        rate,
        ..LsParams::default()
    };
    p.dynamics.pressure_cap = cap;
    p.dynamics.seed = seed;
    p
}

/// Largest relative overlap `1 − r/σ` over all pairs and walls, by brute force.
fn max_overlap(p: &Packing) -> f64 {
    let d = p.dim;
    let mut worst = 0.0f64;
    let mut r = vec![0.0; d];
    for i in 0..p.n() {
        for j in i + 1..p.n() {
            p.container.separation(p.position(i), p.position(j), &mut r);
            let dist = r.iter().map(|x| x * x).sum::<f64>().sqrt();
            worst = worst.max(1.0 - dist / (0.5 * (p.diameters[i] + p.diameters[j])));
        }
        let radius = 0.5 * p.diameters[i];
        p.container.for_each_wall(p.position(i), radius, |w| {
            worst = worst.max(1.0 - w.distance / radius);
        });
    }
    worst
}

/// Runs the LS protocol directly on the system with the overlap audit on; returns the audit.
fn audited_ls<const D: usize, const P: bool>(start: &Packing, rate: f64, cap: f64) -> (f64, u64) {
    let mut sys = System::<D, P>::new(start, 0.0, 0.2, 3);
    loop {
        sys.begin_window(rate);
        match sys.run_window(20 * start.n() as u64, &mut |_, _| false) {
            WindowEnd::Completed { pressure } if pressure >= cap => break,
            WindowEnd::Completed { .. } => {}
            other => panic!("LS ended with {other:?}"),
        }
    }
    (sys.audit.expect("collisions happened"), sys.collisions)
}

#[test]
fn no_overlap_beyond_1e_10_at_any_event() {
    let start = poisson(150, cube(3), mono(), 1);
    let (worst, collisions) = audited_ls::<3, true>(&start, 1.0, 1e12);
    assert!(collisions > 50_000);
    assert!(worst < 1e-10, "relative overlap {worst}");
    let walls = Container::with_flags(&[1.0, 1.0], &[true, true]).unwrap();
    let bi = SizeDistribution::Bidisperse {
        d1: 1.0,
        d2: 1.4,
        p: 0.5,
    };
    let start = poisson(150, walls, bi, 2);
    let (worst, _) = audited_ls::<2, false>(&start, 1.0, 1e12);
    assert!(worst < 1e-10, "relative overlap {worst} with walls");
    // 200 spheres in a 4D unit box: two cells per axis (cells ≈ 0.43 wide near jamming), so
    // pairs are imaged through their bounding-sphere centres (`pair_time_anchored`).
    let start = poisson(200, cube(4), mono(), 3);
    let (worst, _) = audited_ls::<4, true>(&start, 1.0, 1e12);
    assert!(worst < 1e-10, "relative overlap {worst} in 4D");
}

#[test]
fn zero_rate_conserves_energy_and_momentum_between_rescalings() {
    // A dense liquid: LS to a modest pressure, then free flight with collisions at γ = 0.
    let start = poisson(200, cube(3), mono(), 4);
    let liquid = run_ls(&start, &ls_params(1.0, 20.0, 4), &mut NullObserver).unwrap();
    assert_eq!(liquid.termination, "pressure_cap");
    let mean = liquid.packing.diameters[0];
    let mut sys = System::<3, true>::new(&liquid.packing, mean, 0.2, 5);
    // Give the box a drift so that momentum conservation is a non-trivial check.
    for i in 0..sys.n() {
        sys.add_velocity(i, [0.3, -0.1, 0.2]);
    }
    sys.start_window(0.0, false);
    let (ke0, p0) = (sys.kinetic_energy(), sys.momentum());
    let end = sys.run_window(20 * 200, &mut |_, _| false);
    assert!(matches!(end, WindowEnd::Completed { .. }), "{end:?}");
    let (ke1, p1) = (sys.kinetic_energy(), sys.momentum());
    assert!(((ke1 - ke0) / ke0).abs() < 1e-12, "KE {ke0} → {ke1}");
    for k in 0..3 {
        assert!((p1[k] - p0[k]).abs() < 1e-11, "momentum {p0:?} → {p1:?}");
    }
    assert!((p0[0] - 0.3 * 200.0).abs() < 1e-9);
}

#[test]
fn same_seed_same_packing_bit_for_bit() {
    let start = poisson(120, cube(3), mono(), 6);
    let a = run_ls(&start, &ls_params(1.0, 1e12, 9), &mut NullObserver).unwrap();
    let b = run_ls(&start, &ls_params(1.0, 1e12, 9), &mut NullObserver).unwrap();
    assert_eq!(a.packing, b.packing);
    assert_eq!(a.steps, b.steps);
    let c = run_ls(&start, &ls_params(1.0, 1e12, 10), &mut NullObserver).unwrap();
    assert_ne!(a.packing.positions, c.packing.positions);
}

/// The SIMD prediction (3D, the widest set here: AVX-512F or AVX2) gives the scalar path's
/// trajectory bit for bit: an LS run to the pressure cap, periodic and walled, ends in the same
/// packing after the same collisions.
#[test]
fn simd_and_scalar_predictions_give_the_same_trajectory() {
    fn ls<const P: bool>(start: &Packing, simd: bool) -> (Packing, u64) {
        let mut sys = System::<3, P>::new(start, 0.0, 0.2, 8);
        #[cfg(target_arch = "x86_64")]
        if !simd {
            sys.simd = None;
        }
        loop {
            sys.begin_window(1.0);
            match sys.run_window(20 * start.n() as u64, &mut |_, _| false) {
                WindowEnd::Completed { pressure } if pressure >= 1e12 => break,
                WindowEnd::Completed { .. } => {}
                other => panic!("LS ended with {other:?}"),
            }
        }
        (sys.packing(start), sys.collisions)
    }
    let start = poisson(300, cube(3), mono(), 12);
    assert_eq!(ls::<true>(&start, true), ls::<true>(&start, false));
    let walls = Container::with_flags(&[1.0, 1.0, 1.0], &[true, false, true]).unwrap();
    let lognormal = SizeDistribution::LognormalMean1 { sigma: 0.3 };
    let start = poisson(300, walls, lognormal, 13);
    assert_eq!(ls::<false>(&start, true), ls::<false>(&start, false));
}

/// Keeps the last checkpoint a run passes.
#[derive(Default)]
struct Checkpoints(Option<serde_json::Value>);

impl Observer for Checkpoints {
    fn checkpoint(&mut self, state: &serde_json::Value) {
        self.0 = Some(state.clone());
    }
}

/// An MLS run stopped by its budget and resumed from the checkpoint it left ends bit for bit
/// where the run without a stop ends, periodic in 3D and walled in 2D; a resumed run counts
/// its collisions and run time from the start.
#[test]
fn a_resumed_mls_run_continues_bit_for_bit() {
    let walls = Container::with_flags(&[1.0, 1.0], &[true, false]).unwrap();
    let bi = SizeDistribution::Bidisperse {
        d1: 1.0,
        d2: 1.4,
        p: 0.5,
    };
    for (start, stops) in [
        (poisson(80, cube(3), mono(), 21), [30_000u64, 150_000]),
        (poisson(60, walls, bi, 22), [20_000, 100_000]),
    ] {
        let mut params = MlsParams {
            rate_final: 0.05,
            ..MlsParams::default()
        };
        params.dynamics.seed = 5;
        let whole = run_mls(&start, &params, &mut NullObserver).unwrap();
        for stop in stops {
            assert!(
                stop < whole.steps,
                "stop {stop} after the end {}",
                whole.steps
            );
            let mut first = params.clone();
            first.dynamics.max_collisions = stop;
            let mut saved = Checkpoints::default();
            let leg = run_mls(&start, &first, &mut saved).unwrap();
            assert_eq!(leg.termination, "max_steps");
            let checkpoint: crate::Checkpoint =
                serde_json::from_value(saved.0.expect("a stopped run leaves a checkpoint"))
                    .unwrap();
            assert!(checkpoint.collisions <= leg.steps);
            let rest = crate::resume_mls(&checkpoint, &params, &mut NullObserver).unwrap();
            assert_eq!(rest.termination, whole.termination);
            assert_eq!(rest.steps, whole.steps);
            assert_eq!(rest.packing, whole.packing);
            assert_eq!(
                rest.extra["compression_stages"],
                whole.extra["compression_stages"]
            );
            assert_eq!(rest.extra["resumed_at_collisions"], checkpoint.collisions);
        }
    }
}

/// A checkpoint that does not describe one set of particles is refused with a reason.
#[test]
fn an_inconsistent_checkpoint_is_refused() {
    let start = poisson(40, cube(3), mono(), 23);
    let mut params = MlsParams::default();
    params.dynamics.max_collisions = 5000;
    let mut saved = Checkpoints::default();
    run_mls(&start, &params, &mut saved).unwrap();
    let good: crate::Checkpoint = serde_json::from_value(saved.0.unwrap()).unwrap();
    let mut dup = good.clone();
    dup.id[1] = dup.id[0];
    let mut short = good.clone();
    short.v.pop();
    let mut other = good.clone();
    other.format = "something else".into();
    for bad in [dup, short, other] {
        let e = crate::resume_mls(&bad, &params, &mut NullObserver).unwrap_err();
        assert!(matches!(e, MlsError::Checkpoint(_)), "{e}");
    }
}

#[test]
fn fast_ls_jams_in_the_random_loose_to_close_range() {
    for rate in [1.0, 10.0] {
        let start = poisson(400, cube(3), mono(), 11);
        let out = run_ls(&start, &ls_params(rate, 1e12, 11), &mut NullObserver).unwrap();
        assert_eq!(out.termination, "pressure_cap");
        let phi = out.packing.phi();
        assert!((0.58..0.645).contains(&phi), "γ = {rate}: φ = {phi}");
        assert!(max_overlap(&out.packing) < 1e-10);
        // The trace records every window: pressure rises to the cap.
        let last = out.trace.last().unwrap();
        assert!(last.values[0].1 >= 1e12 && out.trace.len() as u64 == out.extra["windows"]);
    }
}

/// MLS from a fast LS packing with a shortened schedule (γ from 10 to 1e-3).
fn ls_then_mls(start: &Packing, seed: u64) -> (Outcome, Outcome) {
    let ls = run_ls(start, &ls_params(1.0, 1e12, seed), &mut NullObserver).unwrap();
    let mut params = MlsParams {
        rate_final: 1e-3,
        ..MlsParams::default()
    };
    params.dynamics.seed = seed;
    let mls = run_mls(&ls.packing, &params, &mut NullObserver).unwrap();
    (ls, mls)
}

#[test]
fn mls_reaches_a_nearly_isostatic_jammed_packing() {
    let start = poisson(80, cube(3), mono(), 12);
    let (ls, mls) = ls_then_mls(&start, 12);
    assert!(mls.packing.phi() > ls.packing.phi());
    let phi = mls.packing.phi();
    assert!((0.62..0.66).contains(&phi), "φ_J = {phi}");
    let m = analyze(&mls.packing, &AnalysisOptions::default()).unwrap();
    assert!(m.max_overlap < 1e-10);
    // Near-isostatic non-rattlers: at most 3% of n_dof from N_c = n_dof.
    assert!(
        (m.iso_gap.unsigned_abs() as f64) <= 0.03 * m.n_dof as f64,
        "{m:?}"
    );
    assert!((5.6..6.4).contains(&m.z_nonrattler), "{m:?}");
    assert!(m.force_balance.unwrap() < 1e-3, "{m:?}");
    assert!(["rate_final", "jammed"].contains(&mls.termination.as_str()));
}

#[test]
fn walls_keep_every_sphere_inside() {
    let c = Container::with_flags(&[1.0, 1.0, 1.0], &[true, false, true]).unwrap();
    let start = poisson(200, c, mono(), 13);
    let out = run_ls(&start, &ls_params(1.0, 1e12, 13), &mut NullObserver).unwrap();
    assert_eq!(out.termination, "pressure_cap");
    out.packing.validate().unwrap();
    assert!(max_overlap(&out.packing) < 1e-10);
    // Walls lower the density of a small packing below the periodic value.
    assert!((0.5..0.64).contains(&out.packing.phi()));
}

#[test]
fn extremes_give_results_not_hangs() {
    // N = 1 and N = 2 in a periodic box: the spheres outgrow half the box before jamming.
    for n in [1, 2] {
        let out = run_ls(
            &poisson(n, cube(3), mono(), 14),
            &LsParams::default(),
            &mut NullObserver,
        )
        .unwrap();
        assert_eq!(out.termination, "box_limit", "N = {n}");
        assert!(max_overlap(&out.packing) < 1e-10);
        let out = run_mls(&out.packing, &MlsParams::default(), &mut NullObserver).unwrap();
        assert_eq!(out.termination, "box_limit");
    }
    // N = 1 between walls: it jams against them.
    let walls = Container::with_flags(&[1.0, 1.0], &[true, true]).unwrap();
    let out = run_ls(
        &poisson(1, walls, mono(), 15),
        &LsParams::default(),
        &mut NullObserver,
    )
    .unwrap();
    assert_eq!(out.termination, "pressure_cap");
    assert!((out.packing.diameters[0] - 1.0).abs() < 1e-6);
    // Size ratio 20.
    // Size ratio 20: one large disc among 300 small ones in a walled square.
    let walls = Container::with_flags(&[1.0, 1.0], &[true, true]).unwrap();
    let mut start = poisson(301, walls, mono(), 16);
    start.diameters[0] *= 20.0;
    let out = run_ls(&start, &LsParams::default(), &mut NullObserver).unwrap();
    assert_eq!(out.termination, "pressure_cap");
    assert!((out.packing.diameters[0] / out.packing.diameters[1] - 20.0).abs() < 1e-9);
    assert!(max_overlap(&out.packing) < 1e-10);
    // A thin slab: two diameters high between walls.
    let slab = Container::with_flags(&[6.0, 6.0, 1.0], &[false, false, true]).unwrap();
    let out = run_ls(
        &poisson(150, slab, mono(), 17),
        &LsParams::default(),
        &mut NullObserver,
    )
    .unwrap();
    assert_eq!(out.termination, "pressure_cap");
    out.packing.validate().unwrap();
    assert!(max_overlap(&out.packing) < 1e-10);
    assert!(out.packing.phi() > 0.4, "φ = {}", out.packing.phi());
}

#[test]
fn higher_dimensions_jam_at_sensible_densities() {
    // d = 2 bidisperse 1:1.4 jams near 0.84 and d = 4 near 0.46 (fast LS lands a little lower);
    // d = 8 must just finish.
    let bi = SizeDistribution::Bidisperse {
        d1: 1.0,
        d2: 1.4,
        p: 0.5,
    };
    let out = run_ls(
        &poisson(300, cube(2), bi, 18),
        &LsParams::default(),
        &mut NullObserver,
    )
    .unwrap();
    assert!(
        (0.80..0.86).contains(&out.packing.phi()),
        "2D φ = {}",
        out.packing.phi()
    );
    let out = run_ls(
        &poisson(300, cube(4), mono(), 19),
        &LsParams::default(),
        &mut NullObserver,
    )
    .unwrap();
    assert!(
        (0.40..0.48).contains(&out.packing.phi()),
        "4D φ = {}",
        out.packing.phi()
    );
    let out = run_ls(
        &poisson(60, cube(8), mono(), 20),
        &LsParams::default(),
        &mut NullObserver,
    )
    .unwrap();
    // 60 spheres in 8D outgrow half the box (φ ≈ 0.004) long before they jam.
    assert_eq!(out.termination, "box_limit");
    assert!(max_overlap(&out.packing) < 1e-10);
    assert!(out.packing.phi() > 0.003);
}

#[test]
fn mls_clears_overlaps_of_its_start() {
    // A Poisson start keeps its sampled diameters (φ = 0.3 here) and so overlaps.
    let scene = Scene {
        n: 100,
        distribution: mono(),
        container: cube(3),
        phi: 0.3,
        seed: Some(21),
        placement: Placement::Poisson,
    };
    let start = initial_packing(&scene, 21).unwrap();
    assert!(max_overlap(&start) > 0.1);
    let mut params = MlsParams {
        rate_final: 0.5,
        ..MlsParams::default()
    };
    params.dynamics.seed = 21;
    let out = run_mls(&start, &params, &mut NullObserver).unwrap();
    assert!(out.extra["initial_shrink"].as_f64().unwrap() < 1.0);
    assert!(max_overlap(&out.packing) < 1e-10);
    // Compressed to near random close packing (0.64), never past it into order or overlap.
    let phi = out.packing.phi();
    assert!((0.55..0.66).contains(&phi), "φ = {phi}");
}

/// The compression rates progress reports carry.
#[derive(Default)]
struct ReportedRates(Vec<f64>);
impl Observer for ReportedRates {
    fn progress(&mut self, p: &packbench_core::run::Progress) {
        let rate = p.more.iter().find(|(name, _)| *name == "rate");
        self.0.extend(rate.map(|&(_, r)| r));
    }
}

/// Every compression stage an MLS run passes is reported as it begins, however fast the run
/// (a whole N = 100 run takes less than the period between timed reports): the rates of the
/// progress reports include every positive rate of the trace's windows.
#[test]
fn every_compression_stage_is_reported() {
    let start = poisson(100, cube(3), mono(), 31);
    let params = MlsParams {
        rate_final: 1e-2,
        ..MlsParams::default()
    };
    let mut reports = ReportedRates::default();
    let out = run_mls(&start, &params, &mut reports).unwrap();
    let rate = |row: &packbench_core::run::TraceRow| {
        let r = row.values.iter().find(|(name, _)| name == "rate");
        r.map_or(0.0, |&(_, r)| r)
    };
    let mut stages: Vec<f64> = out.trace.iter().map(rate).filter(|&r| r > 0.0).collect();
    stages.dedup();
    assert!(stages.len() >= 5, "too few stages to test: {stages:?}");
    for r in &stages {
        assert!(
            reports.0.contains(r),
            "stage at γ = {r} not reported: {:?}",
            reports.0
        );
    }
}

struct StopAfter(u32);
impl Observer for StopAfter {
    fn should_stop(&self) -> bool {
        self.0 == 0
    }
    fn progress(&mut self, _: &packbench_core::run::Progress) {}
    fn snapshot(&mut self, _: u64, p: &Packing) {
        p.validate().unwrap();
        self.0 = self.0.saturating_sub(1);
    }
}

#[test]
fn interruption_budget_and_snapshots_return_valid_packings() {
    let start = poisson(200, cube(3), mono(), 22);
    let mut params = ls_params(0.1, 1e12, 22);
    params.dynamics.save_interval = 4000;
    let out = run_ls(&start, &params, &mut StopAfter(3)).unwrap();
    assert_eq!(out.termination, "interrupted");
    assert!(max_overlap(&out.packing) < 1e-10);
    let mut params = ls_params(0.1, 1e12, 22);
    params.dynamics.max_collisions = 10_000;
    let out = run_ls(&start, &params, &mut NullObserver).unwrap();
    assert_eq!(out.termination, "max_steps");
    assert!(out.steps >= 10_000 && out.steps < 30_000);
}

#[test]
fn bad_input_is_refused_with_a_reason() {
    let start = poisson(10, cube(3), mono(), 23);
    let err = |r: Result<Outcome, MlsError>| r.unwrap_err().to_string();
    assert!(err(run_ls(&start, &ls_params(-1.0, 1e12, 0), &mut NullObserver)).contains("rate"));
    assert!(
        err(run_ls(&start, &ls_params(1.0, 0.5, 0), &mut NullObserver)).contains("pressure_cap")
    );
    let p = MlsParams {
        rate_factor: 1.0,
        ..MlsParams::default()
    };
    assert!(err(run_mls(&start, &p, &mut NullObserver)).contains("rate_factor"));
    let ball = Container::from_rcp_flags(&[1.0, 1.0, 1.0], &[-3, 0, 0]).unwrap();
    let s = poisson(10, ball, mono(), 24);
    assert!(err(run_ls(&s, &LsParams::default(), &mut NullObserver)).contains("curved"));
    let s9 = poisson(5, cube(9), mono(), 25);
    assert!(err(run_ls(&s9, &LsParams::default(), &mut NullObserver)).contains("dimension 9"));
    let mut empty = start.clone();
    empty.positions.clear();
    empty.diameters.clear();
    assert!(matches!(
        run_ls(&empty, &LsParams::default(), &mut NullObserver),
        Err(MlsError::Empty)
    ));
    let mut nan = start.clone();
    nan.positions[0] = f64::NAN;
    assert!(run_mls(&nan, &MlsParams::default(), &mut NullObserver).is_err());
}

#[test]
fn params_round_trip_with_seed_defaults() {
    let p: MlsParams = serde_json::from_str(r#"{"rate_final": 0.001, "seed": 4}"#).unwrap();
    assert_eq!(p.rate_initial, 10.0);
    assert_eq!(p.rate_factor, 2.0);
    assert_eq!(p.rate_final, 0.001);
    assert_eq!(p.equilibration_windows, 50);
    assert_eq!(p.dynamics.seed, 4);
    assert_eq!(p.dynamics.temperature, 0.2);
    assert_eq!(p.dynamics.collisions_per_particle, 20);
    assert_eq!(p.dynamics.pressure_cap, 1e12);
    let back: MlsParams = serde_json::from_str(&serde_json::to_string(&p).unwrap()).unwrap();
    assert_eq!(back, p);
    let l: LsParams = serde_json::from_str("{}").unwrap();
    assert_eq!(l, LsParams::default());
}
