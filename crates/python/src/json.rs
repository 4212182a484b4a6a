//! Plain Python data (dicts, lists, numbers, strings, booleans, None) to and from JSON values,
//! through Python's own `json` module so that both sides keep their usual rules.

use pyo3::prelude::*;
use serde_json::Value;

use crate::errors::value_err;

/// The JSON value of a Python object; `what` names it in the error (a `ValueError`) when it
/// is not plain data.
pub fn to_json(py: Python<'_>, obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Value> {
    let text: String = py
        .import("json")?
        .call_method1("dumps", (obj,))
        .map_err(|e| value_err(format!("{what}: {}", e.value(py))))?
        .extract()?;
    serde_json::from_str(&text).map_err(|e| value_err(format!("{what}: {e}")))
}

/// The Python object of a serialisable value (dicts keep their key order).
pub fn to_py<'py, T: serde::Serialize>(py: Python<'py>, value: &T) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
    py.import("json")?.call_method1("loads", (text,))
}
