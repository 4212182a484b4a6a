//! `ls` and `mls`: event-driven Lubachevsky–Stillinger and its MLS schedule (packbench-mls).

use packbench_core::Packing;
use packbench_core::run::{Observer, Outcome};
use packbench_mls::{LsParams, MlsParams, run_ls, run_mls};
use serde_json::{Map, Value};

use super::{Method, decode, encode};
use crate::error::BenchError;

/// LS at a fixed compression rate from a Poisson start.
pub struct Ls;
/// MLS: the closest-jamming search of Baranau & Tallarek (seed 001 §III).
pub struct Mls;

impl Method for Ls {
    fn name(&self) -> &'static str {
        "ls"
    }
    fn summary(&self) -> &'static str {
        "event-driven hard spheres growing at a fixed rate γ until the reduced pressure reaches the cap"
    }
    fn default_params(&self) -> Map<String, Value> {
        encode(&LsParams::default())
    }
    fn accuracy_knob(&self) -> &'static str {
        "rate"
    }
    fn run(
        &self,
        start: &Packing,
        params: &Map<String, Value>,
        obs: &mut dyn Observer,
    ) -> Result<Outcome, BenchError> {
        let p: LsParams = decode(self.name(), params)?;
        run_ls(start, &p, obs).map_err(|e| BenchError::Run(format!("ls: {e}")))
    }
}

impl Method for Mls {
    fn name(&self) -> &'static str {
        "mls"
    }
    fn summary(&self) -> &'static str {
        "LS whose rate is halved each time the pressure reaches 1e12, with equilibration, until jammed"
    }
    fn default_params(&self) -> Map<String, Value> {
        encode(&MlsParams::default())
    }
    fn accuracy_knob(&self) -> &'static str {
        "rate_final"
    }
    fn run(
        &self,
        start: &Packing,
        params: &Map<String, Value>,
        obs: &mut dyn Observer,
    ) -> Result<Outcome, BenchError> {
        let p: MlsParams = decode(self.name(), params)?;
        run_mls(start, &p, obs).map_err(|e| BenchError::Run(format!("mls: {e}")))
    }
}
