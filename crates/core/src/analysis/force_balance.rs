//! Force balance of a hard-sphere packing: the non-negative contact forces with mean 1 that
//! best balance every non-rattler.
//!
//! Solved as a second-order cone program with clarabel: minimise t subject to
//! ‖G f‖ ≤ t, Σ f = N_c, f ≥ 0, where column c of G puts −f_c n_c on particle i and +f_c n_c
//! on particle j (a wall contact only acts on i). Minimising the norm itself, not its square,
//! keeps the residual accurate to the solver tolerance rather than its square root.
//! The returned value is recomputed from the clipped forces, ‖G f‖ / Σ f.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT::NonnegativeConeT,
    SupportedConeT::SecondOrderConeT, SupportedConeT::ZeroConeT,
};

use super::ContactNetwork;
use crate::error::CoreError;

/// Relative residual of the best force-balancing contact forces over the non-rattlers.
/// Contacts touching a rattler are ignored. Returns 1 (no balance at all) when the
/// non-rattlers share no contact.
pub fn force_balance(net: &ContactNetwork, rattler: &[bool], d: usize) -> Result<f64, CoreError> {
    // Row index of each non-rattler's first coordinate in G.
    let mut row_of = vec![usize::MAX; rattler.len()];
    let mut rows = 0;
    for (i, &r) in rattler.iter().enumerate() {
        if !r {
            row_of[i] = rows;
            rows += d;
        }
    }
    let active: Vec<usize> = (0..net.contacts.len())
        .filter(|&c| {
            let ct = &net.contacts[c];
            !rattler[ct.i] && ct.j.is_none_or(|j| !rattler[j])
        })
        .collect();
    let nc = active.len();
    if nc == 0 {
        return Ok(1.0);
    }
    // Variables x = [t, f_1 … f_nc]. Constraint rows: 1 zero-cone row (Σf = nc), nc
    // non-negative rows (f ≥ 0), then the cone [t; G f] ∈ SOC(1 + rows).
    let (mut ii, mut jj, mut vv) = (Vec::new(), Vec::new(), Vec::new());
    let soc0 = 1 + nc;
    ii.push(soc0);
    jj.push(0);
    vv.push(-1.0);
    for (k, &c) in active.iter().enumerate() {
        let col = 1 + k;
        let ct = &net.contacts[c];
        let n = &net.normals[c * d..(c + 1) * d];
        ii.push(0);
        jj.push(col);
        vv.push(1.0);
        ii.push(1 + k);
        jj.push(col);
        vv.push(-1.0);
        // s = b − A x = G f, so A = −G: force on i is −f n, on j is +f n.
        for a in 0..d {
            ii.push(soc0 + 1 + row_of[ct.i] + a);
            jj.push(col);
            vv.push(n[a]);
            if let Some(j) = ct.j {
                ii.push(soc0 + 1 + row_of[j] + a);
                jj.push(col);
                vv.push(-n[a]);
            }
        }
    }
    let m = soc0 + 1 + rows;
    let a = CscMatrix::new_from_triplets(m, 1 + nc, ii, jj, vv);
    let p = CscMatrix::zeros((1 + nc, 1 + nc));
    let mut q = vec![0.0; 1 + nc];
    q[0] = 1.0;
    let mut b = vec![0.0; m];
    b[0] = nc as f64;
    let cones = [
        ZeroConeT(1),
        NonnegativeConeT(nc),
        SecondOrderConeT(1 + rows),
    ];
    let settings = DefaultSettings {
        verbose: false,
        tol_gap_abs: 1e-12,
        tol_gap_rel: 1e-12,
        tol_feas: 1e-12,
        max_iter: 200,
        ..DefaultSettings::default()
    };
    let mut solver = DefaultSolver::new(&p, &q, &a, &b, &cones, settings)
        .map_err(|e| CoreError::Solver(format!("could not set up the cone program: {e:?}")))?;
    solver.solve();
    match solver.solution.status {
        SolverStatus::Solved
        | SolverStatus::AlmostSolved
        | SolverStatus::MaxIterations
        | SolverStatus::InsufficientProgress => {}
        other => {
            return Err(CoreError::Solver(format!(
                "the cone program ended with status {other:?}"
            )));
        }
    }
    let f: Vec<f64> = solver.solution.x[1..].iter().map(|&v| v.max(0.0)).collect();
    let total: f64 = f.iter().sum();
    if total.is_nan() || total <= 0.0 {
        return Ok(1.0);
    }
    let mut net_force = vec![0.0; rows];
    for (k, &c) in active.iter().enumerate() {
        let ct = &net.contacts[c];
        let n = &net.normals[c * d..(c + 1) * d];
        for a in 0..d {
            net_force[row_of[ct.i] + a] -= f[k] * n[a];
            if let Some(j) = ct.j {
                net_force[row_of[j] + a] += f[k] * n[a];
            }
        }
    }
    Ok(net_force.iter().map(|v| v * v).sum::<f64>().sqrt() / total)
}
