//! A thin wrapper over clarabel for the linear and quadratic programs of this crate.
//!
//! clarabel solves min ½xᵀPx + qᵀx subject to Ax + s = b, s in cones; a constraint `Gx ≥ h`
//! is written as `A = −G, b = −h` with a non-negative cone. Only P's upper triangle is read.

use std::sync::atomic::{AtomicBool, Ordering};

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};

/// A program assembled row by row: zero-cone rows (equalities) first, then `Gx ≥ h` rows.
pub(crate) struct Program {
    pub n_vars: usize,
    /// Triplets (row, col, value) of A = [E; −G].
    rows: Vec<usize>,
    cols: Vec<usize>,
    vals: Vec<f64>,
    b: Vec<f64>,
    n_equalities: usize,
    /// Diagonal of P (upper triangle of a diagonal matrix).
    p_diag: Vec<f64>,
    q: Vec<f64>,
    /// clarabel's `direct_solve_method` for the KKT systems.
    ldl: KktSolver,
    /// clarabel's iterative refinement of each KKT solve.
    refine: bool,
    /// A stop request, polled by clarabel after every interior-point iteration.
    stop: Option<&'static AtomicBool>,
}

/// The sparse LDLᵀ factorisation clarabel uses for its KKT systems.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum KktSolver {
    /// qdldl: a scalar (column by column) LDLᵀ, cheap for small or very sparse systems.
    Qdldl,
    /// faer's supernodal LDLᵀ (clarabel's `faer-sparse` feature), one thread: dense blocks
    /// for the fill of 3D contact graphs.
    Faer,
}

/// Result of a solve: primal `x`, duals `z` of the inequality rows (in insertion order), and
/// whether clarabel proved the program infeasible (then `z` is the Farkas certificate).
pub(crate) struct Solution {
    pub x: Vec<f64>,
    pub z: Vec<f64>,
    pub infeasible: bool,
    /// Interior-point iterations clarabel took.
    pub iterations: u32,
    /// The solve was stopped by a stop request; nothing else in the solution is meaningful.
    pub interrupted: bool,
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
            n_equalities: 0,
            p_diag,
            q,
            ldl: KktSolver::Qdldl,
            refine: true,
            stop: None,
        }
    }

    /// Selects the KKT factorisation (qdldl unless set).
    pub fn kkt_solver(mut self, ldl: KktSolver) -> Self {
        self.ldl = ldl;
        self
    }

    /// Turns clarabel's iterative refinement of the KKT solves on (the default) or off.
    pub fn iterative_refinement(mut self, refine: bool) -> Self {
        self.refine = refine;
        self
    }

    /// Lets `stop` end the solve between interior-point iterations.
    pub fn stop_flag(mut self, stop: Option<&'static AtomicBool>) -> Self {
        self.stop = stop;
        self
    }

    /// Adds the equality `Σ coef·x = rhs`. All equalities must come before inequalities.
    pub fn equality(&mut self, terms: &[(usize, f64)], rhs: f64) {
        assert_eq!(self.b.len(), self.n_equalities, "equalities come first");
        let r = self.b.len();
        for &(c, v) in terms {
            self.rows.push(r);
            self.cols.push(c);
            self.vals.push(v);
        }
        self.b.push(rhs);
        self.n_equalities += 1;
    }

    /// Adds the inequality `Σ coef·x ≥ rhs`; returns its index among inequalities.
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
        r - self.n_equalities
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
        let mut cones = Vec::new();
        if self.n_equalities > 0 {
            cones.push(SupportedConeT::ZeroConeT(self.n_equalities));
        }
        if m > self.n_equalities {
            cones.push(SupportedConeT::NonnegativeConeT(m - self.n_equalities));
        }
        let settings = DefaultSettings {
            verbose: false,
            tol_gap_abs: tol,
            tol_gap_rel: tol,
            tol_feas: tol,
            tol_ktratio: tol.max(1e-10),
            max_iter,
            direct_solve_method: match self.ldl {
                KktSolver::Qdldl => "qdldl",
                KktSolver::Faer => "faer",
            }
            .to_string(),
            // faer's factorisation on one thread: on the shared 2-core machine rayon's two threads
            // cost more CPU time and wall time (docs/BENCHMARKS.md, calippso fourth pass).
            max_threads: 1,
            iterative_refinement_enable: self.refine,
            ..DefaultSettings::default()
        };
        let mut solver = DefaultSolver::new(&p, &self.q, &a, &self.b, &cones, settings)
            .map_err(|e| format!("clarabel could not set up the program ({e:?})"))?;
        if let Some(stop) = self.stop {
            solver.set_termination_callback(move |_| stop.load(Ordering::Relaxed));
        }
        solver.solve();
        let status = solver.solution.status;
        if status == SolverStatus::CallbackTerminated {
            return Ok(Solution {
                x: Vec::new(),
                z: Vec::new(),
                infeasible: false,
                iterations: solver.solution.iterations,
                interrupted: true,
            });
        }
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
            z: solver.solution.z[self.n_equalities..].to_vec(),
            infeasible,
            iterations: solver.solution.iterations,
            interrupted: false,
        })
    }
}
