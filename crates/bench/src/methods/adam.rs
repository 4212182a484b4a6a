//! `adam` and `fire`: Desmond–Weeks expansion–contraction (packbench-adam).

use packbench_adam::{Params, run};
use packbench_core::Packing;
use packbench_core::run::{Observer, Outcome};
use serde_json::{Map, Value};

use super::{Method, decode, encode};
use crate::error::BenchError;

/// ADAM → AMSGrad → overdamped Verlet (seed 000).
pub struct Adam;
/// The same protocol minimised by FIRE (seed 004).
pub struct Fire;

fn run_adam(
    name: &str,
    start: &Packing,
    params: &Map<String, Value>,
    obs: &mut dyn Observer,
) -> Result<Outcome, BenchError> {
    let p: Params = decode(name, params)?;
    run(start, &p, obs).map_err(|e| BenchError::Run(format!("{name}: {e}")))
}

impl Method for Adam {
    fn name(&self) -> &'static str {
        "adam"
    }
    fn summary(&self) -> &'static str {
        "soft-sphere inflate/deflate (Desmond & Weeks), ADAM → AMSGrad → Verlet minimiser (RCPGenerator)"
    }
    fn default_params(&self) -> Map<String, Value> {
        encode(&Params::default())
    }
    fn accuracy_knob(&self) -> &'static str {
        "delta_phi_tol"
    }
    fn run(
        &self,
        start: &Packing,
        params: &Map<String, Value>,
        obs: &mut dyn Observer,
    ) -> Result<Outcome, BenchError> {
        run_adam(self.name(), start, params, obs)
    }
}

impl Method for Fire {
    fn name(&self) -> &'static str {
        "fire"
    }
    fn summary(&self) -> &'static str {
        "the same inflate/deflate protocol with the FIRE minimiser (Particle Assembler)"
    }
    fn default_params(&self) -> Map<String, Value> {
        encode(&Params::fire())
    }
    fn accuracy_knob(&self) -> &'static str {
        "delta_phi_tol"
    }
    fn run(
        &self,
        start: &Packing,
        params: &Map<String, Value>,
        obs: &mut dyn Observer,
    ) -> Result<Outcome, BenchError> {
        run_adam(self.name(), start, params, obs)
    }
}
