//! `packbench.pack`: one method on one starting packing, through the bench's `pack_run` (the
//! run `packbench pack` makes), with the GIL released while it runs.

use packbench::commands::pack::start_packing;
use packbench::methods::{self, params_with};
use packbench::pack_run::{RunFrom, budget_overrides, pack_run};
use packbench_core::Packing;
use packbench_core::analysis::AnalysisOptions;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use serde_json::Value;

use crate::container::ContainerKeywords;
use crate::errors::{bench_err, value_err};
use crate::interrupt::{OnInterrupt, finish};
use crate::json::to_json;
use crate::packing::PyPacking;
use crate::progress_display::{Display, progress_values};
use crate::run_result::PyRunResult;
use crate::supervised_run::{Event, supervise};

/// The starting packing: a `Packing`, a `(positions, diameters)` pair placed in the container
/// keywords, or (None) the default scene of `packbench pack` without `--file` (3D, N = 1000,
/// monodisperse, periodic unit box, φ = 0.05) drawn with `seed`.
fn start_from(
    packing: Option<&Bound<'_, PyAny>>,
    container: &ContainerKeywords,
    seed: u64,
) -> PyResult<Packing> {
    match packing {
        Some(p) if p.is_instance_of::<PyPacking>() => {
            container.refuse_for_packing()?;
            Ok(p.cast::<PyPacking>()?.get().inner.clone())
        }
        Some(p) => {
            let pair = p
                .cast::<PyTuple>()
                .ok()
                .filter(|t| t.len() == 2)
                .ok_or_else(|| {
                    value_err("packing must be a Packing or a (positions, diameters) pair")
                })?;
            Ok(PyPacking::from_arrays(&pair.get_item(0)?, &pair.get_item(1)?, container)?.inner)
        }
        None => {
            let scene = packbench::args::SceneArgs {
                container: container.args(),
                ..Default::default()
            };
            Ok(start_packing(None, &scene, seed).map_err(bench_err)?.0)
        }
    }
}

/// Method parameters given as keywords, as `(key, value)` overrides (`--set key=value`).
pub fn keyword_overrides(
    py: Python<'_>,
    params: Option<&Bound<'_, PyDict>>,
) -> PyResult<Vec<(String, Value)>> {
    let mut out = Vec::new();
    if let Some(params) = params {
        for (k, v) in params.iter() {
            let key: String = k.extract()?;
            let value = to_json(py, &v, &format!("parameter `{key}`"))?;
            out.push((key, value));
        }
    }
    Ok(out)
}

/// Runs a packing method and returns a `Result`.
///
/// `method` is a name of `packbench.methods()` (adam, fire, ls, mls, closest-jammed,
/// closest-jammed-qp, calippso, seq-fill). `packing` is the start: a `Packing`, a
/// `(positions, diameters)` pair placed in the container given by `box`, `walls`,
/// `fix_height`, `shell` or `hemispheres` (as in `Packing(...)`), or None for the default scene
/// of `packbench pack` (3D, N = 1000, monodisperse, periodic unit box, φ = 0.05, drawn with
/// `seed`). `seed` seeds every random choice (the same seed gives the same bits, as
/// `packbench pack --seed` does); `max_steps` is the step budget in the method's own unit.
/// Every other keyword is a method parameter by the name `packbench methods` lists
/// (`mu_min=1e-5`, `rate=0.1`, `tol_gamma=1e-12`, …); a dotted name reaches a nested
/// one (`**{"a.b": 1}`). The final packing is analysed with `contact_tol` (the largest
/// relative gap counted as a contact) and, unless `force_balance=False`, the force-balance
/// residual.
///
/// The method runs with the GIL released. `progress=True` shows a bar (tqdm when installed,
/// else a line on stderr); `callback(step, phi, values)` receives each progress report
/// (`values`: a dict of the method's quantities — energy, pressure, rate …, and `fraction` of
/// the budget when known) and stops the run by returning True. Ctrl-C stops the method, which
/// returns its best packing so far; then `on_interrupt="raise"` (default) raises
/// `KeyboardInterrupt` with that `Result` as its attribute `result`, and
/// `on_interrupt="return"` returns it (its `termination` is `interrupted`).
///
/// Raises ValueError for bad input (unknown method or parameter, a bad start or container),
/// with the sentence `packbench pack` prints, and RuntimeError for a run that failed.
#[pyfunction]
#[pyo3(signature = (method, packing = None, *, seed = 0, max_steps = None, r#box = None, walls = None, fix_height = false, shell = None, hemispheres = None, contact_tol = 1e-6, force_balance = true, progress = false, callback = None, on_interrupt = "raise", **params))]
#[allow(clippy::too_many_arguments)]
pub fn pack(
    py: Python<'_>,
    method: &str,
    packing: Option<&Bound<'_, PyAny>>,
    seed: u64,
    max_steps: Option<u64>,
    r#box: Option<Vec<f64>>,
    walls: Option<Vec<i64>>,
    fix_height: bool,
    shell: Option<Vec<f64>>,
    hemispheres: Option<Vec<f64>>,
    contact_tol: f64,
    force_balance: bool,
    progress: bool,
    callback: Option<Bound<'_, PyAny>>,
    on_interrupt: &str,
    params: Option<&Bound<'_, PyDict>>,
) -> PyResult<Py<PyAny>> {
    let on_interrupt = OnInterrupt::parse(on_interrupt)?;
    let method = methods::find(method).map_err(bench_err)?;
    let container = ContainerKeywords::new(r#box, walls, fix_height, shell, hemispheres);
    let mut overrides = budget_overrides(method, seed, max_steps).map_err(bench_err)?;
    overrides.extend(keyword_overrides(py, params)?);
    let params = params_with(method, &overrides).map_err(bench_err)?;
    let start = start_from(packing, &container, seed)?;
    let analysis = AnalysisOptions {
        contact_tol,
        force_balance,
    };
    let display = Display::new(py, progress, method.name(), None)?;
    let supervised = supervise(
        py,
        |reports| {
            let mut observer = reports.observer();
            pack_run(
                method,
                RunFrom::Start(&start),
                &params,
                &mut observer,
                false,
                &analysis,
            )
        },
        |py, event| {
            let Event::Progress(p) = event else {
                return Ok(false);
            };
            let values = progress_values(py, &p)?;
            display.report(py, &p, &values)?;
            match &callback {
                Some(f) => f.call1((p.step, p.phi, values))?.is_truthy(),
                None => Ok(false),
            }
        },
    );
    display.close(py)?;
    let supervised = supervised?;
    let run = match supervised.value {
        Ok(run) => run,
        Err(e) => return Err(supervised.stopped_by.unwrap_or_else(|| bench_err(e))),
    };
    let result = Py::new(py, PyRunResult::new(py, run, method.name(), seed, &params)?)?;
    finish(
        py,
        result.into_any(),
        supervised.stopped_by,
        on_interrupt,
        "result",
    )
}
