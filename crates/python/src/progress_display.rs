//! `progress=True` and `callback=`: progress reports handed to Python — to the display of
//! `packbench._progress` (a tqdm bar when tqdm is installed, else a line on stderr) and to
//! the user's callback — with the method's own progress towards its stopping rule
//! (`packbench::methods::StopProgress`).

use packbench_core::run::Progress;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The method's named quantities of a report (its labelled value, then the others), plus the
/// fraction of its budget used when it can tell (`fraction`) and its progress towards its
/// stopping rule (`progress`, see [`MethodProgress`]).
pub fn progress_values<'py>(
    py: Python<'py>,
    p: &Progress,
    progress: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let values = PyDict::new(py);
    values.set_item(p.label, p.value)?;
    for (name, v) in &p.more {
        values.set_item(*name, *v)?;
    }
    if let Some(f) = p.fraction {
        values.set_item("fraction", f)?;
    }
    if let Some(f) = progress {
        values.set_item("progress", f)?;
    }
    Ok(values)
}

/// A progress display of `packbench._progress`, when asked for.
pub struct Display(Option<Py<PyAny>>);

impl Display {
    /// A display titled `label` counting `total` items (None: a method's own progress), or no
    /// display when `shown` is false.
    pub fn new(py: Python<'_>, shown: bool, label: &str, total: Option<usize>) -> PyResult<Self> {
        if !shown {
            return Ok(Display(None));
        }
        let d = py
            .import("packbench._progress")?
            .getattr("ProgressDisplay")?
            .call1((label, total))?;
        Ok(Display(Some(d.unbind())))
    }

    /// Shows a method's report.
    pub fn report(&self, py: Python<'_>, p: &Progress, values: &Bound<'_, PyDict>) -> PyResult<()> {
        if let Some(d) = &self.0 {
            d.call_method1(py, "report", (p.step, p.phi, values))?;
        }
        Ok(())
    }

    /// Counts one finished item described by `text`.
    pub fn advance(&self, py: Python<'_>, text: String) -> PyResult<()> {
        if let Some(d) = &self.0 {
            d.call_method1(py, "advance", (text,))?;
        }
        Ok(())
    }

    /// Removes the display; `done` fills the bar first (the method met its stopping rule).
    pub fn close(&self, py: Python<'_>, done: bool) -> PyResult<()> {
        if let Some(d) = &self.0 {
            d.call_method1(py, "close", (done,))?;
        }
        Ok(())
    }
}
