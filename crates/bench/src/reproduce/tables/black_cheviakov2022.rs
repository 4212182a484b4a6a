//! Black & Cheviakov, 3DRSP, SoftwareX 18, 101051 (2022), Black & Cheviakov 2022: Examples 1A and 1B of
//! Method 1 — spheres in one unit cube of side 15 r̄ and 30 r̄ with Weibull radii, at sphere
//! contact parameters ε = 0.1 and 0.2 (their Table 1).
//!
//! Run by `seq-fill` with the examples' parameters (its defaults are Example 1A's) in one unit
//! cube, whose sphere count is the published one; the fill's φ is set beside Example 1A's
//! BodyGoal, the target the fill stops at (the paper publishes no measured φ).

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
        30 r̄ (1B), ε = 0.1 and 0.2",
    published_n: None,
    default_n: None,
    min_n: 1,
    axis: "example, ε",
    cases,
};

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
                    ],
                }),
                cells: vec![
                    Cell {
                        quantity: "N per unit cube",
                        published: r.num("n_unit_cube"),
                        recompute: Recompute::Runs(Statistic::Mean, Field::N),
                        note: None,
                    },
                    Cell {
                        quantity: "φ of the cube",
                        published: r.num("body_goal"),
                        recompute: Recompute::Runs(Statistic::Mean, Field::Phi),
                        note: Some("published: BodyGoal, the target, not a measurement"),
                    },
                ],
            })
        })
        .collect()
}
