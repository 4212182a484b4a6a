//! Preconditioned conjugate gradients for the bond Gram system `A Aᵀ λ = r` (Baranau & Tallarek 2014 App. C:
//! `y = Aᵀ(A Aᵀ)⁻¹ b`; Zinchenko's original algorithm solved eqn 1 by conjugate gradients).
//!
//! Consecutive steps of the integrator change `A Aᵀ` a little (the particles move) and by a
//! few rows (one bond added or released), so the Cholesky factor of an earlier step is an
//! excellent preconditioner: a few iterations replace a numeric factorisation. The caller
//! refactorises when the iteration count grows or the iteration does not converge.
//!
//! This file holds the iteration ([`pcg`]) and the form of [`MinNorm`] that uses it
//! ([`Iterative`]): `A Aᵀ` is applied matrix-free from the bonds' rows and preconditioned by a
//! [`Preconditioner`]. It fails (returns `None`, counted in [`CgStats::failures`]) when the
//! residual has not reached the tolerance after `CG_MAX_ITERATIONS` or a breakdown shows
//! `A Aᵀ` is not positive definite; the form then makes the exact factor of its bonds (sparse
//! Cholesky, or the dense pseudoinverse for a small system) and answers with that.

/// Solves `G x = b` for symmetric positive definite `G` given by `apply(v, out)` (out = G v),
/// with the preconditioner `precond(r, out)` (out ≈ G⁻¹ r). Stops when `‖G x − b‖ ≤ tol·‖b‖`.
/// Returns the solution and the iterations used, or `None` when `max_iterations` were not
/// enough (or a breakdown showed `G` is not positive definite).
fn pcg(
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

use std::cell::{Cell, RefCell};
use std::rc::Rc;

use super::bordered_preconditioner::{Preconditioner, Role};
use super::gram_pattern::GramPattern;
use super::{DENSE_FALLBACK_COORDINATES, MinNorm};
use crate::contacts::{Key, Link};

/// The state of [`MinNorm::Iterative`].
pub(crate) struct Iterative {
    pub(super) pre: Rc<Preconditioner>,
    keys: Vec<Key>,
    links: Vec<Link>,
    /// Where each bond sits in `pre`.
    pub(super) roles: Vec<Role>,
    n: usize,
    d: usize,
    /// Iteration counts (shared with the owner, who refactorises when they grow).
    stats: Rc<CgStats>,
    /// The exact factor, made when the iteration failed.
    pub(super) exact: RefCell<Option<MinNorm>>,
}

/// Conjugate-gradient iteration counts of the solves with one preconditioner.
#[derive(Default)]
pub(crate) struct CgStats {
    /// Largest iteration count of a solve, `usize::MAX` after a failure.
    pub worst: Cell<usize>,
    /// Solves and iterations in total.
    pub solves: Cell<u64>,
    pub iterations: Cell<u64>,
    pub failures: Cell<u64>,
}

/// Relative residual `‖A Aᵀ λ − r‖/‖r‖` at which conjugate gradients stop.
pub(super) const CG_TOL: f64 = 1e-13;
/// Iterations after which conjugate gradients give up and the exact factor is made (about the
/// cost of a numeric factorisation in triangular solves at N·d ~ 3000 in 3D).
const CG_MAX_ITERATIONS: usize = 20;

impl MinNorm {
    /// Conjugate-gradient solves for the bonds `keys` (rows `links`), preconditioned with
    /// `pre`; `None` unless `keys` are exactly the bonds `pre` holds. `stats` records the
    /// iteration counts.
    pub fn iterative(
        pre: &Rc<Preconditioner>,
        keys: &[Key],
        links: &[Link],
        n: usize,
        d: usize,
        stats: &Rc<CgStats>,
    ) -> Option<MinNorm> {
        let roles: Vec<Role> = keys.iter().map(|k| pre.role(k)).collect::<Option<_>>()?;
        if roles.len() != pre.len() {
            return None;
        }
        Some(MinNorm::Iterative(Box::new(Iterative {
            pre: Rc::clone(pre),
            keys: keys.to_vec(),
            links: links.to_vec(),
            roles,
            n,
            d,
            stats: Rc::clone(stats),
            exact: RefCell::new(None),
        })))
    }
}

impl Iterative {
    /// The slots of the basis bonds `ks` in the preconditioner's base pattern; `None` when one
    /// of them is a border column instead.
    pub(super) fn base_slots(&self, ks: &[usize]) -> Option<Vec<usize>> {
        ks.iter()
            .map(|&k| match self.roles[k] {
                Role::Base(s) => Some(s),
                Role::Added(_) => None,
            })
            .collect()
    }

    /// `(A Aᵀ)⁻¹ rhs` by conjugate gradients to the relative residual `tol`. Only solves to
    /// full accuracy ([`CG_TOL`]) enter `stats.worst`, which decides when to refactorise: a
    /// loose solve's few iterations say nothing about the preconditioner.
    pub(super) fn gram_solve(&self, rhs: &[f64], tol: f64) -> Vec<f64> {
        if let Some(exact) = self.exact.borrow().as_ref() {
            return exact.gram_solve(rhs);
        }
        let (n, d) = (self.n, self.d);
        let (pattern, _) = self.pre.factor();
        // out = A Aᵀ v.
        let apply = |v: &[f64], out: &mut [f64]| {
            let mut y = vec![0.0; n * d];
            for (l, &c) in self.links.iter().zip(v) {
                l.add_transposed(c, &mut y, d);
            }
            for (o, l) in out.iter_mut().zip(&self.links) {
                *o = l.rate(&y, d);
            }
        };
        let precond = |r: &[f64], out: &mut [f64]| self.pre.apply(&self.roles, r, out);
        let st = &self.stats;
        st.solves.set(st.solves.get() + 1);
        if let Some((x, iterations)) = pcg(apply, precond, rhs, tol, CG_MAX_ITERATIONS) {
            if tol <= CG_TOL {
                st.worst.set(st.worst.get().max(iterations));
            }
            st.iterations.set(st.iterations.get() + iterations as u64);
            return x;
        }
        // Not converged: the exact factor of these bonds.
        st.worst.set(usize::MAX);
        st.failures.set(st.failures.get() + 1);
        // (Over the preconditioner's pattern when every bond has a slot there, which saves the
        // symbolic factorisation.)
        let exact = pattern
            .factor(&self.keys, &self.links, d)
            .ok()
            .flatten()
            .or_else(|| {
                GramPattern::new(&self.keys, n)
                    .map(Rc::new)
                    .and_then(|p| p.factor(&self.keys, &self.links, d))
                    .ok()
                    .flatten()
            })
            .or_else(|| {
                (n * d <= DENSE_FALLBACK_COORDINATES)
                    .then(|| MinNorm::dense(&self.links, n, d).ok())
                    .flatten()
            });
        let z = match &exact {
            Some(e) => e.gram_solve(rhs),
            None => vec![f64::NAN; rhs.len()],
        };
        *self.exact.borrow_mut() = exact;
        z
    }
}
