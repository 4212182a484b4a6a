//! The native part of the Python package `packbench`: the packbench library with NumPy arrays
//! in and out. What it is: conversions at the boundary, the GIL released around the work, and
//! the library's errors as Python exceptions with the command line's sentences. What it is
//! not: no method, metric or file format lives here — each function calls the bench library
//! (`packbench`) or `packbench-core`, the code the `packbench` binary runs.

mod analyze;
mod arrays;
mod compare;
mod container;
mod design;
mod errors;
mod interrupt;
mod json;
mod keywords;
mod methods;
mod pack;
mod packing;
mod pores;
mod progress_display;
mod run_result;
mod scene;
mod supervised_run;
mod threads;
mod viewer_html;

use pyo3::prelude::*;

/// Jammed and random close packings of spheres in any dimension by the eight methods of
/// `methods()` on one shared core (NumPy in, NumPy out): `initial_packing`, `pack`, `analyze`,
/// `compare`, `design`, `methods`, `set_num_threads`, and the classes `Packing` and `Result`.
#[pymodule]
fn _packbench(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<packing::PyPacking>()?;
    m.add_class::<run_result::PyRunResult>()?;
    m.add_function(wrap_pyfunction!(scene::initial_packing, m)?)?;
    m.add_function(wrap_pyfunction!(pack::pack, m)?)?;
    m.add_function(wrap_pyfunction!(analyze::analyze, m)?)?;
    m.add_function(wrap_pyfunction!(compare::compare, m)?)?;
    m.add_function(wrap_pyfunction!(design::design_search, m)?)?;
    m.add_function(wrap_pyfunction!(methods::methods, m)?)?;
    m.add_function(wrap_pyfunction!(threads::set_num_threads, m)?)?;
    m.add_function(wrap_pyfunction!(threads::get_num_threads, m)?)?;
    pores::register(m)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
