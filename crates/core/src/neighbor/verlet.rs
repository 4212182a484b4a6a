//! A Verlet list: the near pairs of a [`CellList`] with a skin, rebuilt only when the largest
//! displacement and growth since the last build could let an unlisted pair touch.

use super::CellList;
use crate::container::Container;

/// Near pairs within contact plus `skin`, valid until particles move or grow by about skin/2.
pub struct VerletList {
    /// Pairs `(i, j)` whose gap was below `skin` at the last build.
    pub pairs: Vec<(u32, u32)>,
    /// The skin in length units.
    pub skin: f64,
    ref_positions: Vec<f64>,
    ref_diameters: Vec<f64>,
    ref_lengths: Vec<f64>,
    builds: u64,
}

impl VerletList {
    /// Builds the list for the given configuration.
    pub fn new(container: &Container, positions: &[f64], diameters: &[f64], skin: f64) -> Self {
        let mut v = VerletList {
            pairs: Vec::new(),
            skin,
            ref_positions: Vec::new(),
            ref_diameters: Vec::new(),
            ref_lengths: Vec::new(),
            builds: 0,
        };
        v.rebuild(container, positions, diameters);
        v
    }

    /// Rebuilds unconditionally.
    pub fn rebuild(&mut self, container: &Container, positions: &[f64], diameters: &[f64]) {
        CellList::near_pairs_into(container, positions, diameters, self.skin, &mut self.pairs);
        self.ref_positions.clear();
        self.ref_positions.extend_from_slice(positions);
        self.ref_diameters.clear();
        self.ref_diameters.extend_from_slice(diameters);
        self.ref_lengths.clear();
        self.ref_lengths.extend_from_slice(&container.lengths);
        self.builds += 1;
    }

    /// True when the list may miss a pair: a gap can shrink by at most the two largest
    /// displacements plus the growth of the two radii, so the list stays valid while
    /// `2·max|Δx| + max ΔD < skin`.
    pub fn is_stale(&self, container: &Container, positions: &[f64], diameters: &[f64]) -> bool {
        if container.lengths != self.ref_lengths || positions.len() != self.ref_positions.len() {
            return true;
        }
        let d = container.dim();
        let mut max_disp2: f64 = 0.0;
        let mut delta = [0.0; crate::MAX_DIM];
        for (x, x0) in positions
            .chunks_exact(d)
            .zip(self.ref_positions.chunks_exact(d))
        {
            for k in 0..d {
                delta[k] = x[k] - x0[k];
            }
            container.min_image(&mut delta[..d]);
            max_disp2 = max_disp2.max(delta[..d].iter().map(|v| v * v).sum());
        }
        let max_growth = diameters
            .iter()
            .zip(&self.ref_diameters)
            .fold(0.0f64, |m, (&a, &b)| m.max(a - b));
        2.0 * max_disp2.sqrt() + max_growth >= self.skin
    }

    /// Rebuilds if stale; returns whether it did.
    pub fn update(&mut self, container: &Container, positions: &[f64], diameters: &[f64]) -> bool {
        if self.is_stale(container, positions, diameters) {
            self.rebuild(container, positions, diameters);
            true
        } else {
            false
        }
    }

    /// How many times the list has been built.
    pub fn builds(&self) -> u64 {
        self.builds
    }
}
