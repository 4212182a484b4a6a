//! Force balance of a hard-sphere packing: the non-negative contact forces with mean 1 that
//! best balance every non-rattler.
//!
//! Solved as a sparse quadratic program with clarabel: minimise ½‖G f‖² subject to Σ f = N_c,
//! f ≥ 0, where column c of G puts −f_c n_c on particle i and +f_c n_c on particle j (a wall
//! contact only acts on i).
//! The returned value is recomputed from the clipped forces, ‖G f‖ / Σ f.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT::NonnegativeConeT,
    SupportedConeT::ZeroConeT,
};

use super::ContactNetwork;
use crate::error::CoreError;

/// Relative residual of the best force-balancing contact forces over the non-rattlers (see
/// [`balancing_forces`]).
pub fn force_balance(net: &ContactNetwork, rattler: &[bool], d: usize) -> Result<f64, CoreError> {
    Ok(balancing_forces(net, rattler, d)?.residual)
}

/// The best force-balancing contact forces of a network and how well they balance.
#[derive(Clone, Debug, Default)]
pub struct BalancingForces {
    /// Indices into the network's contacts of the contacts that carry a force.
    pub contacts: Vec<usize>,
    /// The force of each of those contacts, non-negative with mean 1.
    pub forces: Vec<f64>,
    /// ‖Σ f_c n_c‖ / Σ f_c over the non-rattlers (1 when no contact carries force).
    pub residual: f64,
}

/// The non-negative contact forces with mean 1 that best balance every non-rattler. Contacts
/// touching a rattler are ignored, and so are contacts of a particle with its own periodic
/// image: they push it both ways at once, so their force is free and would otherwise absorb
/// the whole force budget at zero residual. The residual is 1 (no balance at all) when the
/// non-rattlers share no contact. Errors when the solver fails.
pub fn balancing_forces(
    net: &ContactNetwork,
    rattler: &[bool],
    d: usize,
) -> Result<BalancingForces, CoreError> {
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
            !rattler[ct.i] && ct.j.is_none_or(|j| j != ct.i && !rattler[j])
        })
        .collect();
    let nc = active.len();
    let unbalanced = BalancingForces {
        residual: 1.0,
        ..BalancingForces::default()
    };
    if nc == 0 {
        return Ok(unbalanced);
    }
    // Variables x = [f_1 … f_nc, u_1 … u_rows] with u = G f the net forces: minimise ½‖u‖²
    // subject to G f − u = 0, Σ f = nc, f ≥ 0. A quadratic objective keeps the KKT system
    // sparse (no large second-order cone); the residual is accurate to about the square root
    // of the solver's gap tolerance, ~1e-6 absolute, i.e. ~1e-6/nc relative.
    let (mut ii, mut jj, mut vv) = (Vec::new(), Vec::new(), Vec::new());
    for (k, &c) in active.iter().enumerate() {
        let ct = &net.contacts[c];
        let n = &net.normals[c * d..(c + 1) * d];
        // Rows 0..rows: G f − u = 0; the force on i is −f n, on j is +f n.
        for a in 0..d {
            ii.push(row_of[ct.i] + a);
            jj.push(k);
            vv.push(-n[a]);
            if let Some(j) = ct.j {
                ii.push(row_of[j] + a);
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
        | SolverStatus::InsufficientProgress => {}
        other => {
            return Err(CoreError::Solver(format!(
                "the force-balance program ended with status {other:?}"
            )));
        }
    }
    let f: Vec<f64> = solver.solution.x[..nc]
        .iter()
        .map(|&v| v.max(0.0))
        .collect();
    let total: f64 = f.iter().sum();
    if total.is_nan() || total <= 0.0 {
        return Ok(unbalanced);
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
    let residual = net_force.iter().map(|v| v * v).sum::<f64>().sqrt() / total;
    let mean = total / nc as f64;
    Ok(BalancingForces {
        contacts: active,
        forces: f.iter().map(|v| v / mean).collect(),
        residual,
    })
}
