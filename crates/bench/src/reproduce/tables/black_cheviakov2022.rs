//! Black & Cheviakov, 3DRSP, SoftwareX 18, 101051 (2022), Black & Cheviakov 2022: Examples 1A and 1B of
//! Method 1 — spheres in one unit cube of side 15 r̄ and 30 r̄ with Weibull radii, at sphere
//! contact parameters ε = 0.1 and 0.2 (their Table 1).
//!
//! Run by `seq-fill` with the examples' parameters (its defaults are Example 1A's), ε bounding
//! the overlap of a new sphere as well as the contacts (`contact_overlap`), in one unit
//! cube, whose sphere count is the published one (the paper publishes no measured φ: its
//! BodyGoal 0.55 is the target the fill stops at, an input).

use packbench_core::SizeDistribution;
use packbench_core::scene::Placement;
use packbench_seqfill::Params;
use serde_json::Value;

use super::super::published::{BLACK_CHEVIAKOV2022, rows};
use super::super::{Case, CaseRun, Cell, Field, Recompute, Statistic, Table};
use super::periodic_scene;
use crate::error::BenchError;

/// Examples 1A and 1B.
pub const TABLE: Table = Table {
    name: "3drsp-2022",
    source: "T. J. Black and A. F. Cheviakov, 3DRSP, SoftwareX 18, 101051 (2022), Table 1 \
        (Examples 1A and 1B: spheres in a unit cube)",
    protocol: "seq-fill Method 1 with Example 1's parameters (Weibull radii λ = 15.7, k = 3.55; \
        FaceGoal 0.8, BodyGoal 0.55, ParentParameter 0.5) in one unit cube of side 15 r̄ (1A) or \
        30 r̄ (1B), ε = 0.1 and 0.2 as §2.1 describes it: the acceptable separation or overlap of \
        two spheres in contact (a new sphere may overlap others by up to ε·r̄); each radius tries \
        up to 1024 parent tuples before it is discarded",
    published_n: None,
    default_n: None,
    min_n: 1,
    axis: "example, ε",
    cases,
};

/// Parent tuples a drawn radius tries before it is discarded: §2.1 runs "through the list of
/// possible parents" before discarding a radius; 1024 comes close to that list in Examples 1A
/// and 1B (seq-fill's default 64 discards more large radii: placed mean radius 0.85 r̄ against
/// 0.87–0.96 r̄ here, measured with seq-fill's `table1` example, seeds 1–2).
const EXHAUSTIVE_TUPLES: usize = 1024;

/// A value for a seq-fill override.
fn json<T: serde::Serialize>(v: T) -> Value {
    serde_json::to_value(v).unwrap_or(Value::Null)
}

fn cases(_n: usize) -> Result<Vec<Case>, BenchError> {
    // seq-fill's default brick is Example 1A's cube of side 15 r̄.
    let mean_radius = Params::default().brick_lengths[0] / 15.0;
    rows(BLACK_CHEVIAKOV2022)
        .iter()
        .map(|r| {
            let side = r.num("side_rbar").unwrap_or_default() * mean_radius;
            let eps = r.num("contact_param").unwrap_or_default();
            let set = |k: &str, v: Value| ("seq-fill".to_string(), k.to_string(), v);
            Ok(Case {
                label: format!("{} ε {eps}", r.text("example")),
                run: Some(CaseRun {
                    // seq-fill builds its own cube (from_start = false); the scene only
                    // supplies the start the bench hands every method.
                    scene: periodic_scene(8, 3, SizeDistribution::Mono { d: 1.0 }, Placement::Rsa)?,
                    method: "seq-fill",
                    refine: None,
                    overrides: vec![
                        set("from_start", Value::Bool(false)),
                        set("brick_lengths", json([side; 3])),
                        set("brick_numbers", json([1, 1, 1])),
                        set("contact_param", json(eps)),
                        set("contact_overlap", Value::Bool(true)),
                        set("tuples_per_draw", json(EXHAUSTIVE_TUPLES)),
                    ],
                }),
                cells: vec![Cell::of_row(
                    "N per unit cube",
                    r,
                    "n_unit_cube",
                    None,
                    Recompute::Runs(Statistic::Mean, Field::N),
                )],
            })
        })
        .collect()
}
