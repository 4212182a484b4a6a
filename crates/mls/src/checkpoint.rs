//! An exact resume point of an MLS run: the state at the end of a pressure window, from which
//! [`crate::mls::resume`] continues bit for bit as the run would have gone on (tested in
//! `crate::tests`). An MLS run of 10⁴ spheres takes hours, longer than many batch-job time
//! limits; a run stopped by a signal leaves the checkpoint of its last completed window.
//!
//! A window boundary is the only exact place: there every particle has been moved to the same
//! time and the next window re-predicts every event from scratch, so positions, velocities,
//! the diameter scale, the particle order and the last pressure are the whole state. Mid-window
//! the calendar holds events predicted at many earlier times, and predicting them again from
//! the present would round differently.

use packbench_core::Container;
use serde::{Deserialize, Serialize};

use crate::error::MlsError;

/// The tag of the current checkpoint format.
pub const FORMAT: &str = "packbench-mls checkpoint 1";

/// Where the MLS schedule of Baranau & Tallarek 2014 §III.B stands.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Schedule {
    /// The compression rate γ of the current stage (the next one, while equilibrating).
    pub rate: f64,
    /// Compression stages completed (pressure cap reached).
    pub stages: u64,
    /// Windows of the current equilibration at γ = 0 done so far; `None` while compressing.
    pub equilibrating: Option<u64>,
}

/// The state of an event-driven system at a window boundary, and the schedule.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Checkpoint {
    /// [`FORMAT`].
    pub format: String,
    pub dim: usize,
    pub container: Container,
    /// The length unit ℓ (the mean diameter at which φ would be 1).
    pub length_unit: f64,
    /// Mean diameter now.
    pub scale: f64,
    /// Temperature the thermostat holds.
    pub temperature: f64,
    /// Reduced pressure of the last window (it sets the neighbour-list skin).
    pub pressure: Option<f64>,
    /// Particles in the run's internal order: index in the starting packing, diameter over
    /// the mean diameter, position and velocity (N·d each, row-major).
    pub id: Vec<usize>,
    pub ratio: Vec<f64>,
    pub x: Vec<f64>,
    pub v: Vec<f64>,
    /// Counters since the start of the run.
    pub collisions: u64,
    pub events: u64,
    pub rebuilds: u64,
    pub windows: u64,
    /// Seconds of run time before this point (all earlier legs).
    pub runtime_s: f64,
    /// The factor by which the start was shrunk to clear overlaps.
    pub initial_shrink: f64,
    pub schedule: Schedule,
    /// The parameters of the run (a resume uses them unless told otherwise).
    pub params: crate::MlsParams,
}

impl Checkpoint {
    /// A checkpoint of a run in `container` with nothing in it yet (filled by the system at
    /// each window boundary).
    pub(crate) fn empty(
        container: &Container,
        schedule: Schedule,
        params: &crate::MlsParams,
    ) -> Self {
        Checkpoint {
            format: FORMAT.into(),
            dim: container.dim(),
            container: container.clone(),
            length_unit: 0.0,
            scale: 0.0,
            temperature: 0.0,
            pressure: None,
            id: Vec::new(),
            ratio: Vec::new(),
            x: Vec::new(),
            v: Vec::new(),
            collisions: 0,
            events: 0,
            rebuilds: 0,
            windows: 0,
            runtime_s: 0.0,
            initial_shrink: 1.0,
            schedule,
            params: params.clone(),
        }
    }

    /// Checks that the checkpoint is complete and consistent, with a reason when not.
    pub fn validate(&self) -> Result<(), MlsError> {
        let bad = |what: String| Err(MlsError::Checkpoint(what));
        if self.format != FORMAT {
            return bad(format!(
                "format `{}` is not `{FORMAT}` (written by another version?)",
                self.format
            ));
        }
        if !(2..=crate::MAX_DIM).contains(&self.dim) || self.container.dim() != self.dim {
            return bad(format!(
                "dimension {} does not match its container ({})",
                self.dim,
                self.container.describe()
            ));
        }
        let n = self.id.len();
        if n == 0
            || self.ratio.len() != n
            || self.x.len() != n * self.dim
            || self.v.len() != n * self.dim
        {
            return bad(format!(
                "{n} ids, {} ratios, {} coordinates and {} velocity components do not describe one set of particles in {} dimensions",
                self.ratio.len(),
                self.x.len(),
                self.v.len(),
                self.dim
            ));
        }
        let mut seen = vec![false; n];
        for &i in &self.id {
            if i >= n || std::mem::replace(&mut seen[i], true) {
                return bad(format!("the ids are not a permutation of 0..{n}"));
            }
        }
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        let numbers_ok = finite(&self.x)
            && finite(&self.v)
            && self.ratio.iter().all(|&r| r.is_finite() && r >= 0.0)
            && self.scale.is_finite()
            && self.scale >= 0.0
            && self.length_unit.is_finite()
            && self.length_unit > 0.0;
        if !numbers_ok {
            return bad("a position, velocity, diameter or scale is not a finite number".into());
        }
        if !(self.schedule.rate.is_finite() && self.schedule.rate > 0.0) {
            return bad(format!(
                "the schedule's rate {} is not a positive number",
                self.schedule.rate
            ));
        }
        Ok(())
    }
}
