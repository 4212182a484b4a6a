//! The radical Voronoi cells and the pore network of a packing from one tessellation:
//! voro++ computes each cell once, and both the cell summaries and the network read it.

use super::pore_network::{NetworkBuilder, PoreOptions, PoreReport, check_options, pore_report};
use super::radical_voronoi::{CellCollector, VoronoiReport, for_each_cell, summarize};
use crate::error::CoreError;
use crate::packing::Packing;

/// What [`super::voronoi`] and [`super::pores`] return, from a single tessellation (the
/// tessellation is most of either's cost).
///
/// Errors: those of [`super::voronoi`] and [`super::pores`].
pub fn voronoi_and_pores(
    packing: &Packing,
    options: &PoreOptions,
) -> Result<(VoronoiReport, PoreReport), CoreError> {
    check_options(options)?;
    let mut cells = CellCollector::new(packing.n());
    let mut network = NetworkBuilder::new(packing);
    for_each_cell(packing, None, |cell| {
        cells.add(cell);
        network.add(cell);
    })?;
    let (net, spheres) = network.finish();
    let pores = pore_report(packing, net, &spheres, options)?;
    Ok((summarize(cells.finish(packing)), pores))
}
