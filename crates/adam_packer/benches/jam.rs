//! Time to jam from φ = 0.05: 3D monodisperse N = 1000 (ADAM chain and FIRE) and 2D bidisperse
//! N = 1000 (FIRE). Run with `cargo bench -p packbench-adam`; the figures are in
//! docs/BENCHMARKS.md. Larger N is measured with `examples/jam.rs`.

use criterion::{Criterion, criterion_group, criterion_main};
use packbench_adam::{Params, run};
use packbench_core::init::initial_packing;
use packbench_core::run::NullObserver;
use packbench_core::scene::{Placement, Scene};
use packbench_core::{Container, SizeDistribution};

fn start(d: usize, distribution: SizeDistribution) -> packbench_core::Packing {
    let scene = Scene {
        n: 1000,
        distribution,
        container: Container::periodic_box(&vec![1.0; d]).unwrap(),
        phi: 0.05,
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

criterion_group!(benches, jam);
criterion_main!(benches);
