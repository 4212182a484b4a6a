//! Builds the near-pair list of N = 10^5 monodisperse spheres at φ = 0.6 in a periodic cube
//! (target: under 30 ms on one core), and of RCPGenerator 1.0's power-law example.

use criterion::{Criterion, criterion_group, criterion_main};
use packbench_core::neighbor::CellList;
use packbench_core::scene::{Placement, Scene};
use packbench_core::{Container, SizeDistribution, init::initial_packing};

fn bench(c: &mut Criterion) {
    let mono = Scene {
        n: 100_000,
        distribution: SizeDistribution::Mono { d: 1.0 },
        container: Container::periodic_box(&[1.0, 1.0, 1.0]).unwrap(),
        phi: 0.6,
        seed: Some(1),
        placement: Placement::Random,
    };
    let p = initial_packing(&mono, 1).unwrap();
    let skin = 0.1 * p.diameters[0];
    let mut g = c.benchmark_group("cell_list");
    g.sample_size(20);
    g.bench_function("near_pairs_mono_3d_1e5_phi0.6", |b| {
        b.iter(|| CellList::near_pairs(&p.container, &p.positions, &p.diameters, skin).len())
    });
    let q = initial_packing(&Scene::power_law_between_walls(15_000, 0.6, 1), 1).unwrap();
    let skin = 0.1 * q.min_diameter();
    g.bench_function("near_pairs_powerlaw_1_15_3d_15000_phi0.6", |b| {
        b.iter(|| CellList::near_pairs(&q.container, &q.positions, &q.diameters, skin).len())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
