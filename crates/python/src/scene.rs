//! Scenes from Python keywords, read by the command line's own scene flags (`--N`, `--Ndim`,
//! `--phi`, `--dist` and its parameters, the container flags), and `packbench.initial_packing`.

use packbench::args::{DistributionArgs, SceneArgs};
use packbench_core::init::initial_packing as core_initial_packing;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::container::ContainerKeywords;
use crate::errors::{bench_err, core_err, value_err};
use crate::packing::PyPacking;

/// The size-distribution parameters, by the names of `packbench init`'s flags.
const DIST_PARAMS: [&str; 16] = [
    "d",
    "d1",
    "d2",
    "p",
    "mu",
    "sigma",
    "mu1",
    "sigma1",
    "mu2",
    "sigma2",
    "d_min",
    "d_max",
    "exponent",
    "scale",
    "shape",
    "custom_list",
];

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
        let slot = match key.as_str() {
            "d" => &mut a.d,
            "d1" => &mut a.d1,
            "d2" => &mut a.d2,
            "p" => &mut a.p,
            "mu" => &mut a.mu,
            "sigma" => &mut a.sigma,
            "mu1" => &mut a.mu1,
            "sigma1" => &mut a.sigma1,
            "mu2" => &mut a.mu2,
            "sigma2" => &mut a.sigma2,
            "d_min" => &mut a.d_min,
            "d_max" => &mut a.d_max,
            "exponent" => &mut a.exponent,
            "scale" => &mut a.scale,
            "shape" => &mut a.shape,
            "custom_list" => {
                a.custom_list = Some(v.extract()?);
                continue;
            }
            _ => {
                return Err(value_err(format!(
                    "unknown keyword `{key}`; the size-distribution parameters are {}",
                    DIST_PARAMS.join(", ")
                )));
            }
        };
        *slot = Some(v.extract()?);
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
/// container of `box` and `walls` (as in `Packing(...)`). `placement` is `random` (whole
/// spheres inside walls) or `poisson` (centres anywhere inside). The same seed gives the same
/// packing as `packbench init --seed`.
///
/// Raises ValueError for a bad scene, with the sentence `packbench init` prints.
#[pyfunction]
#[pyo3(signature = (n, dim, phi = 0.05, dist = "mono", r#box = None, walls = None, seed = 0, *, fix_height = false, shell = None, hemispheres = None, placement = None, **dist_params))]
#[allow(clippy::too_many_arguments)]
pub fn initial_packing(
    py: Python<'_>,
    n: usize,
    dim: usize,
    phi: f64,
    dist: &str,
    r#box: Option<Vec<f64>>,
    walls: Option<Vec<i64>>,
    seed: u64,
    fix_height: bool,
    shell: Option<Vec<f64>>,
    hemispheres: Option<Vec<f64>>,
    placement: Option<String>,
    dist_params: Option<&Bound<'_, PyDict>>,
) -> PyResult<PyPacking> {
    let container = ContainerKeywords::new(r#box, walls, fix_height, shell, hemispheres);
    let distribution = distribution_args(Some(dist.to_string()), dist_params)?;
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
