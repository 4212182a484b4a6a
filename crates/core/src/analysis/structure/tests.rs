//! Structure measures on known structures: crystals at contact, a triangular lattice, Poisson
//! points.

use rand::RngExt;
use rand::SeedableRng;
use rand::rngs::StdRng;

use super::*;
use crate::container::Container;

/// A periodic packing of diameter-1 spheres at the given sites of a box of side `lengths`.
fn packing(sites: Vec<f64>, lengths: &[f64]) -> Packing {
    let n = sites.len() / lengths.len();
    Packing::new(
        sites,
        vec![1.0; n],
        Container::periodic_box(lengths).unwrap(),
    )
    .unwrap()
}

/// `cells` cubic cells of side `a` per axis with the given basis (in units of `a`).
fn cubic(basis: &[[f64; 3]], a: f64, cells: usize) -> Packing {
    let mut x = Vec::new();
    for i in 0..cells {
        for j in 0..cells {
            for k in 0..cells {
                for b in basis {
                    x.extend([
                        (i as f64 + b[0]) * a,
                        (j as f64 + b[1]) * a,
                        (k as f64 + b[2]) * a,
                    ]);
                }
            }
        }
    }
    let l = cells as f64 * a;
    packing(x, &[l, l, l])
}

fn fcc() -> Packing {
    let basis = [
        [0.0, 0.0, 0.0],
        [0.5, 0.5, 0.0],
        [0.5, 0.0, 0.5],
        [0.0, 0.5, 0.5],
    ];
    cubic(&basis, 2f64.sqrt(), 3)
}

fn bcc() -> Packing {
    cubic(&[[0.0, 0.0, 0.0], [0.5, 0.5, 0.5]], 2.0 / 3f64.sqrt(), 4)
}

fn simple_cubic(cells: usize) -> Packing {
    cubic(&[[0.0, 0.0, 0.0]], 1.0, cells)
}

/// Ideal HCP (c/a = √(8/3)) in an orthorhombic cell a × a√3 × c of four sites.
fn hcp() -> Packing {
    let (a, b, c) = (1.0, 3f64.sqrt(), (8.0f64 / 3.0).sqrt());
    let basis = [
        [0.0, 0.0, 0.0],
        [0.5, 0.5, 0.0],
        [0.5, 1.0 / 6.0, 0.5],
        [0.0, 2.0 / 3.0, 0.5],
    ];
    let (nx, ny, nz) = (4, 3, 3);
    let mut x = Vec::new();
    for i in 0..nx {
        for j in 0..ny {
            for k in 0..nz {
                for s in &basis {
                    x.extend([
                        (i as f64 + s[0]) * a,
                        (j as f64 + s[1]) * b,
                        (k as f64 + s[2]) * c,
                    ]);
                }
            }
        }
    }
    packing(x, &[nx as f64 * a, ny as f64 * b, nz as f64 * c])
}

fn close(a: Option<f64>, b: f64) -> bool {
    a.is_some_and(|a| (a - b).abs() < 1e-4)
}

const CONTACT: Neighbours = Neighbours::Contact { tol: 1e-6 };
const SHELL: Neighbours = Neighbours::Cutoff { factor: 1.2 };

#[test]
fn crystals_at_contact_give_their_known_q4_and_q6() {
    // Steinhardt, Nelson & Ronchetti (1983), Table I; exact values: SC Q4 = √(7/12),
    // Q6 = √(1/8); FCC Q4 = √(7/192).
    let cases = [
        (
            "fcc",
            fcc(),
            CONTACT,
            12.0,
            (7.0f64 / 192.0).sqrt(),
            0.574_524,
        ),
        ("hcp", hcp(), CONTACT, 12.0, 0.097_222, 0.484_762),
        ("bcc, 8 touching", bcc(), CONTACT, 8.0, 0.509_175, 0.628_539),
        (
            "bcc, 14 in the shell",
            bcc(),
            SHELL,
            14.0,
            0.036_370,
            0.510_688,
        ),
        (
            "sc",
            simple_cubic(4),
            CONTACT,
            6.0,
            (7.0f64 / 12.0).sqrt(),
            (1.0f64 / 8.0).sqrt(),
        ),
    ];
    for (name, p, rule, z, q4, q6) in cases {
        let b = bond_order(&p, rule);
        assert!(
            (b.mean_bonds - z).abs() < 1e-12,
            "{name}: {} bonds",
            b.mean_bonds
        );
        assert!(close(b.q4, q4), "{name}: Q4 = {:?}", b.q4);
        assert!(close(b.q6, q6), "{name}: Q6 = {:?}", b.q6);
        // Every site of a perfect crystal has the global value locally.
        assert!(
            close(b.local_mean, q6),
            "{name}: local q6 {:?}",
            b.local_mean
        );
    }
}

#[test]
fn crystals_are_crystal_like_and_poisson_points_are_not() {
    for p in [fcc(), hcp(), bcc()] {
        assert_eq!(bond_order(&p, CONTACT).crystal_fraction, Some(1.0));
    }
    let gas = poisson(3, 2000, 0.2, 7);
    let f = bond_order(&gas, SHELL).crystal_fraction.unwrap();
    assert!(f < 0.01, "{f}");
}

#[test]
fn triangular_lattice_has_unit_hexatic_order() {
    let (nx, ny) = (6, 6);
    let h = 3f64.sqrt() / 2.0;
    let mut x = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            x.extend([i as f64 + 0.5 * (j % 2) as f64, j as f64 * h]);
        }
    }
    let p = packing(x, &[nx as f64, ny as f64 * h]);
    let b = bond_order(&p, CONTACT);
    assert!((b.mean_bonds - 6.0).abs() < 1e-12);
    assert!((b.psi6.unwrap() - 1.0).abs() < 1e-12);
    assert!((b.local_mean.unwrap() - 1.0).abs() < 1e-12);
    assert_eq!(b.crystal_fraction, Some(1.0));
    assert!(b.q6.is_none());
}

#[test]
fn fcc_pair_correlation_has_its_shells_at_their_radii() {
    let p = fcc();
    let gr = pair_correlation(&p, 200);
    // Coordination n(R) = Σ_b g_b ρ (shell volume)_b: 12 within 1.2, 18 within 1.5, 42 within 1.8.
    let rho = p.n() as f64 / p.container.volume();
    let dr = gr.r[1] - gr.r[0];
    let coordination = |r_max: f64| -> f64 {
        gr.r.iter()
            .zip(&gr.g)
            .filter(|(r, _)| **r < r_max)
            .map(|(r, g)| {
                let (r0, r1) = (r - 0.5 * dr, r + 0.5 * dr);
                g * rho * 4.0 / 3.0 * std::f64::consts::PI * (r1.powi(3) - r0.powi(3))
            })
            .sum()
    };
    for (r, z) in [(1.2, 12.0), (1.5, 18.0), (1.8, 42.0)] {
        assert!(
            (coordination(r) - z).abs() < 1e-9,
            "n({r}) = {}",
            coordination(r)
        );
    }
    let peak =
        gr.g.iter()
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(b.1))
            .unwrap()
            .0;
    assert!((gr.r[peak] - 1.0).abs() <= 0.5 * dr + 1e-12);
}

/// Reciprocal-lattice magnitudes |G|·D of FCC at contact up to k_max: 2π/a √(h²+k²+l²) with
/// h, k, l all even or all odd.
fn fcc_bragg(k_max: f64) -> Vec<f64> {
    let a = 2f64.sqrt();
    let mut g = Vec::new();
    for h in -6i32..=6 {
        for k in -6i32..=6 {
            for l in -6i32..=6 {
                let parity = [h, k, l].map(|v| v.rem_euclid(2));
                if (h, k, l) != (0, 0, 0) && parity[0] == parity[1] && parity[1] == parity[2] {
                    let m =
                        2.0 * std::f64::consts::PI / a * ((h * h + k * k + l * l) as f64).sqrt();
                    if m <= k_max {
                        g.push(m);
                    }
                }
            }
        }
    }
    g
}

#[test]
fn crystal_structure_factor_peaks_only_at_reciprocal_lattice_vectors() {
    let opt = StructureFactorOptions {
        relative_error: 1e-3,
        ..StructureFactorOptions::default()
    };
    let width = opt.k_max / opt.bins as f64;
    let p = fcc();
    let sf = structure_factor(&p, &opt).unwrap();
    let bragg = fcc_bragg(opt.k_max);
    assert!(!bragg.is_empty());
    let mut peaks = 0;
    for (&k, &s) in sf.k.iter().zip(&sf.s) {
        let bin = (k / width).floor();
        let on_bragg = bragg.iter().any(|&g| (g / width).floor() == bin);
        if on_bragg {
            assert!(s > 1.0, "k = {k}: S = {s} on a Bragg bin");
            peaks += 1;
        } else {
            assert!(s < 1e-9, "k = {k}: S = {s} off every Bragg bin");
        }
    }
    assert_eq!(peaks, 2, "(111) and (200) below k·D = 12");
    // At a Bragg vector every phase is 1: S = N, so a bin holding only Bragg vectors has S = N.
    let max = sf.s.iter().cloned().fold(0.0, f64::max);
    assert!(max <= p.n() as f64 + 1e-9);
}

/// `n` uniform random centres of diameter-1 particles in `d` dimensions at nominal φ.
fn poisson(d: usize, n: usize, phi: f64, seed: u64) -> Packing {
    let v = n as f64 * crate::geometry::ball_volume(d, 1.0) / phi;
    let l = v.powf(1.0 / d as f64);
    let mut rng = StdRng::seed_from_u64(seed);
    let x: Vec<f64> = (0..n * d).map(|_| rng.random_range(0.0..l)).collect();
    packing(x, &vec![l; d])
}

#[test]
fn poisson_points_have_a_flat_unit_structure_factor() {
    let p = poisson(3, 3000, 0.3, 11);
    let sf = structure_factor(&p, &StructureFactorOptions::default()).unwrap();
    let total: usize = sf.vectors.iter().sum();
    let mean =
        sf.s.iter()
            .zip(&sf.vectors)
            .map(|(s, &c)| s * c as f64)
            .sum::<f64>()
            / total as f64;
    assert!(
        (mean - 1.0).abs() < 0.05,
        "mean S = {mean} over {total} vectors"
    );
    let s0 = sf.s_k0.unwrap();
    assert!((s0 - 1.0).abs() < 0.35, "S(0) = {s0}");
    // Equal spheres: χ̃ = S·(m/v)², which tends to S at low k.
    let chi = sf.chi.as_ref().unwrap();
    assert!((chi[0] / sf.s[0] - 1.0).abs() < 0.05 * sf.k[0] * sf.k[0] + 1e-9);
}

#[test]
fn uncorrelated_points_have_a_flat_gap_distribution() {
    let p = poisson(3, 4000, 0.3, 5);
    let g = gap_distribution(&p, &vec![false; p.n()], 1e-6, [1e-3, 0.05]);
    let gamma = g.gamma.unwrap();
    assert!(
        gamma.abs() < 0.15,
        "γ = {gamma} from {} gaps",
        g.fit_samples
    );
}

#[test]
fn crystal_forces_balance_with_mean_one() {
    let p = fcc();
    let net = crate::analysis::contact_network(&p, 1e-6);
    let rattler = crate::analysis::rattlers(&net, p.n(), 3);
    let n_dof = 3 * p.n() + 1 - 3;
    let f = force_distribution(&net, &rattler, 3, n_dof, [0.01, 0.3]).unwrap();
    assert_eq!(f.count, 6 * p.n());
    assert!(f.residual < 1e-6, "{}", f.residual);
    // z = 12 > 2d: the forces are one solution of many, so no θ_e/θ_ℓ, and a note says why.
    assert!(!f.unique && f.extended.is_none() && f.localised.is_none());
    assert!(
        f.note.as_deref().unwrap().contains("one solution of many"),
        "{f:?}"
    );
}

#[test]
fn analyze_structure_reports_everything_for_a_periodic_packing() {
    let r = analyze_structure(&fcc(), &StructureOptions::default()).unwrap();
    assert!(close(r.bond_order.q6, 0.574_524));
    assert!(r.structure_factor.is_some() && r.pair_correlation.is_some());
    assert!(r.forces.is_some());
    let json = serde_json::to_value(&r).unwrap();
    assert!(json.get("q6").is_some() && json.get("q4").is_some());
    assert!(json["structure_factor"].get("s_k0").is_some());
    let bad = StructureOptions {
        gap_window: [1e-2, 1e-5],
        ..StructureOptions::default()
    };
    assert!(analyze_structure(&fcc(), &bad).is_err());
}
