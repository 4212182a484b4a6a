use super::*;
use crate::analysis::tests::fcc;
use crate::analysis::{contact_network, rattlers};
use crate::container::Container;
use crate::packing::Packing;

/// FCC balances with equal forces on all twelve contacts of each sphere, so the projection of
/// equal forces onto the balancing ones is themselves.
#[test]
fn the_projection_of_equal_forces_in_fcc_is_equal_forces() {
    let p = fcc(2);
    let net = contact_network(&p, 1e-9);
    let g = ContactColumns::new(&net, &vec![false; p.n()], 3);
    let f = projection::projected_forces(&g).expect("FCC is rigid");
    assert_eq!(f.len(), 6 * p.n());
    assert!(f.iter().all(|v| (v - 1.0).abs() < 1e-12), "{f:?}");
    let (_, residual) = g.balance(f);
    assert!(residual < 1e-14, "residual {residual}");
}

/// 80 spheres at random in a periodic box, overlapping at φ ≈ 0.75: a network no
/// non-negative forces balance exactly.
fn overlapping_spheres() -> Packing {
    let (n, l) = (80, 4.0);
    let mut state = 12345u64;
    let mut uniform = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let x: Vec<f64> = (0..3 * n).map(|_| l * uniform()).collect();
    let diameter = (0.75 * l * l * l * 6.0 / (std::f64::consts::PI * n as f64)).cbrt();
    let c = Container::periodic_box(&[l, l, l]).unwrap();
    Packing::new(x, vec![diameter; n], c).unwrap()
}

/// The descent's certified residual is the quadratic program's to the certificate's 0.5 %,
/// and never below it by more than the program's own accuracy.
#[test]
fn the_descent_reaches_the_programs_least_residual() {
    let p = overlapping_spheres();
    let net = contact_network(&p, 0.0);
    let rattler = rattlers(&net, p.n(), 3);
    let g = ContactColumns::new(&net, &rattler, 3);
    assert!(g.columns() > g.rows, "more contacts than coordinates");
    assert!(projection::projected_forces(&g).is_none_or(|f| g.balance(f).1 > 1e-6));
    let descent = descent::least_net_force(&g);
    assert!(descent.certified);
    let (_, by_descent) = g.balance(descent.forces);
    let (_, by_program) = g.balance(qp::least_net_force(&g).unwrap());
    assert!(
        by_program > 1e-4,
        "the least residual is not zero: {by_program}"
    );
    assert!(
        by_descent <= 1.005 * by_program && by_descent >= 0.999 * by_program,
        "descent {by_descent} against the program's {by_program}"
    );
}

/// Two particles with coincident centres touch along no direction (a zero normal): the
/// forces and the residual stay finite.
#[test]
fn a_contact_without_a_normal_gives_finite_forces() {
    let net = ContactNetwork {
        contacts: vec![crate::analysis::Contact {
            i: 0,
            j: Some(1),
            wall: None,
            gap: -1.0,
        }],
        normals: vec![0.0; 3],
        max_overlap: 1.0,
    };
    let b = balancing_forces(&net, &[false, false], 3).unwrap();
    assert!(b.forces.iter().all(|f| f.is_finite()), "{:?}", b.forces);
    assert!(
        b.residual.is_finite() && b.residual <= 1.0,
        "{}",
        b.residual
    );
}
