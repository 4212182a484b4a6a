//! Force balance of a hard-sphere packing: the non-negative contact forces with mean 1 that
//! best balance every non-rattler, i.e. the minimiser of ½‖G f‖² subject to Σ f = N_c, f ≥ 0,
//! where column c of G puts −f_c n_c on particle i and +f_c n_c on particle j (a wall contact
//! only acts on i).
//!
//! Three solvers, the cheapest first:
//! - [`projection`]: the exactly balancing forces nearest to equal ones, one sparse Cholesky
//!   factorisation of G Gᵀ (up to about N = 2·10⁴ in 3D). When none comes out negative the
//!   minimum (zero) is reached: the exactly jammed packings of calippso and closest-jammed.
//! - [`descent`]: accelerated projected gradient on the program, stopped by a duality-gap
//!   certificate; soft packings (adam, FIRE), whose least residual is not zero, and every
//!   packing too large to factorise. N = 10⁵ in 3D in about 25 s on one thread.
//! - [`qp`]: the program by clarabel's interior point, when the descent ends without its
//!   certificate (a least residual near zero is reached slowly) and the network has at most
//!   [`QP_MAX_COLUMNS`] contacts. Above, the descent's residual is reported: an upper bound
//!   of the least one, attained by the forces returned.
//!
//! The returned residual is recomputed from the clipped forces, ‖G f‖ / Σ f, whichever solver
//! made them, so it is always attained by the forces returned.

mod descent;
mod projection;
mod qp;

use super::ContactNetwork;
use crate::error::CoreError;

/// The best force-balancing contact forces of a packing and how well they balance it.
#[derive(Clone, Debug, PartialEq)]
pub struct BalancingForces {
    /// One non-negative force per contact of the network, in units of the mean force over the
    /// contacts that carry one (0 for contacts touching a rattler and self-image contacts).
    pub forces: Vec<f64>,
    /// Relative residual ‖Σ f_c n_c‖ / Σ f_c (1 when the non-rattlers share no contact).
    pub residual: f64,
}

/// Relative residual of the best force-balancing contact forces over the non-rattlers.
/// Contacts touching a rattler are ignored, and so are contacts of a particle with its own
/// periodic image: they push it both ways at once, so their force is free and would otherwise
/// absorb the whole force budget at zero residual. Returns 1 (no balance at all) when the
/// non-rattlers share no contact. Errors: the solver failed ([`CoreError::Solver`]).
pub fn force_balance(net: &ContactNetwork, rattler: &[bool], d: usize) -> Result<f64, CoreError> {
    balancing_forces(net, rattler, d).map(|b| b.residual)
}

/// Residual below which the projection's forces are kept: the quadratic program's own
/// accuracy is about 1e-6 absolute (the square root of its gap tolerance), 1e-11 relative at
/// N = 10⁴, so forces balanced to 1e-12 are at least as good.
const PROJECTION_ACCEPTED: f64 = 1e-12;

/// Columns above which the quadratic program is not tried after an uncertified descent: its
/// interior point needs about twenty factorisations of a matrix as large as the projection's.
const QP_MAX_COLUMNS: usize = 60_000;

/// The forces behind [`force_balance`]: the non-negative contact forces with mean 1 that
/// minimise the net force on every non-rattler, one per contact of `net`, with their residual.
/// Errors: the solver failed ([`CoreError::Solver`]).
pub fn balancing_forces(
    net: &ContactNetwork,
    rattler: &[bool],
    d: usize,
) -> Result<BalancingForces, CoreError> {
    let g = ContactColumns::new(net, rattler, d);
    let unbalanced = || BalancingForces {
        forces: vec![0.0; net.contacts.len()],
        residual: 1.0,
    };
    if g.columns() == 0 {
        return Ok(unbalanced());
    }
    let projected = projection::projected_forces(&g).map(|f| g.balance(f));
    let (f, residual) = match projected {
        Some(balanced) if balanced.1 <= PROJECTION_ACCEPTED => balanced,
        _ => {
            let descent = descent::least_net_force(&g);
            let (f, r) = g.balance(descent.forces);
            if descent.certified || g.columns() > QP_MAX_COLUMNS {
                (f, r)
            } else {
                match g.balance(qp::least_net_force(&g)?) {
                    (fq, rq) if rq < r || (r.is_nan() && !rq.is_nan()) => (fq, rq),
                    _ => (f, r),
                }
            }
        }
    };
    if residual.is_nan() {
        return Ok(unbalanced());
    }
    let mut forces = vec![0.0; net.contacts.len()];
    for (k, &c) in g.active.iter().enumerate() {
        forces[c] = f[k];
    }
    Ok(BalancingForces { forces, residual })
}

/// The columns of G: the contacts between non-rattlers (self-image contacts left out), each
/// with the rows of its two particles' coordinates and its normal, stored column by column
/// (the descent multiplies by G and Gᵀ thousands of times).
struct ContactColumns {
    d: usize,
    /// Rows of G: `d` per non-rattler.
    rows: usize,
    /// The contact of each column.
    active: Vec<usize>,
    /// Per column, the first rows of particle i and of particle j (`NO_ROW` for a wall).
    first_rows: Vec<[usize; 2]>,
    /// Per column, its unit normal (`d` entries), from i to j.
    normals: Vec<f64>,
}

/// The row of a wall in [`ContactColumns::first_rows`].
const NO_ROW: usize = usize::MAX;

/// The first row of each non-rattler (`NO_ROW` for rattlers), numbered in breadth-first order
/// over the contact network: neighbours get nearby rows, so G's products touch memory nearly
/// in order (a file's particle order is usually random; at N = 10⁵ the descent took 17 % less).
fn breadth_first_rows(
    net: &ContactNetwork,
    active: &[usize],
    rattler: &[bool],
    d: usize,
) -> Vec<usize> {
    let n = rattler.len();
    let mut degree = vec![0usize; n + 1];
    for &c in active {
        let ct = &net.contacts[c];
        if let Some(j) = ct.j {
            degree[ct.i + 1] += 1;
            degree[j + 1] += 1;
        }
    }
    for i in 0..n {
        degree[i + 1] += degree[i];
    }
    let mut fill = degree.clone();
    let mut neighbours = vec![0usize; degree[n]];
    for &c in active {
        let ct = &net.contacts[c];
        if let Some(j) = ct.j {
            neighbours[fill[ct.i]] = j;
            fill[ct.i] += 1;
            neighbours[fill[j]] = ct.i;
            fill[j] += 1;
        }
    }
    let mut row_of = vec![NO_ROW; n];
    let mut queue = std::collections::VecDeque::new();
    let mut next = 0;
    for root in (0..n).filter(|&i| !rattler[i]) {
        if row_of[root] != NO_ROW {
            continue;
        }
        row_of[root] = next;
        next += d;
        queue.push_back(root);
        while let Some(i) = queue.pop_front() {
            for &j in &neighbours[degree[i]..degree[i + 1]] {
                if row_of[j] == NO_ROW {
                    row_of[j] = next;
                    next += d;
                    queue.push_back(j);
                }
            }
        }
    }
    row_of
}

impl ContactColumns {
    fn new(net: &ContactNetwork, rattler: &[bool], d: usize) -> Self {
        let mut active: Vec<usize> = (0..net.contacts.len())
            .filter(|&c| {
                let ct = &net.contacts[c];
                !rattler[ct.i] && ct.j.is_none_or(|j| j != ct.i && !rattler[j])
            })
            .collect();
        let row_of = breadth_first_rows(net, &active, rattler, d);
        let rows = d * rattler.iter().filter(|&&r| !r).count();
        // Columns by their first row, so that both products sweep G's rows nearly in order.
        active.sort_by_key(|&c| {
            let ct = &net.contacts[c];
            let ri = row_of[ct.i];
            ct.j.map_or(ri, |j| ri.min(row_of[j]))
        });
        let first_rows = active
            .iter()
            .map(|&c| {
                let ct = &net.contacts[c];
                [row_of[ct.i], ct.j.map_or(NO_ROW, |j| row_of[j])]
            })
            .collect();
        let normals = active
            .iter()
            .flat_map(|&c| &net.normals[c * d..(c + 1) * d])
            .copied()
            .collect();
        ContactColumns {
            d,
            rows,
            active,
            first_rows,
            normals,
        }
    }

    fn columns(&self) -> usize {
        self.active.len()
    }

    /// Column k: the first rows of its particles i and j (None for a wall) and its normal.
    fn column(&self, k: usize) -> (usize, Option<usize>, &[f64]) {
        let [ri, rj] = self.first_rows[k];
        (
            ri,
            (rj != NO_ROW).then_some(rj),
            &self.normals[k * self.d..(k + 1) * self.d],
        )
    }

    /// G f: the net force on every non-rattler coordinate.
    fn net_forces(&self, f: &[f64]) -> Vec<f64> {
        let mut net_force = vec![0.0; self.rows];
        self.net_forces_into(f, &mut net_force);
        net_force
    }

    /// G f into `out`: the force on i is −f n, on j +f n.
    fn net_forces_into(&self, f: &[f64], out: &mut [f64]) {
        crate::dispatch_dim!(self.d, D => self.net_forces_in::<D>(f, out),
            _ => unreachable!("dimension checked by Container::validate"))
    }

    fn net_forces_in<const D: usize>(&self, f: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        for ((&[ri, rj], n), &fk) in self
            .first_rows
            .iter()
            .zip(self.normals.chunks_exact(D))
            .zip(f)
        {
            let fi: &mut [f64; D] = (&mut out[ri..ri + D]).try_into().expect("D rows");
            for a in 0..D {
                fi[a] -= fk * n[a];
            }
            if rj != NO_ROW {
                let fj: &mut [f64; D] = (&mut out[rj..rj + D]).try_into().expect("D rows");
                for a in 0..D {
                    fj[a] += fk * n[a];
                }
            }
        }
    }

    /// Gᵀ u into `out`: per column, the normal's component of u_j − u_i (of −u_i at a wall).
    fn gt_times_into(&self, u: &[f64], out: &mut [f64]) {
        crate::dispatch_dim!(self.d, D => self.gt_times_in::<D>(u, out),
            _ => unreachable!("dimension checked by Container::validate"))
    }

    fn gt_times_in<const D: usize>(&self, u: &[f64], out: &mut [f64]) {
        for ((o, &[ri, rj]), n) in out
            .iter_mut()
            .zip(&self.first_rows)
            .zip(self.normals.chunks_exact(D))
        {
            let ui: &[f64; D] = u[ri..ri + D].try_into().expect("D rows");
            let mut s = 0.0;
            if rj != NO_ROW {
                let uj: &[f64; D] = u[rj..rj + D].try_into().expect("D rows");
                for a in 0..D {
                    s += n[a] * (uj[a] - ui[a]);
                }
            } else {
                for a in 0..D {
                    s -= n[a] * ui[a];
                }
            }
            *o = s;
        }
    }

    /// The forces clipped at zero and scaled to mean 1 over the columns, with their relative
    /// residual ‖G f‖ / Σ f (NaN when nothing is left to scale).
    fn balance(&self, mut f: Vec<f64>) -> (Vec<f64>, f64) {
        f.iter_mut().for_each(|v| *v = v.max(0.0));
        let total: f64 = f.iter().sum();
        if total.is_nan() || total <= 0.0 {
            return (f, f64::NAN);
        }
        let scale = self.columns() as f64 / total;
        f.iter_mut().for_each(|v| *v *= scale);
        let residual = self
            .net_forces(&f)
            .iter()
            .map(|v| v * v)
            .sum::<f64>()
            .sqrt()
            / self.columns() as f64;
        (f, residual)
    }
}

#[cfg(test)]
mod tests;
