//! `seq-fill`: 3DRSP sequential contact placement (packbench-seqfill). It builds its own bed;
//! from a starting packing it takes the size distribution (the empirical diameters) and the
//! box, so a comparison fills the same box with the same sizes.

use packbench_core::run::{Observer, Outcome};
use packbench_core::{Packing, SizeDistribution};
use packbench_seqfill::{Params, SeqFillOutcome, run, write_contacts_csv, write_face_lists_csv};
use serde_json::{Map, Value};

use super::flags::{FlagValue, MethodFlag};
use super::{Method, Product, decode, encode, method_error};
use crate::args::SceneArgs;
use crate::error::BenchError;

/// 3DRSP, Methods 1 and 2.
pub struct SeqFill;

/// Its options of `pack`; with `--brick` (or a `--dist`) it fills that brick with that
/// distribution instead of mirroring a starting packing.
const FLAGS: [MethodFlag; 7] = [
    MethodFlag::new(
        "variant",
        "variant",
        FlagValue::Count,
        "1 (reflected bricks) or 2 (copied bricks).",
    ),
    MethodFlag::new(
        "brick",
        "brick_lengths",
        FlagValue::Numbers,
        "Unit brick side lengths, absolute (then the fill uses the --dist flags, not a start).",
    ),
    MethodFlag::new(
        "bricks",
        "brick_numbers",
        FlagValue::Counts,
        "Bricks per axis.",
    ),
    MethodFlag::number(
        "face-goal",
        "face_goal",
        "FaceGoal, the face fraction to reach.",
    ),
    MethodFlag::number(
        "body-goal",
        "body_goal",
        "BodyGoal, the volume fraction to reach.",
    ),
    MethodFlag::number(
        "contact-param",
        "contact_param",
        "SphereContactParameter ε (contacts within ε·r̄).",
    ),
    MethodFlag::number(
        "parent-param",
        "parent_param",
        "ParentParameter δ (parents within δ·r̄).",
    ),
];

impl Method for SeqFill {
    fn name(&self) -> &'static str {
        "seq-fill"
    }
    fn seed_key(&self) -> Option<&'static str> {
        Some("seed")
    }
    fn snapshot_key(&self) -> Option<&'static str> {
        Some("save_interval")
    }
    fn frame_interval(&self, n: usize) -> u64 {
        (n as u64 / 50).max(1)
    }
    fn step_unit(&self) -> &'static str {
        "radii drawn"
    }
    fn summary(&self) -> &'static str {
        "3DRSP: each new sphere placed in contact with three parents, edges → faces → volume, in unit bricks"
    }
    fn notes(&self) -> &'static str {
        "it ignores --N: it fills its unit brick (the start's box, or --brick) until its face and \
         body goals (--face-goal, --body-goal), so the number of spheres follows from the brick \
         and the size distribution. It refuses, before it starts, a domain that would hold more \
         than 5e7 spheres, and stops at once on Ctrl-C or SIGTERM with what it has placed."
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
    fn flags(&self) -> &'static [MethodFlag] {
        &FLAGS
    }
    fn check(&self, params: &Map<String, Value>) -> Result<(), BenchError> {
        let mut params = params.clone();
        params.remove("from_start");
        let p: Params = decode("seq-fill", &params)?;
        p.validate().map_err(|e| method_error("seq-fill", e))
    }
    fn scene_overrides(
        &self,
        scene: &SceneArgs,
        given: &[(String, Value)],
    ) -> Result<Vec<(String, Value)>, BenchError> {
        let mut out = Vec::new();
        // seq-fill builds its own bed: with a brick or a distribution given it fills that
        // brick with that distribution instead of mirroring a starting packing.
        let brick = given.iter().any(|(k, _)| k == "brick_lengths");
        if brick || scene.distribution.dist.is_some() {
            out.push(("from_start".into(), Value::Bool(false)));
            if scene.distribution.dist.is_some() {
                let dist = scene.distribution.distribution()?;
                out.push((
                    "distribution".into(),
                    serde_json::to_value(dist).map_err(|e| BenchError::Run(e.to_string()))?,
                ));
            }
        }
        if let Some(h) = &scene.container.hemispheres {
            out.push(("hemispheres".into(), Value::from(h.clone())));
        }
        Ok(out)
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
    ) -> Result<(Outcome, Vec<Product>), BenchError> {
        let (o, p) = fill(start, params, obs)?;
        let mut contacts = Vec::new();
        write_contacts_csv(&o.contacts, &mut contacts).map_err(|e| method_error("seq-fill", e))?;
        let mut faces = Vec::new();
        write_face_lists_csv(&o.faces, &mut faces).map_err(|e| method_error("seq-fill", e))?;
        let products = vec![
            Product::Table {
                suffix: "_contacts.csv",
                csv: contacts,
            },
            Product::Table {
                suffix: "_faces.csv",
                csv: faces,
            },
            Product::RadiusHistogram {
                placed: o.radii_placed,
                discarded: o.radii_discarded,
                target: p.distribution,
            },
        ];
        Ok((o.outcome, products))
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
    let o = run(&p, obs).map_err(|e| method_error("seq-fill", e))?;
    Ok((o, p))
}
