//! The list's upkeep on a fixed packing, for benchmarks of one step's neighbour share: a few
//! particles move past the refresh budget, and the list is kept either by a whole build or by
//! searching the movers' rows again ([`super::refresh`]), as adam does for broad sizes.

use packbench_core::Packing;

use super::NeighborList;
use crate::AdamError;
use crate::system::System;

/// A built list over a packing whose particles can be moved by hand.
pub struct NeighborUpkeep {
    sys: System,
    nl: NeighborList,
    skin: f64,
    refresh: bool,
    /// +1 or −1: the movers go back and forth, so the packing stays what it was.
    sign: f64,
}

impl NeighborUpkeep {
    /// Builds the list of `packing` with a skin of `skin` mean diameters; with `refresh` it is
    /// kept by searching the rows of particles that moved.
    pub fn new(packing: &Packing, skin: f64, refresh: bool) -> Result<Self, AdamError> {
        let mut sys = System::new(packing, &[])?;
        let mut nl = NeighborList::new();
        nl.update(&mut sys, (skin, skin), 0.0, refresh);
        Ok(NeighborUpkeep {
            sys,
            nl,
            skin,
            refresh,
            sign: 1.0,
        })
    }

    /// Moves every `every`-th particle (in the list's order) along the first axis by `delta`
    /// skins, the other way from the last call, and keeps the list. Returns whether it was
    /// built whole (more than half a skin moved makes a whole-build list stale; a fifth of
    /// one sends a refreshing list's movers to be searched again).
    pub fn shift(&mut self, every: usize, delta: f64) -> bool {
        let d = self.sys.dim;
        let step = self.sign * delta * self.skin * self.sys.kappa * self.sys.d0_mean;
        for x in self.sys.x.chunks_exact_mut(d).step_by(every.max(1)) {
            x[0] += step;
        }
        self.sign = -self.sign;
        self.nl
            .update(&mut self.sys, (self.skin, self.skin), 0.0, self.refresh)
    }
}
