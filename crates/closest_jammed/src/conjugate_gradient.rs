//! Preconditioned conjugate gradients for the bond Gram system `A Aᵀ λ = r` (seed 001 App. C:
//! `y = Aᵀ(A Aᵀ)⁻¹ b`; Zinchenko's original algorithm solved eqn 1 by conjugate gradients).
//!
//! Consecutive steps of the integrator change `A Aᵀ` a little (the particles move) and by a
//! few rows (one bond added or released), so the Cholesky factor of an earlier step is an
//! excellent preconditioner: a few iterations replace a numeric factorisation. The caller
//! refactorises when the iteration count grows or the iteration does not converge.

/// Solves `G x = b` for symmetric positive definite `G` given by `apply(v, out)` (out = G v),
/// with the preconditioner `precond(r, out)` (out ≈ G⁻¹ r). Stops when `‖G x − b‖ ≤ tol·‖b‖`.
/// Returns the solution and the iterations used, or `None` when `max_iterations` were not
/// enough (or a breakdown showed `G` is not positive definite).
pub(crate) fn pcg(
    apply: impl Fn(&[f64], &mut [f64]),
    precond: impl Fn(&[f64], &mut [f64]),
    b: &[f64],
    tol: f64,
    max_iterations: usize,
) -> Option<(Vec<f64>, usize)> {
    let m = b.len();
    let dot = |u: &[f64], v: &[f64]| u.iter().zip(v).map(|(a, c)| a * c).sum::<f64>();
    let bnorm = dot(b, b).sqrt();
    let mut x = vec![0.0; m];
    if bnorm == 0.0 {
        return Some((x, 0));
    }
    let mut r = b.to_vec();
    let mut z = vec![0.0; m];
    precond(&r, &mut z);
    let mut p = z.clone();
    let mut rz = dot(&r, &z);
    let mut q = vec![0.0; m];
    for it in 1..=max_iterations {
        apply(&p, &mut q);
        let pq = dot(&p, &q);
        // Not positive definite (or NaN): give up.
        if pq.is_nan() || rz.is_nan() || pq <= 0.0 || rz <= 0.0 {
            return None;
        }
        let alpha = rz / pq;
        for k in 0..m {
            x[k] += alpha * p[k];
            r[k] -= alpha * q[k];
        }
        if dot(&r, &r).sqrt() <= tol * bnorm {
            return Some((x, it));
        }
        precond(&r, &mut z);
        let rz_new = dot(&r, &z);
        let beta = rz_new / rz;
        rz = rz_new;
        for k in 0..m {
            p[k] = z[k] + beta * p[k];
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::pcg;

    /// A 1D Laplacian (tridiagonal 2, −1) with a Jacobi preconditioner: the exact solution
    /// of `G x = G·1` is 1.
    #[test]
    fn solves_a_laplacian() {
        let m = 50;
        let apply = |v: &[f64], out: &mut [f64]| {
            for k in 0..m {
                let left = if k > 0 { v[k - 1] } else { 0.0 };
                let right = if k + 1 < m { v[k + 1] } else { 0.0 };
                out[k] = 2.0 * v[k] - left - right;
            }
        };
        let ones = vec![1.0; m];
        let mut b = vec![0.0; m];
        apply(&ones, &mut b);
        let jacobi = |r: &[f64], out: &mut [f64]| {
            for k in 0..r.len() {
                out[k] = 0.5 * r[k];
            }
        };
        let (x, it) = pcg(apply, jacobi, &b, 1e-13, 200).unwrap();
        assert!(it <= m + 1);
        assert!(x.iter().all(|v| (v - 1.0).abs() < 1e-10), "{x:?}");
    }
}
