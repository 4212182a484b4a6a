//! Figures of the void space (PNG or SVG, plotters), two panels each, several packings
//! overlaid: `voronoi` (density of local φ; local φ against diameter), `pores` (volume-weighted
//! pore-size and throat-size distributions), `chords` (void and solid chord-length
//! distributions, log–log).

use packbench_core::Packing;
use packbench_core::analysis::structure::Histogram;
use packbench_core::analysis::void_space::{PoreReport, VoronoiReport};
use plotters::coord::Shift;
use plotters::prelude::*;

use super::{Res, colour, labelled_line, panel, range};

/// One packing's void-space curves, by figure kind.
#[derive(Clone, Debug)]
pub struct VoidSpaceSeries {
    /// Legend entry.
    pub name: String,
    /// Left and right panel: points to draw (already on log10 axes where the panel is).
    pub panels: [Vec<(f64, f64)>; 2],
}

/// What a void-space figure shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VoidSpaceKind {
    /// Density of local φ, and local φ against diameter.
    Voronoi,
    /// Pore-size and throat-size distributions.
    Pores,
    /// Void and solid chord-length distributions, log–log.
    Chords,
}

impl VoidSpaceKind {
    /// Panel titles and axis labels, and whether points are drawn as a scatter.
    fn panels(self) -> [(&'static str, &'static str, &'static str, bool); 2] {
        match self {
            VoidSpaceKind::Voronoi => [
                (
                    "local φ distribution",
                    "local φ = v_particle/v_cell",
                    "density",
                    false,
                ),
                (
                    "local φ against diameter",
                    "diameter / mean D",
                    "local φ",
                    true,
                ),
            ],
            VoidSpaceKind::Pores => [
                (
                    "pore-size distribution (volume-weighted)",
                    "covering sphere diameter / mean D",
                    "density (per mean D)",
                    false,
                ),
                (
                    "throat-size distribution",
                    "throat diameter / mean D",
                    "density (per mean D)",
                    false,
                ),
            ],
            VoidSpaceKind::Chords => [
                (
                    "void chords",
                    "log10 chord length / mean D",
                    "log10 density (per mean D)",
                    false,
                ),
                (
                    "solid chords",
                    "log10 chord length / mean D",
                    "log10 density (per mean D)",
                    false,
                ),
            ],
        }
    }
}

/// Points of a histogram of a length, in units of `unit` (the packing's mean diameter, so
/// that figures of packings of any box size read alike): x / unit and the density per unit
/// times unit; on log10 axes when `log` (empty bins dropped there).
pub fn histogram_points(h: &Histogram, unit: f64, log: bool) -> Vec<(f64, f64)> {
    h.x.iter()
        .zip(&h.density)
        .map(|(&x, &y)| (x / unit, y * unit))
        .filter(|&(x, y)| !log || (x > 0.0 && y > 0.0))
        .map(|(x, y)| if log { (x.log10(), y.log10()) } else { (x, y) })
        .collect()
}

/// The panels of a `voronoi` figure of packing `p`: the local-φ density, and local φ against
/// diameter (in mean diameters).
pub fn voronoi_panels(cells: &VoronoiReport, p: &Packing) -> [Vec<(f64, f64)>; 2] {
    let unit = p.mean_diameter();
    [
        histogram_points(&cells.local_phi_histogram, 1.0, false),
        p.diameters
            .iter()
            .map(|d| d / unit)
            .zip(cells.cells.local_phi.iter().cloned())
            .collect(),
    ]
}

/// The panels of a `pores` figure of packing `p`: the pore-size and throat-size densities,
/// sizes in its mean diameters.
pub fn pore_panels(pores: &PoreReport, p: &Packing) -> [Vec<(f64, f64)>; 2] {
    let unit = p.mean_diameter();
    [
        histogram_points(&pores.pore_size_distribution, unit, false),
        histogram_points(&pores.throat_size_distribution, unit, false),
    ]
}

/// Draws the two panels of `kind` for `series`.
pub fn draw_void_space<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    kind: VoidSpaceKind,
    series: &[VoidSpaceSeries],
) -> Res
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let areas = root.split_evenly((1, 2));
    for (p, (area, (title, xdesc, ydesc, scatter))) in areas.iter().zip(kind.panels()).enumerate() {
        let all = || series.iter().flat_map(|s| s.panels[p].iter());
        let (x0, x1) = range(all().map(|q| q.0), 0.05);
        let (y0, y1) = range(all().map(|q| q.1), 0.05);
        let mut chart = panel(area, title, 16, 55, x0..x1, y0..y1, xdesc, ydesc)?;
        for (k, s) in series.iter().enumerate() {
            let c = colour(k);
            if scatter {
                chart
                    .draw_series(s.panels[p].iter().map(|&q| Circle::new(q, 1, c.filled())))?
                    .label(s.name.as_str())
                    .legend(move |(x, y)| Circle::new((x + 7, y), 3, c.filled()));
            } else {
                labelled_line(&mut chart, &s.panels[p], c.to_rgba(), Some(&s.name))?;
            }
        }
        super::draw_legend(&mut chart, SeriesLabelPosition::UpperRight)?;
    }
    Ok(())
}
