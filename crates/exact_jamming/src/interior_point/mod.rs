//! A primal–dual interior-point solver (Mehrotra's predictor–corrector) for linear programs in
//! inequality form, `min cᵀx` subject to `Gx ≤ h`, over the normal equations `Gᵀ W G Δx = r`
//! factorised by faer's sparse Cholesky.
//!
//! Why not clarabel for the CALiPPSO LPs: clarabel factorises the quasi-definite KKT matrix of
//! every row and variable (rows, displacements and the `2Nd` bound rows) at each iteration; the
//! normal equations of an LP are the particle graph's `Nd × Nd` matrix (bound rows only add to
//! its diagonal), ordered by METIS's nested dissection with the dense column of Γ (in every
//! pair row) last. At N = 10⁴ in 3D that gives nnz(L) = 25.7M and a 1.0 s factorisation,
//! against 53.0M and 3.2 s with AMD (docs/notes/calippso-lp-solver.md).
//!
//! The method is the textbook one (Nocedal & Wright, *Numerical Optimization*, §14.2; the
//! starting point of CVXOPT's `coneqp`): slacks `s = h − Gx ≥ 0` and duals `z ≥ 0`, residuals
//! `r_x = Gᵀz + c`, `r_z = Gx + s − h`, centring `σ = (μ_aff/μ)³`, separate primal and dual
//! step lengths, and up to two of Gondzio's centrality correctors per iteration. The normal
//! matrix is Jacobi-scaled, and a pivot below 1e-13 of its column's diagonal (a direction no
//! row with a large weight constrains, as a rattler's near the optimum) is replaced by a huge
//! one, which zeroes the step along it (S. Wright, *Modified Cholesky factorizations in
//! interior-point algorithms for linear programming*, SIAM J. Optim. 9, 1999). Near the optimum
//! the weights span twenty decades and `Δz = W(GΔx + r_z) − …` amplifies the error of Δx, so
//! each direction is refined against the residual of `GᵀΔz = −r_x`.
//!
//! The iteration is here; the normal equations (assembly, scaling, factor, refinement) are in
//! `normal_equations.rs`.

use std::sync::atomic::{AtomicBool, Ordering};

use crate::conic::Program;

mod direction;
mod normal_equations;
mod starting_point;
#[cfg(test)]
mod tests;

use direction::Newton;
use normal_equations::{NormalEquations, Workspace, max_abs};

/// `min cᵀx` subject to `Gx ≤ h`, assembled row by row (stored as `Gx ≤ h`), with some
/// variables fixed at zero.
pub(crate) struct InequalityLp {
    c: Vec<f64>,
    row_ptr: Vec<usize>,
    col: Vec<usize>,
    val: Vec<f64>,
    h: Vec<f64>,
    fixed: Vec<bool>,
    /// Factorise on rayon's threads when the system is large ([`Self::factorise_in_parallel`]).
    parallel: bool,
}

/// The result of [`InequalityLp::solve`]: primal `x`, duals `z ≥ 0` of the rows in insertion
/// order.
pub(crate) struct LpSolution {
    pub x: Vec<f64>,
    pub z: Vec<f64>,
    /// Iterations taken.
    pub iterations: u32,
    /// The tolerances were met (otherwise the last iterate, after `max_iter` iterations, when
    /// the steps stalled, or before a direction that overflowed).
    pub converged: bool,
    /// A stop request ended the solve; nothing else is meaningful.
    pub interrupted: bool,
    /// Solved by clarabel ([`InequalityLp::solve_by_clarabel`]), not by this solver.
    pub by_clarabel: bool,
}

impl InequalityLp {
    /// An LP in `c.len()` variables with objective `min cᵀx` and no rows.
    pub fn new(c: Vec<f64>) -> Self {
        let n = c.len();
        InequalityLp {
            c,
            row_ptr: vec![0],
            col: Vec::new(),
            val: Vec::new(),
            h: Vec::new(),
            fixed: vec![false; n],
            parallel: false,
        }
    }

    /// Runs the numeric factorisations and solves of the normal equations on rayon's threads
    /// when they are large (10⁴ free variables or more). Faster on many cores, but faer's
    /// parallel kernels sum in another order, so the last digits (and an LP path through a
    /// degenerate optimum) depend on the thread count.
    pub fn factorise_in_parallel(&mut self, parallel: bool) {
        self.parallel = parallel;
    }

    /// Holds variable `v` at zero (its terms in every row are dropped).
    pub fn fix_at_zero(&mut self, v: usize) {
        self.fixed[v] = true;
    }

    /// Adds `Σ coef·x ≥ rhs`; returns its row index. Terms on the same variable are summed
    /// (the normal equations take each column once per row).
    pub fn at_least(&mut self, terms: impl IntoIterator<Item = (usize, f64)>, rhs: f64) -> usize {
        let start = *self.row_ptr.last().expect("row_ptr starts with 0");
        for (c, v) in terms {
            match self.col[start..].iter().position(|&e| e == c) {
                Some(e) => self.val[start + e] -= v,
                None if v != 0.0 => {
                    self.col.push(c);
                    self.val.push(-v);
                }
                None => {}
            }
        }
        self.row_ptr.push(self.col.len());
        self.h.push(-rhs);
        self.h.len() - 1
    }

    pub fn rows(&self) -> usize {
        self.h.len()
    }

    /// Solves to relative tolerance `tol` (feasibility and duality gap), in at most `max_iter`
    /// iterations; `stop` is polled between iterations. `warm`, one dual per row, starts the
    /// iterations from `x = 0` and those duals instead of CVXOPT's cold start.
    ///
    /// # Errors
    /// When the normal-equations matrix has no symbolic factorisation or its numeric one fails.
    pub fn solve(
        &self,
        tol: f64,
        max_iter: u32,
        stop: Option<&AtomicBool>,
        warm: Option<&[f64]>,
    ) -> Result<LpSolution, String> {
        let normal = NormalEquations::new(self)?;
        let (m, nv) = (self.rows(), normal.n);
        let c: Vec<f64> = normal.var.iter().map(|&v| self.c[v]).collect();
        let h_norm = self.h.iter().fold(1.0f64, |a, v| a.max(v.abs()));
        let c_norm = c.iter().fold(1.0f64, |a, v| a.max(v.abs()));

        // The factor's storage and scratch, reused by every iteration (allocating 10⁸ bytes
        // per factorisation cost a tenth of the run time in page faults at N = 10⁴).
        let mut work = Workspace::new(&normal);
        let (mut x, mut s, mut z) = match warm {
            Some(z_prev) => starting_point::warm(&self.h, z_prev, nv),
            None => starting_point::cold(&normal, &mut work, &self.h, &c)?,
        };

        let mut iterations = 0;
        let mut stalled = 0;
        loop {
            let gx = normal.g_times(&x);
            let r_z: Vec<f64> = (0..m).map(|k| gx[k] + s[k] - self.h[k]).collect();
            let gtz = normal.gt_times(&z);
            let r_x: Vec<f64> = (0..nv).map(|j| gtz[j] + c[j]).collect();
            let sz: f64 = s.iter().zip(&z).map(|(a, b)| a * b).sum();
            let primal: f64 = c.iter().zip(&x).map(|(a, b)| a * b).sum();
            let dual: f64 = -self.h.iter().zip(&z).map(|(a, b)| a * b).sum::<f64>();
            let gap_ok = sz <= tol || sz <= tol * primal.abs().min(dual.abs());
            let feasible = max_abs(&r_z) <= tol * h_norm && max_abs(&r_x) <= tol * c_norm;
            if (gap_ok && feasible) || iterations >= max_iter || stalled >= 3 {
                return Ok(normal.solution(x, z, iterations, gap_ok && feasible));
            }
            if stop.is_some_and(|f| f.load(Ordering::Relaxed)) {
                return Ok(LpSolution {
                    x: Vec::new(),
                    z: Vec::new(),
                    iterations,
                    converged: false,
                    interrupted: true,
                    by_clarabel: false,
                });
            }
            iterations += 1;
            let w: Vec<f64> = z.iter().zip(&s).map(|(z, s)| z / s).collect();
            let factor = normal.factor(&w, &mut work)?;
            let newton = Newton {
                normal: &normal,
                factor: &factor,
                w: &w,
                s: &s,
                c_norm,
            };
            let (dx, ds, dz, ap, ad) = newton.predictor_corrector(&z, &r_x, &r_z, sz);
            // A chain of pivots just above the threshold can overflow a solve near the
            // optimum: stop at the current iterate rather than step into NaN.
            let finite = |v: &[f64]| v.iter().all(|e| e.is_finite());
            if !(finite(&dx) && finite(&ds) && finite(&dz) && ap.is_finite() && ad.is_finite()) {
                return Ok(normal.solution(x, z, iterations, false));
            }
            stalled = if ap.max(ad) < 1e-8 { stalled + 1 } else { 0 };
            x.iter_mut().zip(&dx).for_each(|(a, b)| *a += ap * b);
            s.iter_mut().zip(&ds).for_each(|(a, b)| *a += ap * b);
            z.iter_mut().zip(&dz).for_each(|(a, b)| *a += ad * b);
        }
    }
}

impl InequalityLp {
    /// The same LP solved by clarabel over the free variables: the fallback when the normal
    /// equations have no factor (a pivot made NaN by rounding in a matrix whose weights span
    /// hundreds of decades), at the cost of clarabel's larger KKT system.
    ///
    /// # Errors
    /// When clarabel fails or finds the LP infeasible.
    pub fn solve_by_clarabel(&self, tol: f64, max_iter: u32) -> Result<LpSolution, String> {
        let var: Vec<usize> = (0..self.c.len()).filter(|&v| !self.fixed[v]).collect();
        let mut column = vec![usize::MAX; self.c.len()];
        for (j, &v) in var.iter().enumerate() {
            column[v] = j;
        }
        let mut program = Program::new(
            var.iter().map(|&v| self.c[v]).collect(),
            vec![0.0; var.len()],
        );
        for k in 0..self.rows() {
            let terms = (self.row_ptr[k]..self.row_ptr[k + 1])
                .filter(|&e| !self.fixed[self.col[e]])
                .map(|e| (column[self.col[e]], -self.val[e]));
            program.at_least(terms, -self.h[k]);
        }
        let sol = program.solve(tol, max_iter)?;
        if sol.infeasible {
            return Err("clarabel finds the LP infeasible".into());
        }
        let mut x = vec![0.0; self.c.len()];
        for (j, &v) in var.iter().enumerate() {
            x[v] = sol.x[j];
        }
        Ok(LpSolution {
            x,
            z: sol.z,
            iterations: sol.iterations,
            converged: sol.solved,
            interrupted: false,
            by_clarabel: true,
        })
    }
}
