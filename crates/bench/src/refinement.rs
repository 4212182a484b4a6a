//! `--refine`: a run's packing chained into further methods, and `--refine exact`, the exact
//! refinement by the chain that is fastest at the run's N ([`methods::exact_chain`] says which).

use packbench_core::run::Observer;
use serde_json::{Map, Value};

use crate::error::BenchError;
use crate::methods::{self, Method};
use crate::runs::{QuietObserver, RunResult, run_one_observed};

/// One leg of a refinement: a method and its complete parameters.
pub type Leg = (&'static dyn Method, Map<String, Value>);

/// The `--refine` value that asks for the fastest exact chain.
pub const EXACT: &str = "exact";

/// The methods that refine a packing of `n` particles made by `method` when `--refine` is
/// `refine`: that one method, or for [`EXACT`] the fastest exact chain
/// ([`methods::exact_chain::fastest`]). Errors: an unknown method name.
pub fn legs(refine: &str, method: &str, n: usize) -> Result<Vec<&'static dyn Method>, BenchError> {
    if refine == EXACT {
        return methods::exact_chain::fastest(method, n);
    }
    Ok(vec![methods::find(refine)?])
}

/// [`legs`] with each method's parameters from `params`: what [`refine_observed`] runs.
/// Errors: an unknown method name, and those of `params`.
pub fn legs_with_params(
    refine: &str,
    method: &str,
    n: usize,
    params: impl Fn(&dyn Method) -> Result<Map<String, Value>, BenchError>,
) -> Result<Vec<Leg>, BenchError> {
    legs(refine, method, n)?
        .into_iter()
        .map(|m| Ok((m, params(m)?)))
        .collect()
}

/// Every method `--refine refine` may run, for checking parameters before the first run;
/// with `exact_only`, a usage error unless the refinement ends in an exact jamming method
/// (`compare --refine`).
pub fn possible_legs(
    refine: &str,
    exact_only: bool,
) -> Result<Vec<&'static dyn Method>, BenchError> {
    if refine == EXACT {
        return methods::exact_chain::every_leg();
    }
    if exact_only {
        return Ok(vec![methods::find_refiner(refine)?]);
    }
    Ok(vec![methods::find(refine)?])
}

/// The chain as reports name it: `mls → calippso`.
pub fn chain_label(legs: &[&dyn Method]) -> String {
    legs.iter()
        .map(|m| m.name())
        .collect::<Vec<_>>()
        .join(" → ")
}

/// Chains the packing of `result` through `legs` (each method with its parameters, in
/// order) and records in its row the last leg's φ, termination, isostaticity gap and force
/// balance, Δφ = φ_refined − φ, the chain and the legs' summed wall time. A failed leg, or one
/// that leaves no packing for the next, is the row's error.
pub fn refine_observed(
    result: &mut RunResult,
    legs: &[Leg],
    seed: u64,
    observer: &mut dyn Observer,
) {
    let Some(mut packing) = result.packing.clone() else {
        return;
    };
    let record = &mut result.record;
    let methods: Vec<&dyn Method> = legs.iter().map(|(m, _)| *m).collect();
    record.refined_by = Some(chain_label(&methods));
    let mut runtime = 0.0;
    for (k, (method, params)) in legs.iter().enumerate() {
        let leg = run_one_observed(*method, params, &packing, seed, observer);
        runtime += leg.record.runtime_s;
        record.refined_runtime_s = Some(runtime);
        if let Some(e) = &leg.record.error
            && (k + 1 == legs.len() || leg.packing.is_none())
        {
            record.error = Some(format!("refinement failed ({}): {e}", method.name()));
        }
        if k + 1 == legs.len() {
            record.refined_phi = leg.record.phi;
            // `run_one` has already judged the claim (a contradicted one is `not_jammed`).
            record.refined_jammed = method.is_exact().then(|| {
                method
                    .jammed_terminations()
                    .contains(&leg.record.termination.as_str())
            });
            record.refined_termination = Some(leg.record.termination);
            record.refined_iso_gap = leg.record.iso_gap;
            record.refined_force_balance = leg.record.force_balance;
            record.delta_phi = match (leg.record.phi, record.phi) {
                (Some(a), Some(b)) => Some(a - b),
                _ => None,
            };
            return;
        }
        match leg.packing {
            Some(next) => packing = next,
            None => {
                record.refined_termination = Some(leg.record.termination);
                return;
            }
        }
    }
}

/// [`refine_observed`] without an observer of its own (Ctrl-C still stops it).
pub fn refine(result: &mut RunResult, legs: &[Leg], seed: u64) {
    refine_observed(result, legs, seed, &mut QuietObserver);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::methods::exact_chain::MLS_FIRST_ABOVE;

    fn names(legs: &[&dyn Method]) -> Vec<&'static str> {
        legs.iter().map(|m| m.name()).collect()
    }

    #[test]
    fn the_exact_chain_goes_through_mls_only_above_the_crossover() {
        let below = legs(EXACT, "adam", MLS_FIRST_ABOVE).unwrap();
        assert_eq!(names(&below), ["calippso"]);
        let above = legs(EXACT, "adam", MLS_FIRST_ABOVE + 1).unwrap();
        assert_eq!(names(&above), ["mls", "calippso"]);
        assert_eq!(chain_label(&above), "mls → calippso");
        // An MLS packing is already the first leg's product.
        let mls = legs(EXACT, "mls", 10 * MLS_FIRST_ABOVE).unwrap();
        assert_eq!(names(&mls), ["calippso"]);
        // A named refiner is used as it is, at any N.
        let named = legs("closest-jammed", "adam", 10 * MLS_FIRST_ABOVE).unwrap();
        assert_eq!(names(&named), ["closest-jammed"]);
    }

    /// The two-leg chain on 40 bidisperse disks: ADAM's packing compressed by MLS, then closed
    /// by calippso; the row names the chain, sums both legs' time and records calippso's
    /// exactly jammed packing.
    #[test]
    fn a_two_leg_chain_records_its_last_leg_and_both_times() {
        use crate::args::default_compare_scene;
        use crate::methods::ParamSources;
        use crate::runs::run_one;
        use packbench_core::init::initial_packing;

        let start = initial_packing(&default_compare_scene(), 3).unwrap();
        let params = |m: &dyn Method| {
            let sources = ParamSources {
                seed: Some(3),
                ..Default::default()
            };
            sources.resolve(m).unwrap()
        };
        let adam = methods::find("adam").unwrap();
        let mut result = run_one(adam, &params(adam), &start, 3);
        let phi = result.record.phi.unwrap();
        let chain: Vec<_> = ["mls", "calippso"]
            .iter()
            .map(|name| {
                let m = methods::find(name).unwrap();
                (m, params(m))
            })
            .collect();
        refine(&mut result, &chain, 3);
        let r = &result.record;
        assert_eq!(r.error, None);
        assert_eq!(r.refined_by.as_deref(), Some("mls → calippso"));
        assert_eq!(r.refined_termination.as_deref(), Some("converged"));
        assert_eq!(r.refined_iso_gap, Some(0), "{r:?}");
        assert_eq!(r.refined_jammed, Some(true), "{r:?}");
        assert!(r.refined_force_balance.unwrap() < 1e-9, "{r:?}");
        let refined = r.refined_phi.unwrap();
        assert_eq!(r.delta_phi, Some(refined - phi));
        // 40 bidisperse disks jam between φ ≈ 0.80 and 0.86 (CALiPPSO.jl's 2D range).
        assert!((0.80..0.87).contains(&refined), "φ_J {refined}");
        assert!(r.refined_runtime_s.unwrap() > 0.0);
    }

    #[test]
    fn compare_refuses_a_refiner_that_does_not_jam_exactly() {
        assert!(possible_legs("mls", true).is_err());
        assert_eq!(names(&possible_legs("mls", false).unwrap()), ["mls"]);
        assert_eq!(
            names(&possible_legs(EXACT, true).unwrap()),
            ["mls", "calippso"]
        );
        assert!(possible_legs("no-such-method", false).is_err());
    }
}
