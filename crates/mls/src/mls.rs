//! `mls`: the modified Lubachevsky–Stillinger schedule of seed 001 §III.B, which searches for
//! the closest jammed configuration of a starting packing: compress at γ until the reduced
//! pressure reaches the cap, divide γ by the decrease factor, equilibrate at γ = 0 until the
//! pressure falls below the cap (or declare the packing jammed after 50 windows), repeat until
//! γ falls below the final rate.

use packbench_core::Packing;
use packbench_core::run::{Observer, Outcome};
use serde::{Deserialize, Serialize};
use serde_json::{Map, json};

use crate::driver::Driver;
use crate::error::MlsError;
use crate::params::{Dynamics, positive};
use crate::system::System;

/// Parameters of `mls`; defaults are seed 001 §III.B's.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Params {
    /// Initial compression rate γ₀ in ℓ per time unit (`--rate-initial`, default 10).
    pub rate_initial: f64,
    /// Compression rate decrease factor (`--rate-factor`, default 2).
    pub rate_factor: f64,
    /// The run ends when γ falls below this (`--rate-final`, default 1e-4).
    pub rate_final: f64,
    /// Windows of equilibration at γ = 0 after which a pressure still above the cap means
    /// jammed (default 50).
    pub equilibration_windows: u64,
    /// Thermostat, pressure window, pressure cap, velocity seed and budget.
    #[serde(flatten)]
    pub dynamics: Dynamics,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            rate_initial: 10.0,
            rate_factor: 2.0,
            rate_final: 1e-4,
            equilibration_windows: 50,
            dynamics: Dynamics::default(),
        }
    }
}

impl Params {
    /// Checks ranges.
    pub fn validate(&self) -> Result<(), MlsError> {
        positive("rate_initial", self.rate_initial)?;
        positive("rate_final", self.rate_final)?;
        if !(self.rate_factor.is_finite() && self.rate_factor > 1.0) {
            return Err(MlsError::Parameter(format!(
                "rate_factor = {} must be a finite number above 1",
                self.rate_factor
            )));
        }
        if self.equilibration_windows == 0 {
            return Err(MlsError::Parameter(
                "equilibration_windows must be at least 1".into(),
            ));
        }
        self.dynamics.validate()
    }
}

/// Runs MLS from `start`, which may be any packing: its diameters are kept, except that a
/// packing with overlaps (from a soft-sphere method, say) is first shrunk uniformly until no
/// pair or wall overlaps (the factor is reported as `initial_shrink` in `extra`).
///
/// Terminations: `jammed` (pressure above the cap after `equilibration_windows` windows at
/// γ = 0), `rate_final` (γ fell below `rate_final`), and as for [`crate::ls::run`]
/// `box_limit`, `no_collisions`, `max_steps`, `interrupted`. The final φ is the closest
/// jamming density φ_J of the start.
///
/// Errors: as for [`crate::ls::run`].
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
        mls,
        start,
        params,
        observer
    )
}

fn mls<const D: usize, const P: bool>(
    start: &Packing,
    params: &Params,
    observer: &mut dyn Observer,
) -> Result<Outcome, MlsError> {
    let dynamics = &params.dynamics;
    let cap = dynamics.pressure_cap;
    let mean = start.diameters.iter().sum::<f64>() / start.n() as f64;
    let mut sys = System::<D, P>::new(start, mean, dynamics.temperature, dynamics.seed);
    // Clear overlaps so that every pair starts apart (rounding margin 1e-12).
    let contact = sys.min_contact_ratio();
    let shrink = if contact < 1.0 {
        contact * (1.0 - 1e-12)
    } else {
        1.0
    };
    if shrink < 1.0 {
        sys.shrink(shrink);
    }
    let mut driver = Driver::new(observer, dynamics, start);
    let mut rate = params.rate_initial;
    let mut stages = 0u64;
    let termination = 'schedule: loop {
        // Compress at γ until the pressure reaches the cap.
        loop {
            match driver.window(&mut sys, rate) {
                Ok(p) if p >= cap => break,
                Ok(_) => {}
                Err(t) => break 'schedule t,
            }
        }
        stages += 1;
        rate /= params.rate_factor;
        if rate < params.rate_final {
            break 'schedule "rate_final";
        }
        // Equilibrate at γ = 0 until the pressure falls below the cap.
        let mut relaxed = false;
        for _ in 0..params.equilibration_windows {
            match driver.window(&mut sys, 0.0) {
                Ok(p) if p < cap => {
                    relaxed = true;
                    break;
                }
                Ok(_) => {}
                Err(t) => break 'schedule t,
            }
        }
        if !relaxed {
            break 'schedule "jammed";
        }
    };
    let mut more = Map::new();
    more.insert("initial_shrink".into(), json!(shrink));
    more.insert("compression_stages".into(), json!(stages));
    Ok(driver.finish(&sys, termination, rate, more))
}
