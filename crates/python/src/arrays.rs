//! NumPy arrays at the boundary: positions (N×d) and diameters (N) in, checked value by value
//! with the text reader's sentences, and out again as new float64 arrays. Each direction
//! copies the data once (into the packing's `Vec`, or into the returned array).

use numpy::{PyArray1, PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use packbench_core::format::value_problem;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::value_err;

/// `obj` as a C-contiguous float64 array (no copy when it already is one), flattened into a
/// `Vec` with its shape.
fn float_data(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<(Vec<f64>, Vec<usize>)> {
    let py = obj.py();
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", "float64")?;
    let arr = py
        .import("numpy")?
        .call_method("ascontiguousarray", (obj,), Some(&kwargs))
        .map_err(|e| value_err(format!("{what}: {}", e.value(py))))?;
    let arr = arr.cast_into::<PyArrayDyn<f64>>()?;
    let shape = arr.shape().to_vec();
    let data = arr
        .to_vec()
        .map_err(|e| value_err(format!("{what}: {e}")))?;
    Ok((data, shape))
}

/// Positions (N×d) and diameters (N) from array-likes, row-major. Errors (`ValueError`): a
/// shape that is not N×d and N, and every value the text reader refuses, with its sentence
/// after the value's index (`positions[2, 0]: `NaN` is not a finite number`).
pub fn particles_from(
    positions: &Bound<'_, PyAny>,
    diameters: &Bound<'_, PyAny>,
) -> PyResult<(Vec<f64>, Vec<f64>, usize)> {
    let (x, shape) = float_data(positions, "positions")?;
    let [n, d] = shape[..] else {
        return Err(value_err(format!(
            "positions must be an N×d array, one row per particle; got shape {shape:?}"
        )));
    };
    let (dia, dshape) = float_data(diameters, "diameters")?;
    if dshape.len() != 1 || dshape[0] != n {
        return Err(value_err(format!(
            "diameters must be an array of N = {n} values, one per row of positions; got shape {dshape:?}"
        )));
    }
    for (i, &v) in x.iter().enumerate() {
        if let Some(problem) = value_problem(v, false, &v.to_string()) {
            return Err(value_err(format!(
                "positions[{}, {}]: {problem}",
                i / d.max(1),
                i % d.max(1)
            )));
        }
    }
    for (i, &v) in dia.iter().enumerate() {
        if let Some(problem) = value_problem(v, true, &v.to_string()) {
            return Err(value_err(format!("diameters[{i}]: {problem}")));
        }
    }
    Ok((x, dia, d))
}

/// A new float64 array of shape N×d holding `flat` (row-major).
pub fn matrix<'py>(
    py: Python<'py>,
    flat: Vec<f64>,
    d: usize,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let n = flat.len().checked_div(d).unwrap_or(0);
    PyArray1::from_vec(py, flat).reshape(vec![n, d])
}

/// The particles named by `fixed=`: a boolean mask of N values (True: held) or a sequence of
/// indices in 0..N, as sorted, distinct indices. Anything else is a `ValueError` naming the
/// keyword.
pub fn held_indices(obj: &Bound<'_, PyAny>, n: usize) -> PyResult<Vec<usize>> {
    let py = obj.py();
    let np = py.import("numpy")?;
    let arr = np
        .call_method1("asarray", (obj,))
        .map_err(|e| value_err(format!("fixed: {}", e.value(py))))?;
    let shape: Vec<usize> = arr.getattr("shape")?.extract()?;
    let kind: String = arr.getattr("dtype")?.getattr("kind")?.extract()?;
    if shape.len() != 1 {
        return Err(value_err(format!(
            "fixed must be a mask of N = {n} booleans or a list of particle indices; got shape {shape:?}"
        )));
    }
    let indices: Vec<i64> = match kind.as_str() {
        "b" if shape[0] == n => np.call_method1("flatnonzero", (&arr,))?.extract()?,
        "b" => {
            return Err(value_err(format!(
                "fixed: a mask needs one boolean per particle, N = {n}; got {}",
                shape[0]
            )));
        }
        "i" | "u" => arr.call_method0("tolist")?.extract()?,
        _ if shape[0] == 0 => Vec::new(),
        _ => {
            return Err(value_err(format!(
                "fixed must be a mask of N = {n} booleans or a list of particle indices; got values of dtype kind `{kind}`"
            )));
        }
    };
    let mut out = Vec::with_capacity(indices.len());
    for i in indices {
        match usize::try_from(i) {
            Ok(u) if u < n => out.push(u),
            _ => {
                return Err(value_err(format!(
                    "fixed: index {i} names no particle (the packing has N = {n}, indices 0..{})",
                    n.saturating_sub(1)
                )));
            }
        }
    }
    out.sort_unstable();
    out.dedup();
    Ok(out)
}
