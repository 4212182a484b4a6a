//! `seq-fill`: 3DRSP sequential contact placement (packbench-seqfill). It builds its own bed;
//! from a starting packing it takes the size distribution (the empirical diameters) and the
//! box, so a comparison fills the same box with the same sizes.

use packbench_core::run::{Observer, Outcome};
use packbench_core::{Packing, SizeDistribution};
use packbench_seqfill::{Params, run};
use serde_json::{Map, Value};

use super::{Method, decode, encode};
use crate::error::BenchError;

/// 3DRSP, Methods 1 and 2.
pub struct SeqFill;

impl Method for SeqFill {
    fn name(&self) -> &'static str {
        "seq-fill"
    }
    fn summary(&self) -> &'static str {
        "3DRSP: each new sphere placed in contact with three parents, edges → faces → volume, in unit bricks"
    }
    fn default_params(&self) -> Map<String, Value> {
        let mut p = encode(&Params::default());
        // `from_start` (bench-level): take sizes and box from the starting packing.
        p.insert("from_start".into(), Value::Bool(true));
        p
    }
    fn accuracy_knob(&self) -> &'static str {
        "contact_param"
    }
    fn run(
        &self,
        start: &Packing,
        params: &Map<String, Value>,
        obs: &mut dyn Observer,
    ) -> Result<Outcome, BenchError> {
        let mut params = params.clone();
        let from_start = params
            .remove("from_start")
            .and_then(|v| v.as_bool())
            .unwrap_or(true);
        let mut p: Params = decode(self.name(), &params)?;
        if from_start {
            p.distribution = SizeDistribution::Custom {
                list: start.diameters.clone(),
            };
            p.brick_lengths = start.container.lengths.clone();
            p.brick_numbers = vec![1; start.dim];
        }
        run(&p, obs)
            .map(|o| o.outcome)
            .map_err(|e| BenchError::Run(format!("seq-fill: {e}")))
    }
}
