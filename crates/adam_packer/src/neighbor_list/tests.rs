use super::*;
use packbench_core::{Container, Packing};

/// The staleness bound (the two largest displacements) keeps the list complete: after
/// every update each overlapping pair is listed, while all spheres jiggle, the diameters
/// grow, and the closest pair left out (at the last build, or when refreshing at the last
/// update) is driven straight together by 0.3 skin per step, as far as the bound lets it;
/// with the fixed skin, with one grown to last four steps, and with that growth capped at
/// half a mean diameter; building whole lists and refreshing movers' rows.
#[test]
fn every_overlapping_pair_stays_listed() {
    for refresh in [false, true] {
        overlapping_pairs_stay_listed(0.0, 0.2, refresh);
        overlapping_pairs_stay_listed(4.0, 100.0, refresh);
        overlapping_pairs_stay_listed(4.0, 0.5, refresh);
    }
}

fn overlapping_pairs_stay_listed(lifetime_steps: f64, skin_max: f64, refresh: bool) {
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut uniform = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let n = 80;
    let box_len = 12.0;
    let c = Container::with_flags(&[box_len; 3], &[false; 3]).unwrap();
    let x: Vec<f64> = (0..3 * n).map(|_| box_len * uniform()).collect();
    let dia: Vec<f64> = (0..n).map(|_| 1.0 + 2.0 * uniform()).collect();
    let mut sys = System::new(&Packing::new(x, dia, c).unwrap(), &[]).unwrap();
    let mut nl = NeighborList::new();
    let skin = 0.2;
    // Gap between i and j (negative: overlap) and the unit vector from i to j.
    let gap = |sys: &System, i: usize, j: usize| {
        let mut dx: Vec<f64> = (0..3)
            .map(|k| sys.x[3 * j + k] - sys.x[3 * i + k])
            .collect();
        sys.container.min_image(&mut dx);
        let r = dx.iter().map(|t| t * t).sum::<f64>().sqrt();
        dx.iter_mut().for_each(|t| *t /= r);
        (r - 0.5 * (sys.dia[i] + sys.dia[j]), dx)
    };
    let listed = |nl: &NeighborList, i: usize, j: usize| nl.rows.get(i).contains(&(j as u32));
    let (mut builds, mut overlaps, mut driven) = (0, 0, (0, 0));
    for step in 0..300 {
        let refreshed = nl.refreshed();
        let built = nl.update(&mut sys, (skin, skin_max), lifetime_steps, refresh);
        builds += u64::from(built);
        if built {
            let mean = sys.kappa * sys.d0_mean;
            assert!(
                nl.skin <= skin_max * mean * (1.0 + 1e-12),
                "skin {}",
                nl.skin
            );
        }
        if built || nl.refreshed() > refreshed {
            driven = (0..n)
                .flat_map(|i| (i + 1..n).map(move |j| (i, j)))
                .filter(|&(i, j)| !listed(&nl, i, j))
                .min_by(|a, b| gap(&sys, a.0, a.1).0.total_cmp(&gap(&sys, b.0, b.1).0))
                .unwrap();
        }
        if refresh {
            // Each particle's lower partners mirror the rows, pair for pair.
            let mirrored: usize = (0..n).map(|j| nl.lower.get(j).len()).sum();
            assert_eq!(mirrored, nl.pairs(), "step {step}");
            for i in 0..n {
                for &j in nl.rows.get(i) {
                    assert!(
                        nl.lower.get(j as usize).contains(&(i as u32)),
                        "step {step}"
                    );
                }
            }
        }
        for i in 0..n {
            for j in i + 1..n {
                if gap(&sys, i, j).0 < 0.0 {
                    overlaps += 1;
                    assert!(listed(&nl, i, j), "step {step}: pair {i}–{j} not listed");
                }
            }
        }
        let step_len = 0.15 * skin;
        let (i, j) = driven;
        let (_, dir) = gap(&sys, i, j);
        for (k, u) in dir.iter().enumerate() {
            sys.x[3 * i + k] += step_len * u;
            sys.x[3 * j + k] -= step_len * u;
        }
        for v in sys.x.iter_mut() {
            *v += 0.002 * skin * (2.0 * uniform() - 1.0);
        }
        sys.set_kappa(sys.kappa * 1.0002);
    }
    assert!(
        builds > 20 || nl.refreshed() > 100,
        "{builds} builds, {} refreshed",
        nl.refreshed()
    );
    assert!(overlaps > 100, "{overlaps} overlapping pairs checked");
}

/// A small sphere whose only neighbour is 15× larger, with a wall out of reach: its length
/// stays within √c̄·R₀, so touching the wall later keeps its stiffness R₀⁻²·ℓ² ≤ c̄ (the
/// bound the Verlet step is stable under), where the neighbour alone would give ℓ = √c̄·8.
#[test]
fn a_small_sphere_near_a_wall_keeps_a_wall_stable_length() {
    let walls = Container::with_flags(&[40.0, 20.0, 40.0], &[false, true, false]).unwrap();
    // Small sphere (D = 1) touching the large one (D = 15) centred 8 away in x; the walls at
    // y = 0 and 20 are beyond its reach (R + skin).
    let packing =
        Packing::new(vec![1.0, 10.0, 5.0, 9.0, 10.0, 5.0], vec![1.0, 15.0], walls).unwrap();
    let mut sys = System::new(&packing, &[]).unwrap();
    let mut nl = NeighborList::new();
    nl.update(&mut sys, (0.1, 0.1), 0.0, false);
    assert_eq!(nl.pairs(), 1);
    let mut unit0 = vec![0.0; 6];
    nl.contact_lengths(&sys, &mut unit0);
    let small = sys.d0.iter().position(|&v| v == 1.0).unwrap();
    let l = unit0[3 * small];
    // c̄ = 1 (one pair, both ends listed): ℓ ≤ √1·R₀ = 0.5, against 8 without the cap.
    assert!((l - 0.5).abs() < 1e-12, "ℓ = {l}");
}
