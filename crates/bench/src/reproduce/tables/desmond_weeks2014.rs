//! Desmond & Weeks, Phys. Rev. E 90, 022204 (2014): φ_RCP of 3D spheres against the
//! polydispersity δ and skewness S of their sizes, as the relation the paper publishes
//! (`crates/bench/data/published/desmond_weeks2014.csv` says what exactly is taken from it).
//!
//! Beside each published value: packbench's predictor (`packbench predict`, the same relation
//! on the moments of 10⁵ drawn diameters) and packings by `adam`, whose default protocol
//! `rcpgenerator` is the schedule of Desmond & Weeks' own RCPGenerator 1.0 ().

use packbench_core::SizeDistribution;
use packbench_core::rcp_prediction::predict_rcp;
use packbench_core::scene::Placement;
use rand::SeedableRng;
use rand::rngs::StdRng;

use super::super::published::{Band, DESMOND_WEEKS2014, Row, rows};
use super::super::{Case, CaseRun, Cell, Field, Recompute, Statistic, Table};
use super::periodic_scene;
use crate::error::{BenchError, usage};

/// The φ_RCP table.
pub const TABLE: Table = Table {
    name: "desmond-weeks-2014",
    source: "K. W. Desmond and E. R. Weeks, Phys. Rev. E 90, 022204 (2014), the relation \
        φ_RCP(δ, S) and its monodisperse value",
    protocol: "adam (default protocol rcpgenerator, RCPGenerator's schedule) from random \
        sequential addition at φ = 0.05, 3D periodic box; the predictor is `packbench predict` \
        on 10⁵ diameters drawn with seed 0",
    published_n: None,
    default_n: Some(1000),
    // At N = 50 the largest of the log-normal σ = 0.3 and 1 : 2 diameters reaches half the
    // box (3 of 40 runs, seeds 101–105), where spheres touch through several images: a
    // finite-size packing, not the published bulk one. At 100 none of 40 did.
    min_n: 100,
    axis: "size distribution",
    cases,
};

/// Diameters drawn to measure a distribution's moments, as `packbench predict` does.
const PREDICT_DRAWS: usize = 100_000;

/// The predictor is the published relation on moments of [`PREDICT_DRAWS`] sampled
/// diameters: their sampling error moves δ by about δ/√(2·10⁵) and S by √(6/10⁵) ≈ 0.008, so the
/// relation by less than 10⁻³ (its slopes are below 0.2 in δ and 0.01 in S here).
const PREDICT_TOLERANCE: f64 = 1e-3;

/// The distribution of a row of the published file.
fn distribution(r: &Row) -> Result<SizeDistribution, BenchError> {
    let num = |c: &str| r.num(c).unwrap_or_default();
    Ok(match r.text("dist") {
        "mono" => SizeDistribution::Mono { d: num("a") },
        "lognormal-mean1" => SizeDistribution::LognormalMean1 { sigma: num("a") },
        "bidisperse" => SizeDistribution::Bidisperse {
            d1: num("a"),
            d2: num("b"),
            p: num("c"),
        },
        other => {
            return Err(usage(format!(
                "desmond_weeks2014.csv: distribution `{other}`"
            )));
        }
    })
}

fn cases(n: usize) -> Result<Vec<Case>, BenchError> {
    rows(DESMOND_WEEKS2014)
        .iter()
        .map(|r| {
            let dist = distribution(r)?;
            let draws = dist.sample(PREDICT_DRAWS, &mut StdRng::seed_from_u64(0))?;
            let predicted = predict_rcp(3, &draws).desmond_weeks.unwrap_or(f64::NAN);
            let published = r.num("phi_rcp");
            Ok(Case {
                label: r.text("label").to_string(),
                run: Some(CaseRun {
                    scene: periodic_scene(n, 3, dist, Placement::Rsa)?,
                    method: "adam",
                    refine: None,
                    overrides: Vec::new(),
                }),
                cells: vec![
                    Cell {
                        note: Some("the relation on sampled moments"),
                        band: published.map(|p| Band {
                            lo: p - PREDICT_TOLERANCE,
                            hi: p + PREDICT_TOLERANCE,
                        }),
                        ..Cell::unbanded("φ_RCP predicted", published, Recompute::Value(predicted))
                    },
                    Cell::of_row(
                        "φ_RCP packed (adam)",
                        r,
                        "phi_rcp",
                        Some(n),
                        Recompute::Runs(Statistic::Mean, Field::Phi),
                    ),
                ],
            })
        })
        .collect()
}
