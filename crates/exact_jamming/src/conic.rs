//! A thin wrapper over clarabel for the QPs of the closest-jammed inequality form, and for the
//! CALiPPSO LPs whose normal equations have no factor (the tests check
//! [`crate::interior_point`] against it).
//!
//! clarabel solves min ½xᵀPx + qᵀx subject to Ax + s = b, s in cones; a constraint `Gx ≥ h`
//! is written as `A = −G, b = −h` with a non-negative cone. Only P's upper triangle is read.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};

/// A program assembled row by row: `Gx ≥ h` rows.
pub(crate) struct Program {
    pub n_vars: usize,
    /// Triplets (row, col, value) of A = −G.
    rows: Vec<usize>,
    cols: Vec<usize>,
    vals: Vec<f64>,
    b: Vec<f64>,
    /// Diagonal of P (upper triangle of a diagonal matrix).
    p_diag: Vec<f64>,
    q: Vec<f64>,
}

/// Result of a solve: primal `x`, duals `z` of the inequality rows (in insertion order), and
/// whether clarabel proved the program infeasible (then `z` is the Farkas certificate).
pub(crate) struct Solution {
    pub x: Vec<f64>,
    pub z: Vec<f64>,
    pub infeasible: bool,
    /// clarabel's status is `Solved` (its tolerances met).
    pub solved: bool,
    /// Interior-point iterations taken.
    pub iterations: u32,
}

impl Program {
    /// An empty program in `n_vars` variables with objective `q` and diagonal `P`.
    pub fn new(q: Vec<f64>, p_diag: Vec<f64>) -> Self {
        Program {
            n_vars: q.len(),
            rows: Vec::new(),
            cols: Vec::new(),
            vals: Vec::new(),
            b: Vec::new(),
            p_diag,
            q,
        }
    }

    /// Adds the inequality `Σ coef·x ≥ rhs`; returns its row index.
    pub fn at_least(&mut self, terms: impl IntoIterator<Item = (usize, f64)>, rhs: f64) -> usize {
        let r = self.b.len();
        for (c, v) in terms {
            if v != 0.0 {
                self.rows.push(r);
                self.cols.push(c);
                self.vals.push(-v);
            }
        }
        self.b.push(-rhs);
        r
    }

    /// Solves with tolerances `tol` (gap and feasibility) and at most `max_iter` iterations.
    pub fn solve(self, tol: f64, max_iter: u32) -> Result<Solution, String> {
        let m = self.b.len();
        let a = CscMatrix::new_from_triplets(m, self.n_vars, self.rows, self.cols, self.vals);
        let (pi, pv): (Vec<usize>, Vec<f64>) = self
            .p_diag
            .iter()
            .enumerate()
            .filter(|(_, v)| **v != 0.0)
            .map(|(i, v)| (i, *v))
            .unzip();
        let p = CscMatrix::new_from_triplets(self.n_vars, self.n_vars, pi.clone(), pi, pv);
        let cones = [SupportedConeT::NonnegativeConeT(m)];
        let settings = DefaultSettings {
            verbose: false,
            tol_gap_abs: tol,
            tol_gap_rel: tol,
            tol_feas: tol,
            tol_ktratio: tol.max(1e-10),
            max_iter,
            ..DefaultSettings::default()
        };
        let mut solver = DefaultSolver::new(&p, &self.q, &a, &self.b, &cones, settings)
            .map_err(|e| format!("clarabel could not set up the program ({e:?})"))?;
        solver.solve();
        let status = solver.solution.status;
        let infeasible = matches!(
            status,
            SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible
        );
        let usable = infeasible
            || matches!(
                status,
                SolverStatus::Solved
                    | SolverStatus::AlmostSolved
                    | SolverStatus::MaxIterations
                    | SolverStatus::InsufficientProgress
            );
        if !usable {
            return Err(format!("clarabel ended with status {status:?}"));
        }
        let x = solver.solution.x.clone();
        if x.iter().any(|v| !v.is_finite()) && !infeasible {
            return Err(format!(
                "clarabel returned a non-finite solution (status {status:?})"
            ));
        }
        Ok(Solution {
            x,
            z: solver.solution.z.clone(),
            infeasible,
            solved: status == SolverStatus::Solved,
            iterations: solver.solution.iterations,
        })
    }
}
