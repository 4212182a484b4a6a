use super::*;
use crate::distribution::SizeDistribution;
use crate::scene::{Placement, Scene};
use proptest::prelude::*;

fn brute(c: &Container, x: &[f64], dia: &[f64], skin: f64) -> Vec<(u32, u32)> {
    let d = c.dim();
    let mut out = Vec::new();
    let mut delta = vec![0.0; d];
    for i in 0..dia.len() {
        for j in i + 1..dia.len() {
            c.separation(&x[i * d..(i + 1) * d], &x[j * d..(j + 1) * d], &mut delta);
            let r2: f64 = delta.iter().map(|v| v * v).sum();
            let cut = 0.5 * (dia[i] + dia[j]) + skin;
            if r2 < cut * cut {
                out.push((i as u32, j as u32));
            }
        }
    }
    out
}

fn sorted(mut v: Vec<(u32, u32)>) -> Vec<(u32, u32)> {
    for p in &mut v {
        *p = (p.0.min(p.1), p.0.max(p.1));
    }
    v.sort();
    v
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(60))]
    #[test]
    fn matches_brute_force(
        d in 2usize..=4,
        n in 1usize..80,
        seed in any::<u64>(),
        walls in any::<u8>(),
        spread in 1.0f64..8.0,
        skin in 0.0f64..0.5,
    ) {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
        let lengths: Vec<f64> = (0..d).map(|_| rng.random_range(2.0..9.0)).collect();
        let flags: Vec<bool> = (0..d).map(|k| walls >> k & 1 == 1).collect();
        let c = Container::with_flags(&lengths, &flags).unwrap();
        let x: Vec<f64> = (0..n * d).map(|k| lengths[k % d] * rng.random::<f64>()).collect();
        let dia: Vec<f64> = (0..n).map(|_| 0.3 * (1.0 + (spread - 1.0) * rng.random::<f64>().powi(3))).collect();
        let got = sorted(CellList::near_pairs(&c, &x, &dia, skin));
        let want = sorted(brute(&c, &x, &dia, skin));
        prop_assert_eq!(got, want);
    }
}

/// Random centres (overlapping) of `n` spheres of RCPGenerator 1.0's power law 1–15 between
/// walls on y, at `phi`.
fn walled_power_law(n: usize, phi: f64, seed: u64) -> crate::Packing {
    crate::init::initial_packing(&Scene::power_law_between_walls(n, phi, seed), seed).unwrap()
}

#[test]
fn seed_000_power_law_needs_no_tuning() {
    let p = walled_power_law(15_000, 0.6, 1);
    let pairs = CellList::near_pairs(&p.container, &p.positions, &p.diameters, 0.0);
    // Random centres at φ = 0.6 overlap heavily; every listed pair must really overlap.
    assert!(!pairs.is_empty());
    let d = 3;
    let mut delta = [0.0; 3];
    for &(i, j) in pairs.iter().take(2000) {
        let (i, j) = (i as usize, j as usize);
        p.container.separation(
            &p.positions[i * d..i * d + d],
            &p.positions[j * d..j * d + d],
            &mut delta,
        );
        let r = delta.iter().map(|v| v * v).sum::<f64>().sqrt();
        assert!(r < 0.5 * (p.diameters[i] + p.diameters[j]));
    }
}

/// Above [`PARALLEL_MIN_PARTICLES`], the list scanned on two threads is the one-thread
/// list, pair for pair in the same order (the packings' bytes at any thread count rest on
/// it): a periodic box of equal spheres and the walled power law 1–15.
#[test]
fn the_parallel_scan_lists_the_same_pairs_in_the_same_order() {
    let n = 2 * PARALLEL_MIN_PARTICLES;
    let mono = Scene {
        n,
        distribution: SizeDistribution::Mono { d: 1.0 },
        container: Container::with_flags(&[1.0, 1.0, 1.0], &[true; 3]).unwrap(),
        phi: 0.5,
        seed: Some(3),
        placement: Placement::Random,
    };
    let mono = crate::init::initial_packing(&mono, 3).unwrap();
    for p in [mono, walled_power_law(n, 0.5, 3)] {
        let skin = 0.1 * typical_diameter(&p.diameters);
        let mut one = Vec::new();
        CellList::for_each_near_pair(&p.container, &p.positions, &p.diameters, skin, |i, j| {
            one.push((i as u32, j as u32))
        });
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let two =
            pool.install(|| CellList::near_pairs(&p.container, &p.positions, &p.diameters, skin));
        assert!(one.len() > p.diameters.len(), "{} pairs", one.len());
        assert!(one == two, "{} pairs against {}", one.len(), two.len());
    }
}
