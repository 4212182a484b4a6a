//! Knobs shared by `ls` and `mls`: the thermostat, the pressure window, the pressure cap and
//! the run budget. Defaults are the constants of Baranau & Tallarek 2014 §III.B.

use serde::{Deserialize, Serialize};

use crate::error::MlsError;

/// Event-driven dynamics settings common to both methods.
///
/// Units: lengths are measured in the *length unit* `ℓ`, the mean diameter at which the
/// spheres (keeping their diameter ratios) would fill the container (φ = 1); masses are 1 and
/// k_B = 1, so a temperature `T` means a root-mean-square speed `√(d·T)·ℓ` per time unit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Dynamics {
    /// Temperature `T` held by rescaling velocities after every pressure window (Baranau & Tallarek 2014
    /// §III.B: 0.2, i.e. rms speed √(3·0.2) in 3D).
    pub temperature: f64,
    /// Collisions per particle in one pressure window (Baranau & Tallarek 2014 §III.B: 20, i.e. 2·10⁵
    /// collisions for 10⁴ spheres). Wall collisions count.
    pub collisions_per_particle: u64,
    /// Reduced pressure `PV/(N k_B T)` at which a compression stage ends (Baranau & Tallarek 2014: 1e12).
    pub pressure_cap: f64,
    /// Seed of the initial velocities (Maxwell–Boltzmann).
    pub seed: u64,
    /// Stop after this many collisions (0: no limit); the run ends with `max_steps`.
    pub max_collisions: u64,
    /// Pass a snapshot to the observer after every this many collisions, at the next window
    /// end (0: never).
    pub save_interval: u64,
}

impl Default for Dynamics {
    fn default() -> Self {
        Dynamics {
            temperature: 0.2,
            collisions_per_particle: 20,
            pressure_cap: 1e12,
            seed: 0,
            max_collisions: 0,
            save_interval: 0,
        }
    }
}

impl Dynamics {
    /// Checks ranges.
    pub fn validate(&self) -> Result<(), MlsError> {
        positive("temperature", self.temperature)?;
        if self.collisions_per_particle == 0 {
            return Err(MlsError::Parameter(
                "collisions_per_particle must be at least 1".into(),
            ));
        }
        if !(self.pressure_cap.is_finite() && self.pressure_cap > 1.0) {
            return Err(MlsError::Parameter(format!(
                "pressure_cap = {} must be a finite reduced pressure above 1 (the ideal gas)",
                self.pressure_cap
            )));
        }
        Ok(())
    }
}

/// Refuses a value that is not a positive finite number.
pub(crate) fn positive(name: &str, value: f64) -> Result<(), MlsError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(MlsError::Parameter(format!(
            "{name} = {value} must be a positive finite number"
        )))
    }
}
