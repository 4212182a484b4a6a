//! Time to jam from φ = 0.05: 3D monodisperse N = 1000 (ADAM chain and FIRE), 2D bidisperse
//! N = 1000 (FIRE) and 3D monodisperse N = 10⁴ (FIRE, one thread, `-- jam_n10000`); and the
//! force loop's throughput (pair interactions per second) at N = 10⁴ and 10⁵, 3D monodisperse
//! at φ = 0.64, on one thread and on all (`-- forces`); and the neighbour list's upkeep after
//! 1 % of the particles moved past the refresh budget, by a whole build or by searching their
//! rows again (`-- neighbor_upkeep`). Run with `cargo bench -p packbench-adam`; the figures are
//! in docs/BENCHMARKS.md. N = 10⁵ is timed with `examples/jam.rs`.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use packbench_adam::{NeighborUpkeep, OverlapForces, Params, run};
use packbench_core::init::initial_packing;
use packbench_core::run::NullObserver;
use packbench_core::scene::{Placement, Scene};
use packbench_core::{Container, SizeDistribution};

fn start(d: usize, distribution: SizeDistribution) -> packbench_core::Packing {
    scene_packing(1000, d, distribution, 0.05)
}

fn scene_packing(
    n: usize,
    d: usize,
    distribution: SizeDistribution,
    phi: f64,
) -> packbench_core::Packing {
    let scene = Scene {
        n,
        distribution,
        container: Container::periodic_box(&vec![1.0; d]).unwrap(),
        phi,
        seed: Some(1),
        placement: Placement::Random,
    };
    initial_packing(&scene, 1).unwrap()
}

fn jam(c: &mut Criterion) {
    let mono3 = start(3, SizeDistribution::Mono { d: 1.0 });
    let bi2 = start(
        2,
        SizeDistribution::Bidisperse {
            d1: 1.0,
            d2: 1.4,
            p: 0.5,
        },
    );
    let mut g = c.benchmark_group("jam_n1000");
    g.sample_size(10);
    g.bench_function("3d_mono_fire", |b| {
        b.iter(|| run(&mono3, &Params::fire(), &mut NullObserver).unwrap())
    });
    g.bench_function("3d_mono_adam", |b| {
        b.iter(|| run(&mono3, &Params::default(), &mut NullObserver).unwrap())
    });
    g.bench_function("2d_bidisperse_fire", |b| {
        b.iter(|| run(&bi2, &Params::fire(), &mut NullObserver).unwrap())
    });
    g.finish();
}

/// The headline: 3D monodisperse N = 10⁴ from φ = 0.05 on one thread (FIRE). Ten
/// samples of about 150 s each; run it alone with `-- jam_n10000`.
fn jam_large(c: &mut Criterion) {
    let p = scene_packing(10_000, 3, SizeDistribution::Mono { d: 1.0 }, 0.05);
    let params = Params {
        parallel_min_particles: usize::MAX,
        max_steps: 1_000_000,
        ..Params::fire()
    };
    let mut g = c.benchmark_group("jam_n10000");
    g.sample_size(10);
    g.bench_function("3d_mono_fire_one_thread", |b| {
        b.iter(|| run(&p, &params, &mut NullObserver).unwrap())
    });
    g.finish();
}

fn forces(c: &mut Criterion) {
    let mut g = c.benchmark_group("forces_3d_mono_phi064");
    for n in [10_000, 100_000] {
        let p = scene_packing(n, 3, SizeDistribution::Mono { d: 1.0 }, 0.64);
        for (label, parallel) in [("one_thread", false), ("all_threads", true)] {
            let mut f = OverlapForces::new(&p, Params::default().neighbor_skin, parallel).unwrap();
            g.throughput(Throughput::Elements(f.listed_pairs() as u64));
            g.bench_function(format!("n{n}_{label}"), |b| b.iter(|| f.evaluate()));
        }
    }
    g.finish();
}

/// One step's neighbour upkeep at N = 10⁴ when every hundredth particle moved 0.6 skin (past
/// the refresh budget of a fifth of it, and far enough to make a whole-build list stale): a
/// whole build against a refresh of the movers' rows, on RCPGenerator 1.0's power law 1–15
/// between walls on y (where adam refreshes) and on 3D mono spheres (where it builds whole).
fn neighbor_upkeep(c: &mut Criterion) {
    let mono = scene_packing(10_000, 3, SizeDistribution::Mono { d: 1.0 }, 0.64);
    let power = initial_packing(&Scene::power_law_between_walls(10_000, 0.6, 1), 1).unwrap();
    let skin = Params::default().neighbor_skin;
    let mut g = c.benchmark_group("neighbor_upkeep_n10000_1pc_moved");
    for (name, p) in [("powerlaw_1_15_walls", &power), ("mono_3d", &mono)] {
        for (mode, refresh) in [("whole_build", false), ("refresh_rows", true)] {
            let mut u = NeighborUpkeep::new(p, skin, refresh).unwrap();
            // The case measures what it names: whole builds every time, or refreshes only.
            let whole = (0..4).map(|_| u.shift(100, 0.6)).collect::<Vec<_>>();
            assert!(
                whole.iter().all(|&w| w != refresh),
                "{name} {mode}: {whole:?}"
            );
            g.bench_function(format!("{name}_{mode}"), |b| b.iter(|| u.shift(100, 0.6)));
        }
    }
    g.finish();
}

criterion_group!(benches, jam, forces, jam_large, neighbor_upkeep);
criterion_main!(benches);
