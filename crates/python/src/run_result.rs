//! `packbench.Result`: what `pack` returns — the final packing, the core's metrics, the
//! method's trace as NumPy arrays, and why and when it stopped.

use numpy::PyArray1;
use packbench::runs::PackRun;
use packbench_core::run::TraceRow;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple, PyType};

use crate::errors::{bench_err, value_err};
use crate::json::{to_json, to_py};
use crate::packing::PyPacking;
use crate::viewer_html::{RunInfo, packing_html};

/// The result of `packbench.pack`: `packing` (the final Packing), `metrics` (dict, the keys of
/// `packbench analyze`), `trace` (dict of NumPy arrays over the run: `step`, `time_s`, `phi`
/// and the method's own quantities — energy, reduced pressure, rate, Γ …; NaN where a row
/// lacks one), `termination` (why it stopped: `converged`, `jammed`, `max_steps`,
/// `interrupted`, …), `runtime_s` (wall seconds of the method, analysis excluded), `steps`
/// (in the method's own unit), `method`, `seed`, `params` (the complete parameters used),
/// `extra` (method-specific results) and `frames` (the snapshots `pack(..., frames=K)` asked
/// for, else None).
///
/// Results pickle and deep-copy (their state is `to_dict()`: NumPy arrays and plain values),
/// so `concurrent.futures`, joblib and Dask carry them between processes.
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
    #[pyo3(get)]
    frames: Py<PyAny>,
    /// The trace as the core's rows, for the viewer page.
    rows: Vec<TraceRow>,
}

/// The keys of a Result's state, in the order `to_dict` writes them.
const STATE_KEYS: [&str; 11] = [
    "packing",
    "metrics",
    "trace",
    "termination",
    "runtime_s",
    "steps",
    "method",
    "seed",
    "params",
    "extra",
    "frames",
];

impl PyRunResult {
    /// The Python result of a finished run.
    pub fn new(
        py: Python<'_>,
        run: PackRun,
        method: &str,
        seed: u64,
        params: &serde_json::Map<String, serde_json::Value>,
        frames: Option<Bound<'_, PyAny>>,
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
            frames: frames.map_or_else(|| py.None(), Bound::unbind),
            rows: outcome.trace,
        })
    }

    /// The state of `to_dict`.
    fn state<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let out = PyDict::new(py);
        out.set_item("packing", self.packing.get().state(py)?)?;
        out.set_item("metrics", self.metrics.bind(py))?;
        out.set_item("trace", self.trace.bind(py))?;
        out.set_item("termination", &self.termination)?;
        out.set_item("runtime_s", self.runtime_s)?;
        out.set_item("steps", self.steps)?;
        out.set_item("method", &self.method)?;
        out.set_item("seed", self.seed)?;
        out.set_item("params", self.params.bind(py))?;
        out.set_item("extra", self.extra.bind(py))?;
        out.set_item("frames", self.frames.bind(py))?;
        Ok(out)
    }
}

#[pymethods]
impl PyRunResult {
    /// The result as plain data: `packing` (its `to_dict()`), `metrics`, `trace` (dict of
    /// NumPy arrays), `termination`, `runtime_s`, `steps`, `method`, `seed`, `params`, `extra`
    /// and `frames`; `Result.from_dict` takes it back. Pickling uses it.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.state(py)
    }

    /// The result of a `to_dict()` dict. Raises ValueError for a missing key or a bad value.
    #[classmethod]
    fn from_dict(
        _cls: &Bound<'_, PyType>,
        py: Python<'_>,
        state: &Bound<'_, PyAny>,
    ) -> PyResult<Self> {
        let state = state
            .cast::<PyDict>()
            .map_err(|_| value_err("a Result's state is a dict (see Result.to_dict)"))?;
        let item = |key: &str| {
            state.get_item(key)?.ok_or_else(|| {
                value_err(format!(
                    "a Result's state needs `{key}` (see Result.to_dict)"
                ))
            })
        };
        if let Some(k) = state
            .keys()
            .iter()
            .filter_map(|k| k.extract::<String>().ok())
            .find(|k| !STATE_KEYS.contains(&k.as_str()))
        {
            return Err(value_err(format!(
                "unknown key `{k}` in a Result's state; the keys are {}",
                STATE_KEYS.join(", ")
            )));
        }
        let packing = item("packing")?;
        let packing = match packing.cast::<PyPacking>() {
            Ok(p) => p.clone().unbind(),
            Err(_) => Py::new(py, PyPacking::from_state(py, &packing)?)?,
        };
        let numpy = py.import("numpy")?;
        let trace_in = item("trace")?;
        let trace_in = trace_in
            .cast::<PyDict>()
            .map_err(|_| value_err("trace must be a dict of arrays"))?;
        let trace = PyDict::new(py);
        for (k, v) in trace_in.iter() {
            trace.set_item(k, numpy.call_method1("asarray", (v,))?)?;
        }
        let rows = trace_rows(&trace)?;
        let plain = |key: &str| -> PyResult<Py<PyAny>> {
            let v = item(key)?;
            to_json(py, &v, key)?;
            Ok(v.unbind())
        };
        Ok(PyRunResult {
            packing,
            metrics: plain("metrics")?,
            trace: trace.unbind(),
            termination: item("termination")?.extract()?,
            runtime_s: item("runtime_s")?.extract()?,
            steps: item("steps")?.extract()?,
            method: item("method")?.extract()?,
            seed: item("seed")?.extract()?,
            params: plain("params")?,
            extra: plain("extra")?,
            frames: match state.get_item("frames")? {
                Some(f) => f.unbind(),
                None => py.None(),
            },
            rows,
        })
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let py = slf.py();
        let rebuild = slf.get_type().getattr("from_dict")?;
        let state = slf.get().state(py)?;
        PyTuple::new(
            py,
            [rebuild.into_any(), PyTuple::new(py, [state])?.into_any()],
        )
    }

    /// The run as the `packbench view` page, inline in Jupyter: the final packing in 3D with
    /// its contact network, the metrics, and φ and the method's quantity over the run.
    fn _repr_html_(&self, py: Python<'_>) -> PyResult<String> {
        let packing = self.packing.get().inner.clone();
        let parameters = to_json(py, self.params.bind(py), "params")?;
        py.detach(|| {
            packing_html(
                &packing,
                Some(RunInfo {
                    method: &self.method,
                    parameters,
                    termination: &self.termination,
                    steps: self.steps,
                    trace: &self.rows,
                }),
            )
        })
        .map_err(bench_err)
    }

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

/// The core's trace rows of trace columns (`step`, `time_s`, `phi`, then named quantities;
/// NaN marks a quantity a row lacks).
fn trace_rows(trace: &Bound<'_, PyDict>) -> PyResult<Vec<TraceRow>> {
    let column = |key: &str| -> PyResult<Vec<f64>> {
        match trace.get_item(key)? {
            Some(v) => v
                .call_method1("astype", ("float64",))?
                .call_method0("tolist")?
                .extract(),
            None => Ok(Vec::new()),
        }
    };
    let step = column("step")?;
    let time = column("time_s")?;
    let phi = column("phi")?;
    let mut named = Vec::new();
    for (k, _) in trace.iter() {
        let k: String = k.extract()?;
        if !["step", "time_s", "phi"].contains(&k.as_str()) {
            named.push((column(&k)?, k));
        }
    }
    Ok((0..step.len())
        .map(|r| TraceRow {
            step: step[r] as u64,
            time_s: time.get(r).copied().unwrap_or(f64::NAN),
            phi: phi.get(r).copied().unwrap_or(f64::NAN),
            values: named
                .iter()
                .filter_map(|(c, k)| c.get(r).filter(|v| !v.is_nan()).map(|v| (k.clone(), *v)))
                .collect(),
        })
        .collect())
}
