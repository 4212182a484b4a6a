//! Fines in a scaffold (RCPGenerator's `rcptools` void-fill question): do the small spheres
//! fill the voids of the large ones?
//!
//! The spheres of diameter at least `D_c` form the scaffold; each is given its radical Voronoi
//! cell among the scaffold spheres alone. Every fine (diameter below `D_c`) is assigned to the
//! scaffold cell that contains its centre (least power distance), and each cell's fill fraction
//! is the fines' volume over the cell's void, `Σ v_fine / (V_cell − v_scaffold)`.

use serde::{Deserialize, Serialize};

use super::radical_voronoi::for_each_cell;
use super::sphere_grid::SphereGrid;
use super::{check_packing, mean_std};
use crate::analysis::structure::Histogram;
use crate::error::CoreError;
use crate::geometry::ball_volume;
use crate::packing::Packing;

/// How the fines fill the scaffold's radical cells.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ScaffoldFill {
    /// The cut-off diameter D_c.
    pub cutoff: f64,
    /// Number of scaffold spheres (D ≥ D_c).
    pub scaffold: usize,
    /// Number of fines (D < D_c).
    pub fines: usize,
    /// Total fines volume over the total scaffold void (the scaffold cells minus its spheres).
    pub overall_fill: f64,
    /// Mean fill fraction over scaffold cells.
    pub fill_mean: f64,
    /// Standard deviation of the fill fraction over scaffold cells.
    pub fill_std: f64,
    /// Fraction of scaffold cells holding no fine.
    pub empty_cells: f64,
    /// Density of the fill fraction on 40 bins over [0, max].
    pub fill_histogram: Histogram,
    /// Index of each scaffold sphere in the packing (not serialised).
    #[serde(skip)]
    pub scaffold_ids: Vec<usize>,
    /// Fill fraction of each scaffold sphere's cell, in the order of `scaffold_ids`
    /// (not serialised).
    #[serde(skip)]
    pub fill: Vec<f64>,
}

/// Splits `packing` at `cutoff` and measures how the fines fill the scaffold's cells.
///
/// Errors: a cut-off that leaves no scaffold sphere or is not a positive number, and those of
/// [`super::radical_voronoi`].
pub fn scaffold_fill(packing: &Packing, cutoff: f64) -> Result<ScaffoldFill, CoreError> {
    check_packing(packing)?;
    if !(cutoff.is_finite() && cutoff > 0.0) {
        return Err(CoreError::Parameter(format!(
            "the scaffold cut-off diameter must be a positive number, not {cutoff}"
        )));
    }
    let scaffold_ids: Vec<usize> = (0..packing.n())
        .filter(|&i| packing.diameters[i] >= cutoff)
        .collect();
    if scaffold_ids.is_empty() {
        return Err(CoreError::Parameter(format!(
            "no sphere is at least {cutoff} across, so there is no scaffold; the largest diameter is {}",
            packing.max_diameter()
        )));
    }
    let d = packing.dim;
    let mut slot = vec![usize::MAX; packing.n()];
    for (s, &i) in scaffold_ids.iter().enumerate() {
        slot[i] = s;
    }
    let mut void = vec![0.0; scaffold_ids.len()];
    for_each_cell(packing, Some(&scaffold_ids), |cell| {
        void[slot[cell.id]] = cell.measure - ball_volume(d, packing.diameters[cell.id]);
    })?;
    let grid = SphereGrid::new(packing, Some(&scaffold_ids));
    let mut fines_volume = vec![0.0; scaffold_ids.len()];
    let mut fines = 0;
    for i in (0..packing.n()).filter(|&i| packing.diameters[i] < cutoff) {
        fines += 1;
        let mut x = [0.0; 3];
        x[..d].copy_from_slice(packing.position(i));
        let s = grid
            .power_nearest(&grid.wrap(x))
            .expect("the scaffold is not empty");
        fines_volume[s] += ball_volume(d, packing.diameters[i]);
    }
    let fill: Vec<f64> = fines_volume
        .iter()
        .zip(&void)
        .map(|(&f, &v)| if v > 0.0 { f / v } else { 0.0 })
        .collect();
    let (fill_mean, fill_std) = mean_std(&fill);
    let hi = fill.iter().cloned().fold(0.0, f64::max);
    Ok(ScaffoldFill {
        cutoff,
        scaffold: scaffold_ids.len(),
        fines,
        overall_fill: fines_volume.iter().sum::<f64>()
            / void.iter().sum::<f64>().max(f64::MIN_POSITIVE),
        fill_mean,
        fill_std,
        empty_cells: fines_volume.iter().filter(|&&f| f == 0.0).count() as f64
            / scaffold_ids.len() as f64,
        fill_histogram: Histogram::linear(&fill, 0.0, hi.max(1e-12) * (1.0 + 1e-9), 40),
        scaffold_ids,
        fill,
    })
}
