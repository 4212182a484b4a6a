//! seq-fill's radius histogram: the radii a fill placed and discarded against the target
//! density.

use std::path::Path;

use packbench_core::SizeDistribution;
use plotters::prelude::*;

use super::{FONT, Res, colour, draw_legend, range};
use crate::error::BenchError;

/// Histogram of the radii a fill placed and discarded against the target density (a seeded
/// sample of 10^5 draws from the requested distribution), as a PNG.
pub fn radius_histogram(
    path: &Path,
    placed: &[f64],
    discarded: &[f64],
    target: &SizeDistribution,
) -> Result<(), BenchError> {
    use rand::SeedableRng;
    let mut rng = rand::rngs::StdRng::seed_from_u64(0);
    let reference: Vec<f64> = target
        .sample(100_000, &mut rng)?
        .iter()
        .map(|d| 0.5 * d)
        .collect();
    let (lo, hi) = range(
        placed.iter().chain(discarded).chain(&reference).cloned(),
        0.02,
    );
    let bins = 40usize;
    let w = (hi - lo) / bins as f64;
    let density = |v: &[f64]| {
        let mut c = vec![0.0; bins];
        for &x in v {
            c[(((x - lo) / w) as usize).min(bins - 1)] += 1.0;
        }
        let total = v.len().max(1) as f64 * w;
        c.iter().map(|n| n / total).collect::<Vec<f64>>()
    };
    let (dp, dd, dr) = (density(placed), density(discarded), density(&reference));
    let ymax = dp.iter().chain(&dd).chain(&dr).cloned().fold(0.0, f64::max) * 1.1;
    let draw = || -> Res {
        let root = BitMapBackend::new(path, (900, 540)).into_drawing_area();
        root.fill(&WHITE)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(
                "Radii drawn by the fill against the target density",
                (FONT, 22),
            )
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d(lo..hi, 0.0..ymax.max(1e-12))?;
        chart
            .configure_mesh()
            .label_style((FONT, 12))
            .axis_desc_style((FONT, 14))
            .x_desc("radius")
            .y_desc("probability density")
            .draw()?;
        let bars = |d: &[f64], k: usize, c: RGBColor| {
            d.iter()
                .enumerate()
                .map(|(b, &y)| {
                    let x0 = lo + b as f64 * w + k as f64 * w / 2.0;
                    Rectangle::new([(x0, 0.0), (x0 + w / 2.0, y)], c.mix(0.75).filled())
                })
                .collect::<Vec<_>>()
        };
        chart
            .draw_series(bars(&dp, 0, colour(0)))?
            .label(format!("placed ({})", placed.len()))
            .legend(|(x, y)| Rectangle::new([(x, y - 5), (x + 10, y + 5)], colour(0).filled()));
        chart
            .draw_series(bars(&dd, 1, colour(1)))?
            .label(format!("discarded ({})", discarded.len()))
            .legend(|(x, y)| Rectangle::new([(x, y - 5), (x + 10, y + 5)], colour(1).filled()));
        chart
            .draw_series(LineSeries::new(
                dr.iter()
                    .enumerate()
                    .map(|(b, &y)| (lo + (b as f64 + 0.5) * w, y)),
                BLACK.stroke_width(2),
            ))?
            .label("target density")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], BLACK.stroke_width(2)));
        draw_legend(&mut chart, SeriesLabelPosition::MiddleRight)?;
        root.present()?;
        Ok(())
    };
    draw().map_err(|e| BenchError::Run(format!("drawing {}: {e}", path.display())))
}
