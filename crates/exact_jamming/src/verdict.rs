//! The termination an exact method reports: its own claim of a jammed packing, checked by the
//! core's analysis ([`packbench_core::analysis::not_jammed_because`]) before it is reported.
//!
//! A method's bookkeeping (its bond basis, its LP's duals) can disagree with the packing it
//! returns: a projection that jumped, a network closed to the wrong contacts. The packing is
//! what users take away, so the claim stands only when the packing's own analysis agrees;
//! otherwise the run ends `not_jammed` with the reason in `extra.not_jammed`.

use packbench_core::Packing;
use packbench_core::analysis::{AnalysisOptions, analyze, not_jammed_because};
use serde_json::{Map, Value};

use crate::error::JammingError;

/// The termination of a run whose claim of a jammed packing the core's analysis contradicts.
pub const NOT_JAMMED: &str = "not_jammed";

/// `claimed`, unless `claims_jammed` and the core's analysis of `packing` (contacts at its
/// default tolerance; the force balance is left to the caller's full analysis, since its cone
/// program costs more than the check is worth inside a method) says the packing is not
/// jammed: then [`NOT_JAMMED`], with the reason in `extra["not_jammed"]`.
///
/// # Errors
/// [`JammingError::Solver`] if the packing cannot be analysed.
pub(crate) fn checked_termination(
    claimed: &str,
    claims_jammed: bool,
    packing: &Packing,
    extra: &mut Map<String, Value>,
) -> Result<String, JammingError> {
    if !claims_jammed {
        return Ok(claimed.into());
    }
    let options = AnalysisOptions {
        force_balance: false,
        ..AnalysisOptions::default()
    };
    let metrics = analyze(packing, &options)
        .map_err(|e| JammingError::Solver(format!("analysis of the final packing failed: {e}")))?;
    match not_jammed_because(&metrics) {
        None => Ok(claimed.into()),
        Some(why) => {
            extra.insert(NOT_JAMMED.into(), Value::String(why));
            Ok(NOT_JAMMED.into())
        }
    }
}

/// Where a stalled run's packing goes: `jammed` when the core's analysis, force balance
/// included, finds it jammed (the growth stopped because the packing is rigid: a hyperstatic
/// crystal patch whose extra bond the integrator's own test cannot tell from a dependent one),
/// with the evidence in `extra["jammed_by_analysis"]`; otherwise `stalled`.
///
/// # Errors
/// [`JammingError::Solver`] if the packing cannot be analysed.
pub(crate) fn stalled_termination(
    packing: &Packing,
    extra: &mut Map<String, Value>,
) -> Result<&'static str, JammingError> {
    let metrics = analyze(packing, &AnalysisOptions::default()).map_err(|e| {
        JammingError::Solver(format!("analysis of the stalled packing failed: {e}"))
    })?;
    if not_jammed_because(&metrics).is_some() {
        return Ok("stalled");
    }
    extra.insert(
        "jammed_by_analysis".into(),
        Value::String(format!(
            "the growth stopped and the core's analysis finds the packing jammed: iso_gap {}, largest overlap {:.1e}, force balance {:.1e}",
            metrics.iso_gap,
            metrics.max_overlap,
            metrics.force_balance.unwrap_or(f64::NAN)
        )),
    );
    Ok("jammed")
}

#[cfg(test)]
mod tests {
    use super::*;
    use packbench_core::Container;

    #[test]
    fn a_claim_the_analysis_contradicts_becomes_not_jammed() {
        let container = Container::periodic_box(&[4.0, 4.0]).unwrap();
        let overlapping =
            Packing::new(vec![1.0, 1.0, 1.24, 1.0], vec![1.0, 1.0], container).unwrap();
        let mut extra = Map::new();
        let t = checked_termination("jammed", true, &overlapping, &mut extra).unwrap();
        assert_eq!(t, NOT_JAMMED);
        let why = extra[NOT_JAMMED].as_str().unwrap();
        assert!(why.contains("7.600e-1"), "{why}");
        // A run that claims nothing keeps its termination, unchecked.
        let mut extra = Map::new();
        let t = checked_termination("max_steps", false, &overlapping, &mut extra).unwrap();
        assert_eq!(t, "max_steps");
        assert!(extra.is_empty());
    }
}
