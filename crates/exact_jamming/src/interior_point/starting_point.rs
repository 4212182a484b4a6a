//! Where the interior-point iterations start: CVXOPT's `coneqp` start from scratch, or the
//! previous LP's duals (a warm start).

use super::normal_equations::{NormalEquations, Workspace};

/// A warm start's target complementarity μ_w, as a fraction of the mean force (dual) of the
/// warm rows. Over 3·10⁻⁵·(1 ± ½ decade) the iteration counts of calippso from N = 1000
/// ADAM starts vary by under 5 % (docs/notes/calippso-lp-solver.md).
const WARM_CENTRING: f64 = 3e-5;

/// Duals at or below this are not forces (calippso's default `zero_force`) and do not enter
/// the mean force of [`WARM_CENTRING`].
const WARM_FORCE_FLOOR: f64 = 1e-10;

/// An iterate `(x, s, z)`: the free variables, the slacks and the duals.
pub(super) type Iterate = (Vec<f64>, Vec<f64>, Vec<f64>);

/// `(x, s, z)` warm-started from `z_prev`, one dual per row of `Gx ≤ h`, with `nv` free
/// variables: x = 0 (the LP's own origin, feasible up to rounding in CALiPPSO, where it is
/// the current configuration), s = h, z = the previous LP's duals of the same rows; every
/// product s_k z_k below μ_w is raised to μ_w by moving the factor that is far from zero, so
/// that the start lies near the central path at μ_w (Gondzio & Grothey 2003, §2). μ_w is a
/// small fraction of the mean force: the old active set is nearly right and its slacks start
/// small.
pub(super) fn warm(h: &[f64], z_prev: &[f64], nv: usize) -> Iterate {
    let (sum, count) = z_prev
        .iter()
        .filter(|&&v| v > WARM_FORCE_FLOOR)
        .fold((0.0, 0usize), |(a, c), &v| (a + v, c + 1));
    let mu = WARM_CENTRING * sum / count.max(1) as f64;
    let mut s: Vec<f64> = h.iter().map(|&h| h.max(0.0)).collect();
    let mut z = z_prev.to_vec();
    for (sk, zk) in s.iter_mut().zip(&mut z) {
        if *sk * *zk < mu {
            if *zk > mu.sqrt() {
                *sk = mu / *zk;
            } else if *sk > mu.sqrt() {
                *zk = mu / *sk;
            } else {
                (*sk, *zk) = (mu.sqrt(), mu.sqrt());
            }
        }
    }
    (vec![0.0; nv], s, z)
}

/// `(x, s, z)` as CVXOPT's `coneqp` starts: x, s from min ‖s‖ s.t. Gx + s = h, z from
/// min ‖z‖ s.t. Gᵀz + c = 0, both by the factor of GᵀG, then shifted into the positive
/// orthant.
///
/// Errors: GᵀG has no Cholesky factor.
pub(super) fn cold(
    normal: &NormalEquations,
    work: &mut Workspace,
    h: &[f64],
    c: &[f64],
) -> Result<Iterate, String> {
    let m = h.len();
    let factor = normal.factor(&vec![1.0; m], work)?;
    let x = factor.solve(&normal.gt_times(h));
    let gx = normal.g_times(&x);
    let mut s: Vec<f64> = (0..m).map(|k| h[k] - gx[k]).collect();
    let neg_c: Vec<f64> = c.iter().map(|v| -v).collect();
    let mut z = normal.g_times(&factor.solve(&neg_c));
    for v in [&mut s, &mut z] {
        let worst = v.iter().fold(f64::NEG_INFINITY, |a, &e| a.max(-e));
        let size = v.iter().map(|e| e * e).sum::<f64>().sqrt().max(1.0);
        if worst >= -1e-8 * size {
            v.iter_mut().for_each(|e| *e += 1.0 + worst);
        }
    }
    Ok((x, s, z))
}
