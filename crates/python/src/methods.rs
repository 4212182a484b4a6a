//! `packbench.methods`: the method registry of `packbench methods` as data.

use packbench::methods::registry;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::json::to_py;

/// The registered methods, in the order reports list them: one dict each with `name`,
/// `summary` (one line on what it is), `accuracy_knob` (the parameter that trades speed for
/// accuracy) and `params` (every parameter with its default; these are the keywords `pack`
/// takes).
#[pyfunction]
pub fn methods(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let out = PyList::empty(py);
    for m in registry() {
        let d = PyDict::new(py);
        d.set_item("name", m.name())?;
        d.set_item("summary", m.summary())?;
        d.set_item("accuracy_knob", m.accuracy_knob())?;
        d.set_item("params", to_py(py, &m.default_params())?)?;
        out.append(d)?;
    }
    Ok(out)
}
