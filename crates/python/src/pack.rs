//! `packbench.pack`: one method on one starting packing, through the bench's `pack_run` (the
//! run `packbench pack` makes), with the GIL released while it runs.

use std::sync::{Arc, Mutex};

use numpy::{PyArray1, PyArrayMethods};
use packbench::methods::{self, ParamSources, StopProgress, met_stopping_rule};
use packbench::outputs::start_packing;
use packbench::runs::{RunFrom, pack_run};
use packbench_core::Packing;
use packbench_core::analysis::AnalysisOptions;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use serde_json::Value;

use crate::arrays::{held_indices, matrix};
use crate::container::ContainerKeywords;
use crate::errors::{bench_err, value_err};
use crate::interrupt::{OnInterrupt, finish};
use crate::json::to_json;
use crate::keywords::{opt_count, text};
use crate::packing::PyPacking;
use crate::progress_display::{Display, progress_values};
use crate::run_result::PyRunResult;
use crate::supervised_run::{Event, FrameBuffer, supervise};

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
            let (start, _) = start_packing(None, &scene, seed).map_err(bench_err)?;
            Ok(start)
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

/// The frames of a run as arrays: `step` (K), `phi` (K), `positions` (K×N×d), `diameters`
/// (K×N) and `box` (K×d) — the snapshots `--save-interval` writes, thinned to K. When N
/// changes over the run (seq-fill adds particles) `positions` and `diameters` are lists of
/// K arrays instead.
fn frames_dict<'py>(py: Python<'py>, frames: &[(u64, Packing)]) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    let k = frames.len();
    let (n, d) = frames.first().map_or((0, 0), |(_, p)| (p.n(), p.dim));
    let step: Vec<u64> = frames.iter().map(|(s, _)| *s).collect();
    let phi: Vec<f64> = frames.iter().map(|(_, p)| p.phi()).collect();
    let lengths: Vec<f64> = frames
        .iter()
        .flat_map(|(_, p)| p.container.lengths.iter().copied())
        .collect();
    out.set_item("step", PyArray1::from_vec(py, step))?;
    out.set_item("phi", PyArray1::from_vec(py, phi))?;
    if frames.iter().all(|(_, p)| p.n() == n) {
        let x: Vec<f64> = frames
            .iter()
            .flat_map(|(_, p)| p.positions.iter().copied())
            .collect();
        let dia: Vec<f64> = frames
            .iter()
            .flat_map(|(_, p)| p.diameters.iter().copied())
            .collect();
        out.set_item(
            "positions",
            PyArray1::from_vec(py, x).reshape(vec![k, n, d])?,
        )?;
        out.set_item(
            "diameters",
            PyArray1::from_vec(py, dia).reshape(vec![k, n])?,
        )?;
    } else {
        let x = PyList::empty(py);
        let dia = PyList::empty(py);
        for (_, p) in frames {
            x.append(matrix(py, p.positions.clone(), p.dim)?)?;
            dia.append(PyArray1::from_vec(py, p.diameters.clone()))?;
        }
        out.set_item("positions", x)?;
        out.set_item("diameters", dia)?;
    }
    out.set_item("box", PyArray1::from_vec(py, lengths).reshape(vec![k, d])?)?;
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
/// (`mu_min=1e-5`, `rate=0.1`, `tol_gamma=1e-12`, `target_phi=0.6` for adam and fire to
/// grow to a φ below jamming, …); a dotted name reaches a nested one (`**{"a.b": 1}`).
///
/// The final packing is analysed with `contact_tol` (the largest relative gap counted as a
/// contact, default 1e-6; for closest-jammed and its QP form, which have a parameter of that
/// name, it sets that too unless given as `params`) and, unless `force_balance=False`, the
/// force-balance residual.
///
/// `frames=K` keeps K snapshots of the run, evenly spread, the final packing last, as
/// `Result.frames` (arrays `step`, `phi`, `positions` K×N×d, `diameters` K×N, `box` K×d) —
/// the snapshots `packbench pack --save-interval` writes (lists of arrays for seq-fill, which
/// adds particles as it goes).
/// `trace_every=1` records every step in the trace (adam and fire; default every 250).
/// `fixed` holds diameters at their starting values (adam and fire): a boolean mask of N
/// values or a list of indices; the pressure then acts on the other spheres only, which grow
/// and jam around the held ones (RCPGenerator's mask of fixed diameters, kept here for the
/// whole run). The parameter `fixed_diameters` is the same list of indices.
///
/// The method runs with the GIL released. `progress=True` shows a bar (tqdm when installed,
/// else a line on stderr) of the method's progress towards its own stopping rule (Δφ towards
/// `delta_phi_tol` for adam, γ towards `rate_final` for mls, …), full when it converges;
/// `callback(step, phi, values)` receives each progress report (`values`: a dict of the
/// method's quantities — energy, pressure, rate …, `progress` towards the stopping rule and
/// `fraction` of the budget when known) and stops the run by returning True. Ctrl-C stops
/// the method, which returns its best packing so far; then `on_interrupt="raise"` (default)
/// raises `KeyboardInterrupt` with that `Result` as its attribute `result`, and
/// `on_interrupt="return"` returns it (its `termination` is `interrupted`).
///
/// Raises ValueError for bad input (unknown method or parameter, a bad start or container, a
/// negative seed), with the sentence `packbench pack` prints in the keywords' names, and
/// RuntimeError for a run that failed.
// Long because it maps each Python keyword argument onto the run's parameters in turn, one short
// block each.
#[pyfunction]
#[pyo3(signature = (method, packing = None, *, seed = None, max_steps = None, r#box = None, walls = None, fix_height = false, shell = None, hemispheres = None, contact_tol = None, force_balance = true, progress = false, callback = None, on_interrupt = "raise", frames = None, trace_every = None, fixed = None, **params))]
#[allow(clippy::too_many_arguments)]
pub fn pack(
    py: Python<'_>,
    method: &Bound<'_, PyAny>,
    packing: Option<&Bound<'_, PyAny>>,
    seed: Option<&Bound<'_, PyAny>>,
    max_steps: Option<&Bound<'_, PyAny>>,
    r#box: Option<Vec<f64>>,
    walls: Option<Vec<i64>>,
    fix_height: bool,
    shell: Option<Vec<f64>>,
    hemispheres: Option<Vec<f64>>,
    contact_tol: Option<f64>,
    force_balance: bool,
    progress: bool,
    callback: Option<Bound<'_, PyAny>>,
    on_interrupt: &str,
    frames: Option<&Bound<'_, PyAny>>,
    trace_every: Option<&Bound<'_, PyAny>>,
    fixed: Option<&Bound<'_, PyAny>>,
    params: Option<&Bound<'_, PyDict>>,
) -> PyResult<Py<PyAny>> {
    let on_interrupt = OnInterrupt::parse(on_interrupt)?;
    let name = text(method, "method", "; see packbench.methods()")?;
    let seed = opt_count(seed, "seed", 0)?.unwrap_or(0);
    let max_steps = opt_count(max_steps, "max_steps", 1)?;
    let frames = opt_count(frames, "frames", 1)?;
    let trace_every = opt_count(trace_every, "trace_every", 1)?;
    if let Some(t) = contact_tol
        && !(t.is_finite() && t >= 0.0)
    {
        return Err(value_err(format!(
            "contact_tol={t}: a contact tolerance is a finite number ≥ 0"
        )));
    }
    let method = methods::find(&name).map_err(bench_err)?;
    let defaults = method.default_params();
    let container = ContainerKeywords::new(r#box, walls, fix_height, shell, hemispheres);
    // The named keywords are the method's options; the others are its `--set`.
    let mut options = Vec::new();
    let given = keyword_overrides(py, params)?;
    if let Some(t) = contact_tol
        && defaults.contains_key("contact_tol")
    {
        options.push(("contact_tol".into(), Value::from(t)));
    }
    if let Some(every) = trace_every {
        if !defaults.contains_key("trace_every") {
            return Err(value_err(format!(
                "trace_every: {} records its trace at its own events; trace_every applies to adam and fire",
                method.name()
            )));
        }
        options.push(("trace_every".into(), Value::from(every)));
    }
    let start = start_from(packing, &container, seed)?;
    let mut save_interval = None;
    if frames.is_some() {
        let Some(key) = method.snapshot_key() else {
            return Err(value_err(format!(
                "frames: {} passes no snapshots of its run",
                method.name()
            )));
        };
        if given.iter().all(|(k, _)| k != key) {
            save_interval = Some(method.frame_interval(start.n()));
        }
    }
    if let Some(mask) = fixed {
        if !defaults.contains_key("fixed_diameters") {
            return Err(value_err(format!(
                "fixed: {} holds no diameters fixed; fixed applies to adam and fire",
                method.name()
            )));
        }
        let held = held_indices(mask, start.n())?;
        options.push(("fixed_diameters".into(), Value::from(held)));
    }
    let params = ParamSources {
        scene: None,
        set: given,
        options,
        max_steps,
        save_interval,
        seed: Some(seed),
    }
    .resolve(method)
    .map_err(bench_err)?;
    let analysis = AnalysisOptions {
        contact_tol: contact_tol.unwrap_or(1e-6),
        force_balance,
    };
    let buffer = frames.map(|k| Arc::new(Mutex::new(FrameBuffer::new(k as usize))));
    let display = Display::new(py, progress, method.name(), None)?;
    let mut measure = StopProgress::new(method, &params);
    let supervised = supervise(
        py,
        buffer.clone(),
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
            let values = progress_values(py, &p, measure.fraction(&p))?;
            display.report(py, &p, &values)?;
            match &callback {
                Some(f) => f.call1((p.step, p.phi, values))?.is_truthy(),
                None => Ok(false),
            }
        },
    );
    let done = matches!(&supervised, Ok(s) if s.value.as_ref().is_ok_and(|r| met_stopping_rule(&r.outcome.termination)));
    display.close(py, done)?;
    let supervised = supervised?;
    let run = match supervised.value {
        Ok(run) => run,
        Err(e) => return Err(supervised.stopped_by.unwrap_or_else(|| bench_err(e))),
    };
    let frames = match buffer {
        Some(b) => {
            let b = Arc::try_unwrap(b)
                .ok()
                .and_then(|m| m.into_inner().ok())
                .ok_or_else(|| value_err("frames: the run still holds its snapshots"))?;
            let kept = b.finish(run.outcome.steps, &run.outcome.packing);
            Some(frames_dict(py, &kept)?.into_any())
        }
        None => None,
    };
    let result = Py::new(
        py,
        PyRunResult::new(py, run, method.name(), seed, &params, frames)?,
    )?;
    finish(
        py,
        result.into_any(),
        supervised.stopped_by,
        on_interrupt,
        "result",
    )
}
