//! The force-balance program by accelerated projected gradient: minimise F(f) = ½‖G f‖² over
//! the scaled simplex {f ≥ 0, Σ f = N_c} with FISTA (Beck & Teboulle 2009, SIAM J. Imaging
//! Sci. 2, 183) and its gradient restart (O'Donoghue & Candès 2015, Found. Comput. Math. 15,
//! 715). Each iteration costs two sparse products with G and one projection onto the simplex,
//! so it reaches packings whose stiffness matrix no direct factorisation can afford.
//!
//! The Frank–Wolfe gap g·f − N_c min g (g = ∇F) bounds F(f) − F* from above, so the run stops
//! with a certificate once it is a small fraction of F.

use super::ContactColumns;

/// F(f) − F* at most this fraction of F(f): the residual √(2F)/N_c is then within 0.1 % of the
/// least one.
const GAP: f64 = 1e-2;

/// Iterations at most.
const ITERATIONS: usize = 20_000;

/// Iterations between two evaluations of the gap.
const CHECK_EVERY: usize = 25;

/// Power iterations for the step's estimate of GᵀG's largest eigenvalue, and the margin put
/// on it (the estimate approaches the eigenvalue from below).
const POWER_ITERATIONS: usize = 40;
const POWER_MARGIN: f64 = 1.05;

/// The forces the descent ended with (one per column, on the simplex) and whether the gap
/// certifies them as least to [`GAP`].
pub(super) struct Descent {
    pub forces: Vec<f64>,
    pub certified: bool,
}

/// Runs the descent from equal forces.
pub(super) fn least_net_force(g: &ContactColumns) -> Descent {
    let (nc, total) = (g.columns(), g.columns() as f64);
    let mut products = Products::new(g);
    // G = 0 (every normal zero: coincident centres) has no eigenvalue to estimate; F is then 0
    // everywhere and any step will do.
    let estimate = products.largest_eigenvalue();
    let mut lipschitz = if estimate > 0.0 {
        (POWER_MARGIN * estimate).min(lipschitz_bound(g))
    } else {
        lipschitz_bound(g)
    };
    let mut simplex = Simplex::new(total);
    let mut x = vec![1.0; nc];
    let mut y = x.clone();
    let mut next = vec![0.0; nc];
    let (mut t, mut checked) = (1.0f64, f64::INFINITY);
    for it in 1..=ITERATIONS {
        let grad = products.gradient(&y);
        let step = 1.0 / lipschitz;
        next.iter_mut()
            .zip(&y)
            .zip(grad)
            .for_each(|((z, y), d)| *z = y - step * d);
        simplex.project(&mut next);
        // Restart when the momentum points uphill: (y − next)·(next − x) > 0.
        let uphill = y
            .iter()
            .zip(&next)
            .zip(&x)
            .map(|((y, n), x)| (y - n) * (n - x))
            .sum::<f64>()
            > 0.0;
        let t_next = if uphill {
            1.0
        } else {
            0.5 * (1.0 + (1.0 + 4.0 * t * t).sqrt())
        };
        let momentum = if uphill { 0.0 } else { (t - 1.0) / t_next };
        y.iter_mut()
            .zip(&next)
            .zip(&x)
            .for_each(|((y, n), x)| *y = n + momentum * (n - x));
        std::mem::swap(&mut x, &mut next);
        t = t_next;
        if it % CHECK_EVERY == 0 {
            let (value, certified) = products.check(&x, total);
            if certified {
                return Descent {
                    forces: x,
                    certified,
                };
            }
            // A step too long for the largest eigenvalue makes F grow along it: lengthen the
            // estimate and go on from the current forces without momentum.
            if value > 2.0 * checked {
                lipschitz *= 2.0;
                y.copy_from_slice(&x);
                t = 1.0;
            }
            checked = value;
        }
    }
    let certified = products.check(&x, total).1;
    Descent {
        forces: x,
        certified,
    }
}

/// G and Gᵀ products into kept buffers.
struct Products<'g> {
    g: &'g ContactColumns,
    net: Vec<f64>,
    grad: Vec<f64>,
}

impl<'g> Products<'g> {
    fn new(g: &'g ContactColumns) -> Self {
        Products {
            g,
            net: vec![0.0; g.rows],
            grad: vec![0.0; g.columns()],
        }
    }

    /// ∇F(f) = Gᵀ G f.
    fn gradient(&mut self, f: &[f64]) -> &[f64] {
        self.g.net_forces_into(f, &mut self.net);
        self.g.gt_times_into(&self.net, &mut self.grad);
        &self.grad
    }

    /// F(f), and whether the Frank–Wolfe gap of `f` is at most [`GAP`] F(f).
    fn check(&mut self, f: &[f64], total: f64) -> (f64, bool) {
        self.gradient(f);
        let value = 0.5 * self.net.iter().map(|v| v * v).sum::<f64>();
        let min = self.grad.iter().copied().fold(f64::INFINITY, f64::min);
        let gap = self.grad.iter().zip(f).map(|(a, b)| a * b).sum::<f64>() - total * min;
        (value, gap <= GAP * value)
    }

    /// The power method's estimate of GᵀG's largest eigenvalue, from a fixed start.
    fn largest_eigenvalue(&mut self) -> f64 {
        let mut v: Vec<f64> = (0..self.grad.len())
            .map(|k| 1.0 + (k % 7) as f64 / 7.0)
            .collect();
        let mut estimate = 0.0;
        for _ in 0..POWER_ITERATIONS {
            let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            let w = self.gradient(&v);
            let w_norm = w.iter().map(|x| x * x).sum::<f64>().sqrt();
            if w_norm.is_nan() || w_norm <= 0.0 {
                break;
            }
            estimate = w_norm / norm;
            v = w.iter().map(|x| x / w_norm).collect();
        }
        estimate
    }
}

/// An upper bound of the largest eigenvalue of GᵀG (Gershgorin): entry (k, l) is n_k·n_l,
/// at most 1 in size, for each particle the contacts share, so row k sums to at most
/// z_i + z_j over the columns.
fn lipschitz_bound(g: &ContactColumns) -> f64 {
    let mut z = vec![0.0f64; g.rows / g.d];
    for k in 0..g.columns() {
        let (ri, rj, _) = g.column(k);
        z[ri / g.d] += 1.0;
        if let Some(rj) = rj {
            z[rj / g.d] += 1.0;
        }
    }
    (0..g.columns())
        .map(|k| {
            let (ri, rj, _) = g.column(k);
            z[ri / g.d] + rj.map_or(0.0, |rj| z[rj / g.d])
        })
        .fold(1.0, f64::max)
}

/// Euclidean projection onto {f ≥ 0, Σ f = total}: max(v − τ, 0) with the threshold τ that
/// solves φ(τ) = Σ max(v − τ, 0) − total = 0. φ is convex, decreasing and piecewise linear, so
/// Newton's method from a τ left of the root climbs to it monotonically and ends exactly, in
/// a few passes; the last projection's τ is the start when it is left of the root, else
/// (Σ v − total)/n, which always is (Michelot, J. Optim. Theory Appl. 50, 195, 1986).
struct Simplex {
    total: f64,
    last: Option<f64>,
}

/// Newton steps at most (each one pass over the forces).
const NEWTON_STEPS: usize = 100;

impl Simplex {
    fn new(total: f64) -> Self {
        Simplex { total, last: None }
    }

    /// Replaces `v` by its projection.
    fn project(&mut self, v: &mut [f64]) {
        let left = |tau: f64| -> Option<(f64, f64)> {
            let (above, count) = excess(v, tau);
            (above >= self.total).then_some((above, count))
        };
        let (mut tau, mut at) = match self.last.and_then(|t| Some((t, left(t)?))) {
            Some(start) => start,
            None => {
                let tau = (lane_sum(v) - self.total) / v.len() as f64;
                (tau, excess(v, tau))
            }
        };
        for _ in 0..NEWTON_STEPS {
            let (above, count) = at;
            let next = tau + (above - self.total) / count;
            if next.is_nan() || next <= tau || count == 0.0 {
                break;
            }
            tau = next;
            at = excess(v, tau);
        }
        self.last = Some(tau);
        v.iter_mut().for_each(|x| *x = (*x - tau).max(0.0));
    }
}

/// (Σ max(v − τ, 0), how many v exceed τ), summed in four lanes so that it vectorises.
fn excess(v: &[f64], tau: f64) -> (f64, f64) {
    let (mut s, mut c) = ([0.0; 4], [0.0; 4]);
    let chunks = v.chunks_exact(4);
    let rest = chunks.remainder();
    for ch in chunks {
        for l in 0..4 {
            let e = ch[l] - tau;
            s[l] += e.max(0.0);
            c[l] += if e > 0.0 { 1.0 } else { 0.0 };
        }
    }
    for &x in rest {
        s[0] += (x - tau).max(0.0);
        c[0] += if x > tau { 1.0 } else { 0.0 };
    }
    (s.iter().sum(), c.iter().sum())
}

/// Σ v in four lanes.
fn lane_sum(v: &[f64]) -> f64 {
    let mut s = [0.0; 4];
    let chunks = v.chunks_exact(4);
    let rest: f64 = chunks.remainder().iter().sum();
    for ch in chunks {
        for l in 0..4 {
            s[l] += ch[l];
        }
    }
    s.iter().sum::<f64>() + rest
}
