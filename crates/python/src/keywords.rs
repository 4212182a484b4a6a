//! Keyword values checked at the boundary, so every bad value is a `ValueError` that names the
//! keyword the user typed (`n=-3: …`).

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyString};

use crate::errors::value_err;

/// An integer keyword of at least `min` (`n`, `seed`, `seeds`, `max_steps`, `jobs`, …).
/// ValueError for a bool, a non-integer or a value below `min`.
pub fn count(value: &Bound<'_, PyAny>, name: &str, min: u64) -> PyResult<u64> {
    let type_name = value.get_type().name()?.to_string();
    // Whole numbers are what `operator.index` takes (int, NumPy integers); a bool is not one.
    let whole = if value.is_instance_of::<PyBool>() {
        None
    } else {
        value
            .call_method0("__index__")
            .ok()
            .and_then(|i| i.extract::<i128>().ok())
    };
    let Some(v) = whole else {
        return Err(value_err(format!(
            "{name}={}: {name} must be a whole number, not {type_name}",
            value.repr()?
        )));
    };
    if v < i128::from(min) || v > i128::from(u64::MAX) {
        return Err(value_err(format!(
            "{name}={v}: {name} must be a whole number of at least {min}"
        )));
    }
    Ok(v as u64)
}

/// A real-number keyword (`phi`, …): ValueError naming it for anything `float()` refuses.
pub fn number(value: &Bound<'_, PyAny>, name: &str) -> PyResult<f64> {
    if value.is_instance_of::<PyString>() || value.is_instance_of::<PyBool>() {
        return Err(value_err(format!(
            "{name}={}: {name} must be a number",
            value.repr()?
        )));
    }
    value.extract::<f64>().map_err(|_| {
        value_err(format!(
            "{name}={}: {name} must be a number",
            value.repr().map(|r| r.to_string()).unwrap_or_default()
        ))
    })
}

/// [`number`] of an optional keyword.
pub fn opt_number(value: Option<&Bound<'_, PyAny>>, name: &str) -> PyResult<Option<f64>> {
    value.map(|v| number(v, name)).transpose()
}

/// [`count`] of an optional keyword.
pub fn opt_count(value: Option<&Bound<'_, PyAny>>, name: &str, min: u64) -> PyResult<Option<u64>> {
    value.map(|v| count(v, name, min)).transpose()
}

/// A string keyword (`dist`, `placement`, …): ValueError naming it for anything else, with
/// `hint` after the sentence.
pub fn text(value: &Bound<'_, PyAny>, name: &str, hint: &str) -> PyResult<String> {
    if value.is_instance_of::<PyString>() {
        return value.extract();
    }
    Err(value_err(format!(
        "{name} must be a name (a string), not {}{hint}",
        value.get_type().name()?
    )))
}

/// [`text`] of an optional keyword.
pub fn opt_text(
    value: Option<&Bound<'_, PyAny>>,
    name: &str,
    hint: &str,
) -> PyResult<Option<String>> {
    value.map(|v| text(v, name, hint)).transpose()
}
