//! The figure of g(r), the pair correlation function of a periodic packing (computed by the
//! core).

use packbench_core::Packing;
use packbench_core::analysis::structure::pair_correlation;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::{FONT, Res, colour, draw_legend};

/// g(r) of a periodic packing up to half the smallest box length, r in mean diameters, as
/// `(r, g)` points: the core's [`pair_correlation`].
pub fn radial_distribution(p: &Packing, bins: usize) -> Vec<(f64, f64)> {
    let gr = pair_correlation(p, bins);
    gr.r.into_iter().zip(gr.g).collect()
}

pub fn draw_gr<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    series: &[(String, Vec<(f64, f64)>)],
) -> Res
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let xmax = series
        .iter()
        .flat_map(|s| s.1.iter().map(|p| p.0))
        .fold(0.0, f64::max);
    let ymax = series
        .iter()
        .flat_map(|s| s.1.iter().map(|p| p.1))
        .fold(0.0, f64::max)
        .min(30.0)
        * 1.05;
    let mut chart = ChartBuilder::on(root)
        .caption("Radial distribution function", (FONT, 24))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(50)
        .build_cartesian_2d(0.0..xmax, 0.0..ymax.max(1.0))?;
    chart
        .configure_mesh()
        .label_style((FONT, 12))
        .axis_desc_style((FONT, 14))
        .x_desc("r / mean diameter")
        .y_desc("g(r)")
        .draw()?;
    for (k, (m, pts)) in series.iter().enumerate() {
        let c = colour(k);
        chart
            .draw_series(LineSeries::new(
                pts.iter().map(|&(x, y)| (x, y.min(ymax))),
                c.stroke_width(2),
            ))?
            .label(m.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], c.stroke_width(2)));
    }
    draw_legend(&mut chart, SeriesLabelPosition::MiddleRight)?;
    Ok(())
}
