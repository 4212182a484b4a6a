//! `closest-jammed`, `closest-jammed-qp` and `calippso`: exact jamming
//! (packbench-closest-jammed). They need an overlap-free start; an overlapping one (a random
//! initial packing) is first shrunk until it is free of overlaps.

use packbench_closest_jammed::{
    calippso, closest_jammed, closest_jammed_qp, shrink_to_overlap_free,
};
use packbench_core::Packing;
use packbench_core::analysis::contact_network;
use packbench_core::run::{Observer, Outcome};
use serde_json::{Map, Value};

use super::{Method, decode, encode};
use crate::error::BenchError;

/// Minimum-norm closest-jammed integrator (seed 001 App. C).
pub struct ClosestJammed;
/// Its QP form, where bonds may open.
pub struct ClosestJammedQp;
/// CALiPPSO's iterated LP (seed 002).
pub struct Calippso;

/// Relative gap left between the closest pair after shrinking an overlapping start.
const SHRINK_MARGIN: f64 = 1e-3;

fn overlap_free<'a>(
    name: &str,
    start: &'a Packing,
) -> Result<std::borrow::Cow<'a, Packing>, BenchError> {
    if contact_network(start, 0.0).max_overlap > 0.0 {
        shrink_to_overlap_free(start, SHRINK_MARGIN)
            .map(std::borrow::Cow::Owned)
            .map_err(|e| BenchError::Run(format!("{name}: {e}")))
    } else {
        Ok(std::borrow::Cow::Borrowed(start))
    }
}

impl Method for ClosestJammed {
    fn name(&self) -> &'static str {
        "closest-jammed"
    }
    fn summary(&self) -> &'static str {
        "radii grow as t·D with bonds held in contact and minimum-norm velocities (faer), until jammed"
    }
    fn default_params(&self) -> Map<String, Value> {
        encode(&closest_jammed::Params::default())
    }
    fn accuracy_knob(&self) -> &'static str {
        "contact_tol"
    }
    fn run(
        &self,
        start: &Packing,
        params: &Map<String, Value>,
        obs: &mut dyn Observer,
    ) -> Result<Outcome, BenchError> {
        let p: closest_jammed::Params = decode(self.name(), params)?;
        closest_jammed::run(&*overlap_free(self.name(), start)?, &p, obs)
            .map_err(|e| BenchError::Run(format!("closest-jammed: {e}")))
    }
}

impl Method for ClosestJammedQp {
    fn name(&self) -> &'static str {
        "closest-jammed-qp"
    }
    fn summary(&self) -> &'static str {
        "the closest-jammed growth with min ‖y‖² under inequality bonds (clarabel QP): bonds may open"
    }
    fn default_params(&self) -> Map<String, Value> {
        encode(&closest_jammed_qp::Params::default())
    }
    fn accuracy_knob(&self) -> &'static str {
        "contact_tol"
    }
    fn run(
        &self,
        start: &Packing,
        params: &Map<String, Value>,
        obs: &mut dyn Observer,
    ) -> Result<Outcome, BenchError> {
        let p: closest_jammed_qp::Params = decode(self.name(), params)?;
        closest_jammed_qp::run(&*overlap_free(self.name(), start)?, &p, obs)
            .map_err(|e| BenchError::Run(format!("closest-jammed-qp: {e}")))
    }
}

impl Method for Calippso {
    fn name(&self) -> &'static str {
        "calippso"
    }
    fn summary(&self) -> &'static str {
        "CALiPPSO: iterated LP maximising the inflation Γ over displacements (clarabel), forces from duals"
    }
    fn default_params(&self) -> Map<String, Value> {
        encode(&calippso::Params::default())
    }
    fn accuracy_knob(&self) -> &'static str {
        "tol_gamma"
    }
    fn run(
        &self,
        start: &Packing,
        params: &Map<String, Value>,
        obs: &mut dyn Observer,
    ) -> Result<Outcome, BenchError> {
        let p: calippso::Params = decode(self.name(), params)?;
        calippso::run(&*overlap_free(self.name(), start)?, &p, obs)
            .map_err(|e| BenchError::Run(format!("calippso: {e}")))
    }
}
