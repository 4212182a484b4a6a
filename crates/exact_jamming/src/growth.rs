//! The state shared by the closest-jammed integrators: positions, the growth factor `t`
//! (actual diameters are `t·D_i`, Baranau & Tallarek 2014 App. C), the contact candidates, and the step to the
//! next new contact along a straight motion (the root of the pair-gap equation).

use packbench_core::{Container, Packing};

use crate::contacts::{self, Candidates, Key, Link};
use crate::error::JammingError;

/// Positions and growth factor of a packing whose diameters grow as `t·D_i`.
pub(crate) struct Growth {
    pub container: Container,
    /// Nominal diameters `D_i` (the starting diameters; `t = 1` at the start).
    pub diameters: Vec<f64>,
    /// Positions, never wrapped during a run.
    pub x: Vec<f64>,
    /// Growth factor.
    pub t: f64,
    pub n: usize,
    pub d: usize,
    pub candidates: Candidates,
    /// Candidate skin as a multiple of the mean actual diameter.
    skin_factor: f64,
    mean_diameter: f64,
    max_diameter: f64,
}

/// What a trial move changes in a [`Growth`]: positions, growth factor, and the skin its
/// candidate list has used up. Saved before a step or projection that may be undone.
pub(crate) struct Snapshot {
    x: Vec<f64>,
    t: f64,
    consumed: f64,
}

impl Growth {
    /// The state a later [`Self::restore`] goes back to.
    pub fn snapshot(&self) -> Snapshot {
        Snapshot {
            x: self.x.clone(),
            t: self.t,
            consumed: self.candidates.consumed,
        }
    }

    /// Undoes every move since `saved` was taken.
    pub fn restore(&mut self, saved: &Snapshot) {
        self.x.clone_from(&saved.x);
        self.t = saved.t;
        self.candidates.consumed = saved.consumed;
    }

    /// The largest relative gap `|r − σt|/(σt)` over the pairs `keys` (0 for none; NaN when
    /// a position is not finite).
    pub fn worst_gap(&self, keys: &[Key]) -> f64 {
        max_or_nan(keys.iter().map(|k| {
            let l = self.link(k);
            l.gap(self.t).abs() / (l.size * self.t)
        }))
    }

    /// Takes `start` (validated, overlap-free up to `overlap_tol` relative).
    pub fn new(start: &Packing, skin_factor: f64, overlap_tol: f64) -> Result<Self, JammingError> {
        start.validate()?;
        let n = start.n();
        if n == 0 {
            return Err(JammingError::Parameter(
                "the packing has no particles to jam".into(),
            ));
        }
        let mean_diameter = start.diameters.iter().sum::<f64>() / n as f64;
        let mut g = Growth {
            container: start.container.clone(),
            diameters: start.diameters.clone(),
            x: start.positions.clone(),
            t: 1.0,
            n,
            d: start.dim,
            candidates: Candidates {
                keys: Vec::new(),
                gaps: Vec::new(),
                skin: 0.0,
                consumed: f64::INFINITY,
            },
            skin_factor,
            mean_diameter,
            max_diameter: start.max_diameter(),
        };
        g.rebuild();
        let (ov, i, j) =
            contacts::worst_overlap(&g.container, &g.x, &g.diameters, 1.0, &g.candidates.keys);
        if ov > overlap_tol {
            return Err(JammingError::Overlap { i, j, overlap: ov });
        }
        Ok(g)
    }

    /// Mean actual diameter `t·⟨D⟩`.
    pub fn mean_diameter(&self) -> f64 {
        self.mean_diameter * self.t
    }

    /// Rebuilds the candidate list around the current configuration.
    pub fn rebuild(&mut self) {
        let skin = self.skin_factor * self.mean_diameter * self.t;
        self.candidates =
            Candidates::build(&self.container, &self.x, &self.diameters, self.t, skin);
    }

    /// Rebuilds the candidates if a gap may have shrunk by half the skin since the last build.
    pub fn refresh(&mut self) -> bool {
        if self.candidates.is_stale() {
            self.rebuild();
            true
        } else {
            false
        }
    }

    /// True while the candidate list is sure to hold every pair at or inside contact: no gap
    /// can have shrunk by the whole skin since the list was built. A projection that jumped
    /// farther may have pushed pairs the list does not know into overlap.
    pub fn candidates_cover_contacts(&self) -> bool {
        self.candidates.consumed < self.candidates.skin
    }

    /// Candidate `key` at the current configuration.
    pub fn link(&self, key: &Key) -> Link {
        contacts::link(&self.container, &self.x, &self.diameters, key)
    }

    /// Candidates `keys` at the current configuration.
    pub fn links(&self, keys: &[Key]) -> Vec<Link> {
        keys.iter().map(|k| self.link(k)).collect()
    }

    /// Largest step `τ` that keeps the candidate list valid under velocities with largest
    /// magnitude `vmax`.
    pub fn safe_step(&self, vmax: f64) -> f64 {
        0.25 * self.candidates.skin / self.shrink_rate(vmax)
    }

    /// The fastest a gap can shrink per unit `t` under velocities with largest magnitude `vmax`:
    /// `2·vmax + D_max` (both ends move, and the diameters grow).
    pub fn shrink_rate(&self, vmax: f64) -> f64 {
        2.0 * vmax + self.max_diameter
    }

    /// Moves `x += τ y`, grows `t += τ`, and books the gap shrinkage against the skin.
    pub fn advance(&mut self, y: &[f64], tau: f64) {
        let mut vmax2: f64 = 0.0;
        for (xi, yi) in self.x.chunks_exact_mut(self.d).zip(y.chunks_exact(self.d)) {
            let mut v2 = 0.0;
            for k in 0..self.d {
                xi[k] += tau * yi[k];
                v2 += yi[k] * yi[k];
            }
            vmax2 = vmax2.max(v2);
        }
        self.candidates.consumed += 2.0 * tau * vmax2.sqrt();
        self.grow(tau);
    }

    /// Grows `t += δt` and books the gap shrinkage (`D_max δt` at most) against the skin.
    pub fn grow(&mut self, dt: f64) {
        self.t += dt;
        self.candidates.consumed += dt.max(0.0) * self.max_diameter;
    }

    /// Books a displacement `dx` (e.g. a projection) against the skin and applies it.
    pub fn displace(&mut self, dx: &[f64]) {
        let mut vmax2: f64 = 0.0;
        for (xi, di) in self.x.chunks_exact_mut(self.d).zip(dx.chunks_exact(self.d)) {
            let mut v2 = 0.0;
            for k in 0..self.d {
                xi[k] += di[k];
                v2 += di[k] * di[k];
            }
            vmax2 = vmax2.max(v2);
        }
        self.candidates.consumed += 2.0 * vmax2.sqrt();
    }

    /// The packing at the current configuration: positions wrapped, diameters `t·D`.
    pub fn packing(&self) -> Packing {
        let mut p = Packing {
            dim: self.d,
            positions: self.x.clone(),
            diameters: self.diameters.iter().map(|&v| v * self.t).collect(),
            container: self.container.clone(),
        };
        p.wrap_positions();
        p
    }

    /// Packing fraction at the current growth factor.
    pub fn phi(&self, phi_start: f64) -> f64 {
        phi_start * self.t.powi(self.d as i32)
    }
}

/// Step `τ ≥ 0` at which candidate `l` comes into contact when positions move as `x + τ y` and
/// diameters grow as `t + τ`: the smallest positive root of the pair-gap equation
/// `|r + τ v|² = D_ij² (t + τ)²` (v = y_j − y_i), or of `h − τ n·y_i = R_i (t + τ)` for a
/// wall (the wall's local plane). `None` when it never touches along this motion. A candidate
/// already at or past contact touches at `τ = 0` if it is closing.
pub(crate) fn contact_time(l: &Link, y: &[f64], t: f64, d: usize) -> Option<f64> {
    let rate = l.rate(y, d);
    let s = l.size;
    match l.j {
        None => {
            let closing = s - rate;
            let gap = l.dist - s * t;
            if gap <= 0.0 {
                return (closing > 0.0).then_some(0.0);
            }
            (closing > 0.0).then(|| gap / closing)
        }
        Some(j) => {
            let mut v2 = 0.0;
            if j != l.i {
                for k in 0..d {
                    let v = y[j * d + k] - y[l.i * d + k];
                    v2 += v * v;
                }
            }
            // G(τ) = a τ² + b τ + c with G(0) = |r|² − σ² t².
            let a = v2 - s * s;
            let b = 2.0 * (l.dist * rate - s * s * t);
            let c = (l.dist - s * t) * (l.dist + s * t);
            if c <= 0.0 {
                // At (or within rounding past) contact: touching now if closing; if opening,
                // it closes again at the positive root when the quadratic turns down (a < 0,
                // e.g. a bond just released), or never.
                if b < 0.0 {
                    return Some(0.0);
                }
                if a >= 0.0 {
                    return None;
                }
                let disc = b * b - 4.0 * a * c;
                if disc <= 0.0 {
                    return Some(0.0);
                }
                // a < 0 and c ≤ 0: the larger root (−b − √disc)/(2a) is the positive one.
                return Some((-b - disc.sqrt()) / (2.0 * a));
            }
            if a == 0.0 {
                return (b < 0.0).then(|| -c / b);
            }
            let disc = b * b - 4.0 * a * c;
            if disc < 0.0 {
                return None;
            }
            // Stable quadratic roots: q = −(b + sign(b)√disc)/2, roots q/a and c/q.
            let q = -0.5 * (b + b.signum() * disc.sqrt());
            let mut best: Option<f64> = None;
            for r in [q / a, if q != 0.0 { c / q } else { f64::NAN }] {
                if r.is_finite() && r > 0.0 && best.is_none_or(|bst| r < bst) {
                    best = Some(r);
                }
            }
            best
        }
    }
}

/// The largest of `values` (0 for none), NaN if any is NaN. `f64::max` skips NaN, which would
/// let a failed solve's NaN displacements pass a convergence test as a zero gap.
pub(crate) fn max_or_nan(values: impl IntoIterator<Item = f64>) -> f64 {
    values.into_iter().fold(0.0, |m, v| {
        if m.is_nan() || v.is_nan() {
            f64::NAN
        } else {
            m.max(v)
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    /// After small random moves and growth booked against the skin, every candidate whose gap
    /// is now within a reach is among `within(reach)`: the scans skip no pair that matters, and
    /// they do skip the others.
    #[test]
    fn candidate_scans_skip_no_pair_within_reach() {
        // A jittered simple-cubic lattice, so that most spheres have candidates.
        let (m, d, side) = (6, 3, 6.0);
        let n = m * m * m;
        let mut seed = 7u64;
        let mut uniform = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let start = Packing {
            dim: d,
            positions: (0..n * d)
                .map(|c| ((c / d) / m.pow((c % d) as u32) % m) as f64 + 0.2 * uniform())
                .collect(),
            diameters: vec![1.0; n],
            container: Container::periodic_box(&[side; 3]).unwrap(),
        };
        let start = crate::start::shrink_to_overlap_free(&start, 1e-3).unwrap();
        let mut g = Growth::new(&start, 0.3, 1e-12).unwrap();
        let mut skipped = 0;
        for _ in 0..5 {
            let y: Vec<f64> = (0..n * d).map(|_| 0.02 * (uniform() - 0.5)).collect();
            g.advance(&y, 0.002);
            assert!(!g.candidates.is_stale());
            for reach in [0.0, 0.001, 0.01] {
                let listed: HashSet<usize> = g.candidates.within(reach).map(|(i, _)| i).collect();
                for (i, k) in g.candidates.keys.iter().enumerate() {
                    assert!(g.link(k).gap(g.t) > reach || listed.contains(&i), "{k:?}");
                }
                skipped += g.candidates.keys.len() - listed.len();
            }
        }
        assert!(skipped > 0);
    }

    /// A NaN among the values (a failed solve's displacement) is not skipped as `f64::max`
    /// would: the Newton test must see it and call the phase diverged.
    #[test]
    fn max_or_nan_does_not_skip_nan() {
        assert_eq!(max_or_nan([0.5, 2.0, 1.0]), 2.0);
        assert_eq!(max_or_nan(std::iter::empty()), 0.0);
        assert!(max_or_nan([1e-20, f64::NAN, 0.0]).is_nan());
        assert!(max_or_nan([f64::NAN, 3.0]).is_nan());
    }
}
