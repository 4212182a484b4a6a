//! `packbench.compare`: several methods on the same starting packings, as the rows of
//! `runs.csv` — the runs `packbench compare` makes, returned instead of written.

use packbench::comparison_runs::{CompareOptions, comparison_params, run_comparison};
use packbench::methods;
use packbench::records::run_list;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString};

use crate::container::ContainerKeywords;
use crate::design::method_overrides;
use crate::errors::bench_err;
use crate::interrupt::{OnInterrupt, finish};
use crate::json::to_py;
use crate::keywords::{opt_count, opt_number, opt_text};
use crate::progress_display::Display;
use crate::scene::{DIST_HINT, distribution_args, scene_args};
use crate::supervised_run::{Event, supervise};

/// Method names from a string or a sequence of strings (None: every method).
fn method_names(methods: Option<&Bound<'_, PyAny>>) -> PyResult<Option<Vec<String>>> {
    match methods {
        None => Ok(None),
        Some(m) if m.is_instance_of::<PyString>() => Ok(Some(vec![m.extract()?])),
        Some(m) => Ok(Some(m.extract()?)),
    }
}

/// Runs several methods on the same starting packings and returns one dict per run with the
/// fields of `runs.csv` (method, seed, d, n, phi, z_nonrattler, rattlers, iso_gap, isostatic,
/// max_overlap, force_balance, runtime_s, steps, termination, knob_value (the value of the
/// method's accuracy knob in the run), refined_phi, delta_phi, refined_termination,
/// refined_iso_gap, refined_force_balance, refined_by, refined_runtime_s, refined_jammed, error), in the order of `packbench compare`
/// (seed-major, then method); `pandas.DataFrame(rows)` is the table.
///
/// `methods` is a name or a list of names (None: every method). The starts are drawn from the
/// scene of the keywords — `n`, `dim`, `phi`, `dist` and its parameters, the container
/// keywords and `placement`, as in `initial_packing` — with seeds `seed`, `seed + 1`, …
/// (`seeds` of them); without them the scene is `packbench compare`'s default (2D
/// bidisperse disks 1 : 1.4, N = 40, periodic). `refine` chains every result into that method
/// (an exact-jamming one: closest-jammed, closest-jammed-qp or calippso) and reports Δφ;
/// `refine="exact"` picks the fastest exact chain at `n` (calippso directly up to N = 12 000,
/// MLS then calippso above) and names it in `refined_by`. `params` gives method parameters,
/// `{"adam": {"mu_min": 1e-5}}`. Runs go `jobs` at a time (None: all cores) with the
/// GIL released. A failed run is a row with its `error`, not an exception. `executor=` (any
/// `concurrent.futures.Executor`: a process pool, dask.distributed's `client.get_executor()`)
/// runs each (seed, method) as its own task there instead, with the same rows in the same
/// order.
///
/// `progress=True` counts finished runs (tqdm when installed, else lines on stderr).
/// `callback(row)` receives each run's row as the run finishes (in the order runs finish,
/// without `knob_value`) and stops the comparison by returning True, as Ctrl-C does. Ctrl-C
/// stops the running methods (each keeps its best packing) and leaves the runs not started
/// as `not_run` rows; then `on_interrupt="raise"` (default) raises `KeyboardInterrupt` with
/// the rows as its attribute `rows`, and `on_interrupt="return"` returns them.
///
/// Raises ValueError for bad input, with the sentence `packbench compare` prints.
#[pyfunction]
#[pyo3(signature = (methods = None, *, n = None, dim = None, seeds = None, seed = None, refine = None, jobs = None, params = None, phi = None, dist = None, r#box = None, walls = None, fix_height = false, shell = None, hemispheres = None, placement = None, progress = false, callback = None, on_interrupt = "raise", **dist_params))]
#[allow(clippy::too_many_arguments)]
pub fn compare(
    py: Python<'_>,
    methods: Option<&Bound<'_, PyAny>>,
    n: Option<&Bound<'_, PyAny>>,
    dim: Option<&Bound<'_, PyAny>>,
    seeds: Option<&Bound<'_, PyAny>>,
    seed: Option<&Bound<'_, PyAny>>,
    refine: Option<&Bound<'_, PyAny>>,
    jobs: Option<&Bound<'_, PyAny>>,
    params: Option<&Bound<'_, PyDict>>,
    phi: Option<&Bound<'_, PyAny>>,
    dist: Option<&Bound<'_, PyAny>>,
    r#box: Option<Vec<f64>>,
    walls: Option<Vec<i64>>,
    fix_height: bool,
    shell: Option<Vec<f64>>,
    hemispheres: Option<Vec<f64>>,
    placement: Option<String>,
    progress: bool,
    callback: Option<Bound<'_, PyAny>>,
    on_interrupt: &str,
    dist_params: Option<&Bound<'_, PyDict>>,
) -> PyResult<Py<PyAny>> {
    let on_interrupt = OnInterrupt::parse(on_interrupt)?;
    let n = opt_count(n, "n", 0)?.map(|v| v as usize);
    let phi = opt_number(phi, "phi")?;
    let dim = opt_count(dim, "dim", 2)?.map(|v| v as usize);
    let seeds = opt_count(seeds, "seeds", 1)?.unwrap_or(3);
    let seed = opt_count(seed, "seed", 0)?.unwrap_or(1);
    let jobs = opt_count(jobs, "jobs", 1)?.map(|v| v as usize);
    let refine = opt_text(refine, "refine", "")?;
    let dist = opt_text(dist, "dist", DIST_HINT)?;
    let container = ContainerKeywords::new(r#box, walls, fix_height, shell, hemispheres);
    let options = CompareOptions {
        scene: scene_args(
            n,
            dim,
            phi,
            placement,
            distribution_args(dist, dist_params)?,
            &container,
        ),
        methods: method_names(methods)?,
        seeds,
        base_seed: seed,
        refine,
        overrides: method_overrides(py, params)?,
    };
    let config = options.config().map_err(bench_err)?;
    let list = run_list(&config);
    let display = Display::new(py, progress, "compare", Some(list.len()))?;
    let supervised = supervise(
        py,
        None,
        |reports| {
            run_comparison(
                &config,
                &list,
                jobs,
                || reports.observer(),
                |r| reports.send(Event::RunDone(Box::new(r.clone()))),
            )
        },
        |py, event| {
            if let Event::RunDone(r) = event {
                let phi = r.phi.map_or("—".into(), |p| format!("{p:.6}"));
                display.advance(py, format!("{} seed {}: φ {phi}", r.method, r.seed))?;
                if let Some(f) = &callback {
                    return f.call1((to_py(py, &*r)?,))?.is_truthy();
                }
            }
            Ok(false)
        },
    );
    display.close(py, false)?;
    let supervised = supervised?;
    let mut results = match supervised.value {
        Ok(r) => r,
        Err(e) => return Err(supervised.stopped_by.unwrap_or_else(|| bench_err(e))),
    };
    results.sort_by_key(|(i, _)| *i);
    let rows = PyList::empty(py);
    for (_, r) in &results {
        let row = to_py(py, &r.record)?;
        // The value of the method's accuracy knob in this run (the sweep's column).
        let method = methods::find(&r.record.method).map_err(bench_err)?;
        let params = comparison_params(&config, method, None).map_err(bench_err)?;
        if let Some(v) = params.get(method.accuracy_knob()) {
            row.set_item("knob_value", to_py(py, v)?)?;
        }
        rows.append(row)?;
    }
    finish(
        py,
        rows.into_any().unbind(),
        supervised.stopped_by,
        on_interrupt,
        "rows",
    )
}
