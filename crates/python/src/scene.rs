//! Scenes from Python keywords, read by the command line's own scene flags (`--N`, `--Ndim`,
//! `--phi`, `--dist` and its parameters, the container flags), and `packbench.initial_packing`.

use packbench::args::{DistributionArgs, SceneArgs};
use packbench_core::init::initial_packing as core_initial_packing;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::container::ContainerKeywords;
use crate::errors::{bench_err, core_err, value_err};
use crate::keywords::{count, opt_count, opt_number, opt_text};
use crate::packing::PyPacking;

/// What a `dist` that is not a name is told.
pub const DIST_HINT: &str = "; give the distribution's name and its parameters as keywords: dist=\"bidisperse\", d1=1.0, d2=1.4, p=0.5";

/// The distribution flags of a distribution name and its parameter keywords; an unknown
/// keyword is a ValueError that lists the known ones.
pub fn distribution_args(
    dist: Option<String>,
    params: Option<&Bound<'_, PyDict>>,
) -> PyResult<DistributionArgs> {
    let mut a = DistributionArgs {
        dist,
        ..Default::default()
    };
    let Some(params) = params else {
        return Ok(a);
    };
    for (k, v) in params.iter() {
        let key: String = k.extract()?;
        if key == "custom_list" {
            a.custom_list =
                Some(v.extract().map_err(|_| {
                    value_err("custom_list must be a sequence of diameters (numbers)")
                })?);
            continue;
        }
        let Some(slot) = a.number_mut(&key) else {
            return Err(value_err(format!(
                "unknown keyword `{key}`; the size-distribution parameters are {}, custom_list",
                DistributionArgs::number_names()
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        };
        *slot = Some(v.extract().map_err(|_| {
            value_err(format!(
                "{key}={}: {key} must be a number",
                v.repr().map(|r| r.to_string()).unwrap_or_default()
            ))
        })?);
    }
    Ok(a)
}

/// The scene flags of Python keywords (each None keeps the scene's default).
pub fn scene_args(
    n: Option<usize>,
    dim: Option<usize>,
    phi: Option<f64>,
    placement: Option<String>,
    distribution: DistributionArgs,
    container: &ContainerKeywords,
) -> SceneArgs {
    SceneArgs {
        scene: None,
        n,
        ndim: dim,
        phi,
        placement,
        distribution,
        container: container.args(),
    }
}

/// A random initial packing at a low φ, as `packbench init` makes it (RCPGenerator's
/// InitializeParticles): `n` particles in `dim` dimensions at packing fraction `phi`, sizes
/// from `dist` (mono, bidisperse, gaussian, biGaussian, lognormal, lognormal-mean1, flat,
/// powerlaw, exponential, weibull, gamma, custom) with its parameters as keywords by the
/// names of `packbench init`'s flags (`d`, `d1`, `d2`, `p`, `mu`, `sigma`, `mu1`, `sigma1`,
/// `mu2`, `sigma2`, `d_min`, `d_max`, `exponent`, `scale`, `shape`, `custom_list`), in the
/// container of `box` and `walls` (as in `Packing(...)`). The same seed gives the same
/// packing as `packbench init --seed`.
///
/// `placement` is `rsa` (default): random sequential addition, RCPGenerator's
/// `InitializeParticles` — uniformly random centres, whole spheres inside the walls, and no
/// two spheres overlapping, placed largest first. It saturates below random close packing
/// (equal spheres near φ ≈ 0.38 in 3D, disks near 0.55 in 2D) and a φ it cannot reach is a
/// ValueError ("could not place a non-overlapping particle …"). The overlapping placements
/// are kept by name: `random` (uniform centres, whole spheres inside walls) and `poisson`
/// (centres anywhere inside, the start Lubachevsky–Stillinger methods grow from).
///
/// Raises ValueError for a bad scene, with the sentence `packbench init` prints in the
/// keywords' names (`dist="bidisperse" needs d1=`).
#[pyfunction]
#[pyo3(signature = (n, dim, phi = None, dist = None, r#box = None, walls = None, seed = None, *, fix_height = false, shell = None, hemispheres = None, placement = None, **dist_params))]
#[allow(clippy::too_many_arguments)]
pub fn initial_packing(
    py: Python<'_>,
    n: &Bound<'_, PyAny>,
    dim: &Bound<'_, PyAny>,
    phi: Option<&Bound<'_, PyAny>>,
    dist: Option<&Bound<'_, PyAny>>,
    r#box: Option<Vec<f64>>,
    walls: Option<Vec<i64>>,
    seed: Option<&Bound<'_, PyAny>>,
    fix_height: bool,
    shell: Option<Vec<f64>>,
    hemispheres: Option<Vec<f64>>,
    placement: Option<String>,
    dist_params: Option<&Bound<'_, PyDict>>,
) -> PyResult<PyPacking> {
    let n = count(n, "n", 1)? as usize;
    let phi = opt_number(phi, "phi")?.unwrap_or(0.05);
    let dim = count(dim, "dim", 2)? as usize;
    let seed = opt_count(seed, "seed", 0)?.unwrap_or(0);
    let dist = opt_text(dist, "dist", DIST_HINT)?.unwrap_or_else(|| "mono".into());
    let container = ContainerKeywords::new(r#box, walls, fix_height, shell, hemispheres);
    let distribution = distribution_args(Some(dist), dist_params)?;
    let scene = scene_args(
        Some(n),
        Some(dim),
        Some(phi),
        placement,
        distribution,
        &container,
    )
    .scene(Some(seed))
    .map_err(bench_err)?;
    let inner = py
        .detach(|| core_initial_packing(&scene, seed))
        .map_err(core_err)?;
    Ok(PyPacking { inner })
}
