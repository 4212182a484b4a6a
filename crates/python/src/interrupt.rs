//! What a stopped call does once its work has returned: raise the exception that stopped it
//! with the partial result attached, or (for `on_interrupt="return"` and Ctrl-C) return it.

use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;

use crate::errors::value_err;

/// The `on_interrupt` keyword: what Ctrl-C (`KeyboardInterrupt`) during a run does after the
/// run has stopped and its best result is available.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OnInterrupt {
    /// Raise `KeyboardInterrupt`, with the result as its attribute (`.result` or `.rows`).
    Raise,
    /// Return the result as if the run had ended (its termination says `interrupted`).
    Return,
}

impl OnInterrupt {
    /// Parses the keyword's value.
    pub fn parse(s: &str) -> PyResult<Self> {
        match s {
            "raise" => Ok(OnInterrupt::Raise),
            "return" => Ok(OnInterrupt::Return),
            other => Err(value_err(format!(
                "on_interrupt must be \"raise\" or \"return\", not {other:?}"
            ))),
        }
    }
}

/// `value` when nothing stopped the call, or when Ctrl-C did and `on_interrupt` is `Return`;
/// otherwise the stopping exception, carrying `value` as its attribute `attr`.
pub fn finish(
    py: Python<'_>,
    value: Py<PyAny>,
    stopped_by: Option<PyErr>,
    on_interrupt: OnInterrupt,
    attr: &str,
) -> PyResult<Py<PyAny>> {
    let Some(err) = stopped_by else {
        return Ok(value);
    };
    if on_interrupt == OnInterrupt::Return && err.is_instance_of::<PyKeyboardInterrupt>(py) {
        return Ok(value);
    }
    // An exception type without a `__dict__` cannot carry it; it is raised all the same.
    let _ = err.value(py).setattr(attr, value);
    Err(err)
}
