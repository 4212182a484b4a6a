//! Known answers of the void-space analysis: crystal cells and holes, volume sums, the chord
//! identity, scale invariance and the refusals.

use rand::rngs::StdRng;
use rand::{RngExt, SeedableRng};

use super::*;
use crate::container::Container;
use crate::geometry::ball_volume;
use crate::packing::Packing;

/// A crystal of `basis` (fractions of the cubic cell) repeated `n` times per axis, cubic
/// cell side `a`, periodic, all diameters `dia`.
fn crystal(basis: &[[f64; 3]], n: usize, a: f64, dia: f64) -> Packing {
    let mut pos = Vec::new();
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                for b in basis {
                    pos.extend([
                        (i as f64 + b[0]) * a,
                        (j as f64 + b[1]) * a,
                        (k as f64 + b[2]) * a,
                    ]);
                }
            }
        }
    }
    let count = pos.len() / 3;
    let l = n as f64 * a;
    Packing::new(
        pos,
        vec![dia; count],
        Container::periodic_box(&[l, l, l]).unwrap(),
    )
    .unwrap()
}

const FCC: [[f64; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [0.5, 0.5, 0.0],
    [0.5, 0.0, 0.5],
    [0.0, 0.5, 0.5],
];
const BCC: [[f64; 3]; 2] = [[0.0, 0.0, 0.0], [0.5, 0.5, 0.5]];
const SC: [[f64; 3]; 1] = [[0.0, 0.0, 0.0]];

/// Non-overlapping random spheres (random sequential addition) with diameters drawn from
/// [0.7, 1.3], in a box with the given per-axis periodicity.
fn random_spheres(d: usize, n: usize, phi: f64, walls: &[bool], seed: u64) -> Packing {
    let mut rng = StdRng::seed_from_u64(seed);
    let dias: Vec<f64> = (0..n).map(|_| rng.random_range(0.7..1.3)).collect();
    let vol: f64 = dias.iter().map(|&x| ball_volume(d, x)).sum::<f64>() / phi;
    let l = vol.powf(1.0 / d as f64);
    let container = Container::with_flags(&vec![l; d], walls).unwrap();
    let mut pos: Vec<f64> = Vec::new();
    for i in 0..n {
        'try_again: loop {
            let r = 0.5 * dias[i];
            let x: Vec<f64> = (0..d)
                .map(|k| {
                    if walls[k] {
                        rng.random_range(r..l - r)
                    } else {
                        rng.random_range(0.0..l)
                    }
                })
                .collect();
            for j in 0..i {
                let mut delta = vec![0.0; d];
                container.separation(&x, &pos[j * d..(j + 1) * d], &mut delta);
                let dist = delta.iter().map(|v| v * v).sum::<f64>().sqrt();
                if dist < 0.5 * (dias[i] + dias[j]) {
                    continue 'try_again;
                }
            }
            pos.extend(x);
            break;
        }
    }
    Packing::new(pos, dias, container).unwrap()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn fcc_cells_are_rhombic_dodecahedra_of_a_quarter_cube() {
    let a = 1.3;
    let p = crystal(&FCC, 3, a, a / 2f64.sqrt());
    let cells = radical_voronoi(&p).unwrap();
    for (i, (&v, &f)) in cells.volumes.iter().zip(&cells.faces).enumerate() {
        assert!(rel(v, a * a * a / 4.0) < 1e-12, "cell {i}: volume {v}");
        assert_eq!(f, 12, "cell {i}");
    }
    // FCC close packing: φ = π/(3√2) in every cell.
    let phi_fcc = std::f64::consts::PI / (3.0 * 2f64.sqrt());
    assert!(cells.local_phi.iter().all(|&x| rel(x, phi_fcc) < 1e-12));
    let report = voronoi(&p).unwrap();
    assert!(rel(report.total_volume, p.container.volume()) < 1e-12);
    assert!(report.volume_std_relative < 1e-10);
}

#[test]
fn bcc_cells_are_truncated_octahedra_of_half_a_cube() {
    let a = 0.9;
    let p = crystal(&BCC, 3, a, 3f64.sqrt() / 2.0 * a);
    let cells = radical_voronoi(&p).unwrap();
    for (&v, &f) in cells.volumes.iter().zip(&cells.faces) {
        assert!(rel(v, a * a * a / 2.0) < 1e-12, "volume {v}");
        assert_eq!(f, 14);
    }
}

#[test]
fn cell_volumes_sum_to_the_periodic_and_walled_box() {
    for walls in [[false; 3], [true, false, true], [true; 3]] {
        let p = random_spheres(3, 150, 0.25, &walls, 7);
        let r = voronoi(&p).unwrap();
        assert!(
            rel(r.total_volume, p.container.volume()) < 1e-12,
            "walls {walls:?}: {} against {}",
            r.total_volume,
            p.container.volume()
        );
        // Radical cells of non-overlapping spheres contain their spheres.
        assert!(r.cells.local_phi.iter().all(|&x| x > 0.0 && x < 1.0));
    }
}

#[test]
fn two_dimensional_triangular_cells_are_regular_hexagons() {
    let (nx, ny, a) = (6, 4, 1.1);
    let h = a * 3f64.sqrt() / 2.0;
    let mut pos = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            pos.extend([(i as f64 + 0.5 * (j % 2) as f64) * a, j as f64 * h]);
        }
    }
    let c = Container::periodic_box(&[nx as f64 * a, ny as f64 * h]).unwrap();
    let p = Packing::new(pos, vec![a; nx * ny], c).unwrap();
    let cells = radical_voronoi(&p).unwrap();
    let hexagon = 3f64.sqrt() / 2.0 * a * a;
    for (&v, &f) in cells.volumes.iter().zip(&cells.faces) {
        assert!(rel(v, hexagon) < 1e-12, "area {v} against {hexagon}");
        assert_eq!(f, 6);
    }
    let sum: f64 = cells.volumes.iter().sum();
    assert!(rel(sum, p.container.volume()) < 1e-12);
    // Disks in a walled 2D box tile the box too.
    let q = random_spheres(2, 80, 0.4, &[true, false], 3);
    let s: f64 = radical_voronoi(&q).unwrap().volumes.iter().sum();
    assert!(rel(s, q.container.volume()) < 1e-12);
}

#[test]
fn fcc_holes_are_octahedral_and_tetrahedral() {
    let a = 2.0;
    let r = a / 2f64.sqrt() / 2.0;
    let p = crystal(&FCC, 2, a, 2.0 * r);
    let net = pore_network(&p).unwrap();
    // 4 octahedral and 8 tetrahedral holes per cubic cell.
    assert_eq!(net.centres.len(), 8 * (4 + 8), "{:?}", net.centres.len());
    // From the cell's geometry, not from the radius-ratio formulas: the octahedral hole at an
    // edge midpoint lies a/2 from its nearest centres, the tetrahedral one at (a/4, a/4, a/4)
    // lies a√3/4 from its corner; their ratios to r are the textbook 0.414 and 0.225
    // (Ashcroft & Mermin 1976, ch. 4; the radius-ratio rule).
    let octa = a / 2.0 - r;
    let tetra = a * 3f64.sqrt() / 4.0 - r;
    assert!((octa / r - 0.414).abs() < 5e-4 && (tetra / r - 0.225).abs() < 5e-4);
    let n_octa = net
        .pore_radius
        .iter()
        .filter(|&&x| rel(x, octa) < 1e-9)
        .count();
    let n_tetra = net
        .pore_radius
        .iter()
        .filter(|&&x| rel(x, tetra) < 1e-9)
        .count();
    assert_eq!((n_octa, n_tetra), (32, 64));
    let report = pores(&p, &PoreOptions::default()).unwrap();
    assert!(rel(report.included_sphere_diameter, 2.0 * octa) < 1e-9);
    assert!(rel(octa / r, 0.4142) < 1e-3 && rel(tetra / r, 0.2247) < 1e-3);
}

#[test]
fn simple_cubic_free_sphere_passes_the_square_windows() {
    let a = 1.0;
    let r = 0.5 * a;
    let p = crystal(&SC, 4, a, a);
    let report = pores(&p, &PoreOptions::default()).unwrap();
    // Cube centres hold (√3 − 1)R; the windows between four spheres pass (√2 − 1)R.
    assert!(
        rel(
            report.included_sphere_diameter,
            2.0 * (3f64.sqrt() - 1.0) * r
        ) < 1e-9
    );
    let free = report.free_sphere_diameter.unwrap();
    assert!(
        rel(free, 2.0 * (2f64.sqrt() - 1.0) * r) < 1e-9,
        "D_f = {free}"
    );
    // A walled box has no periodic path.
    let q = random_spheres(3, 60, 0.15, &[true; 3], 2);
    assert_eq!(
        pores(&q, &PoreOptions::default())
            .unwrap()
            .free_sphere_diameter,
        None
    );
}

#[test]
fn scaling_the_packing_scales_every_length() {
    let p = random_spheres(3, 120, 0.3, &[false; 3], 11);
    let s = 2.5;
    let mut q = p.clone();
    for x in &mut q.positions {
        *x *= s;
    }
    q.scale_diameters(s);
    q.container.scale(s);
    let (vp, vq) = (voronoi(&p).unwrap(), voronoi(&q).unwrap());
    for (a, b) in vp.cells.volumes.iter().zip(&vq.cells.volumes) {
        assert!(rel(*b, a * s * s * s) < 1e-10);
    }
    for (a, b) in vp.cells.local_phi.iter().zip(&vq.cells.local_phi) {
        assert!(rel(*b, *a) < 1e-10);
    }
    let (pp, pq) = (
        pores(&p, &PoreOptions::default()).unwrap(),
        pores(&q, &PoreOptions::default()).unwrap(),
    );
    assert!(rel(pq.included_sphere_diameter, s * pp.included_sphere_diameter) < 1e-9);
    assert!(
        rel(
            pq.free_sphere_diameter.unwrap(),
            s * pp.free_sphere_diameter.unwrap()
        ) < 1e-9
    );
    assert!(rel(pq.pore_size_mean, s * pp.pore_size_mean) < 1e-9);
}

#[test]
fn mean_void_chord_obeys_the_stereological_identity() {
    for (d, phi) in [(3, 0.2), (3, 0.32), (2, 0.45)] {
        let p = random_spheres(d, 300, phi, &vec![false; d], 5);
        let r = chords(&p, &ChordOptions::default()).unwrap();
        for (set, predicted) in [
            (&r.void, r.void_mean_predicted),
            (&r.solid, r.solid_mean_predicted),
            (&r.axial_void, r.void_mean_predicted),
        ] {
            // Chords along one line are correlated; allow five standard errors.
            assert!(
                (set.mean - predicted).abs() < 5.0 * set.mean_error,
                "d = {d}, φ = {phi}: mean {} ± {} against {predicted}",
                set.mean,
                set.mean_error
            );
        }
    }
}

#[test]
fn fines_fill_their_scaffold_cells() {
    // Large spheres on a simple cubic lattice, one fine inside each large sphere's cell.
    let a = 1.0;
    let big = crystal(&SC, 3, a, a);
    let mut pos = big.positions.clone();
    let mut dia = big.diameters.clone();
    for i in 0..27 {
        let x = big.position(i).to_vec();
        pos.extend(x.iter().map(|v| v + 0.4 * a));
        dia.push(0.2);
    }
    let p = Packing::new(pos, dia, big.container.clone()).unwrap();
    let fill = scaffold_fill(&p, 0.9).unwrap();
    assert_eq!((fill.scaffold, fill.fines), (27, 27));
    let expected = ball_volume(3, 0.2) / (a * a * a - ball_volume(3, a));
    assert!(fill.fill.iter().all(|&f| rel(f, expected) < 1e-9));
    assert_eq!(fill.empty_cells, 0.0);
    assert!(scaffold_fill(&p, 2.0).is_err());
}

#[test]
fn bad_input_is_refused_with_a_sentence() {
    let c = Container::periodic_box(&[3.0, 3.0, 3.0]).unwrap();
    let same = Packing::new(vec![1.0; 6], vec![1.0, 1.0], c.clone()).unwrap();
    let e = voronoi(&same).unwrap_err().to_string();
    assert!(e.contains("same centre"), "{e}");
    let deep = Packing::new(vec![1.0, 1.0, 1.0, 1.5, 1.0, 1.0], vec![1.0, 1.0], c).unwrap();
    let e = pores(&deep, &PoreOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("overlap"), "{e}");
    let c4 = Container::periodic_box(&[3.0; 4]).unwrap();
    let p4 = Packing::new(vec![1.0; 4], vec![1.0], c4).unwrap();
    let e = voronoi(&p4).unwrap_err().to_string();
    assert!(e.contains("2 and 3 dimensions"), "{e}");
    let walled = random_spheres(3, 20, 0.2, &[true; 3], 1);
    assert!(chords(&walled, &ChordOptions::default()).is_err());
}

#[test]
fn one_tessellation_gives_what_the_two_analyses_give_apart() {
    for (d, walls) in [
        (3, vec![false; 3]),
        (3, vec![true, false, true]),
        (2, vec![false; 2]),
    ] {
        let p = random_spheres(d, 100, 0.2, &walls, 13);
        let options = PoreOptions::default();
        let (v, pr) = voronoi_and_pores(&p, &options).unwrap();
        assert_eq!(v, voronoi(&p).unwrap(), "d = {d}, walls {walls:?}");
        assert_eq!(pr, pores(&p, &options).unwrap(), "d = {d}, walls {walls:?}");
    }
    let none = PoreOptions {
        samples: 0,
        ..PoreOptions::default()
    };
    let p = random_spheres(3, 20, 0.2, &[false; 3], 1);
    assert!(voronoi_and_pores(&p, &none).is_err());
}
