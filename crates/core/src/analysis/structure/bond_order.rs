//! Bond-orientational order (Steinhardt, Nelson & Ronchetti, PRB 28, 784 (1983)): global Q4
//! and Q6 and the local q6 of each particle in 3D; the hexatic ψ6 in 2D; and the fraction of
//! crystal-like particles.
//!
//! q_lm(i) = (1/n_i) Σ_j Y_lm(r̂_ij) over the n_i bonds of i; q_l(i) = √(4π/(2l+1) Σ_m |q_lm(i)|²).
//! The global Q_l uses the same formula with q_lm averaged over every bond of the packing.

use serde::{Deserialize, Serialize};

use super::histogram::Histogram;
use super::neighbours::{Bonds, Neighbours, bonds};
use super::spherical_harmonics::spherical_harmonics;
use crate::packing::Packing;

/// Neighbours of the crystal-like test: the first shell, pairs closer than 1.2 σ_ij.
pub const CRYSTAL_CUTOFF: f64 = 1.2;
/// A bond is solid-like when the normalised q6 vectors of its ends have a dot product above
/// this (ten Wolde, Ruiz-Montero & Frenkel, J. Chem. Phys. 104, 9932 (1996)).
pub const SOLID_BOND_DOT: f64 = 0.7;
/// A particle is crystal-like with at least this many solid-like bonds (Auer & Frenkel,
/// J. Chem. Phys. 120, 3015 (2004)).
pub const SOLID_BONDS_MIN: usize = 7;
/// In 2D, a particle is crystal-like when its local |ψ6| (first-shell neighbours) reaches this.
pub const CRYSTAL_PSI6_MIN: f64 = 0.7;

/// Bond-orientational order of a packing.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BondOrder {
    /// Global Q4 (3D only).
    pub q4: Option<f64>,
    /// Global Q6 (3D only).
    pub q6: Option<f64>,
    /// Global hexatic order |⟨ψ6(i)⟩| over particles with bonds (2D only).
    pub psi6: Option<f64>,
    /// Mean of the local order (q6 in 3D, |ψ6| in 2D) over particles with bonds.
    pub local_mean: Option<f64>,
    /// Distribution of the local order (q6 in 3D, |ψ6| in 2D) on [0, 1].
    pub local_histogram: Histogram,
    /// The neighbour rule of Q4, Q6, ψ6 and the local order.
    pub neighbours: String,
    /// Mean number of bonds per particle under that rule.
    pub mean_bonds: f64,
    /// Fraction of crystal-like particles (2D and 3D), by `crystal_rule`.
    pub crystal_fraction: Option<f64>,
    /// How a particle is judged crystal-like.
    pub crystal_rule: String,
}

/// Local bond-order vectors: for each particle its bond count and q_lm for m = 0..=l.
struct LocalOrder {
    count: Vec<usize>,
    qlm: Vec<(f64, f64)>,
    l: usize,
}

impl LocalOrder {
    /// Sums Y_lm over the bonds of each particle (both ends of each bond; the even l used here
    /// make Y_lm(−r̂) = Y_lm(r̂)) and divides by the bond count.
    fn of(n: usize, b: &Bonds, l: usize) -> LocalOrder {
        let mut count = vec![0usize; n];
        let mut qlm = vec![(0.0, 0.0); n * (l + 1)];
        let mut y = vec![(0.0, 0.0); l + 1];
        for (k, &(i, j)) in b.pairs.iter().enumerate() {
            let u = [
                b.directions[3 * k],
                b.directions[3 * k + 1],
                b.directions[3 * k + 2],
            ];
            spherical_harmonics(l, u, &mut y);
            for p in [i, j] {
                count[p] += 1;
                for m in 0..=l {
                    let q = &mut qlm[p * (l + 1) + m];
                    q.0 += y[m].0;
                    q.1 += y[m].1;
                }
            }
        }
        for p in 0..n {
            if count[p] > 0 {
                for q in &mut qlm[p * (l + 1)..(p + 1) * (l + 1)] {
                    q.0 /= count[p] as f64;
                    q.1 /= count[p] as f64;
                }
            }
        }
        LocalOrder { count, qlm, l }
    }

    fn vector(&self, p: usize) -> &[(f64, f64)] {
        &self.qlm[p * (self.l + 1)..(p + 1) * (self.l + 1)]
    }
}

/// Σ_{m=−l}^{l} a_lm b_lm* (real part) from the m ≥ 0 halves, using a_l,−m = (−1)^m conj(a_lm).
fn dot(a: &[(f64, f64)], b: &[(f64, f64)]) -> f64 {
    let re = |k: usize| a[k].0 * b[k].0 + a[k].1 * b[k].1;
    re(0) + 2.0 * (1..a.len()).map(re).sum::<f64>()
}

/// q_l = √(4π/(2l+1) Σ_m |q_lm|²).
fn invariant(q: &[(f64, f64)]) -> f64 {
    let l = q.len() - 1;
    (4.0 * std::f64::consts::PI / (2 * l + 1) as f64 * dot(q, q))
        .max(0.0)
        .sqrt()
}

/// Global Q_l: q_lm averaged over every bond end, weighted by bond counts.
fn global(local: &LocalOrder) -> Option<f64> {
    let l = local.l;
    let total: usize = local.count.iter().sum();
    if total == 0 {
        return None;
    }
    let mut q = vec![(0.0, 0.0); l + 1];
    for (p, &c) in local.count.iter().enumerate() {
        for (m, v) in local.vector(p).iter().enumerate() {
            q[m].0 += v.0 * c as f64 / total as f64;
            q[m].1 += v.1 * c as f64 / total as f64;
        }
    }
    Some(invariant(&q))
}

/// Bond order of `packing` with neighbours by `rule`; the crystal-like fraction always uses the
/// first shell ([`CRYSTAL_CUTOFF`]). Dimensions above 3 get only the bond count.
pub fn bond_order(packing: &Packing, rule: Neighbours) -> BondOrder {
    let n = packing.n();
    let b = bonds(packing, rule);
    let mean_bonds = if n > 0 {
        2.0 * b.pairs.len() as f64 / n as f64
    } else {
        0.0
    };
    let mut out = BondOrder {
        q4: None,
        q6: None,
        psi6: None,
        local_mean: None,
        local_histogram: Histogram::default(),
        neighbours: rule.describe(),
        mean_bonds,
        crystal_fraction: None,
        crystal_rule: String::new(),
    };
    let local_summary = |values: &[f64], out: &mut BondOrder| {
        if !values.is_empty() {
            out.local_mean = Some(values.iter().sum::<f64>() / values.len() as f64);
            out.local_histogram = Histogram::linear(values, 0.0, 1.0, 50);
        }
    };
    let shell = Neighbours::Cutoff {
        factor: CRYSTAL_CUTOFF,
    };
    match packing.dim {
        3 => {
            let q4 = LocalOrder::of(n, &b, 4);
            let q6 = LocalOrder::of(n, &b, 6);
            out.q4 = global(&q4);
            out.q6 = global(&q6);
            let local: Vec<f64> = (0..n)
                .filter(|&p| q6.count[p] > 0)
                .map(|p| invariant(q6.vector(p)))
                .collect();
            local_summary(&local, &mut out);
            out.crystal_fraction = crystal_fraction_3d(packing, shell);
            out.crystal_rule = format!(
                "at least {SOLID_BONDS_MIN} neighbours with r < {CRYSTAL_CUTOFF}·σ_ij whose \
                 normalised q6 vectors have a dot product above {SOLID_BOND_DOT}"
            );
        }
        2 => {
            let psi = Psi6::of(n, &b);
            out.psi6 = psi.global();
            let local: Vec<f64> = (0..n)
                .filter(|&p| psi.count[p] > 0)
                .map(|p| psi.local_modulus(p))
                .collect();
            local_summary(&local, &mut out);
            let first = Psi6::of(n, &bonds(packing, shell));
            out.crystal_fraction = (n > 0).then(|| {
                (0..n)
                    .filter(|&p| first.count[p] > 0 && first.local_modulus(p) >= CRYSTAL_PSI6_MIN)
                    .count() as f64
                    / n as f64
            });
            out.crystal_rule = format!(
                "local |ψ6| ≥ {CRYSTAL_PSI6_MIN} over neighbours with r < {CRYSTAL_CUTOFF}·σ_ij"
            );
        }
        _ => {}
    }
    out
}

/// Fraction of particles with at least [`SOLID_BONDS_MIN`] solid-like bonds.
fn crystal_fraction_3d(packing: &Packing, shell: Neighbours) -> Option<f64> {
    let n = packing.n();
    if n == 0 {
        return None;
    }
    let b = bonds(packing, shell);
    let q6 = LocalOrder::of(n, &b, 6);
    let norm: Vec<f64> = (0..n)
        .map(|p| dot(q6.vector(p), q6.vector(p)).sqrt())
        .collect();
    let mut solid = vec![0usize; n];
    for &(i, j) in &b.pairs {
        let denom = norm[i] * norm[j];
        if denom > 0.0 && dot(q6.vector(i), q6.vector(j)) / denom > SOLID_BOND_DOT {
            solid[i] += 1;
            solid[j] += 1;
        }
    }
    Some(solid.iter().filter(|&&s| s >= SOLID_BONDS_MIN).count() as f64 / n as f64)
}

/// ψ6(i) = (1/n_i) Σ_j e^{6iθ_ij} of each particle (Nelson & Halperin's hexatic order).
struct Psi6 {
    count: Vec<usize>,
    psi: Vec<(f64, f64)>,
}

impl Psi6 {
    fn of(n: usize, b: &Bonds) -> Psi6 {
        let mut count = vec![0usize; n];
        let mut psi = vec![(0.0, 0.0); n];
        for (k, &(i, j)) in b.pairs.iter().enumerate() {
            // e^{6iθ} is the same for the bond seen from either end (θ + π).
            let theta = b.directions[2 * k + 1].atan2(b.directions[2 * k]);
            let (s, c) = (6.0 * theta).sin_cos();
            for p in [i, j] {
                count[p] += 1;
                psi[p].0 += c;
                psi[p].1 += s;
            }
        }
        for p in 0..n {
            if count[p] > 0 {
                psi[p].0 /= count[p] as f64;
                psi[p].1 /= count[p] as f64;
            }
        }
        Psi6 { count, psi }
    }

    fn local_modulus(&self, p: usize) -> f64 {
        self.psi[p].0.hypot(self.psi[p].1)
    }

    fn global(&self) -> Option<f64> {
        let with: Vec<usize> = (0..self.count.len())
            .filter(|&p| self.count[p] > 0)
            .collect();
        if with.is_empty() {
            return None;
        }
        let (re, im) = with.iter().fold((0.0, 0.0), |(a, b), &p| {
            (a + self.psi[p].0, b + self.psi[p].1)
        });
        Some(re.hypot(im) / with.len() as f64)
    }
}
