//! `ls`: Lubachevsky–Stillinger compression at a fixed rate from a Poisson configuration,
//! until the reduced pressure reaches the cap (the "initial packing" of Baranau & Tallarek 2014, Fig. 2a).

use packbench_core::Packing;
use packbench_core::run::{Observer, Outcome};
use serde::{Deserialize, Serialize};
use serde_json::Map;

use crate::driver::Driver;
use crate::error::MlsError;
use crate::params::{Dynamics, positive};
use crate::system::System;

/// Parameters of `ls`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Params {
    /// Compression rate γ: growth of the mean diameter per unit time, in length units ℓ
    /// (`--rate`; default 1, a fast compression in Baranau & Tallarek 2014's sense, γ⁻¹ < 5).
    pub rate: f64,
    /// Thermostat, pressure window, pressure cap, velocity seed and budget.
    #[serde(flatten)]
    pub dynamics: Dynamics,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            rate: 1.0,
            dynamics: Dynamics::default(),
        }
    }
}

impl Params {
    /// Checks ranges.
    pub fn validate(&self) -> Result<(), MlsError> {
        positive("rate", self.rate)?;
        self.dynamics.validate()
    }
}

/// Runs LS on `start`'s centres and diameter ratios, beginning from zero-size spheres (a
/// Poisson configuration, φ = 0) as Baranau & Tallarek 2014 does: windows of
/// `collisions_per_particle·N` collisions at rate `params.rate` until the reduced pressure
/// of a window reaches `params.dynamics.pressure_cap`.
///
/// Terminations: `pressure_cap`; `box_limit` (the largest sphere reached half the smallest
/// periodic box length before jamming, e.g. N = 1 or 2); `no_collisions`; `max_steps`;
/// `interrupted` (observer). The packing returned is always overlap-free.
///
/// Errors: an invalid packing or parameter, an empty packing, d > 8, or a container that is
/// not a box with periodic and flat-walled axes (curved walls, `fix_height`).
pub fn run(
    start: &Packing,
    params: &Params,
    observer: &mut dyn Observer,
) -> Result<Outcome, MlsError> {
    params.validate()?;
    crate::check_start(start)?;
    crate::dispatch!(
        start.dim,
        start.container.is_fully_periodic(),
        ls,
        start,
        params,
        observer
    )
}

fn ls<const D: usize, const P: bool>(
    start: &Packing,
    params: &Params,
    observer: &mut dyn Observer,
) -> Result<Outcome, MlsError> {
    let dynamics = &params.dynamics;
    let mut sys = System::<D, P>::new(start, 0.0, dynamics.temperature, dynamics.seed);
    let mut driver = Driver::new(observer, dynamics, start);
    let termination = loop {
        match driver.window(&mut sys, params.rate) {
            Ok(p) if p >= dynamics.pressure_cap => break "pressure_cap",
            Ok(_) => {}
            Err(t) => break t,
        }
    };
    Ok(driver.finish(&sys, termination, params.rate, Map::new()))
}
