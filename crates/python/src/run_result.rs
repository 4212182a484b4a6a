//! `packbench.Result`: what `pack` returns — the final packing, the core's metrics, the
//! method's trace as NumPy arrays, and why and when it stopped.

use numpy::PyArray1;
use packbench::pack_run::PackRun;
use packbench_core::run::TraceRow;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::json::to_py;
use crate::packing::PyPacking;

/// The result of `packbench.pack`: `packing` (the final Packing), `metrics` (dict, the keys of
/// `packbench analyze`), `trace` (dict of NumPy arrays over the run: `step`, `time_s`, `phi`
/// and the method's own quantities — energy, reduced pressure, rate, Γ …; NaN where a row
/// lacks one), `termination` (why it stopped: `converged`, `jammed`, `max_steps`,
/// `interrupted`, …), `runtime_s` (wall seconds of the method, analysis excluded), `steps`
/// (in the method's own unit), `method`, `seed`, `params` (the complete parameters used) and
/// `extra` (method-specific results).
#[pyclass(name = "Result", module = "packbench", frozen)]
pub struct PyRunResult {
    #[pyo3(get)]
    packing: Py<PyPacking>,
    #[pyo3(get)]
    metrics: Py<PyAny>,
    #[pyo3(get)]
    trace: Py<PyDict>,
    #[pyo3(get)]
    termination: String,
    #[pyo3(get)]
    runtime_s: f64,
    #[pyo3(get)]
    steps: u64,
    #[pyo3(get)]
    method: String,
    #[pyo3(get)]
    seed: u64,
    #[pyo3(get)]
    params: Py<PyAny>,
    #[pyo3(get)]
    extra: Py<PyAny>,
}

impl PyRunResult {
    /// The Python result of a finished run.
    pub fn new(
        py: Python<'_>,
        run: PackRun,
        method: &str,
        seed: u64,
        params: &serde_json::Map<String, serde_json::Value>,
    ) -> PyResult<Self> {
        let PackRun {
            outcome,
            metrics,
            runtime_s,
            ..
        } = run;
        Ok(PyRunResult {
            trace: trace_arrays(py, &outcome.trace)?.unbind(),
            metrics: to_py(py, &metrics)?.unbind(),
            params: to_py(py, params)?.unbind(),
            extra: to_py(py, &outcome.extra)?.unbind(),
            packing: Py::new(
                py,
                PyPacking {
                    inner: outcome.packing,
                },
            )?,
            termination: outcome.termination,
            runtime_s,
            steps: outcome.steps,
            method: method.to_string(),
            seed,
        })
    }
}

#[pymethods]
impl PyRunResult {
    fn __repr__(&self) -> String {
        let phi = self.packing.get().inner.phi();
        format!(
            "Result(method={:?}, phi={phi:.6}, termination={:?}, steps={}, runtime_s={:.3})",
            self.method, self.termination, self.steps, self.runtime_s
        )
    }
}

/// The trace as columns: `step`, `time_s`, `phi`, then every named quantity in order of first
/// appearance (NaN in the rows that lack it).
fn trace_arrays<'py>(py: Python<'py>, rows: &[TraceRow]) -> PyResult<Bound<'py, PyDict>> {
    let mut names: Vec<&str> = Vec::new();
    for r in rows {
        for (name, _) in &r.values {
            if !names.contains(&name.as_str()) {
                names.push(name);
            }
        }
    }
    let out = PyDict::new(py);
    let step: Vec<u64> = rows.iter().map(|r| r.step).collect();
    out.set_item("step", PyArray1::from_vec(py, step))?;
    let column =
        |f: &dyn Fn(&TraceRow) -> f64| PyArray1::from_vec(py, rows.iter().map(f).collect());
    out.set_item("time_s", column(&|r| r.time_s))?;
    out.set_item("phi", column(&|r| r.phi))?;
    for name in names {
        out.set_item(
            name,
            column(&|r| {
                r.values
                    .iter()
                    .find(|(n, _)| n == name)
                    .map_or(f64::NAN, |(_, v)| *v)
            }),
        )?;
    }
    Ok(out)
}
