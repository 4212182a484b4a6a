//! [`Packer`]: a method crate's `Params` and `run` function seen as a [`Method`], so that
//! adding a packer to the registry is a table entry, not a new impl.

use packbench_core::Packing;
use packbench_core::run::{Observer, Outcome};
use serde::Serialize;
use serde::de::DeserializeOwned;
use serde_json::{Map, Value};

use super::{Method, cannot_resume, decode, encode};
use crate::error::BenchError;

/// A method crate's resume function: a checkpoint, the parameters, the observer.
pub type ResumeFn<P> = fn(&Value, &P, &mut dyn Observer) -> Result<Outcome, String>;

/// A packer: its names, its parameter defaults and its run function.
pub struct Packer<P> {
    pub name: &'static str,
    pub summary: &'static str,
    pub knob: &'static str,
    pub defaults: fn() -> P,
    /// Runs the method; the error is the method crate's message.
    pub run: fn(&Packing, &P, &mut dyn Observer) -> Result<Outcome, String>,
    /// Continues a run from one of its checkpoints, for methods that write them.
    pub resume: Option<ResumeFn<P>>,
}

impl<P: Serialize + DeserializeOwned> Method for Packer<P> {
    fn name(&self) -> &'static str {
        self.name
    }
    fn summary(&self) -> &'static str {
        self.summary
    }
    fn default_params(&self) -> Map<String, Value> {
        encode(&(self.defaults)())
    }
    fn accuracy_knob(&self) -> &'static str {
        self.knob
    }
    fn run(
        &self,
        start: &Packing,
        params: &Map<String, Value>,
        observer: &mut dyn Observer,
    ) -> Result<Outcome, BenchError> {
        let p: P = decode(self.name, params)?;
        (self.run)(start, &p, observer).map_err(|e| BenchError::Run(format!("{}: {e}", self.name)))
    }
    fn resume(
        &self,
        checkpoint: &Value,
        params: &Map<String, Value>,
        observer: &mut dyn Observer,
    ) -> Result<Outcome, BenchError> {
        let resume = self.resume.ok_or_else(|| cannot_resume(self.name))?;
        let p: P = decode(self.name, params)?;
        resume(checkpoint, &p, observer).map_err(|e| BenchError::Run(format!("{}: {e}", self.name)))
    }
}
