//! The fastest exact chain at a packing's N, for `--refine exact`: which methods close a
//! packing made by another method into an exactly jammed one, cheapest first.
//!
//! It follows calippso's LP-count law (docs/BENCHMARKS.md, calippso, "LPs against N, by start"):
//! the whole chain's CPU grows about as N^2.7 from an ADAM packing (its LP count as N^1.0, each
//! LP as N^1.7) and as N^1.8 through MLS, whose packings mostly converge in a few dozen LPs
//! while MLS itself dominates. Refining by calippso directly is the faster chain up to the
//! crossover [`MLS_FIRST_ABOVE`]; above it the packing is first compressed by MLS and then
//! closed by calippso.

use super::{Method, find};
use crate::error::BenchError;

/// Largest N at which the exact chain is calippso directly; above it MLS comes first. The two
/// chains' CPU fits (3D monodisperse, one core, N = 500–10⁴: ADAM chain ≈ N^2.72, MLS chain
/// ≈ N^1.77) cross at N ≈ 1.15·10⁴. Uncertain by a factor of about two: at N = 10⁴ both chains
/// take about an hour and vary 2–3× by start (ADAM chain 33, 62 and 80 min on seeds 1–3; MLS
/// chain 59 min on the one converged start).
pub const MLS_FIRST_ABOVE: usize = 12_000;

/// The methods that close a packing of `n` particles made by `made_by` into an exactly jammed
/// one: calippso, after MLS above [`MLS_FIRST_ABOVE`] unless the packing is already MLS's.
pub fn fastest(made_by: &str, n: usize) -> Result<Vec<&'static dyn Method>, BenchError> {
    let mut legs = Vec::new();
    if n > MLS_FIRST_ABOVE && made_by != "mls" {
        legs.push(find("mls")?);
    }
    legs.push(find("calippso")?);
    Ok(legs)
}

/// Every method an exact chain may run, for checking parameters before the first run.
pub fn every_leg() -> Result<Vec<&'static dyn Method>, BenchError> {
    Ok(vec![find("mls")?, find("calippso")?])
}

/// One sentence for reports: what the exact chain is.
pub fn description() -> String {
    format!(
        "The fastest exact chain at the run's N by calippso's LP-count law: calippso directly up \
         to N = {MLS_FIRST_ABOVE}, MLS then calippso above (docs/BENCHMARKS.md, calippso, \"LPs \
         against N, by start, and the fastest exact chain\")."
    )
}
