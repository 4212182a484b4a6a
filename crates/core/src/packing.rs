//! A packing: dimension, positions (one flat row-major `Vec<f64>` of N·d), diameters and its
//! container.

use serde::{Deserialize, Serialize};

use crate::container::Container;
use crate::error::CoreError;
use crate::geometry::ball_volume;

/// Particles in a container. Positions are row-major: particle `i` is
/// `positions[i*d .. (i+1)*d]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Packing {
    /// Dimension `d`.
    pub dim: usize,
    /// N·d coordinates, row-major.
    pub positions: Vec<f64>,
    /// N diameters.
    pub diameters: Vec<f64>,
    /// The container the particles live in.
    pub container: Container,
}

/// Relative tolerance on container membership used by [`Packing::validate`].
pub const INSIDE_TOL: f64 = 1e-9;

impl Packing {
    /// Builds a packing and checks it with [`Packing::validate`].
    pub fn new(
        positions: Vec<f64>,
        diameters: Vec<f64>,
        container: Container,
    ) -> Result<Self, CoreError> {
        let p = Packing {
            dim: container.dim(),
            positions,
            diameters,
            container,
        };
        p.validate()?;
        Ok(p)
    }

    /// Number of particles.
    #[inline]
    pub fn n(&self) -> usize {
        self.diameters.len()
    }

    /// Position of particle `i`.
    #[inline]
    pub fn position(&self, i: usize) -> &[f64] {
        &self.positions[i * self.dim..(i + 1) * self.dim]
    }

    /// Total particle volume Σ v_d (D_i/2)^d.
    pub fn particle_volume(&self) -> f64 {
        self.diameters
            .iter()
            .map(|&d| ball_volume(self.dim, d))
            .sum()
    }

    /// Packing fraction φ = particle volume / exact container volume.
    pub fn phi(&self) -> f64 {
        self.particle_volume() / self.container.volume()
    }

    /// Mean diameter (NaN for an empty packing).
    pub fn mean_diameter(&self) -> f64 {
        self.diameters.iter().sum::<f64>() / self.n() as f64
    }

    /// Largest diameter (0 for an empty packing).
    pub fn max_diameter(&self) -> f64 {
        self.diameters.iter().fold(0.0, |m: f64, &d| m.max(d))
    }

    /// Smallest diameter (∞ for an empty packing).
    pub fn min_diameter(&self) -> f64 {
        self.diameters
            .iter()
            .fold(f64::INFINITY, |m: f64, &d| m.min(d))
    }

    /// Multiplies every diameter by `s` (positions unchanged).
    pub fn scale_diameters(&mut self, s: f64) {
        for d in &mut self.diameters {
            *d *= s;
        }
    }

    /// Sets the last box length to `fix_height × D_max` when the container asks for it.
    /// Idempotent: the height always follows the current largest diameter, never compounds.
    pub fn apply_fix_height(&mut self) {
        if let Some(k) = self.container.fix_height {
            let d = self.dim;
            let new_h = k * self.max_diameter();
            let old_h = self.container.lengths[d - 1];
            if new_h > 0.0 && old_h > 0.0 {
                let ratio = new_h / old_h;
                for i in 0..self.n() {
                    self.positions[i * d + d - 1] *= ratio;
                }
                self.container.lengths[d - 1] = new_h;
            }
        }
    }

    /// Two particles whose centres coincide (after wrapping into the box), if any: a
    /// degenerate start (every particle at one point, a duplicated line) that no method can
    /// separate, since the direction between the two is undefined. O(N log N).
    pub fn coincident_centres(&self) -> Option<(usize, usize)> {
        let d = self.dim;
        let mut wrapped = self.positions.clone();
        for x in wrapped.chunks_exact_mut(d) {
            self.container.wrap(x);
        }
        let centre = |i: usize| &wrapped[i * d..(i + 1) * d];
        let mut order: Vec<usize> = (0..self.n()).collect();
        order.sort_by(|&a, &b| {
            centre(a)
                .iter()
                .zip(centre(b))
                .map(|(x, y)| x.total_cmp(y))
                .find(|o| o.is_ne())
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        order
            .windows(2)
            .find(|w| centre(w[0]) == centre(w[1]))
            .map(|w| (w[0].min(w[1]), w[0].max(w[1])))
    }

    /// Wraps every position into the box along periodic axes.
    pub fn wrap_positions(&mut self) {
        let d = self.dim;
        for x in self.positions.chunks_exact_mut(d) {
            self.container.wrap(x);
        }
    }

    /// Checks consistency: dimension, lengths, finite positions, positive finite diameters
    /// no wider than any periodic length, every particle inside its container (up to
    /// [`INSIDE_TOL`] times its diameter).
    pub fn validate(&self) -> Result<(), CoreError> {
        self.container.validate()?;
        if self.dim != self.container.dim() {
            return Err(CoreError::Packing(format!(
                "the particles are {}-dimensional but the container is {}-dimensional",
                self.dim,
                self.container.dim()
            )));
        }
        if self.positions.len() != self.n() * self.dim {
            return Err(CoreError::Packing(format!(
                "{} coordinates for {} particles in {} dimensions",
                self.positions.len(),
                self.n(),
                self.dim
            )));
        }
        for (i, &dia) in self.diameters.iter().enumerate() {
            if !(dia.is_finite() && dia > 0.0) {
                return Err(CoreError::Packing(format!(
                    "particle {} has diameter {dia}; diameters must be positive finite numbers",
                    i + 1
                )));
            }
            if let Some(why) = self.container.too_wide_for_periodic_axis(dia) {
                return Err(CoreError::Packing(format!("particle {}: {why}", i + 1)));
            }
            let x = self.position(i);
            if let Some(k) = x.iter().position(|v| !v.is_finite()) {
                return Err(CoreError::Packing(format!(
                    "particle {} has coordinate {} = {}",
                    i + 1,
                    k + 1,
                    x[k]
                )));
            }
            let mut xw = x.to_vec();
            self.container.wrap(&mut xw);
            // Centres must lie in the container; particles may poke through a wall only by the
            // tolerance (initial configurations keep whole spheres inside).
            if !self.container.contains(&xw, 0.0, INSIDE_TOL * dia) {
                return Err(CoreError::Packing(format!(
                    "particle {} at ({}) lies outside the container ({})",
                    i + 1,
                    x.iter()
                        .map(|v| format!("{v}"))
                        .collect::<Vec<_>>()
                        .join(", "),
                    self.container.describe()
                )));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coincident_centres_are_found_through_the_periodic_wrap() {
        let c = Container::periodic_box(&[1.0, 1.0]).unwrap();
        let distinct = Packing::new(vec![0.1, 0.1, 0.5, 0.5, 0.9, 0.1], vec![0.1; 3], c.clone());
        assert_eq!(distinct.unwrap().coincident_centres(), None);
        // 1.25 wraps onto 0.25.
        let p = Packing::new(vec![0.25, 0.25, 0.5, 0.5, 1.25, 0.25], vec![0.1; 3], c).unwrap();
        assert_eq!(p.coincident_centres(), Some((0, 2)));
    }
}
