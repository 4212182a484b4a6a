//! The figures of a design search: its history (φ_J of each packed candidate and of the best
//! so far against the packings used; predicted against packed φ_J) and the probability density
//! of the best distribution's diameters.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{FONT, Res, colour, draw_legend, range};
use crate::error::BenchError;

/// One packed candidate of a design search, for the history figure.
pub struct DesignPoint {
    /// Island (search) the candidate belongs to.
    pub island: usize,
    /// Packings the island had used when the candidate's generation finished.
    pub packings: usize,
    /// Mean φ_J over the candidate's seeds.
    pub phi: f64,
    /// φ_J of the best candidate of the island so far (by the objective).
    pub best_phi: f64,
    /// Desmond–Weeks and Farr–Groot predictions of φ_RCP.
    pub predicted_dw: Option<f64>,
    pub predicted_fg: Option<f64>,
}

/// Writes `figures/history.{png,svg}` and `figures/distribution.{png,svg}` under `out`; returns
/// each PNG's path relative to `out` with a caption.
pub fn design_figures(
    out: &Path,
    title: &str,
    target: Option<f64>,
    pts: &[DesignPoint],
    diameters: &[f64],
) -> Result<Vec<(String, String)>, BenchError> {
    let dir = out.join("figures");
    std::fs::create_dir_all(&dir)
        .map_err(|e| BenchError::Run(format!("creating {}: {e}", dir.display())))?;
    let mut figs = Vec::new();
    if !pts.is_empty() {
        both!(dir, "history", (1200, 520), |root: &DrawingArea<
            _,
            Shift,
        >| {
            history(root, title, target, pts)
        })?;
        figs.push((
            "figures/history.png".into(),
            "left: φ_J of each packed candidate (dots) and of the best so far (line) against the \
             packings used; right: predicted φ_RCP against packed φ_J, one dot per candidate"
                .into(),
        ));
    }
    if !diameters.is_empty() {
        both!(dir, "distribution", (900, 520), |root: &DrawingArea<
            _,
            Shift,
        >| density(
            root, diameters
        ))?;
        figs.push((
            "figures/distribution.png".into(),
            format!(
                "probability density of the best distribution's diameters ({} drawn)",
                diameters.len()
            ),
        ));
    }
    Ok(figs)
}

/// The history figure: φ_J of each packed candidate against the packings used, with the best
/// so far (left), and the predictions against the packed φ_J (right).
fn history<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    target: Option<f64>,
    pts: &[DesignPoint],
) -> Res
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let (left, right) = root.split_horizontally(680);
    search_panel(&left, title, target, pts)?;
    predictor_panel(&right, pts)
}

/// φ_J of each packed candidate against the packings its island had used, and each island's
/// best so far, with the target when there is one.
fn search_panel<DB: DrawingBackend>(
    left: &DrawingArea<DB, Shift>,
    title: &str,
    target: Option<f64>,
    pts: &[DesignPoint],
) -> Res
where
    DB::ErrorType: 'static,
{
    let xmax = pts.iter().map(|p| p.packings).max().unwrap_or(1).max(1) as f64;
    let (lo, hi) = range(pts.iter().map(|p| p.phi).chain(target), 0.1);
    let mut chart = ChartBuilder::on(left)
        .caption(title, (FONT, 20))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(80)
        .build_cartesian_2d(0.0..xmax * 1.05, lo..hi)?;
    chart
        .configure_mesh()
        .label_style((FONT, 12))
        .axis_desc_style((FONT, 14))
        .x_desc("packings used")
        .y_desc("φ_J")
        .y_label_formatter(&|y| format!("{y:.4}"))
        .draw()?;
    let mut islands: Vec<usize> = pts.iter().map(|p| p.island).collect();
    islands.sort_unstable();
    islands.dedup();
    for (k, &i) in islands.iter().enumerate() {
        let c = colour(k);
        let mine: Vec<&DesignPoint> = pts.iter().filter(|p| p.island == i).collect();
        chart.draw_series(
            mine.iter()
                .map(|p| Circle::new((p.packings as f64, p.phi), 3, c.mix(0.5).filled())),
        )?;
        // One step per generation: the best at the end of it (the last point of its packings).
        let mut steps: Vec<(f64, f64)> = Vec::new();
        for p in &mine {
            match steps.last_mut() {
                Some(last) if last.0 == p.packings as f64 => last.1 = p.best_phi,
                _ => steps.push((p.packings as f64, p.best_phi)),
            }
        }
        chart
            .draw_series(LineSeries::new(steps, c.stroke_width(2)))?
            .label(if islands.len() > 1 {
                format!("best so far, island {i}")
            } else {
                "best so far".into()
            })
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], c.stroke_width(2)));
    }
    if let Some(t) = target {
        chart
            .draw_series(LineSeries::new(
                [(0.0, t), (xmax * 1.05, t)],
                BLACK.stroke_width(1),
            ))?
            .label(format!("target {t}"))
            .legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], BLACK));
    }
    draw_legend(&mut chart, SeriesLabelPosition::LowerRight)?;
    Ok(())
}

/// Desmond–Weeks and Farr–Groot predictions against the packed φ_J, with the diagonal.
fn predictor_panel<DB: DrawingBackend>(right: &DrawingArea<DB, Shift>, pts: &[DesignPoint]) -> Res
where
    DB::ErrorType: 'static,
{
    let preds: Vec<f64> = pts
        .iter()
        .flat_map(|p| p.predicted_dw.into_iter().chain(p.predicted_fg))
        .collect();
    let (a, b) = range(pts.iter().map(|p| p.phi).chain(preds.iter().copied()), 0.1);
    let mut chart = ChartBuilder::on(right)
        .caption("predicted against packed", (FONT, 20))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(80)
        .build_cartesian_2d(a..b, a..b)?;
    chart
        .configure_mesh()
        .label_style((FONT, 12))
        .axis_desc_style((FONT, 14))
        .x_desc("packed φ_J")
        .y_desc("predicted φ_RCP")
        .x_label_formatter(&|x| format!("{x:.3}"))
        .y_label_formatter(&|y| format!("{y:.3}"))
        .draw()?;
    chart.draw_series(LineSeries::new([(a, a), (b, b)], BLACK.mix(0.5)))?;
    if preds.is_empty() {
        return Ok(());
    }
    let (c0, c1) = (colour(2), colour(3));
    chart
        .draw_series(
            pts.iter()
                .filter_map(|p| Some(Circle::new((p.phi, p.predicted_dw?), 4, c0.filled()))),
        )?
        .label("Desmond–Weeks")
        .legend(move |(x, y)| Circle::new((x, y), 4, c0.filled()));
    chart
        .draw_series(
            pts.iter()
                .filter_map(|p| Some(Circle::new((p.phi, p.predicted_fg?), 4, c1.filled()))),
        )?
        .label("Farr–Groot")
        .legend(move |(x, y)| Circle::new((x, y), 4, c1.filled()));
    draw_legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
    Ok(())
}

fn density<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, diameters: &[f64]) -> Res
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let (lo, hi) = range(diameters.iter().copied(), 0.02);
    let bins = 60usize;
    let w = (hi - lo) / bins as f64;
    let mut c = vec![0.0; bins];
    for &x in diameters {
        c[(((x - lo) / w) as usize).min(bins - 1)] += 1.0;
    }
    let total = diameters.len() as f64 * w;
    let dens: Vec<f64> = c.iter().map(|n| n / total).collect();
    let ymax = dens.iter().cloned().fold(0.0, f64::max) * 1.1;
    let mut chart = ChartBuilder::on(root)
        .caption("Best distribution: density of diameters", (FONT, 22))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(80)
        .build_cartesian_2d(lo..hi, 0.0..ymax.max(1e-12))?;
    chart
        .configure_mesh()
        .label_style((FONT, 12))
        .axis_desc_style((FONT, 14))
        .x_desc("diameter (smallest or scale = 1)")
        .y_desc("probability density")
        .draw()?;
    chart.draw_series(dens.iter().enumerate().map(|(b, &y)| {
        let x0 = lo + b as f64 * w;
        Rectangle::new([(x0, 0.0), (x0 + w, y)], colour(0).mix(0.75).filled())
    }))?;
    Ok(())
}
