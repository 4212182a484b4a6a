//! The void space between the spheres, measured exactly (no voxel images) in 2D and 3D:
//!
//! - [`radical_voronoi`]: the radical (Laguerre, power) Voronoi tessellation by voro++, with
//!   local φ, cell-volume spread and entropy per packing;
//! - [`pore_network`]: the Voronoi network of pores (cell vertices) and throats (cell edges),
//!   the largest included sphere D_i, the largest free sphere D_f, pore- and throat-size
//!   distributions;
//! - [`voronoi_and_pores`]: both of the above from one tessellation;
//! - [`chords`]: void and solid chord-length distributions along random and axial lines;
//! - [`scaffold_fill`]: how the spheres below a cut-off diameter fill the radical cells of the
//!   spheres above it.
//!
//! Every function refuses, with one sentence, what it cannot measure: a dimension other than
//! 2 or 3, coincident centres, overlaps above [`MAX_RELATIVE_OVERLAP`], a container voro++
//! cannot cut (cylindrical shells and hemisphere-cut bricks are concave).

mod chords;
mod pore_network;
mod radical_voronoi;
mod scaffold_fill;
mod sphere_grid;
mod voronoi_and_pores;

pub use chords::{ChordOptions, ChordReport, ChordSet, chords};
pub use pore_network::{
    PoreNetwork, PoreOptions, PoreReport, free_sphere_radius, pore_network, pores,
};
pub use radical_voronoi::{VoronoiCells, VoronoiReport, radical_voronoi, voronoi};
pub use scaffold_fill::{ScaffoldFill, scaffold_fill};
pub use voronoi_and_pores::voronoi_and_pores;

use crate::error::CoreError;
use crate::packing::Packing;

/// Largest relative overlap `1 − r/σ` the void-space analysis accepts. Radical cells stay
/// defined under overlaps, but a sphere that reaches deep into its neighbour's cell makes the
/// local φ and pore sizes meaningless; jammed soft-sphere packings overlap by ~1e-3 at most.
pub const MAX_RELATIVE_OVERLAP: f64 = 0.1;

/// Checks what every void-space function needs: a valid packing in 2D or 3D, at least one
/// particle, no coincident centres and no overlap above [`MAX_RELATIVE_OVERLAP`].
fn check_packing(packing: &Packing) -> Result<(), CoreError> {
    packing.validate()?;
    if packing.dim != 2 && packing.dim != 3 {
        return Err(CoreError::Parameter(format!(
            "the void-space analysis (Voronoi cells, pores, chords) works in 2 and 3 dimensions, not {}: voro++ tessellates 3D space only",
            packing.dim
        )));
    }
    if packing.n() == 0 {
        return Err(CoreError::Packing(
            "the packing has no particles, so it has no Voronoi cells".into(),
        ));
    }
    if let Some((i, j)) = packing.coincident_centres() {
        return Err(CoreError::Packing(format!(
            "particles {} and {} have the same centre, so their Voronoi cells are undefined",
            i + 1,
            j + 1
        )));
    }
    let mut worst: Option<(usize, usize, f64)> = None;
    crate::neighbor::CellList::for_each_near_pair(
        &packing.container,
        &packing.positions,
        &packing.diameters,
        0.0,
        |i, j| {
            let mut delta = [0.0; 3];
            packing.container.separation(
                packing.position(i),
                packing.position(j),
                &mut delta[..packing.dim],
            );
            let r = crate::geometry::norm2(&delta[..packing.dim]).sqrt();
            let overlap = 1.0 - r / (0.5 * (packing.diameters[i] + packing.diameters[j]));
            if worst.is_none_or(|w| overlap > w.2) {
                worst = Some((i, j, overlap));
            }
        },
    );
    if let Some((i, j, overlap)) = worst
        && overlap > MAX_RELATIVE_OVERLAP
    {
        return Err(CoreError::Packing(format!(
            "particles {} and {} overlap by {:.3} of their mean diameter, more than the {} the void-space analysis accepts; minimise or pack the configuration first",
            i + 1,
            j + 1,
            overlap,
            MAX_RELATIVE_OVERLAP
        )));
    }
    Ok(())
}

/// Mean and standard deviation of `values` (population std; zeros for an empty slice).
fn mean_std(values: &[f64]) -> (f64, f64) {
    if values.is_empty() {
        return (0.0, 0.0);
    }
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n;
    (mean, var.sqrt())
}

#[cfg(test)]
mod tests;
