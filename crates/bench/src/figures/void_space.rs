//! Figures of the void space (PNG or SVG, plotters), two panels each, several packings
//! overlaid: `voronoi` (density of local φ; local φ against diameter), `pores` (volume-weighted
//! pore-size and throat-size distributions), `chords` (void and solid chord-length
//! distributions, log–log).

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
                ("local φ against diameter", "diameter", "local φ", true),
            ],
            VoidSpaceKind::Pores => [
                (
                    "pore-size distribution (volume-weighted)",
                    "covering sphere diameter",
                    "density",
                    false,
                ),
                (
                    "throat-size distribution",
                    "throat diameter",
                    "density",
                    false,
                ),
            ],
            VoidSpaceKind::Chords => [
                ("void chords", "log10 chord length", "log10 density", false),
                ("solid chords", "log10 chord length", "log10 density", false),
            ],
        }
    }
}

/// Points of a histogram, on log10 axes when `log` (empty bins dropped there).
pub fn histogram_points(h: &Histogram, log: bool) -> Vec<(f64, f64)> {
    h.x.iter()
        .zip(&h.density)
        .filter(|&(&x, &y)| !log || (x > 0.0 && y > 0.0))
        .map(|(&x, &y)| if log { (x.log10(), y.log10()) } else { (x, y) })
        .collect()
}

/// The panels of a `voronoi` figure: the local-φ density, and local φ against diameter.
pub fn voronoi_panels(cells: &VoronoiReport, diameters: &[f64]) -> [Vec<(f64, f64)>; 2] {
    [
        histogram_points(&cells.local_phi_histogram, false),
        diameters
            .iter()
            .cloned()
            .zip(cells.cells.local_phi.iter().cloned())
            .collect(),
    ]
}

/// The panels of a `pores` figure: the pore-size and throat-size densities.
pub fn pore_panels(pores: &PoreReport) -> [Vec<(f64, f64)>; 2] {
    [
        histogram_points(&pores.pore_size_distribution, false),
        histogram_points(&pores.throat_size_distribution, false),
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
