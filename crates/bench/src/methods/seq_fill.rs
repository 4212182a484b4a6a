//! `seq-fill`: 3DRSP sequential contact placement (packbench-seqfill). It builds its own bed;
//! from a starting packing it takes the size distribution (the empirical diameters) and the
//! box, so a comparison fills the same box with the same sizes.

use packbench_core::run::{Observer, Outcome};
use packbench_core::{Packing, SizeDistribution};
use std::path::{Path, PathBuf};

use packbench_core::format::write_atomic;
use packbench_seqfill::{Params, SeqFillOutcome, run, write_contacts_csv, write_face_lists_csv};
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
        fill(start, params, obs).map(|(o, _)| o.outcome)
    }
    fn run_with_products(
        &self,
        start: &Packing,
        params: &Map<String, Value>,
        obs: &mut dyn Observer,
        stem: &Path,
    ) -> Result<(Outcome, Vec<PathBuf>), BenchError> {
        let (o, p) = fill(start, params, obs)?;
        let path = |suffix: &str| PathBuf::from(format!("{}{suffix}", stem.display()));
        let io = |e: packbench_seqfill::SeqFillError| BenchError::Run(format!("seq-fill: {e}"));
        let mut contacts = Vec::new();
        write_contacts_csv(&o.contacts, &mut contacts).map_err(io)?;
        write_atomic(&path("_contacts.csv"), &contacts)?;
        let mut faces = Vec::new();
        write_face_lists_csv(&o.faces, &mut faces).map_err(io)?;
        write_atomic(&path("_faces.csv"), &faces)?;
        let hist = path("_radii.png");
        crate::figures::radius_histogram(
            &hist,
            &o.radii_placed,
            &o.radii_discarded,
            &p.distribution,
        )?;
        Ok((
            o.outcome,
            vec![path("_contacts.csv"), path("_faces.csv"), hist],
        ))
    }
}

/// Runs the fill with the parameters resolved against the start.
fn fill(
    start: &Packing,
    params: &Map<String, Value>,
    obs: &mut dyn Observer,
) -> Result<(SeqFillOutcome, Params), BenchError> {
    let mut params = params.clone();
    let from_start = params
        .remove("from_start")
        .and_then(|v| v.as_bool())
        .unwrap_or(true);
    let mut p: Params = decode("seq-fill", &params)?;
    if from_start {
        p.distribution = SizeDistribution::Custom {
            list: start.diameters.clone(),
        };
        p.brick_lengths = start.container.lengths.clone();
        p.brick_numbers = vec![1; start.dim];
    }
    let o = run(&p, obs).map_err(|e| BenchError::Run(format!("seq-fill: {e}")))?;
    Ok((o, p))
}
