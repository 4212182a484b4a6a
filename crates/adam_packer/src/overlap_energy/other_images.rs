//! Contacts through periodic images other than the nearest one.
//!
//! Spheres i and j can touch through a second image along a periodic axis of length L only
//! when D_i + D_j > L: the nearest image's separation along the axis is at most L/2, every other
//! image's at least L/2 (Baranau & Tallarek 2014, App. C). The neighbour list holds the
//! nearest image; this adds the others. Such pairs join spheres wider than L − D_max, at most
//! 128 of them (`System::check_own_image`), so they are found afresh at each evaluation
//! (`System::wide_spheres`): an O(N) scan, and nothing at all while 2·D_max ≤ L on every
//! periodic axis. A sphere as wide as L would overlap its own image and is refused before, so
//! with σ_ij < L only the images one length away along each axis can overlap.

use super::{Frame, PairSums};
use crate::system::System;

/// Adds to `force` (sorted order, N·d) the forces of every overlapping pair image other than
/// the nearest, and returns their sums. The images of one pair are visited in the order of an
/// odometer over the shifts −1, 0, 1 per axis, first axis fastest.
pub(super) fn add_forces<const D: usize, const ABSOLUTE: bool, const VIRIAL: bool>(
    sys: &System,
    force: &mut [[f64; D]],
    frame: &Frame<D, ABSOLUTE>,
) -> PairSums<VIRIAL> {
    let mut sums = PairSums::<VIRIAL>::default();
    let geo = &frame.geo;
    let Some((_, _, wide)) = sys.wide_spheres() else {
        return sums;
    };
    let wide: Vec<usize> = wide.collect();
    let (x, _) = sys.x.as_chunks::<D>();
    for (a, &i) in wide.iter().enumerate() {
        for &j in &wide[a + 1..] {
            let (di, dj) = (sys.dia[i], sys.dia[j]);
            let sigma = 0.5 * (di + dj);
            // The nearest image, and per axis the shifts (in lengths) that keep it within σ.
            let mut near = [0.0; D];
            let mut shifts = [[0i8; 3]; D];
            let mut counts = [1usize; D];
            for k in 0..D {
                let mut t = x[j][k] - x[i][k];
                if geo.periodic[k] {
                    // The neighbour list's image, ties included, so it is not counted twice.
                    t = geo.nearest_image(t, k);
                    for s in [-1i8, 1] {
                        if (t + f64::from(s) * geo.length[k]).abs() < sigma {
                            shifts[k][counts[k]] = s;
                            counts[k] += 1;
                        }
                    }
                }
                near[k] = t;
            }
            let w = frame.weight(sigma);
            let g = frame.growth(i, j, di, dj);
            let mut digit = [0usize; D];
            // Each step moves the odometer on, so the all-zero position (the nearest image)
            // is never visited.
            while let Some(k) = (0..D).find(|&k| digit[k] + 1 < counts[k]) {
                digit[k] += 1;
                digit[..k].fill(0);
                let mut dx = [0.0; D];
                let mut r2 = 0.0;
                for m in 0..D {
                    dx[m] = near[m] + f64::from(shifts[m][digit[m]]) * geo.length[m];
                    r2 += dx[m] * dx[m];
                }
                if r2 >= sigma * sigma {
                    continue;
                }
                let r = r2.sqrt();
                let eps = 1.0 - r / sigma;
                sums.add(eps, sigma / r - 1.0, w, g);
                let c = w * eps / (sigma * r);
                for m in 0..D {
                    force[i][m] -= c * dx[m];
                    force[j][m] += c * dx[m];
                }
            }
        }
    }
    sums
}

#[cfg(test)]
mod tests {
    use packbench_core::neighbor::for_each_image_pair;
    use packbench_core::{Container, Packing};

    use super::super::evaluate;
    use crate::neighbor_list::NeighborList;
    use crate::system::System;

    /// Three spheres wider than half the shortest side (L = 4, 4.5, 5) among thirty small
    /// ones, placed by a fixed congruential sequence; the two widest sit half a side apart
    /// along x, so that they overlap through two images at once.
    fn wide_mixture() -> Packing {
        let c = Container::periodic_box(&[4.0, 4.5, 5.0]).unwrap();
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut x = Vec::new();
        let mut d = Vec::new();
        for i in 0..33 {
            for l in [4.0, 4.5, 5.0] {
                x.push(l * next());
            }
            d.push(match i {
                0 => 3.4,
                1 => 2.9,
                2 => 2.6,
                _ => 0.5 + 0.3 * next(),
            });
        }
        x[..6].copy_from_slice(&[0.5, 0.5, 0.5, 2.5, 0.7, 0.9]);
        Packing::new(x, d, c).unwrap()
    }

    /// U = Σ ½ ε² over every overlapping pair image, listed by the core's all-image
    /// enumeration (independent of the packer's neighbour list), and the number of them.
    fn energy_over_all_images(p: &Packing) -> (f64, usize) {
        let (mut u, mut contacts) = (0.0, 0);
        let c = &p.container;
        for_each_image_pair(c, &p.positions, &p.diameters, 0.0, |i, j, shift| {
            let sigma = 0.5 * (p.diameters[i] + p.diameters[j]);
            let r2: f64 = (0..3)
                .map(|k| {
                    let t = p.positions[3 * j + k] + f64::from(shift[k]) * c.lengths[k]
                        - p.positions[3 * i + k];
                    t * t
                })
                .sum();
            let eps = 1.0 - r2.sqrt() / sigma;
            if eps > 0.0 {
                u += 0.5 * eps * eps;
                contacts += 1;
            }
        });
        (u, contacts)
    }

    /// The packer's evaluation of `p`: its sums, and the forces with the system (whose sorted
    /// order they follow).
    fn evaluated(p: &Packing, parallel: bool) -> (super::super::Evaluation, Vec<f64>, System) {
        let mut sys = System::new(p, &[]).unwrap();
        let mut nl = NeighborList::new();
        nl.update(&mut sys, (0.2, 0.2), 0.0, false);
        let mut force = vec![0.0; sys.x.len()];
        let ev = evaluate(&sys, &mut nl, &mut force, &mut Vec::new(), parallel, true);
        (ev, force, sys)
    }

    #[test]
    fn energy_counts_every_overlapping_image() {
        let p = wide_mixture();
        let (ev, _, _) = evaluated(&p, false);
        let (u, contacts) = energy_over_all_images(&p);
        // The wide pairs must really overlap through more than one image for this to test
        // anything: spheres 0 and 1 (σ = 3.15, 2 apart along x, L_x = 4) do.
        let mut images01 = 0;
        for_each_image_pair(&p.container, &p.positions, &p.diameters, 0.0, |i, j, _| {
            images01 += usize::from(i == 0 && j == 1);
        });
        assert!(
            images01 >= 2,
            "{images01} images of the pair 0-1 within reach"
        );
        assert!(
            (ev.energy - u).abs() <= 1e-12 * u,
            "U {} against {u}",
            ev.energy
        );
        assert_eq!(ev.contacts as usize, contacts);
    }

    #[test]
    fn forces_are_minus_the_energy_gradient() {
        let p = wide_mixture();
        let (_, force, sys) = evaluated(&p, false);
        let h = 1e-6;
        // The widest sphere (input 0) in the system's sorted order.
        let s = (0..sys.n()).find(|&s| sys.d0[s] == 3.4).unwrap();
        for k in 0..3 {
            let energy_at = |delta: f64| {
                let mut q = p.clone();
                q.positions[k] += delta;
                energy_over_all_images(&q).0
            };
            let gradient = (energy_at(h) - energy_at(-h)) / (2.0 * h);
            let f = force[3 * s + k];
            assert!(
                (f + gradient).abs() <= 1e-6 * (1.0 + f.abs()),
                "axis {k}: F {f}, -dU/dx {}",
                -gradient
            );
        }
    }

    #[test]
    fn two_threads_give_the_same_forces_to_the_bit() {
        let p = wide_mixture();
        let (one, f1, _) = evaluated(&p, false);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let (two, f2, _) = pool.install(|| evaluated(&p, true));
        assert_eq!(f1, f2);
        assert_eq!(one.energy, two.energy);
    }
}
