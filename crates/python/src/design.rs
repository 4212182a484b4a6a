//! `packbench.design`: the search of `packbench design` — which member of a family of size
//! distributions reaches the highest φ_J, a target φ_J, or a target with the smallest size
//! ratio — returned as its rows and its best distribution instead of written to a folder.
//!
//! The search is the bench library's [`packbench::design::design`] on a [`DesignConfig`] built
//! here from the keywords with the library's own parts (family, objective, screen) and checked
//! by [`DesignConfig::check`], the checks `packbench design` makes before packing.

use numpy::PyArray1;
use packbench::design::family::{Draw, Family, Fractions, Shape};
use packbench::design::history::{DesignRow, RowKind};
use packbench::design::objective::{Constraints, Objective};
use packbench::design::optimizer::Optimizer;
use packbench::design::screen::Screen;
use packbench::design::{BestDistribution, DesignConfig, DesignOutcome, design};
use packbench::error::BenchError;
use packbench_core::run::Observer;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use std::sync::Mutex;

use crate::container::ContainerKeywords;
use crate::errors::{bench_err, value_err};
use crate::interrupt::{OnInterrupt, finish};
use crate::json::{to_json, to_py};
use crate::keywords::{number, opt_count, opt_number, opt_text, text};
use crate::progress_display::Display;
use crate::scene::{distribution_args, scene_args};
use crate::supervised_run::{Event, supervise};

/// Scene of a design when no scene keyword is given: `packbench design`'s (3D, N = 1000,
/// periodic unit box, initial φ = 0.05).
fn default_design_scene() -> packbench_core::Scene {
    packbench::args::default_scene()
}

/// The family `name` with the bounds of `bounds` (`{"ratio": (1.0, 1.4), "p": 0.5}`: a pair
/// searches the interval, a number fixes the parameter).
fn family_with_bounds(
    name: &str,
    shape: &Shape,
    bounds: Option<&Bound<'_, PyDict>>,
) -> PyResult<Family> {
    let mut family = Family::with_defaults(name, shape).map_err(bench_err)?;
    if let Some(bounds) = bounds {
        for (k, v) in bounds.iter() {
            let key = text(
                &k,
                "bounds",
                " (parameter names such as \"sigma\" or \"ratio\")",
            )?;
            let shown = format!("bounds[{key:?}]={}", v.repr()?);
            let (lo, hi) = if let Ok(pair) = v.cast::<PyTuple>().map(|t| t.as_any().clone()) {
                pair_of(&pair, &shown)?
            } else if v.is_instance_of::<PyList>() {
                pair_of(&v, &shown)?
            } else {
                let x = number(&v, &shown)
                    .map_err(|_| value_err(format!("{shown}: give a number or a pair (lo, hi)")))?;
                (x, x)
            };
            family.set_range(&key, lo, hi).map_err(|e| match e {
                // The unknown-parameter sentence stands alone; the others follow the value.
                BenchError::Usage(m) if m.starts_with("the ") && m.contains("no parameter") => {
                    value_err(m)
                }
                BenchError::Usage(m) => value_err(format!("{shown}: {m}")),
                e => bench_err(e),
            })?;
        }
    }
    Ok(family)
}

/// `(lo, hi)` of a two-element tuple or list.
fn pair_of(v: &Bound<'_, PyAny>, shown: &str) -> PyResult<(f64, f64)> {
    let items: Vec<Bound<'_, PyAny>> = v.try_iter()?.collect::<PyResult<_>>()?;
    if items.len() != 2 {
        return Err(value_err(format!(
            "{shown}: give a number or a pair (lo, hi), not {} values",
            items.len()
        )));
    }
    let n = |x: &Bound<'_, PyAny>| {
        number(x, shown).map_err(|_| value_err(format!("{shown}: the bounds must be numbers")))
    };
    Ok((n(&items[0])?, n(&items[1])?))
}

/// `{"adam": {"mu_min": 1e-5}}` as method parameters `(method, key, value)`; ValueError for a
/// value that is not a dict or not plain data.
pub fn method_overrides(
    py: Python<'_>,
    params: Option<&Bound<'_, PyDict>>,
) -> PyResult<Vec<(String, String, serde_json::Value)>> {
    let mut out = Vec::new();
    let Some(params) = params else {
        return Ok(out);
    };
    for (m, kv) in params.iter() {
        let method: String = m.extract()?;
        let kv = kv.cast::<PyDict>().map_err(|_| {
            value_err(format!(
                "params[{method:?}] must be a dict of that method's parameters"
            ))
        })?;
        for (k, v) in kv.iter() {
            let key: String = k.extract()?;
            let value = to_json(py, &v, &format!("parameter `{method}.{key}`"))?;
            out.push((method.clone(), key, value));
        }
    }
    Ok(out)
}

/// One row as a dict with the columns of `evaluations.csv`, in its order: the candidate's
/// (kind, island, generation, candidate, each parameter by name, size_ratio, polydispersity,
/// predicted_dw, predicted_fg, screened), then runs.csv's.
fn row_dict<'py>(
    py: Python<'py>,
    family: &Family,
    row: &DesignRow,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let kind = match row.kind {
        RowKind::Search => "search",
        RowKind::Confirm => "confirm",
    };
    d.set_item("kind", kind)?;
    d.set_item("island", row.island)?;
    d.set_item("generation", row.generation)?;
    d.set_item("candidate", row.candidate)?;
    for (p, v) in family.params.iter().zip(&row.params) {
        d.set_item(&p.name, v)?;
    }
    d.set_item("size_ratio", row.size_ratio)?;
    d.set_item("polydispersity", row.polydispersity)?;
    d.set_item("predicted_dw", row.predicted_dw)?;
    d.set_item("predicted_fg", row.predicted_fg)?;
    d.set_item("screened", &row.screened)?;
    let record = to_py(py, &row.record)?;
    d.update(record.cast::<PyDict>()?.as_mapping())?;
    Ok(d)
}

/// The best distribution as a dict: its parameters by name, the core's distribution, the
/// search's and the confirmation's φ_J, size measures, and its diameters as a NumPy array.
fn best_dict<'py>(py: Python<'py>, best: &BestDistribution) -> PyResult<Bound<'py, PyDict>> {
    let d = to_py(py, best)?.cast_into::<PyDict>()?;
    let params = PyDict::new(py);
    for (name, v) in best.names.iter().zip(&best.values) {
        params.set_item(name, v)?;
    }
    d.set_item("params", params)?;
    d.set_item("diameters", PyArray1::from_vec(py, best.diameters.clone()))?;
    Ok(d)
}

/// The dict `design` returns.
fn outcome_dict<'py>(
    py: Python<'py>,
    family: &Family,
    rows: &[DesignRow],
    outcome: Option<&DesignOutcome>,
) -> PyResult<Bound<'py, PyDict>> {
    let list = PyList::empty(py);
    for r in rows {
        list.append(row_dict(py, family, r)?)?;
    }
    let d = PyDict::new(py);
    d.set_item("rows", list)?;
    match outcome {
        Some(o) => {
            d.set_item(
                "best",
                o.best.as_ref().map(|b| best_dict(py, b)).transpose()?,
            )?;
            d.set_item("generations", o.generations)?;
            d.set_item("packings", o.packings)?;
            d.set_item("stop", &o.stop)?;
        }
        None => {
            d.set_item("best", py.None())?;
            d.set_item("generations", rows.iter().map(|r| r.generation + 1).max())?;
            d.set_item(
                "packings",
                rows.iter()
                    .filter(|r| r.kind == RowKind::Search && r.screened.is_empty())
                    .count(),
            )?;
            d.set_item("stop", "interrupted")?;
        }
    }
    Ok(d)
}

/// Searches a family of size distributions for the one that maximises φ_J, reaches a target
/// φ_J, or has the smallest size ratio (or polydispersity) with φ_J ≥ a target — the search of
/// `packbench design`: CMA-ES over the family's free parameters, each candidate screened by the
/// predicted φ_RCP and scored by packing it, then the best candidate packed again with fresh
/// seeds.
///
/// `family` is `lognormal` (parameter `sigma`), `powerlaw` (`ratio`, `exponent`),
/// `bidisperse` (`ratio`, `p`), `weibull` (`shape`), `gamma` (`shape`), `mixture`
/// (`w<i>`, `c<i>`, `s<i>` for i = 1..`components`, on the support [1, `max_ratio`]) or
/// `discrete` (`components` sizes: d1 = 1 and `d<i>` in [1, `max_ratio`], shares `x<i>` by
/// stick-breaking, as volume or, with `fractions="number"`, number fractions); sizes
/// are in units of the smallest diameter or of the scale. A packing's N diameters are the
/// distribution's N mid-point quantiles, the same for every seed (`draw="quantile"`), or N
/// random draws with the packing's seed (`draw="random"`). `bounds` sets a parameter's search
/// interval, `{"ratio": (1.0, 1.4)}`, or fixes it, `{"p": 0.5}`; the others keep their
/// defaults (`packbench design --help` lists them). `objective` is `max-phi`, `target`,
/// `min-ratio` or `min-polydispersity`, the last three with `target` (a φ_J); `max_ratio`
/// also bounds the other families' packed D_max/D_min. `max_rattlers` (a fraction) ranks every
/// candidate whose packings have more rattlers on average behind every one within it;
/// `refine="calippso"` makes φ_J exact (the jamming point of each packing).
///
/// Candidates are packed by `method` (refined by `refine`, with method parameters `params` as
/// in `compare`) in the scene of the keywords `n`, `dim`, `phi`, the container keywords and
/// `placement` (default: 3D, N = 1000, periodic), `seeds_per_candidate` times with seeds
/// `seed`, `seed + 1`, … (the same for every candidate) with `search_n` particles (default
/// `n`: a smaller `search_n` searches at a cheaper fidelity and confirms at `n`); `budget`
/// packings at most, searched by `optimizer`: IPOP-CMA-ES (`"cmaes"`) with
/// populations of `population` (default 4 + ⌊3 ln(free parameters)⌋, doubled at each
/// restart) seeded with `seed`, or `"bracket"` (bisection with a local line fit on
/// φ_J − target, for one free parameter and an objective with a target); `"auto"` is the
/// bracket where it applies and CMA-ES otherwise; the incumbent is packed again with fresh seeds;
/// `screen` (`auto`, `dw`, `fg`, `none`) skips candidates predicted to be hopeless by
/// `screen_margin` or more; then `confirm` reruns of the best with fresh seeds. Packings run
/// `jobs` at a time (None: all cores) with the GIL released. The same keywords give the same
/// rows (bit for bit but `runtime_s`) and the same rows as `packbench design` with the same
/// flags.
///
/// Returns a dict: `rows`, one dict per evaluation with the columns of `evaluations.csv`
/// (kind, island, generation, candidate, each parameter by name, size_ratio, polydispersity,
/// predicted_dw, predicted_fg, screened, then the fields of `runs.csv`) in key order —
/// `pandas.DataFrame(result["rows"])` is the table —; `best`, the best distribution (`names`,
/// `values` and `params` by name, `distribution`, `search_phi`, `confirm_phi`,
/// `confirm_mean`, `confirm_std`, `size_ratio`, `polydispersity`, and `diameters`, a NumPy
/// array of its N diameters) or None when no candidate made a packing; `generations`,
/// `packings` (the search's, confirmations excluded) and `stop` (why it stopped).
///
/// `progress=True` counts finished packings. Ctrl-C stops the packings under way and the
/// search; `on_interrupt="raise"` (default) raises `KeyboardInterrupt` with the rows so far
/// as the dict of its attribute `result` (no best), `on_interrupt="return"` returns it.
///
/// Raises ValueError for bad input (an unknown family or parameter, reversed bounds, an
/// impossible target, a budget smaller than one generation), before any packing, with the
/// sentence `packbench design` prints in the keywords' names.
#[pyfunction]
#[pyo3(name = "design", signature = (family, *, bounds = None, objective = "max-phi", target = None, max_ratio = None, components = None, fractions = "volume", draw = "quantile", max_rattlers = None, search_n = None, n = None, dim = None, phi = None, r#box = None, walls = None, fix_height = false, shell = None, hemispheres = None, placement = None, method = "adam", refine = None, params = None, seeds_per_candidate = None, seed = None, budget = None, population = None, optimizer = "auto", screen = "auto", screen_margin = None, confirm = None, jobs = None, progress = false, on_interrupt = "raise"))]
// One argument a keyword, and one sentence a keyword in the errors: the body reads them into
// the search's configuration and hands it to `run_design`.
#[allow(clippy::too_many_arguments)]
pub fn design_search(
    py: Python<'_>,
    family: &Bound<'_, PyAny>,
    bounds: Option<&Bound<'_, PyDict>>,
    objective: &str,
    target: Option<&Bound<'_, PyAny>>,
    max_ratio: Option<&Bound<'_, PyAny>>,
    components: Option<&Bound<'_, PyAny>>,
    fractions: &str,
    draw: &str,
    max_rattlers: Option<&Bound<'_, PyAny>>,
    search_n: Option<&Bound<'_, PyAny>>,
    n: Option<&Bound<'_, PyAny>>,
    dim: Option<&Bound<'_, PyAny>>,
    phi: Option<&Bound<'_, PyAny>>,
    r#box: Option<Vec<f64>>,
    walls: Option<Vec<i64>>,
    fix_height: bool,
    shell: Option<Vec<f64>>,
    hemispheres: Option<Vec<f64>>,
    placement: Option<String>,
    method: &str,
    refine: Option<&Bound<'_, PyAny>>,
    params: Option<&Bound<'_, PyDict>>,
    seeds_per_candidate: Option<&Bound<'_, PyAny>>,
    seed: Option<&Bound<'_, PyAny>>,
    budget: Option<&Bound<'_, PyAny>>,
    population: Option<&Bound<'_, PyAny>>,
    optimizer: &str,
    screen: &str,
    screen_margin: Option<&Bound<'_, PyAny>>,
    confirm: Option<&Bound<'_, PyAny>>,
    jobs: Option<&Bound<'_, PyAny>>,
    progress: bool,
    on_interrupt: &str,
) -> PyResult<Py<PyAny>> {
    let on_interrupt = OnInterrupt::parse(on_interrupt)?;
    let family_name = text(family, "family", "")?;
    let max_ratio = opt_number(max_ratio, "max_ratio")?;
    let container = ContainerKeywords::new(r#box, walls, fix_height, shell, hemispheres);
    let scene = scene_args(
        opt_count(n, "n", 1)?.map(|v| v as usize),
        opt_count(dim, "dim", 2)?.map(|v| v as usize),
        opt_number(phi, "phi")?,
        placement,
        distribution_args(None, None)?,
        &container,
    )
    .scene_or(default_design_scene(), None)
    .map_err(bench_err)?;
    let shape = Shape {
        components: opt_count(components, "components", 0)?.unwrap_or(2) as usize,
        max_ratio,
        dim: scene.dim(),
        fractions: Fractions::parse(fractions).map_err(bench_err)?,
        draw: Draw::parse(draw).map_err(bench_err)?,
    };
    let family = family_with_bounds(&family_name, &shape, bounds)?;
    let objective =
        Objective::parse(objective, opt_number(target, "target")?).map_err(bench_err)?;
    let screen = Screen::for_family(screen, &family).map_err(bench_err)?;
    let jobs = opt_count(jobs, "jobs", 1)?.map(|v| v as usize);
    let max_ratio = family.ratio_constraint(max_ratio);
    let optimizer =
        Optimizer::for_search(optimizer, family.free().len(), objective.target().is_some())
            .map_err(bench_err)?;
    let config = DesignConfig {
        family,
        objective,
        constraints: Constraints::new(opt_number(max_rattlers, "max_rattlers")?)
            .map_err(|e| value_err(e.to_string().replace("--max-rattlers ", "max_rattlers=")))?,
        search_n: opt_count(search_n, "search_n", 2)?.map(|v| v as usize),
        max_ratio,
        scene,
        method: method.to_string(),
        refine: opt_text(refine, "refine", "")?,
        overrides: method_overrides(py, params)?,
        seeds_per_candidate: opt_count(seeds_per_candidate, "seeds_per_candidate", 1)?.unwrap_or(2),
        base_seed: opt_count(seed, "seed", 0)?.unwrap_or(1),
        budget: opt_count(budget, "budget", 1)?.unwrap_or(60) as usize,
        population: opt_count(population, "population", 2)?.map(|v| v as usize),
        optimizer,
        screen,
        screen_margin: opt_number(screen_margin, "screen_margin")?.unwrap_or(0.01),
        confirm: opt_count(confirm, "confirm", 0)?.unwrap_or(5),
    };
    config.check(1).map_err(bench_err)?;
    run_design(py, &config, jobs, progress, on_interrupt)
}

/// Runs the search `config` with the GIL released, `jobs` packings at a time, a progress bar
/// when `progress`; the dict of its outcome, or of the rows so far when interrupted.
fn run_design(
    py: Python<'_>,
    config: &DesignConfig,
    jobs: Option<usize>,
    progress: bool,
    on_interrupt: OnInterrupt,
) -> PyResult<Py<PyAny>> {
    let display = Display::new(
        py,
        progress,
        "design",
        Some(config.budget + config.confirm as usize),
    )?;
    // Rows as they finish: what an interrupted search hands back.
    let finished: Mutex<Vec<DesignRow>> = Mutex::new(Vec::new());
    let supervised = supervise(
        py,
        None,
        |reports| {
            let stop = reports.observer().stop_flag();
            design(
                config,
                jobs,
                || Box::new(reports.observer()) as Box<dyn Observer>,
                |row| {
                    if let Ok(mut f) = finished.lock() {
                        f.push(row.clone());
                    }
                    if row.screened.is_empty() {
                        reports.send(Event::RunDone(Box::new(row.record.clone())));
                    }
                    // A stopped packing ends the search rather than letting it start the next
                    // generation.
                    if stop.is_some_and(|s| s.load(std::sync::atomic::Ordering::SeqCst)) {
                        return Err(BenchError::Run("interrupted".into()));
                    }
                    Ok(())
                },
            )
        },
        |py, event| {
            if let Event::RunDone(r) = event {
                let phi = r.phi.map_or("—".into(), |p| format!("{p:.6}"));
                display.advance(py, format!("seed {}: φ {phi}", r.seed))?;
            }
            Ok(false)
        },
    );
    display.close(py, false)?;
    let supervised = supervised?;
    let value = match (supervised.value, &supervised.stopped_by) {
        (Ok(outcome), _) => outcome_dict(py, &config.family, &outcome.rows, Some(&outcome))?,
        (Err(_), Some(_)) => {
            let mut rows = finished.into_inner().unwrap_or_default();
            rows.sort_by_key(|r| r.key());
            outcome_dict(py, &config.family, &rows, None)?
        }
        (Err(e), None) => return Err(bench_err(e)),
    };
    finish(
        py,
        value.into_any().unbind(),
        supervised.stopped_by,
        on_interrupt,
        "result",
    )
}
