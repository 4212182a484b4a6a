//! `packbench.voronoi` and `packbench.pores`: the void space of a packing (radical Voronoi
//! cells, pore network, chord lengths, scaffold fill) as dicts with the keys of
//! `packbench analyze --voronoi/--pores`, plus the per-particle, per-pore and per-chord values
//! as NumPy arrays.

use numpy::{PyArray1, PyArrayMethods};
use packbench::void_space::{VoidSpaceRequest, void_space};
use packbench_core::analysis::void_space::voronoi as core_voronoi;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::matrix;
use crate::container::ContainerKeywords;
use crate::errors::{core_err, value_err};
use crate::json::to_py;
use crate::packing::packing_of;

/// Registers `voronoi` and `pores` in the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(voronoi, m)?)?;
    m.add_function(wrap_pyfunction!(pores, m)?)?;
    Ok(())
}

fn dict<'py>(value: Bound<'py, PyAny>) -> PyResult<Bound<'py, PyDict>> {
    Ok(value.cast_into::<PyDict>()?)
}

/// The radical (Laguerre) Voronoi cells of a packing (voro++; 2D and 3D), as a dict: the
/// summaries of `packbench analyze --voronoi` (total_volume, mean_volume,
/// volume_std_relative, volume_entropy, local_phi_mean, local_phi_std, faces_mean,
/// local_phi_histogram) and the arrays `volumes` (cell volume, area in 2D), `local_phi`
/// (particle volume / cell volume) and `faces` (Voronoi neighbours), one entry per particle.
///
/// Give a `Packing`, or `positions` (N×d) and `diameters` (N) with the container keywords of
/// `Packing(...)`. Runs with the GIL released. Raises ValueError for a dimension other than 2
/// or 3, coincident centres, overlaps above 10 %, or a concave container.
#[pyfunction]
#[pyo3(signature = (positions, diameters = None, *, r#box = None, walls = None, fix_height = false, shell = None, hemispheres = None))]
#[allow(clippy::too_many_arguments)]
pub fn voronoi<'py>(
    py: Python<'py>,
    positions: &Bound<'py, PyAny>,
    diameters: Option<&Bound<'py, PyAny>>,
    r#box: Option<Vec<f64>>,
    walls: Option<Vec<i64>>,
    fix_height: bool,
    shell: Option<Vec<f64>>,
    hemispheres: Option<Vec<f64>>,
) -> PyResult<Bound<'py, PyDict>> {
    let container = ContainerKeywords::new(r#box, walls, fix_height, shell, hemispheres);
    let packing = packing_of(positions, diameters, &container, "voronoi")?;
    let report = py.detach(|| core_voronoi(&packing)).map_err(core_err)?;
    let out = dict(to_py(py, &report)?)?;
    let cells = report.cells;
    out.set_item("volumes", PyArray1::from_vec(py, cells.volumes))?;
    out.set_item("local_phi", PyArray1::from_vec(py, cells.local_phi))?;
    let faces: Vec<i64> = cells.faces.iter().map(|&f| f as i64).collect();
    out.set_item("faces", PyArray1::from_vec(py, faces))?;
    Ok(out)
}

/// The pore space of a packing as a dict with the keys of `packbench analyze --pores`:
/// `voronoi` (as `packbench.voronoi` returns it), `pores` (pores, throats,
/// included_sphere_diameter D_i, free_sphere_diameter D_f or None without a periodic axis,
/// pore- and throat-size distributions and means), `chords` in a fully periodic box (void and
/// solid chord sets with their means and the stereological prediction), and `scaffold_fill`
/// when `scaffold_cutoff` is given.
///
/// Arrays: `pores["centres"]` (M×d pore centres), `pores["diameters"]` (largest empty sphere
/// at each pore), `pores["throat_pores"]` (K×2 pore indices), `pores["throat_diameters"]`,
/// `pores["pore_size_samples"]` (covering diameter of each sampled void point);
/// `chords["void"]["lengths"]`, `chords["solid"]["lengths"]`; `scaffold_fill["fill"]` and
/// `scaffold_fill["scaffold_ids"]`.
///
/// `samples` void points (seeded by `seed`) make the pore-size distribution, `lines` random
/// lines the chord lengths. Runs with the GIL released. Raises ValueError for bad input.
#[pyfunction]
#[pyo3(signature = (positions, diameters = None, *, r#box = None, walls = None, fix_height = false, shell = None, hemispheres = None, samples = 20_000, lines = 1000, seed = 1, scaffold_cutoff = None))]
#[allow(clippy::too_many_arguments)]
pub fn pores<'py>(
    py: Python<'py>,
    positions: &Bound<'py, PyAny>,
    diameters: Option<&Bound<'py, PyAny>>,
    r#box: Option<Vec<f64>>,
    walls: Option<Vec<i64>>,
    fix_height: bool,
    shell: Option<Vec<f64>>,
    hemispheres: Option<Vec<f64>>,
    samples: usize,
    lines: usize,
    seed: u64,
    scaffold_cutoff: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let container = ContainerKeywords::new(r#box, walls, fix_height, shell, hemispheres);
    let packing = packing_of(positions, diameters, &container, "pores")?;
    let d = packing.dim;
    let request = VoidSpaceRequest {
        voronoi: true,
        pores: true,
        pore_samples: samples,
        chord_lines: lines,
        seed,
        scaffold_cutoff,
    };
    let found = py
        .detach(|| void_space(&packing, &request))
        .map_err(core_err)?;
    let (Some(cells), Some(pore_report)) = (found.voronoi, found.pores) else {
        return Err(value_err("the pore analysis returned no cells or pores"));
    };
    let (chord_report, fill) = (found.chords, found.scaffold_fill);
    let out = PyDict::new(py);
    let v = dict(to_py(py, &cells)?)?;
    v.set_item("volumes", PyArray1::from_vec(py, cells.cells.volumes))?;
    v.set_item("local_phi", PyArray1::from_vec(py, cells.cells.local_phi))?;
    out.set_item("voronoi", v)?;
    let p = dict(to_py(py, &pore_report)?)?;
    if let Some(net) = &pore_report.network {
        let flat: Vec<f64> = net.centres.iter().flat_map(|c| c[..d].to_vec()).collect();
        p.set_item("centres", matrix(py, flat, d)?)?;
        let dia: Vec<f64> = net.pore_radius.iter().map(|r| 2.0 * r).collect();
        p.set_item("diameters", PyArray1::from_vec(py, dia))?;
        let throats: Vec<i64> = net
            .throats
            .iter()
            .flat_map(|t| [t[0] as i64, t[1] as i64])
            .collect();
        let throats = PyArray1::from_vec(py, throats).reshape(vec![net.throats.len(), 2])?;
        p.set_item("throat_pores", throats)?;
        let tdia: Vec<f64> = net.throat_radius.iter().map(|r| 2.0 * r).collect();
        p.set_item("throat_diameters", PyArray1::from_vec(py, tdia))?;
    }
    p.set_item(
        "pore_size_samples",
        PyArray1::from_vec(py, pore_report.pore_size_samples),
    )?;
    out.set_item("pores", p)?;
    if let Some(c) = chord_report {
        let cd = dict(to_py(py, &c)?)?;
        for (key, set) in [("void", &c.void), ("solid", &c.solid)] {
            let s = cd
                .get_item(key)?
                .ok_or_else(|| value_err("chords lost a key"))?;
            s.set_item("lengths", PyArray1::from_vec(py, set.lengths.clone()))?;
        }
        out.set_item("chords", cd)?;
    }
    if let Some(f) = fill {
        let fd = dict(to_py(py, &f)?)?;
        fd.set_item("fill", PyArray1::from_vec(py, f.fill.clone()))?;
        let ids: Vec<i64> = f.scaffold_ids.iter().map(|&i| i as i64).collect();
        fd.set_item("scaffold_ids", PyArray1::from_vec(py, ids))?;
        out.set_item("scaffold_fill", fd)?;
    }
    Ok(out)
}
