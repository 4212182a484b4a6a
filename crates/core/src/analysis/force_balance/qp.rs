//! The force-balance quadratic program solved by clarabel: minimise ½‖G f‖² subject to
//! Σ f = N_c, f ≥ 0 (see the module above).

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT::NonnegativeConeT,
    SupportedConeT::ZeroConeT,
};

use super::ContactColumns;
use crate::error::CoreError;

/// The forces of the program's solution, one per column of `g` (not yet clipped at zero).
pub(super) fn least_net_force(g: &ContactColumns) -> Result<Vec<f64>, CoreError> {
    let (nc, rows) = (g.columns(), g.rows);
    // Variables x = [f_1 … f_nc, u_1 … u_rows] with u = G f the net forces: minimise ½‖u‖²
    // subject to G f − u = 0, Σ f = nc, f ≥ 0. A quadratic objective keeps the KKT system
    // sparse (no large second-order cone); the residual is accurate to about the square root
    // of the solver's gap tolerance, ~1e-6 absolute, i.e. ~1e-6/nc relative.
    let (mut ii, mut jj, mut vv) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..nc {
        let (ri, rj, n) = g.column(k);
        // Rows 0..rows: G f − u = 0; the force on i is −f n, on j is +f n.
        for a in 0..g.d {
            ii.push(ri + a);
            jj.push(k);
            vv.push(-n[a]);
            if let Some(rj) = rj {
                ii.push(rj + a);
                jj.push(k);
                vv.push(n[a]);
            }
        }
        // Row `rows`: Σ f = nc; rows `rows+1+k`: −f_k + s = 0, s ≥ 0.
        ii.push(rows);
        jj.push(k);
        vv.push(1.0);
        ii.push(rows + 1 + k);
        jj.push(k);
        vv.push(-1.0);
    }
    for r in 0..rows {
        ii.push(r);
        jj.push(nc + r);
        vv.push(-1.0);
    }
    let m = rows + 1 + nc;
    let a = CscMatrix::new_from_triplets(m, nc + rows, ii, jj, vv);
    let p = CscMatrix::new_from_triplets(
        nc + rows,
        nc + rows,
        (nc..nc + rows).collect(),
        (nc..nc + rows).collect(),
        vec![1.0; rows],
    );
    let q = vec![0.0; nc + rows];
    let mut b = vec![0.0; m];
    b[rows] = nc as f64;
    let cones = [ZeroConeT(rows + 1), NonnegativeConeT(nc)];
    let settings = DefaultSettings {
        verbose: false,
        tol_gap_abs: 1e-12,
        tol_gap_rel: 1e-12,
        tol_feas: 1e-12,
        max_iter: 200,
        // faer's supernodal LDLᵀ: dense blocks for the fill of 3D contact graphs, where qdldl's
        // column-by-column factorisation took 16 CPU min and 5.8 GB at N = 10⁴. One thread,
        // since analyses already run in parallel across runs.
        direct_solve_method: "faer".to_owned(),
        max_threads: 1,
        ..DefaultSettings::default()
    };
    let mut solver = DefaultSolver::new(&p, &q, &a, &b, &cones, settings).map_err(|e| {
        CoreError::Solver(format!("could not set up the force-balance program: {e:?}"))
    })?;
    solver.solve();
    match solver.solution.status {
        SolverStatus::Solved
        | SolverStatus::AlmostSolved
        | SolverStatus::MaxIterations
        | SolverStatus::InsufficientProgress => Ok(solver.solution.x[..nc].to_vec()),
        other => Err(CoreError::Solver(format!(
            "the force-balance program ended with status {other:?}"
        ))),
    }
}
