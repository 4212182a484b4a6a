//! g(r), the pair correlation function of a periodic packing, and its figure.

use packbench_core::Packing;
use packbench_core::neighbor::CellList;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::{FONT, Res, colour, draw_legend};

/// g(r) of a periodic packing up to half the smallest box length, r in mean diameters.
pub fn radial_distribution(p: &Packing, bins: usize) -> Vec<(f64, f64)> {
    let d = p.dim;
    let mean = p.diameters.iter().sum::<f64>() / p.n().max(1) as f64;
    let r_max = (0.5
        * p.container
            .lengths
            .iter()
            .cloned()
            .fold(f64::INFINITY, f64::min))
    .min(3.0 * mean);
    let dr = r_max / bins as f64;
    let mut hist = vec![0usize; bins];
    let mut delta = vec![0.0; d];
    CellList::for_each_near_pair(&p.container, &p.positions, &p.diameters, r_max, |i, j| {
        p.container
            .separation(p.position(i), p.position(j), &mut delta);
        let r = delta.iter().map(|v| v * v).sum::<f64>().sqrt();
        if r < r_max {
            hist[(r / dr) as usize] += 2;
        }
    });
    let rho = p.n() as f64 / p.container.volume();
    let vd = packbench_core::geometry::unit_ball_volume(d);
    hist.iter()
        .enumerate()
        .map(|(b, &h)| {
            let (r0, r1) = (b as f64 * dr, (b + 1) as f64 * dr);
            let shell = vd * (r1.powi(d as i32) - r0.powi(d as i32));
            (
                (r0 + 0.5 * dr) / mean,
                h as f64 / (p.n() as f64 * rho * shell),
            )
        })
        .collect()
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
