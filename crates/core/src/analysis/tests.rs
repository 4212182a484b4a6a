use super::*;
use crate::container::Container;
use crate::packing::Packing;

/// A 2D hexagonal crystal of unit disks at contact in a periodic box (ny even).
pub(crate) fn hexagonal(nx: usize, ny: usize) -> Packing {
    let h = 3f64.sqrt() / 2.0;
    let mut x = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            x.push(i as f64 + 0.5 * (j % 2) as f64 + 0.25);
            x.push(j as f64 * h + 0.1);
        }
    }
    let c = Container::periodic_box(&[nx as f64, ny as f64 * h]).unwrap();
    Packing::new(x, vec![1.0; nx * ny], c).unwrap()
}

/// A 3D FCC crystal of unit spheres at contact in a periodic box of n³ cubic cells.
pub(crate) fn fcc(n: usize) -> Packing {
    let a = 2f64.sqrt();
    let basis = [
        [0.0, 0.0, 0.0],
        [0.5, 0.5, 0.0],
        [0.5, 0.0, 0.5],
        [0.0, 0.5, 0.5],
    ];
    let mut x = Vec::new();
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                for b in &basis {
                    x.extend([
                        (i as f64 + b[0] + 0.1) * a,
                        (j as f64 + b[1] + 0.1) * a,
                        (k as f64 + b[2] + 0.1) * a,
                    ]);
                }
            }
        }
    }
    let l = n as f64 * a;
    let c = Container::periodic_box(&[l, l, l]).unwrap();
    let count = 4 * n * n * n;
    Packing::new(x, vec![1.0; count], c).unwrap()
}

#[test]
fn hexagonal_crystal_has_phi_0_9069_and_z_6() {
    let p = hexagonal(6, 6);
    let m = analyze(&p, &AnalysisOptions::default()).unwrap();
    assert!(
        (m.phi - std::f64::consts::PI / 12f64.sqrt()).abs() < 1e-12,
        "phi {}",
        m.phi
    );
    assert_eq!(m.contacts, 3 * 36);
    assert_eq!(m.z_mean, 6.0);
    assert_eq!(m.rattlers, 0);
    assert_eq!(m.z_nonrattler, 6.0);
    assert_eq!(m.n_dof, 2 * 35 + 1);
    assert_eq!(m.iso_gap, 108 - 71);
    assert!(!m.isostatic);
    assert!(m.max_overlap < 1e-12);
    assert!(m.force_balance.unwrap() < 1e-9, "{:?}", m.force_balance);
}

#[test]
fn fcc_crystal_has_phi_0_7405_z_12_and_is_force_balanced() {
    let p = fcc(3);
    let m = analyze(&p, &AnalysisOptions::default()).unwrap();
    assert!(
        (m.phi - std::f64::consts::PI / 18f64.sqrt()).abs() < 1e-12,
        "phi {}",
        m.phi
    );
    assert_eq!(m.n, 108);
    assert_eq!(m.z_nonrattler, 12.0);
    assert_eq!(m.contacts, 6 * 108);
    assert_eq!(m.rattlers, 0);
    assert!(m.force_balance.unwrap() < 1e-9, "{:?}", m.force_balance);
}

/// Boxes shorter than two diameters: every disk of a hexagonal crystal still has six contacts,
/// some of them with a second image of the same partner or with its own image.
#[test]
fn contacts_through_several_images_are_all_counted() {
    for (nx, ny) in [(1, 2), (2, 2), (3, 2), (1, 4)] {
        let p = hexagonal(nx, ny);
        let m = analyze(&p, &AnalysisOptions::default()).unwrap();
        assert_eq!(m.z_mean, 6.0, "{nx}×{ny}");
        assert_eq!(m.contacts, 3 * nx * ny, "{nx}×{ny}");
        assert_eq!(m.rattlers, 0, "{nx}×{ny}");
        assert!(m.max_overlap < 1e-12);
        assert!(
            m.force_balance.unwrap() < 1e-9,
            "{nx}×{ny}: {:?}",
            m.force_balance
        );
    }
    // One disk per row: it touches its own image along x, once per ±x pair.
    let net = contact_network(&hexagonal(1, 2), 1e-9);
    let own = net.contacts.iter().filter(|c| c.j == Some(c.i)).count();
    assert_eq!(own, 2);
    // Two disks half a box apart touch through both images of each other.
    let c = Container::periodic_box(&[1.0, 3.0]).unwrap();
    let p = Packing::new(vec![0.25, 1.5, 0.75, 1.5], vec![0.5, 0.5], c).unwrap();
    let net = contact_network(&p, 1e-9);
    assert_eq!(net.contacts.len(), 2);
    let nx: Vec<f64> = (0..2).map(|k| net.normals[2 * k]).collect();
    assert!(nx.contains(&1.0) && nx.contains(&-1.0), "{nx:?}");
}

#[test]
fn two_touching_disks_in_a_walled_box() {
    let c = Container::with_flags(&[2.0, 1.0], &[true, true]).unwrap();
    let p = Packing::new(vec![0.5, 0.5, 1.5, 0.5], vec![1.0, 1.0], c).unwrap();
    let m = analyze(&p, &AnalysisOptions::default()).unwrap();
    // Each disk touches three walls and the other disk.
    assert_eq!(m.contacts, 7);
    assert_eq!(m.rattlers, 0);
    assert_eq!(m.z_nonrattler, 4.0);
    assert_eq!(m.n_dof, 5);
    assert_eq!(m.iso_gap, 2);
    assert!((m.phi - std::f64::consts::PI / 4.0).abs() < 1e-12);
    assert!(m.force_balance.unwrap() < 1e-9);
}

#[test]
fn a_caged_small_disk_is_a_rattler() {
    let mut p = hexagonal(6, 6);
    p.diameters[14] = 0.8;
    let m = analyze(&p, &AnalysisOptions::default()).unwrap();
    assert_eq!(m.rattlers, 1);
    assert_eq!(m.n_dof, 2 * 34 + 1);
    assert_eq!(m.contacts, 108 - 6);
    assert!(m.force_balance.unwrap() < 1e-9);
}

#[test]
fn rattlers_are_removed_iteratively() {
    // A chain of three disks between two walls: the middle one has only 2 contacts, so it is a
    // rattler, and then the outer ones lose a contact and become rattlers too.
    let c = Container::with_flags(&[3.0, 4.0], &[true, true]).unwrap();
    let p = Packing::new(vec![0.5, 2.0, 1.5, 2.0, 2.5, 2.0], vec![1.0; 3], c).unwrap();
    let m = analyze(&p, &AnalysisOptions::default()).unwrap();
    assert_eq!(m.contacts, 4);
    assert_eq!(m.rattlers, 3);
    assert_eq!(m.n_dof, 0);
    assert_eq!(m.force_balance, None);
}

#[test]
fn an_unbalanced_configuration_is_detected() {
    // A large disk hangs from the top wall between two small disks sitting higher than its
    // centre: every force on it points down, so no non-negative forces can balance it.
    let dx = (1.25f64 * 1.25 - 0.25 * 0.25).sqrt();
    let w = 2.0 * (0.5 + dx);
    let c = Container::with_flags(&[w, 5.0], &[true, true]).unwrap();
    let p = Packing::new(
        vec![0.5, 4.5, w - 0.5, 4.5, 0.5 * w, 4.25],
        vec![1.0, 1.0, 1.5],
        c,
    )
    .unwrap();
    let m = analyze(&p, &AnalysisOptions::default()).unwrap();
    assert_eq!(m.contacts, 7);
    assert_eq!(m.rattlers, 0);
    let fb = m.force_balance.unwrap();
    assert!(fb > 1e-2, "force balance residual {fb} should be large");
}

#[test]
fn overlaps_are_contacts_and_measured() {
    let c = Container::periodic_box(&[5.0, 5.0]).unwrap();
    let p = Packing::new(vec![1.0, 1.0, 1.9, 1.0], vec![1.0, 1.0], c).unwrap();
    let m = analyze(
        &p,
        &AnalysisOptions {
            contact_tol: 1e-6,
            force_balance: false,
        },
    )
    .unwrap();
    assert_eq!(m.contacts, 1);
    assert!((m.max_overlap - 0.1).abs() < 1e-12);
}

#[test]
fn metrics_serialise_with_the_documented_keys() {
    let m = analyze(&hexagonal(4, 4), &AnalysisOptions::default()).unwrap();
    let v = serde_json::to_value(&m).unwrap();
    let keys: Vec<&str> = v.as_object().unwrap().keys().map(|k| k.as_str()).collect();
    let mut want = vec![
        "dim",
        "n",
        "phi",
        "contacts",
        "z_mean",
        "rattlers",
        "z_nonrattler",
        "n_dof",
        "iso_gap",
        "isostatic",
        "max_overlap",
        "force_balance",
        "polydispersity",
        "skewness",
    ];
    let mut got = keys.clone();
    want.sort();
    got.sort();
    assert_eq!(got, want);
}

#[test]
fn negative_tolerance_is_refused() {
    let e = analyze(
        &hexagonal(4, 4),
        &AnalysisOptions {
            contact_tol: -1.0,
            force_balance: false,
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("contact tolerance"));
}

/// max(0, max over all pairs of 1 − r/σ), σ the mean of the two diameters, r the minimum-image
/// distance: the definition of `Metrics::max_overlap` for pairs, by brute force.
fn brute_force_max_pair_overlap(p: &Packing) -> f64 {
    let d = p.dim;
    let mut sep = vec![0.0; d];
    let mut most: f64 = 0.0;
    for i in 0..p.n() {
        for j in i + 1..p.n() {
            p.container.separation(
                &p.positions[i * d..(i + 1) * d],
                &p.positions[j * d..(j + 1) * d],
                &mut sep,
            );
            let r = sep.iter().map(|x| x * x).sum::<f64>().sqrt();
            let sigma = 0.5 * (p.diameters[i] + p.diameters[j]);
            most = most.max(1.0 - r / sigma);
        }
    }
    most
}

#[test]
fn extremes_give_clear_results() {
    use crate::distribution::SizeDistribution;
    use crate::scene::{Placement, Scene};
    // One particle, two particles, d = 8, a size ratio of 20, a thin slab.
    let cases = [
        (
            1,
            Container::periodic_box(&[1.0; 3]).unwrap(),
            SizeDistribution::Mono { d: 1.0 },
        ),
        (
            2,
            Container::periodic_box(&[1.0; 2]).unwrap(),
            SizeDistribution::Mono { d: 1.0 },
        ),
        (
            50,
            Container::periodic_box(&[1.0; 8]).unwrap(),
            SizeDistribution::Mono { d: 1.0 },
        ),
        (
            200,
            Container::periodic_box(&[1.0; 3]).unwrap(),
            SizeDistribution::Bidisperse {
                d1: 1.0,
                d2: 20.0,
                p: 0.99,
            },
        ),
        (
            400,
            Container::with_flags(&[10.0, 10.0, 0.3], &[false, false, true]).unwrap(),
            SizeDistribution::Mono { d: 1.0 },
        ),
    ];
    for (n, c, dist) in cases {
        let scene = Scene {
            n,
            distribution: dist,
            container: c,
            phi: 0.05,
            seed: Some(1),
            placement: Placement::Random,
        };
        let p = crate::init::initial_packing(&scene, 1).unwrap();
        let m = analyze(&p, &AnalysisOptions::default()).unwrap();
        assert_eq!(m.n, n);
        assert!((m.phi - 0.05).abs() < 1e-12);
        assert!(m.z_mean.is_finite());
        // The largest pair overlap 1 − r/σ, recomputed here over every pair; walls may add
        // their own, so with walls it is a lower bound.
        let pairs = brute_force_max_pair_overlap(&p);
        if p.container.has_walls() {
            assert!(
                m.max_overlap >= pairs - 1e-12,
                "{} < {pairs}",
                m.max_overlap
            );
        } else {
            assert!(
                (m.max_overlap - pairs).abs() < 1e-12,
                "{} ≠ {pairs}",
                m.max_overlap
            );
        }
        assert!(m.force_balance.is_none_or(|f| f.is_finite()));
    }
}

#[test]
fn balancing_forces_have_mean_one_and_cancel_on_every_particle() {
    let p = hexagonal(4, 4);
    let net = contact_network(&p, 1e-6);
    let rattler = rattlers(&net, p.n(), p.dim);
    let b = balancing_forces(&net, &rattler, p.dim).unwrap();
    assert_eq!(b.forces.len(), net.contacts.len());
    assert!(b.forces.iter().all(|&f| f >= 0.0 && f.is_finite()));
    let mean = b.forces.iter().sum::<f64>() / b.forces.len() as f64;
    assert!((mean - 1.0).abs() < 1e-6, "mean force {mean}");
    // Newton's third law per particle: Σ_c ±f_c n_c = 0 (to the solver's accuracy).
    let mut net_force = vec![0.0; p.n() * p.dim];
    for (c, ct) in net.contacts.iter().enumerate() {
        for a in 0..p.dim {
            let f = b.forces[c] * net.normals[c * p.dim + a];
            net_force[ct.i * p.dim + a] -= f;
            net_force[ct.j.unwrap() * p.dim + a] += f;
        }
    }
    assert!(net_force.iter().all(|v| v.abs() < 1e-6), "{net_force:?}");
    let residual = force_balance(&net, &rattler, p.dim).unwrap();
    assert!(
        (b.residual - residual).abs() <= 1e-12,
        "{} vs {residual}",
        b.residual
    );
    assert!(b.residual < 1e-9, "residual {}", b.residual);
}

/// A dilute packing has no contact network: every particle is a rattler, so its isostatic gap
/// and non-rattler contact number are undefined, written as null, never as 0 ("isostatic").
#[test]
fn without_non_rattlers_iso_gap_and_z_are_null_not_zero() {
    let c = Container::periodic_box(&[10.0, 10.0]).unwrap();
    let p = Packing::new(vec![1.0, 1.0, 5.0, 5.0, 2.0, 7.0], vec![1.0; 3], c).unwrap();
    let m = analyze(&p, &AnalysisOptions::default()).unwrap();
    assert_eq!((m.rattlers, m.n), (3, 3));
    assert!(!m.has_network() && !m.isostatic);
    assert_eq!(
        (m.defined_iso_gap(), m.defined_z_nonrattler()),
        (None, None)
    );
    let json = serde_json::to_value(&m).unwrap();
    assert!(
        json["iso_gap"].is_null() && json["z_nonrattler"].is_null(),
        "{json}"
    );
    // Read back, the metrics are the same.
    let back: Metrics = serde_json::from_value(json).unwrap();
    assert_eq!(back, m);
    // With a network both are numbers.
    let crystal = analyze(&hexagonal(4, 4), &AnalysisOptions::default()).unwrap();
    let json = serde_json::to_value(&crystal).unwrap();
    assert_eq!(json["iso_gap"], serde_json::json!(crystal.iso_gap));
    assert_eq!(json["z_nonrattler"], serde_json::json!(6.0));
}

/// Two particles at one centre (through the periodic wrap too) are refused, as `pack` refuses
/// such a start, never analysed as an overlap of 1.
#[test]
fn coincident_centres_are_refused_by_the_analysis() {
    let c = Container::periodic_box(&[4.0, 4.0]).unwrap();
    let p = Packing::new(vec![1.0, 1.0, 3.0, 3.0, 1.0, 1.0], vec![1.0; 3], c).unwrap();
    let e = analyze(&p, &AnalysisOptions::default()).unwrap_err();
    let why = e.to_string();
    assert!(
        why.contains("particles 1 and 3 have the same centre"),
        "{why}"
    );
}
