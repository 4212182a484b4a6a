//! The JSON sidecar written beside every output packing: scene, method, parameters, the core's
//! metrics, runtime, steps, termination and the method's trace.

use serde::{Deserialize, Serialize};

use crate::analysis::Metrics;
use crate::container::Container;
use crate::run::TraceRow;
use crate::scene::Scene;

/// Everything about how a packing was made and what it is.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Sidecar {
    /// packbench version that wrote it.
    pub packbench_version: String,
    /// Method name (`adam`, `mls`, …) or `init`.
    pub method: String,
    /// The scene, when the packing was made from one.
    pub scene: Option<Scene>,
    /// The container of the written packing (so `analyze` needs no `--box`).
    pub container: Container,
    /// The seed actually used.
    pub seed: Option<u64>,
    /// The method's parameters.
    pub parameters: serde_json::Value,
    /// The core's analysis of the output.
    pub metrics: Option<Metrics>,
    /// Wall time of the method in seconds.
    pub runtime_s: f64,
    /// Steps, iterations or collisions.
    pub steps: u64,
    /// Why the method stopped.
    pub termination: String,
    /// Method-specific results.
    pub extra: serde_json::Map<String, serde_json::Value>,
    /// The method's trace.
    pub trace: Vec<TraceRow>,
}
