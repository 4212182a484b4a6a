//! Time to jam from φ = 0.05: 3D monodisperse N = 1000 (ADAM chain and FIRE), 2D bidisperse
//! N = 1000 (FIRE) and 3D monodisperse N = 10⁴ (FIRE, one thread, `-- jam_n10000`); and the
//! force loop's throughput (pair interactions per second) at N = 10⁴ and 10⁵, 3D monodisperse
//! at φ = 0.64, on one thread and on all (`-- forces`). Run with `cargo bench -p
//! packbench-adam`; the figures are in docs/BENCHMARKS.md. N = 10⁵ is timed with
//! `examples/jam.rs`.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use packbench_adam::{OverlapForces, Params, run};
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

criterion_group!(benches, jam, forces, jam_large);
criterion_main!(benches);
