//! `packbench.Packing`: positions, diameters and container of the core's packing, with the
//! RCPGenerator text format and the exports of `packbench export`.

use numpy::{PyArray1, PyArrayDyn};
use packbench::outputs::read_input;
use packbench_core::format::{ExportFormat, export, write_atomic, write_text};
use packbench_core::{Container, Packing, Shape};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple, PyType};

use crate::arrays::{matrix, particles_from};
use crate::container::{ContainerKeywords, rcp_walls};
use crate::errors::{bench_err, core_err, value_err};
use crate::json::{to_json, to_py};
use crate::viewer_html::packing_html;

/// Particles in a container: `positions` (N×d, float64), `diameters` (N), and the container
/// given by `box` (side lengths, default 1 on every axis) and `walls` (per axis 0 periodic,
/// 1 hard wall; a negative first entry −t makes a (hyper)sphere of diameter box[0] over the
/// first t axes), as `--box` and `--walls` of the command line; `shell=(inner, outer)` and
/// `hemispheres=(r1, r2)` give the other curved containers, `fix_height=True` holds the last
/// box length at that multiple of the largest diameter.
///
/// Raises ValueError for a shape that is not N×d and N, a NaN or infinite value, a diameter
/// that is not positive, a container that does not fit the dimension, or a particle outside it
/// — on a periodic axis too: a centre must lie in [0, L] (wrap unwrapped coordinates first,
/// `positions % box`).
///
/// Packings pickle and deep-copy (their state is `to_dict()`: NumPy arrays and plain
/// values), so `concurrent.futures`, joblib and Dask carry them between processes.
#[pyclass(name = "Packing", module = "packbench", frozen)]
#[derive(Clone)]
pub struct PyPacking {
    pub inner: Packing,
}

impl PyPacking {
    /// A packing from arrays and container keywords (see the class docs).
    pub fn from_arrays(
        positions: &Bound<'_, PyAny>,
        diameters: &Bound<'_, PyAny>,
        container: &ContainerKeywords,
    ) -> PyResult<Self> {
        let (x, dia, d) = particles_from(positions, diameters)?;
        let container = container.args().container(d).map_err(bench_err)?;
        check_periodic_range(&x, &container)?;
        let inner = Packing::new(x, dia, container).map_err(core_err)?;
        Ok(PyPacking { inner })
    }

    /// The state of `to_dict` (positions, diameters, container) as a packing, validated by
    /// the core; positions are kept as given.
    pub fn from_state(py: Python<'_>, state: &Bound<'_, PyAny>) -> PyResult<Self> {
        let state = state.cast::<PyDict>().map_err(|_| {
            value_err("a Packing's state is a dict with positions, diameters and container")
        })?;
        let item = |key: &str| {
            state.get_item(key)?.ok_or_else(|| {
                value_err(format!(
                    "a Packing's state needs `{key}` (see Packing.to_dict)"
                ))
            })
        };
        let (x, dia, d) = particles_from(&item("positions")?, &item("diameters")?)?;
        let container: Container =
            serde_json::from_value(to_json(py, &item("container")?, "container")?)
                .map_err(|e| value_err(format!("container: {e}")))?;
        if container.dim() != d {
            return Err(value_err(format!(
                "container is {}-dimensional but positions have {d} columns",
                container.dim()
            )));
        }
        let inner = Packing::new(x, dia, container).map_err(core_err)?;
        Ok(PyPacking { inner })
    }

    /// The state of `to_dict`.
    pub fn state<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let out = PyDict::new(py);
        out.set_item(
            "positions",
            matrix(py, self.inner.positions.clone(), self.inner.dim)?,
        )?;
        out.set_item(
            "diameters",
            PyArray1::from_vec(py, self.inner.diameters.clone()),
        )?;
        out.set_item("container", to_py(py, &self.inner.container)?)?;
        Ok(out)
    }

    fn export_to(&self, path: &str, format: ExportFormat) -> PyResult<()> {
        let text = export(&self.inner, format).map_err(core_err)?;
        write_atomic(std::path::Path::new(path), text.as_bytes()).map_err(core_err)
    }
}

#[pymethods]
impl PyPacking {
    #[new]
    #[pyo3(signature = (positions, diameters, *, r#box = None, walls = None, fix_height = false, shell = None, hemispheres = None))]
    fn new(
        positions: &Bound<'_, PyAny>,
        diameters: &Bound<'_, PyAny>,
        r#box: Option<Vec<f64>>,
        walls: Option<Vec<i64>>,
        fix_height: bool,
        shell: Option<Vec<f64>>,
        hemispheres: Option<Vec<f64>>,
    ) -> PyResult<Self> {
        let keywords = ContainerKeywords::new(r#box, walls, fix_height, shell, hemispheres);
        Self::from_arrays(positions, diameters, &keywords)
    }

    /// Reads a packing in the RCPGenerator plain text format (`x1 … xd D` per line,
    /// whitespace or commas, `#` comments), as `packbench analyze FILE` does: the container
    /// comes from the keywords when any is given, else from the JSON sidecar beside the file
    /// (`NAME.json`, written by `packbench pack --output NAME`), else a periodic unit box.
    /// Raises ValueError naming the file, line and column of a bad value.
    #[staticmethod]
    #[pyo3(signature = (path, *, r#box = None, walls = None, fix_height = false, shell = None, hemispheres = None))]
    fn read(
        path: &str,
        r#box: Option<Vec<f64>>,
        walls: Option<Vec<i64>>,
        fix_height: bool,
        shell: Option<Vec<f64>>,
        hemispheres: Option<Vec<f64>>,
    ) -> PyResult<Self> {
        let keywords = ContainerKeywords::new(r#box, walls, fix_height, shell, hemispheres);
        let inner = read_input(path, &keywords.args()).map_err(bench_err)?;
        Ok(PyPacking { inner })
    }

    /// Writes the packing in the RCPGenerator plain text format with round-trip precision
    /// (reading it back gives the same bits). The container is not part of the format: give
    /// it again to `Packing.read`. Written to a temporary file and renamed.
    fn write(&self, path: &str) -> PyResult<()> {
        write_atomic(
            std::path::Path::new(path),
            write_text(&self.inner).as_bytes(),
        )
        .map_err(core_err)
    }

    /// Writes extended XYZ (OVITO): the box as `Lattice`, `pbc` flags (F on walled axes), a
    /// radius column; a 2D packing has two position columns, which OVITO reads as 2D (d ≤ 3).
    fn to_xyz(&self, path: &str) -> PyResult<()> {
        self.export_to(path, ExportFormat::Xyz)
    }

    /// Writes a LAMMPS data file, atom_style sphere, whose comments give the `dimension` and
    /// `boundary` input lines that read it (d ≤ 3).
    fn to_lammps(&self, path: &str) -> PyResult<()> {
        self.export_to(path, ExportFormat::Lammps)
    }

    /// Writes a LAMMPS dump: `BOX BOUNDS` with pp/ff flags, `id type x y z radius` (no z column
    /// in 2D), which OVITO reads with its walls and dimension (d ≤ 3).
    fn to_lammps_dump(&self, path: &str) -> PyResult<()> {
        self.export_to(path, ExportFormat::LammpsDump)
    }

    /// Writes VTK XML PolyData of the particles (ParaView, OVITO): `Radius` and `Diameter`
    /// point arrays, the box lengths, periodic flags and dimension as FieldData (d ≤ 3).
    fn to_vtp(&self, path: &str) -> PyResult<()> {
        self.export_to(path, ExportFormat::Vtp)
    }

    /// Writes the box's edges as VTK XML PolyData lines, to show beside `to_vtp`'s file (d ≤ 3).
    fn to_vtp_box(&self, path: &str) -> PyResult<()> {
        self.export_to(path, ExportFormat::VtpBox)
    }

    /// Writes legacy VTK, an unstructured grid of vertices with the arrays and fields of
    /// `to_vtp`, for older VTK readers and meshio; OVITO cannot read it (d ≤ 3).
    fn to_vtk(&self, path: &str) -> PyResult<()> {
        self.export_to(path, ExportFormat::Vtk)
    }

    /// Particle centres, an N×d float64 array (a new array on each access).
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        matrix(py, self.inner.positions.clone(), self.inner.dim)
    }

    /// Diameters, a float64 array of N values (a new array on each access).
    #[getter]
    fn diameters<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_vec(py, self.inner.diameters.clone())
    }

    /// Side lengths of the container's box, one per axis.
    #[getter]
    #[pyo3(name = "box")]
    fn box_lengths(&self) -> Vec<f64> {
        self.inner.container.lengths.clone()
    }

    /// The `walls` list of the container (0 periodic, 1 hard wall per axis; −t first for a
    /// ball over t axes); None for a shell or a hemisphere-cut brick (see `container`).
    #[getter]
    fn walls(&self) -> Option<Vec<i64>> {
        rcp_walls(&self.inner.container)
    }

    /// The full container as a dict (lengths, periodic flags, curved shape, fix_height), as
    /// in the JSON sidecar of `packbench pack`.
    #[getter]
    fn container<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.inner.container)
    }

    /// Packing fraction: particle volume over the exact container volume.
    #[getter]
    fn phi(&self) -> f64 {
        self.inner.phi()
    }

    /// Dimension d.
    #[getter]
    fn dim(&self) -> usize {
        self.inner.dim
    }

    /// Number of particles N.
    #[getter]
    fn n(&self) -> usize {
        self.inner.n()
    }

    fn __len__(&self) -> usize {
        self.inner.n()
    }

    /// True when positions, diameters and container are all equal (bit for bit).
    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<PyPacking>()
            .is_ok_and(|o| o.get().inner == self.inner)
    }

    /// The packing as plain data: `positions` (N×d float64 array), `diameters` (N) and
    /// `container` (a dict as in the JSON sidecar); `Packing.from_dict` takes it back, bit
    /// for bit. Pickling uses it.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.state(py)
    }

    /// The packing of a `to_dict()` dict. Raises ValueError for a missing key or a value the
    /// constructor refuses.
    #[classmethod]
    fn from_dict(
        _cls: &Bound<'_, PyType>,
        py: Python<'_>,
        state: &Bound<'_, PyAny>,
    ) -> PyResult<Self> {
        Self::from_state(py, state)
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let py = slf.py();
        let rebuild = slf.get_type().getattr("from_dict")?;
        let state = slf.get().state(py)?;
        PyTuple::new(
            py,
            [rebuild.into_any(), PyTuple::new(py, [state])?.into_any()],
        )
    }

    fn __copy__(slf: Bound<'_, Self>) -> Bound<'_, Self> {
        slf
    }

    fn __deepcopy__<'py>(slf: Bound<'py, Self>, _memo: &Bound<'py, PyAny>) -> Bound<'py, Self> {
        // Immutable (frozen): a copy is the packing itself.
        slf
    }

    /// The same particles with every diameter scaled so that the packing fraction is `phi`
    /// (positions and container kept; a fix-height container follows the largest diameter).
    /// Raises ValueError for φ outside (0, 1) or diameters the periodic box cannot hold.
    fn with_phi(&self, phi: f64) -> PyResult<Self> {
        if !(phi > 0.0 && phi < 1.0) {
            return Err(value_err(format!(
                "phi={phi}: a packing fraction lies in (0, 1)"
            )));
        }
        let mut p = self.inner.clone();
        let d = p.dim as f64;
        p.scale_diameters((phi / self.inner.phi()).powf(1.0 / d));
        p.apply_fix_height();
        p.validate().map_err(core_err)?;
        Ok(PyPacking { inner: p })
    }

    /// The same particles in a box of side lengths `box` (one per axis): positions scaled
    /// with the box, axis by axis, diameters kept, so φ changes with the volume. A curved
    /// container scales only as a whole (every length by the same factor). Raises ValueError
    /// for a wrong count, a non-positive length or diameters that no longer fit.
    #[pyo3(name = "with_box")]
    fn with_box_lengths(&self, r#box: Vec<f64>) -> PyResult<Self> {
        let p = &self.inner;
        let d = p.dim;
        if r#box.len() != d {
            return Err(value_err(format!(
                "box= has {} lengths but the packing is {d}-dimensional; give one length per axis",
                r#box.len()
            )));
        }
        if let Some(l) = r#box.iter().find(|l| !(l.is_finite() && **l > 0.0)) {
            return Err(value_err(format!(
                "box=: length {l} is not a positive finite number"
            )));
        }
        let ratios: Vec<f64> = r#box
            .iter()
            .zip(&p.container.lengths)
            .map(|(a, b)| a / b)
            .collect();
        let mut container = p.container.clone();
        if container.shape == Shape::Box {
            container.lengths.clone_from(&r#box);
        } else {
            if ratios.iter().any(|r| (r / ratios[0] - 1.0).abs() > 1e-12) {
                return Err(value_err(format!(
                    "box=: a {} scales only as a whole; give lengths proportional to {:?}",
                    p.container.describe(),
                    p.container.lengths
                )));
            }
            container.scale(ratios[0]);
        }
        let positions = p
            .positions
            .chunks_exact(d)
            .flat_map(|x| x.iter().zip(&ratios).map(|(v, r)| v * r))
            .collect();
        let inner = Packing::new(positions, p.diameters.clone(), container).map_err(core_err)?;
        Ok(PyPacking { inner })
    }

    /// Relaxes or compresses this packing with a method (RCPGenerator's `relax`): the same
    /// as `packbench.pack(method, self, **keywords)`, returning its `Result`. With
    /// `target_phi=` (adam, fire) the spheres grow to that φ below jamming and the run stops
    /// there overlap-free; `max_steps=` bounds the steps.
    #[pyo3(signature = (method = "fire", **keywords))]
    fn relax<'py>(
        slf: &Bound<'py, Self>,
        method: &str,
        keywords: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let py = slf.py();
        py.import("packbench")?
            .getattr("pack")?
            .call((method, slf), keywords)
    }

    /// Draws the packing to scale with matplotlib and returns the axes: 2D disks, or for
    /// d ≥ 3 the disks a plane cuts (`axis=`, default the last, `at=`, default mid-box).
    /// Keywords: `ax` (axes to draw on), `color`, `edgecolor`, `linewidth`, `box` (outline).
    #[pyo3(signature = (ax = None, **keywords))]
    fn plot<'py>(
        slf: &Bound<'py, Self>,
        ax: Option<&Bound<'py, PyAny>>,
        keywords: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let py = slf.py();
        let none = py.None().into_bound(py);
        py.import("packbench._plot")?
            .getattr("plot_packing")?
            .call((slf, ax.unwrap_or(&none)), keywords)
    }

    /// The packing as the `packbench view` page (three.js, contacts coloured by contact
    /// number), inline in Jupyter: displaying a Packing at the end of a cell shows it in 3D
    /// (2D packings as disks).
    fn _repr_html_(&self, py: Python<'_>) -> PyResult<String> {
        let p = self.inner.clone();
        py.detach(|| packing_html(&p, None)).map_err(bench_err)
    }

    fn __repr__(&self) -> String {
        format!(
            "Packing(n={}, dim={}, phi={:.6}, container={})",
            self.inner.n(),
            self.inner.dim,
            self.inner.phi(),
            self.inner.container.describe()
        )
    }
}

/// Refuses a centre outside [0, L] on a periodic axis: the core wraps such centres when it
/// reads them, but an array from Python that is not wrapped is more often a unit mistake than
/// an unwrapped trajectory, and the docs promise a ValueError.
fn check_periodic_range(x: &[f64], container: &Container) -> PyResult<()> {
    let d = container.dim();
    for (i, row) in x.chunks_exact(d.max(1)).enumerate() {
        for (k, &v) in row.iter().enumerate() {
            let l = container.lengths[k];
            if container.periodic[k] && !(0.0..=l).contains(&v) {
                return Err(value_err(format!(
                    "positions[{i}, {k}] = {v} lies outside the periodic box [0, {l}] of axis {k}; \
                     wrap unwrapped coordinates first (positions % box)"
                )));
            }
        }
    }
    Ok(())
}

/// The packing of a `Packing`, or of positions, diameters and container keywords.
pub(crate) fn packing_of(
    positions: &Bound<'_, PyAny>,
    diameters: Option<&Bound<'_, PyAny>>,
    container: &ContainerKeywords,
    what: &str,
) -> PyResult<Packing> {
    match diameters {
        Some(d) => Ok(PyPacking::from_arrays(positions, d, container)?.inner),
        None => {
            container.refuse_for_packing()?;
            let p = positions.cast::<PyPacking>().map_err(|_| {
                value_err(format!(
                    "{what} takes a Packing, or positions and diameters"
                ))
            })?;
            Ok(p.get().inner.clone())
        }
    }
}
