//! `progress=True` and `callback=`: progress reports handed to Python — to the display of
//! `packbench._progress` (a tqdm bar when tqdm is installed, else a line on stderr) and to
//! the user's callback — with the method's own progress towards its stopping rule.

use packbench_core::run::Progress;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde_json::{Map, Value};

/// Terminations that mean a method met its own stopping rule (its bar ends at 100 %).
const CONVERGED: [&str; 5] = [
    "converged",
    "jammed",
    "pressure_cap",
    "rate_final",
    "target_reached",
];

/// True when `termination` says the method met its stopping rule.
pub fn converged(termination: &str) -> bool {
    CONVERGED.contains(&termination)
}

/// How far a method is towards its own stopping rule, in [0, 1], from its progress reports:
/// a quantity that falls (or rises) geometrically from its first reported value to the
/// target the parameters set is measured on a log scale.
///
/// - adam, fire: the steps over the run's expected length (the RCPGenerator protocol, whose
///   schedule fixes it), the pressure term's μ from `mu_start` down to `mu_min` (the pressure
///   protocol's rungs), or the φ step Δφ down to `delta_phi_tol` (seed 000's threshold
///   protocol);
/// - mls: the compression rate γ, down to `rate_final`;
/// - ls: the reduced pressure, up to `pressure_cap`;
/// - closest-jammed: non-rattler bonds over N_dof;
/// - calippso: √Γ − 1, down to `tol_gamma`;
/// - otherwise (seq-fill's filled fraction, a run with a target φ): the fraction the method
///   reports, else none.
pub struct MethodProgress {
    method: String,
    params: Map<String, Value>,
    first: Option<f64>,
    best: f64,
}

impl MethodProgress {
    pub fn new(method: &str, params: &Map<String, Value>) -> Self {
        MethodProgress {
            method: method.to_string(),
            params: params.clone(),
            first: None,
            best: 0.0,
        }
    }

    fn param(&self, key: &str) -> Option<f64> {
        self.params.get(key).and_then(Value::as_f64)
    }

    /// log(first/now) / log(first/target), for a quantity going from `first` to `target`.
    fn log_fraction(&mut self, now: f64, target: Option<f64>) -> Option<f64> {
        let target = target?;
        if !(now > 0.0 && target > 0.0) {
            return None;
        }
        let first = *self.first.get_or_insert(now);
        let span = (first / target).ln();
        (span.abs() > 0.0).then(|| (first / now).ln() / span)
    }

    /// The fraction of a report, never below an earlier one (Δφ and γ are not monotonic
    /// within a reversal).
    pub fn fraction(&mut self, p: &Progress) -> Option<f64> {
        let more = |name: &str| p.more.iter().find(|(k, _)| *k == name).map(|(_, v)| *v);
        let f = match self.method.as_str() {
            "adam" | "fire"
                if self.params.get("protocol").and_then(Value::as_str) == Some("rcpgenerator") =>
            {
                p.fraction
            }
            "adam" | "fire" if self.param("target_phi").is_none() => {
                if let Some(mu) = more("mu") {
                    // Pressure protocol: μ lowered rung by rung from mu_start to mu_min.
                    let start = self.param("mu_start").unwrap_or(mu);
                    self.first.get_or_insert(start);
                    let target = self.param("mu_min");
                    self.log_fraction(mu, target)
                } else {
                    let tol = self.param("delta_phi_tol");
                    more("delta_phi").and_then(|d| self.log_fraction(d, tol))
                }
            }
            "mls" => {
                let target = self.param("rate_final");
                more("rate").and_then(|r| self.log_fraction(r, target))
            }
            "ls" => {
                let cap = self.param("pressure_cap");
                self.log_fraction(p.value, cap)
            }
            "closest-jammed" | "closest-jammed-qp" => {
                match (more("non_rattler_bonds"), more("n_dof")) {
                    (Some(b), Some(n)) if n > 0.0 => Some(b / n),
                    _ => None,
                }
            }
            "calippso" => {
                let tol = self.param("tol_gamma");
                self.log_fraction(p.value, tol)
            }
            _ => p.fraction,
        }?;
        self.best = self.best.max(f.clamp(0.0, 1.0));
        Some(self.best)
    }
}

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
