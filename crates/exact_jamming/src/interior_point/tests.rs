//! The interior point against clarabel on random LPs, warm starts, degenerate and
//! infeasible problems.

use super::*;
use rand::rngs::StdRng;
use rand::{RngExt, SeedableRng};

/// A random LP with a strictly feasible origin (`h > 0`), box bounds and sparse rows: as
/// in the CALiPPSO LPs, every row also holds the last variable (Γ's column).
/// Each row's terms `(variable, coefficient)`.
type Rows = Vec<Vec<(usize, f64)>>;

fn random_lp(seed: u64, n: usize, m: usize) -> (Rows, Vec<f64>, Vec<f64>) {
    let mut rng = StdRng::seed_from_u64(seed);
    let c: Vec<f64> = (0..n).map(|_| rng.random_range(-1.0..1.0)).collect();
    let mut rows = Vec::new();
    let mut rhs = Vec::new();
    for _ in 0..m {
        let mut terms: Vec<(usize, f64)> = (0..3)
            .map(|_| (rng.random_range(0..n - 1), rng.random_range(-1.0..1.0)))
            .collect();
        terms.push((n - 1, -1.0));
        rows.push(terms);
        rhs.push(-rng.random_range(0.01..1.0));
    }
    for v in 0..n {
        rows.push(vec![(v, 1.0)]);
        rhs.push(-1.0);
        rows.push(vec![(v, -1.0)]);
        rhs.push(-1.0);
    }
    (rows, rhs, c)
}

#[test]
fn the_optimum_and_duals_match_clarabel() {
    for seed in 0..5 {
        let (rows, rhs, c) = random_lp(seed, 40, 120);
        let mut ipm = InequalityLp::new(c.clone());
        let mut reference = Program::new(c.clone(), vec![0.0; c.len()]);
        for (terms, &b) in rows.iter().zip(&rhs) {
            ipm.at_least(terms.iter().copied(), b);
            reference.at_least(terms.iter().copied(), b);
        }
        let ours = ipm.solve(1e-12, 100, None, None).unwrap();
        let theirs = reference.solve(1e-12, 200).unwrap();
        assert!(ours.converged, "seed {seed}: not converged");
        let objective = |x: &[f64]| c.iter().zip(x).map(|(a, b)| a * b).sum::<f64>();
        let (a, b) = (objective(&ours.x), objective(&theirs.x));
        assert!(
            (a - b).abs() < 1e-9 * b.abs().max(1.0),
            "seed {seed}: {a} vs {b}"
        );
        // Feasibility, dual feasibility (c = Σ z_k g_k) and complementarity of ours.
        let mut grad = vec![0.0; c.len()];
        for ((terms, &b), &z) in rows.iter().zip(&rhs).zip(&ours.z) {
            let lhs: f64 = terms.iter().map(|&(v, a)| a * ours.x[v]).sum();
            assert!(lhs - b > -1e-10, "seed {seed}: row violated by {}", b - lhs);
            assert!(
                z >= 0.0 && z * (lhs - b) < 1e-10,
                "seed {seed}: complementarity"
            );
            terms.iter().for_each(|&(v, a)| grad[v] += z * a);
        }
        for (g, cv) in grad.iter().zip(&c) {
            assert!(
                (g - cv).abs() < 1e-9,
                "seed {seed}: dual residual {}",
                g - cv
            );
        }
    }
}

/// CALiPPSO's case: the next LP is the last one moved to its optimum (x = 0 there) with
/// slightly changed right-hand sides. Warm-started from the last duals it reaches the
/// optimum the cold start reaches, in fewer iterations.
#[test]
fn a_warm_start_reaches_the_cold_optimum_in_fewer_iterations() {
    let build = |rows: &Rows, rhs: &[f64], c: &[f64]| {
        let mut lp = InequalityLp::new(c.to_vec());
        for (terms, &b) in rows.iter().zip(rhs) {
            lp.at_least(terms.iter().copied(), b);
        }
        lp
    };
    let objective = |c: &[f64], x: &[f64]| c.iter().zip(x).map(|(a, b)| a * b).sum::<f64>();
    for seed in 0..5 {
        let (rows, rhs, c) = random_lp(seed, 40, 120);
        let first = build(&rows, &rhs, &c)
            .solve(1e-12, 100, None, None)
            .unwrap();
        // Rows in y = x − x*: Σ a y ≥ b − Σ a x*, each b moved by up to 2 %.
        let mut rng = StdRng::seed_from_u64(100 + seed);
        let moved: Vec<f64> = rows
            .iter()
            .zip(&rhs)
            .map(|(terms, &b)| {
                let ax: f64 = terms.iter().map(|&(v, a)| a * first.x[v]).sum();
                b * (1.0 + rng.random_range(-0.02..0.02)) - ax
            })
            .collect();
        let next = build(&rows, &moved, &c);
        let cold = next.solve(1e-12, 100, None, None).unwrap();
        let warm = next.solve(1e-12, 100, None, Some(&first.z)).unwrap();
        assert!(cold.converged && warm.converged, "seed {seed}");
        let (a, b) = (objective(&c, &cold.x), objective(&c, &warm.x));
        assert!(
            (a - b).abs() < 1e-9 * a.abs().max(1.0),
            "seed {seed}: {a} vs {b}"
        );
        assert!(
            warm.iterations < cold.iterations,
            "seed {seed}: warm {} iterations, cold {}",
            warm.iterations,
            cold.iterations
        );
    }
}

#[test]
fn fixed_variables_stay_at_zero() {
    let (rows, rhs, c) = random_lp(7, 20, 50);
    let mut free = InequalityLp::new(c.clone());
    let mut held = InequalityLp::new(c.clone());
    for (terms, &b) in rows.iter().zip(&rhs) {
        free.at_least(terms.iter().copied(), b);
        held.at_least(terms.iter().copied(), b);
    }
    held.fix_at_zero(3);
    let (a, b) = (
        free.solve(1e-12, 100, None, None).unwrap(),
        held.solve(1e-12, 100, None, None).unwrap(),
    );
    assert!(b.converged && b.x[3] == 0.0);
    let objective = |x: &[f64]| c.iter().zip(x).map(|(a, b)| a * b).sum::<f64>();
    // Holding a variable cannot improve the minimum.
    assert!(objective(&b.x) >= objective(&a.x) - 1e-10);
}
