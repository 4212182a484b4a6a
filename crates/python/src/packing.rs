//! `packbench.Packing`: positions, diameters and container of the core's packing, with the
//! RCPGenerator text format and the exports of `packbench export`.

use numpy::{PyArray1, PyArrayDyn};
use packbench::outputs::read_input;
use packbench_core::Packing;
use packbench_core::format::{ExportFormat, export, write_atomic, write_text};
use pyo3::prelude::*;

use crate::arrays::{matrix, particles_from};
use crate::container::{ContainerKeywords, rcp_walls};
use crate::errors::{bench_err, core_err};
use crate::json::to_py;

/// Particles in a container: `positions` (N×d, float64), `diameters` (N), and the container
/// given by `box` (side lengths, default 1 on every axis) and `walls` (per axis 0 periodic,
/// 1 hard wall; a negative first entry −t makes a (hyper)sphere of diameter box[0] over the
/// first t axes), as `--box` and `--walls` of the command line; `shell=(inner, outer)` and
/// `hemispheres=(r1, r2)` give the other curved containers, `fix_height=True` holds the last
/// box length at that multiple of the largest diameter.
///
/// Raises ValueError for a shape that is not N×d and N, a NaN or infinite value, a diameter
/// that is not positive, a container that does not fit the dimension, or a particle outside it.
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
        let inner = Packing::new(x, dia, container).map_err(core_err)?;
        Ok(PyPacking { inner })
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

    /// Writes extended XYZ (OVITO), with the box as `Lattice` and a radius column (d ≤ 3).
    fn to_xyz(&self, path: &str) -> PyResult<()> {
        self.export_to(path, ExportFormat::Xyz)
    }

    /// Writes a LAMMPS data file, atom_style sphere (d ≤ 3).
    fn to_lammps(&self, path: &str) -> PyResult<()> {
        self.export_to(path, ExportFormat::Lammps)
    }

    /// Writes legacy VTK polydata with a `diameter` point array (ParaView; d ≤ 3).
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
