//! [`Packer`]: a method crate's `Params` and `run` function seen as a [`Method`], so that
//! adding a packer to the registry is a table entry, not a new impl.

use packbench_core::Packing;
use packbench_core::run::{Observer, Outcome};
use serde::Serialize;
use serde::de::DeserializeOwned;
use serde_json::{Map, Value};

use super::{Method, MethodFlag, StopMeasure, cannot_resume, decode, encode};
use crate::error::{BenchError, usage};

/// A method crate's run function: the start, the parameters, the observer; its error is
/// reported through [`super::method_error`].
pub type RunFn<P> = fn(&Packing, &P, &mut dyn Observer) -> Result<Outcome, BenchError>;

/// A method crate's resume function: a checkpoint, the parameters, the observer.
pub type ResumeFn<P> = fn(&Value, &P, &mut dyn Observer) -> Result<Outcome, BenchError>;

/// A packer: its names, its parameter defaults, its flags and its run function.
pub struct Packer<P> {
    /// Name on the command line.
    pub name: &'static str,
    /// One line on what it is.
    pub summary: &'static str,
    /// The parameter `sweep` varies.
    pub knob: &'static str,
    /// The terminations by which it claims an exactly jammed packing (none for the
    /// compression methods); see [`Method::jammed_terminations`].
    pub jammed_terminations: &'static [&'static str],
    /// The method crate's default parameters.
    pub defaults: fn() -> P,
    /// Its options of `packbench pack`.
    pub flags: &'static [MethodFlag],
    /// Checks a parameter object before any run (the method crate's `Params::validate`).
    pub validate: fn(&P) -> Result<(), BenchError>,
    /// Runs the method.
    pub run: RunFn<P>,
    /// Continues a run from one of its checkpoints, for methods that write them.
    pub resume: Option<ResumeFn<P>>,
    /// See [`Method::budget_key`].
    pub budget_key: Option<&'static str>,
    /// See [`Method::seed_key`].
    pub seed_key: Option<&'static str>,
    /// See [`Method::snapshot_key`].
    pub snapshot_key: Option<&'static str>,
    /// See [`Method::frame_interval`].
    pub frame_interval: fn(usize) -> u64,
    /// See [`Method::stop_measures`].
    pub stop_measures: fn(&Map<String, Value>) -> Vec<StopMeasure>,
    /// See [`Method::step_unit`].
    pub step_unit: &'static str,
    /// See [`Method::notes`].
    pub notes: &'static str,
}

impl<P: Serialize + DeserializeOwned> Method for Packer<P> {
    fn name(&self) -> &'static str {
        self.name
    }
    fn summary(&self) -> &'static str {
        self.summary
    }
    fn notes(&self) -> &'static str {
        self.notes
    }
    fn default_params(&self) -> Map<String, Value> {
        encode(&(self.defaults)())
    }
    fn accuracy_knob(&self) -> &'static str {
        self.knob
    }
    fn jammed_terminations(&self) -> &'static [&'static str] {
        self.jammed_terminations
    }
    fn flags(&self) -> &'static [MethodFlag] {
        self.flags
    }
    fn check(&self, params: &Map<String, Value>) -> Result<(), BenchError> {
        (self.validate)(&decode(self.name, params)?)
    }
    fn run(
        &self,
        start: &Packing,
        params: &Map<String, Value>,
        observer: &mut dyn Observer,
    ) -> Result<Outcome, BenchError> {
        let p: P = decode(self.name, params)?;
        check_distinct_centres(self.name, start)?;
        (self.run)(start, &p, observer)
    }
    fn budget_key(&self) -> Option<&'static str> {
        self.budget_key
    }
    fn seed_key(&self) -> Option<&'static str> {
        self.seed_key
    }
    fn snapshot_key(&self) -> Option<&'static str> {
        self.snapshot_key
    }
    fn frame_interval(&self, n: usize) -> u64 {
        (self.frame_interval)(n)
    }
    fn stop_measures(&self, params: &Map<String, Value>) -> Vec<StopMeasure> {
        (self.stop_measures)(params)
    }
    fn step_unit(&self) -> &'static str {
        self.step_unit
    }
    fn can_resume(&self) -> bool {
        self.resume.is_some()
    }
    fn resume(
        &self,
        checkpoint: &Value,
        params: &Map<String, Value>,
        observer: &mut dyn Observer,
    ) -> Result<Outcome, BenchError> {
        let resume = self.resume.ok_or_else(|| cannot_resume(self.name))?;
        let p: P = decode(self.name, params)?;
        resume(checkpoint, &p, observer)
    }
}

/// Refuses a start with two particles at one centre (every particle at one point, a duplicated
/// line): no method can tell which way to separate them.
fn check_distinct_centres(method: &str, start: &Packing) -> Result<(), BenchError> {
    match start.coincident_centres() {
        Some((i, j)) => Err(usage(format!(
            "{method}: particles {} and {} of the starting packing are at the same centre; the start is degenerate (give distinct positions)",
            i + 1,
            j + 1
        ))),
        None => Ok(()),
    }
}
