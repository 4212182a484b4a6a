//! `packbench.analyze`: the core's metrics of a packing, the JSON object of
//! `packbench analyze` as a dict.

use packbench_core::analysis::{AnalysisOptions, analyze as core_analyze};
use pyo3::prelude::*;

use crate::container::ContainerKeywords;
use crate::errors::core_err;
use crate::json::to_py;
use crate::packing::packing_of;

/// The metrics of a packing as a dict with the keys of `packbench analyze`: dim, n, phi,
/// contacts, z_mean, rattlers, z_nonrattler, n_dof, iso_gap, isostatic, max_overlap,
/// force_balance, polydispersity, skewness.
///
/// Give a `Packing`, or `positions` (N×d) and `diameters` (N) with the container keywords of
/// `Packing(...)`. `contact_tol` is the largest relative gap r/σ − 1 counted as a contact;
/// `force_balance=False` skips the force-balance solve (about 3 s at N = 10⁴ and 25 s at
/// N = 10⁵ in 3D). The analysis runs with the GIL released. Raises ValueError for bad input.
#[pyfunction]
#[pyo3(signature = (positions, diameters = None, *, r#box = None, walls = None, fix_height = false, shell = None, hemispheres = None, contact_tol = 1e-6, force_balance = true))]
#[allow(clippy::too_many_arguments)]
pub fn analyze<'py>(
    py: Python<'py>,
    positions: &Bound<'py, PyAny>,
    diameters: Option<&Bound<'py, PyAny>>,
    r#box: Option<Vec<f64>>,
    walls: Option<Vec<i64>>,
    fix_height: bool,
    shell: Option<Vec<f64>>,
    hemispheres: Option<Vec<f64>>,
    contact_tol: f64,
    force_balance: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let container = ContainerKeywords::new(r#box, walls, fix_height, shell, hemispheres);
    let packing = packing_of(positions, diameters, &container, "analyze")?;
    let options = AnalysisOptions {
        contact_tol,
        force_balance,
    };
    let metrics = py
        .detach(|| core_analyze(&packing, &options))
        .map_err(core_err)?;
    to_py(py, &metrics)
}
