//! The method registry: every packer of the workspace behind one trait, so that `pack`,
//! `compare` and `sweep` never special-case a method. A method is one file here — its names,
//! parameters, flags and run function — and one line in [`registry`].

use packbench_core::run::{MethodError, Observer, Outcome};
use packbench_core::{Packing, SizeDistribution};
use serde_json::{Map, Value};

use crate::args::SceneArgs;
use crate::error::{BenchError, usage};

mod adam;
mod closest_jammed;
pub mod exact_chain;
pub mod flags;
mod mls;
mod packer;
pub mod run_params;
mod seq_fill;
pub mod stop_progress;

pub use flags::{FlagValue, MethodFlag};
pub use run_params::ParamSources;
pub use stop_progress::{StopMeasure, StopProgress, met_stopping_rule};

/// A product of a run beside its packing, returned as data; the command that ran the method
/// writes it (`pack --output NAME` writes `NAME<suffix>`).
#[derive(Clone, Debug)]
pub enum Product {
    /// A CSV table, written as `NAME<suffix>` (seq-fill's `_contacts.csv`, `_faces.csv`).
    Table {
        /// File-name suffix, with its extension.
        suffix: &'static str,
        /// The table's bytes.
        csv: Vec<u8>,
    },
    /// The radii a fill placed and discarded against the distribution it sampled, drawn as
    /// `NAME_radii.png`.
    RadiusHistogram {
        /// Radii of the placed particles.
        placed: Vec<f64>,
        /// Radii drawn but not placed.
        discarded: Vec<f64>,
        /// The distribution the radii were drawn from.
        target: SizeDistribution,
    },
}

/// One packing method as the bench sees it.
pub trait Method: Sync {
    /// The name used on the command line (`adam`, `mls`, …).
    fn name(&self) -> &'static str;
    /// One line on what it is.
    fn summary(&self) -> &'static str;
    /// Its parameters with their defaults, as a JSON object (the method crate's `Params`).
    fn default_params(&self) -> Map<String, Value>;
    /// The parameter that trades speed for accuracy, for `sweep` (e.g. `rate`).
    fn accuracy_knob(&self) -> &'static str;
    /// What a user should know beyond its parameters, shown by `packbench methods` and
    /// `packbench pack --help` (empty when nothing).
    fn notes(&self) -> &'static str {
        ""
    }
    /// The terminations by which the method claims an exactly jammed hard-sphere packing
    /// (`jammed`, CALiPPSO's `converged`); empty for the methods that compress without that
    /// claim. The bench checks each claim with the core's analysis
    /// ([`crate::runs::judged_termination`]).
    fn jammed_terminations(&self) -> &'static [&'static str] {
        &[]
    }
    /// True for the exact jamming methods (those that claim jammed packings).
    fn is_exact(&self) -> bool {
        !self.jammed_terminations().is_empty()
    }
    /// Its options of `packbench pack`, each setting one of its parameters.
    fn flags(&self) -> &'static [MethodFlag] {
        &[]
    }
    /// Checks a complete parameter object without running: a parameter out of range is a
    /// usage error naming it. `compare` and `sweep` check every run's parameters before the
    /// first run starts.
    fn check(&self, _params: &Map<String, Value>) -> Result<(), BenchError> {
        Ok(())
    }
    /// Parameters the method derives from the scene flags of `pack`, given the overrides so
    /// far (seq-fill fills a brick with the `--dist` sizes instead of mirroring a start).
    fn scene_overrides(
        &self,
        _scene: &SceneArgs,
        _given: &[(String, Value)],
    ) -> Result<Vec<(String, Value)>, BenchError> {
        Ok(Vec::new())
    }
    /// Runs the method from `start` with `params` (a complete parameter object). Bad
    /// parameters or a start the method cannot take are [`BenchError::Usage`].
    fn run(
        &self,
        start: &Packing,
        params: &Map<String, Value>,
        observer: &mut dyn Observer,
    ) -> Result<Outcome, BenchError>;
    /// The parameter a step budget (`--max-steps`) sets, in the method's own unit (steps,
    /// collisions, LPs); `None` for a method that takes none.
    fn budget_key(&self) -> Option<&'static str> {
        None
    }
    /// The parameter that seeds the method's random choices (`--seed`); `None` for a method
    /// that draws none.
    fn seed_key(&self) -> Option<&'static str> {
        None
    }
    /// The parameter that sets the snapshot interval in the method's steps (`--save-interval`,
    /// Python's `frames=`); `None` for a method that passes no snapshots to its observer.
    fn snapshot_key(&self) -> Option<&'static str> {
        None
    }
    /// Snapshot interval (in the method's steps) that still gives a short run of `n` particles
    /// a few frames when the user sets none (Python's `frames=`).
    fn frame_interval(&self, _n: usize) -> u64 {
        1
    }
    /// How its progress reports measure the way to its own stopping rule under `params`,
    /// tried in order ([`StopProgress`]); by default the fraction the method reports.
    fn stop_measures(&self, _params: &Map<String, Value>) -> Vec<StopMeasure> {
        vec![StopMeasure::Reported]
    }
    /// What one of its steps is (`collisions`, `LPs`, …): the unit of `--max-steps`, of its
    /// trace's step axis and of its progress reports.
    fn step_unit(&self) -> &'static str {
        "steps"
    }
    /// True when the method writes checkpoints it can resume from ([`Method::resume`]).
    fn can_resume(&self) -> bool {
        false
    }
    /// Continues a run exactly from a checkpoint this method passed to its observer
    /// (`pack --resume`), with `params` (a complete parameter object, normally the
    /// checkpoint's own). Methods that write no checkpoints refuse.
    fn resume(
        &self,
        _checkpoint: &Value,
        _params: &Map<String, Value>,
        _observer: &mut dyn Observer,
    ) -> Result<Outcome, BenchError> {
        Err(cannot_resume(self.name()))
    }
    /// Runs like [`Method::run`] and also returns the method's own products (seq-fill's
    /// contact list, face lists and radius histogram) as data.
    fn run_with_products(
        &self,
        start: &Packing,
        params: &Map<String, Value>,
        observer: &mut dyn Observer,
    ) -> Result<(Outcome, Vec<Product>), BenchError> {
        Ok((self.run(start, params, observer)?, Vec::new()))
    }
}

/// A method crate's error as the bench reports it: bad input is a usage error (exit 2), a
/// failed run a run error (exit 1); either way prefixed with the method's name.
pub fn method_error<E: MethodError>(method: &str, e: E) -> BenchError {
    let msg = format!("{method}: {e}");
    if e.is_input_error() {
        BenchError::Usage(msg)
    } else {
        BenchError::Run(msg)
    }
}

/// `packbench methods`: every method with its summary, accuracy knob, defaults and notes.
pub fn listing() -> String {
    let mut s = String::new();
    for m in registry() {
        s.push_str(&format!("{:<16} {}\n", m.name(), m.summary()));
        let params = serde_json::to_string(&m.default_params()).unwrap_or_default();
        s.push_str(&format!(
            "{:<16} accuracy knob: {}; defaults: {params}\n",
            "",
            m.accuracy_knob()
        ));
        if !m.notes().is_empty() {
            s.push_str(&format!("{:<16} {}\n", "", m.notes()));
        }
    }
    s
}

/// The methods' notes for `packbench pack --help`, one paragraph per method that has one.
pub fn pack_help_notes() -> String {
    registry()
        .iter()
        .filter(|m| !m.notes().is_empty())
        .map(|m| format!("{}: {}", m.name(), m.notes()))
        .collect::<Vec<_>>()
        .join("\n\n")
}

/// Every method that has landed, in the order reports list them.
pub fn registry() -> Vec<&'static dyn Method> {
    vec![
        &adam::ADAM,
        &adam::FIRE,
        &mls::LS,
        &mls::MLS,
        &closest_jammed::CLOSEST_JAMMED,
        &closest_jammed::CLOSEST_JAMMED_QP,
        &closest_jammed::CALIPPSO,
        &seq_fill::SeqFill,
    ]
}

/// The method named `name` when it jams exactly ([`Method::is_exact`]: the closest-jammed
/// integrator, its QP form and CALiPPSO), so it can refine another method's result
/// (`compare --refine`): a usage error otherwise.
pub fn find_refiner(name: &str) -> Result<&'static dyn Method, BenchError> {
    let method = find(name)?;
    if !method.is_exact() {
        let exact: Vec<_> = registry()
            .into_iter()
            .filter(|m| m.is_exact())
            .map(|m| m.name())
            .collect();
        return Err(usage(format!(
            "--refine {name}: a refinement must jam exactly; use {}, or `exact` for the fastest \
             exact chain at the run's N",
            exact.join(", ")
        )));
    }
    Ok(method)
}

/// The method called `name`.
pub fn find(name: &str) -> Result<&'static dyn Method, BenchError> {
    registry()
        .into_iter()
        .find(|m| m.name() == name)
        .ok_or_else(|| {
            let names: Vec<_> = registry().iter().map(|m| m.name()).collect();
            usage(format!(
                "unknown method `{name}`; available: {}",
                names.join(", ")
            ))
        })
}

/// The refusal of a method that writes no checkpoints, naming those that do.
pub fn cannot_resume(method: &str) -> BenchError {
    let can: Vec<_> = registry()
        .into_iter()
        .filter(|m| m.can_resume())
        .map(|m| m.name())
        .collect();
    usage(format!(
        "method {method} writes no checkpoints, so it cannot resume; only {} runs can",
        can.join(" and ")
    ))
}

/// Deserialises a parameter object into a method crate's `Params`, as a usage error on failure.
pub fn decode<P: serde::de::DeserializeOwned>(
    method: &str,
    params: &Map<String, Value>,
) -> Result<P, BenchError> {
    serde_json::from_value(Value::Object(params.clone()))
        .map_err(|e| usage(format!("invalid parameters for {method}: {e}")))
}

/// Serialises a method crate's `Params` into a parameter object.
pub fn encode<P: serde::Serialize>(p: &P) -> Map<String, Value> {
    match serde_json::to_value(p) {
        Ok(Value::Object(m)) => m,
        _ => Map::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `--max-steps`, `--save-interval` and `--seed` land on parameters the method has, for
    /// every method that takes them.
    #[test]
    fn every_budget_snapshot_and_seed_key_is_a_parameter_of_its_method() {
        for m in registry() {
            for key in [m.budget_key(), m.snapshot_key(), m.seed_key()]
                .into_iter()
                .flatten()
            {
                assert!(m.default_params().contains_key(key), "{}: {key}", m.name());
            }
        }
        let seeded: Vec<_> = registry()
            .into_iter()
            .filter(|m| m.seed_key().is_some())
            .map(|m| m.name())
            .collect();
        assert_eq!(seeded, ["ls", "mls", "seq-fill"]);
        assert!(registry().iter().all(|m| m.snapshot_key().is_some()));
        let budgeted: Vec<_> = registry()
            .into_iter()
            .filter(|m| m.budget_key().is_some())
            .map(|m| m.name())
            .collect();
        assert_eq!(
            budgeted,
            [
                "adam",
                "fire",
                "ls",
                "mls",
                "closest-jammed",
                "closest-jammed-qp",
                "calippso"
            ]
        );
    }
}
