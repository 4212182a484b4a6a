//! What a list needs to refresh the rows of the particles that moved, as RCPGenerator 1.0
//! keeps its lists: each particle's position at its own last
//! refresh, the budgets that say when it or the whole list is stale, and a query that finds
//! one particle's partners.
//!
//! With a list skin S at a whole build, a pair is listed when r < σ(1 + γ) + 4b, where
//! b = S/5 and γ = b/D_max (for a pair of the largest spheres the reach is the whole skin;
//! a larger γ made the power law 1–15 list twice the pairs through its large spheres). A pair
//! left out was at least that far apart when the later of its two particles was last
//! searched; since then that one moved less than b, the other less than 2b (b either side of
//! its own last refresh), the box height changed by less than b and σ grew by less than the
//! factor 1 + γ. So no pair left out can overlap while every particle that moved b is
//! searched again, and the whole list is built when the height or κ (against its lowest
//! value since the build) changes more.

use packbench_core::neighbor::{NearQuery, Reach};

use crate::system::System;

pub(super) struct Refresher {
    /// Displacement that sends a particle's row to be searched again, and the height
    /// change that sends the whole list.
    pub budget: f64,
    /// Relative growth of the diameters the listed reach allows for.
    pub gamma: f64,
    kappa_low: f64,
    /// Each particle's position at its last search.
    ref_x: Vec<f64>,
    query: NearQuery,
    /// The diameters grown by γ, as the reach uses them.
    inflated: Vec<f64>,
    pub movers: Vec<u32>,
    pub near: Vec<u32>,
}

impl Refresher {
    /// The budgets for a list of skin `skin` built at the current positions.
    pub fn new(sys: &System, skin: f64) -> Self {
        let budget = 0.2 * skin;
        let gamma = budget / (sys.kappa * sys.d0_max);
        let inflated: Vec<f64> = sys.dia.iter().map(|&v| v * (1.0 + gamma)).collect();
        let nc = sys.n() * sys.dim;
        let reach = Reach {
            skin: 4.0 * budget,
            slack: budget,
            growth: 1.0 + gamma,
        };
        Refresher {
            budget,
            gamma,
            kappa_low: sys.kappa,
            ref_x: sys.x[..nc].to_vec(),
            query: NearQuery::new(&sys.container, &sys.x[..nc], &inflated, reach),
            inflated,
            movers: Vec::new(),
            near: Vec::new(),
        }
    }

    /// The listed reach beyond the grown contact, 4b.
    pub fn skin(&self) -> f64 {
        4.0 * self.budget
    }

    /// The diameters grown by γ, as the listed reach uses them (as of the last
    /// [`Refresher::place_movers`], or the build).
    pub fn inflated(&self) -> &[f64] {
        &self.inflated
    }

    /// Whether the diameters grew, against their smallest since the build, by more than the
    /// reach allows.
    pub fn outgrown(&mut self, sys: &System) -> bool {
        self.kappa_low = self.kappa_low.min(sys.kappa);
        sys.kappa >= (1.0 + self.gamma) * self.kappa_low
    }

    /// Whether particle `i` at `x` moved by the budget since its last search (`moved2`: the
    /// squared displacement between two positions).
    #[inline(always)]
    pub fn moved(&self, i: usize, x: &[f64], moved2: impl Fn(&[f64], &[f64]) -> f64) -> bool {
        let d = x.len();
        moved2(x, &self.ref_x[i * d..(i + 1) * d]) >= self.budget * self.budget
    }

    /// Lists into `near`, sorted, the partners of mover `m` at the current positions; call
    /// [`Refresher::place_movers`] first, so that every mover is found where it is.
    pub fn search(&mut self, sys: &System, m: usize) {
        let nc = sys.n() * sys.dim;
        self.near.clear();
        let near = &mut self.near;
        self.query
            .for_each_near(&sys.container, &sys.x[..nc], &self.inflated, m, |j| {
                near.push(j as u32)
            });
        self.near.sort_unstable();
    }

    /// Records the movers' current positions and the current diameters for the searches.
    pub fn place_movers(&mut self, sys: &System) {
        let d = sys.dim;
        for &mu in &self.movers {
            let m = mu as usize;
            let x = &sys.x[m * d..(m + 1) * d];
            self.ref_x[m * d..(m + 1) * d].copy_from_slice(x);
            self.query.place(&sys.container, m, x);
        }
        for (g, &v) in self.inflated.iter_mut().zip(&sys.dia) {
            *g = v * (1.0 + self.gamma);
        }
    }
}
