//! `mls`: the modified Lubachevsky–Stillinger schedule of Baranau & Tallarek 2014 §III.B, which searches for
//! the closest jammed configuration of a starting packing: compress at γ until the reduced
//! pressure reaches the cap, divide γ by the decrease factor, equilibrate at γ = 0 until the
//! pressure falls below the cap (or declare the packing jammed after 50 windows), repeat until
//! γ falls below the final rate.

use packbench_core::Packing;
use packbench_core::run::{Observer, Outcome};
use serde::{Deserialize, Serialize};
use serde_json::{Map, json};

use crate::checkpoint::{Checkpoint, Schedule};
use crate::driver::Driver;
use crate::error::MlsError;
use crate::params::{Dynamics, positive};
use crate::system::System;

/// Parameters of `mls`; defaults are Baranau & Tallarek 2014 §III.B's.
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
    let driver = Driver::new(observer, dynamics, start);
    let schedule = Schedule {
        rate: params.rate_initial,
        stages: 0,
        equilibrating: None,
    };
    Ok(run_schedule(
        sys, driver, start, params, schedule, shrink, None,
    ))
}

/// Continues an MLS run from a checkpoint written by an earlier run (see [`crate::checkpoint`]):
/// bit for bit the run that would have gone on from there when `params` are the earlier run's
/// (`checkpoint.params`; the budget `max_collisions` counts from the run's start). The
/// outcome's `runtime_s` includes the earlier legs.
///
/// Errors: an inconsistent checkpoint or invalid parameters.
pub fn resume(
    checkpoint: &Checkpoint,
    params: &Params,
    observer: &mut dyn Observer,
) -> Result<Outcome, MlsError> {
    params.validate()?;
    checkpoint.validate()?;
    let c = checkpoint;
    // The packing the run reports in: the checkpoint's particles in their original order.
    let n = c.id.len();
    let mut template = Packing {
        dim: c.dim,
        positions: vec![0.0; n * c.dim],
        diameters: vec![0.0; n],
        container: c.container.clone(),
    };
    for (k, &i) in c.id.iter().enumerate() {
        template.positions[i * c.dim..(i + 1) * c.dim]
            .copy_from_slice(&c.x[k * c.dim..(k + 1) * c.dim]);
        template.diameters[i] = c.ratio[k] * c.scale;
    }
    crate::check_start(&template)?;
    crate::dispatch!(
        c.dim,
        c.container.is_fully_periodic(),
        resume_in,
        c,
        &template,
        params,
        observer
    )
}

fn resume_in<const D: usize, const P: bool>(
    c: &Checkpoint,
    template: &Packing,
    params: &Params,
    observer: &mut dyn Observer,
) -> Result<Outcome, MlsError> {
    let sys = System::<D, P>::from_checkpoint(c);
    let driver = Driver::resumed(observer, &params.dynamics, template, c);
    Ok(run_schedule(
        sys,
        driver,
        template,
        params,
        c.schedule,
        c.initial_shrink,
        Some(c),
    ))
}

/// Baranau & Tallarek 2014's schedule from `s` on: compress at γ until a window's pressure reaches the cap,
/// divide γ, equilibrate at γ = 0 until a window's pressure is below the cap (jammed after
/// `equilibration_windows` windows), until γ falls below the final rate. After every completed
/// window the state is a checkpoint, passed to the observer with each snapshot and kept for an
/// interruption.
fn run_schedule<const D: usize, const P: bool>(
    mut sys: System<D, P>,
    mut driver: Driver<'_>,
    template: &Packing,
    params: &Params,
    mut s: Schedule,
    shrink: f64,
    resumed_from: Option<&Checkpoint>,
) -> Outcome {
    let cap = params.dynamics.pressure_cap;
    // The last window boundary, for an interruption (kept up to date in place: copying N
    // positions and velocities per window costs nothing beside its 20·N collisions).
    let (mut last, mut have_last) = match resumed_from {
        Some(c) => {
            let mut c = c.clone();
            c.params = params.clone();
            (c, true)
        }
        None => (Checkpoint::empty(&template.container, s, params), false),
    };
    let termination = loop {
        let rate = if s.equilibrating.is_some() {
            0.0
        } else {
            s.rate
        };
        let pressure = match driver.window(&mut sys, rate) {
            Ok(p) => p,
            Err(t) => break t,
        };
        match s.equilibrating {
            None if pressure >= cap => {
                s.stages += 1;
                s.rate /= params.rate_factor;
                if s.rate < params.rate_final {
                    break "rate_final";
                }
                s.equilibrating = Some(0);
            }
            None => {}
            Some(_) if pressure < cap => s.equilibrating = None,
            Some(k) => {
                if k + 1 >= params.equilibration_windows {
                    break "jammed";
                }
                s.equilibrating = Some(k + 1);
            }
        }
        sys.write_checkpoint(&mut last);
        last.windows = driver.windows;
        last.runtime_s = driver.runtime_s();
        last.initial_shrink = shrink;
        last.schedule = s;
        have_last = true;
        if driver.snapshot_taken {
            driver.checkpoint(&last);
        }
    };
    // A run stopped before its schedule ended leaves its last boundary to continue from.
    if matches!(termination, "interrupted" | "max_steps") && have_last {
        driver.checkpoint(&last);
    }
    let mut more = Map::new();
    more.insert("initial_shrink".into(), json!(shrink));
    more.insert("compression_stages".into(), json!(s.stages));
    driver.finish(&sys, termination, s.rate, more)
}
