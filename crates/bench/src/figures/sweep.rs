//! The speed–accuracy figures of a sweep: runtime against |φ_J − φ_ref|, and φ_J against the
//! knob.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{FONT, Res, colour, draw_legend, range};
use crate::error::BenchError;

/// One run of a sweep, for the speed–accuracy figures.
pub struct SweepPoint {
    pub value: f64,
    pub runtime_s: f64,
    pub phi: f64,
    /// |φ_J − φ_ref|.
    pub error: f64,
    /// The isostatic gap; `None` when every particle is a rattler (undefined).
    pub iso_gap: Option<f64>,
    /// φ after the sweep's `--refine` method.
    pub refined_phi: Option<f64>,
}

/// The Pareto plot (runtime against |φ_J − φ_ref|) and φ_J against the knob (with the
/// refined φ beside it when the sweep chains a `refiner`).
pub fn sweep(
    out: &Path,
    method: &str,
    knob: &str,
    refiner: Option<&str>,
    pts: &[SweepPoint],
) -> Result<Vec<(String, String)>, BenchError> {
    let dir = out.join("figures");
    std::fs::create_dir_all(&dir)
        .map_err(|e| BenchError::Run(format!("creating {}: {e}", dir.display())))?;
    if pts.is_empty() {
        return Ok(vec![]);
    }
    both!(dir, "pareto", (900, 560), |root: &DrawingArea<_, Shift>| {
        pareto(root, method, knob, pts)
    })?;
    both!(dir, "phi_vs_knob", (900, 560), |root: &DrawingArea<
        _,
        Shift,
    >| phi_vs_knob(
        root, method, knob, refiner, pts
    ))?;
    let against = knob_axis(knob, pts).0;
    Ok(vec![
        (
            "figures/pareto.png".into(),
            format!(
                "{method}: runtime against |φ_J − φ_ref| (log–log), one dot per run, coloured by {knob}"
            ),
        ),
        (
            "figures/phi_vs_knob.png".into(),
            match refiner {
                Some(r) => {
                    format!("{method} φ and the φ after {r} of each packing, against {against}")
                }
                None => format!("{method}: φ_J against {against}"),
            },
        ),
    ])
}

/// The x axis of φ against a knob: a compression rate γ is drawn as 1/γ, the compression
/// time, as in Baranau & Tallarek 2014 Fig. 2 (slow compressions to the right); other knobs as they are.
/// Returns the axis label and the map from knob value to x.
fn knob_axis(knob: &str, pts: &[SweepPoint]) -> (String, fn(f64) -> f64) {
    if knob == "rate" && pts.iter().all(|p| p.value > 0.0) {
        ("1/γ".into(), |v| 1.0 / v)
    } else {
        (knob.to_string(), |v| v)
    }
}

fn pareto<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    method: &str,
    knob: &str,
    pts: &[SweepPoint],
) -> Res
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    // Reference runs have zero error; draw them at the floor of the axis.
    let floor = pts
        .iter()
        .map(|p| p.error)
        .filter(|&e| e > 0.0)
        .fold(f64::INFINITY, f64::min)
        .min(1e-3)
        / 10.0;
    let emax = pts.iter().map(|p| p.error).fold(floor * 10.0, f64::max) * 3.0;
    let tmin = pts
        .iter()
        .map(|p| p.runtime_s)
        .fold(f64::INFINITY, f64::min)
        .max(1e-4)
        / 2.0;
    let tmax = pts.iter().map(|p| p.runtime_s).fold(tmin * 10.0, f64::max) * 2.0;
    let mut chart = ChartBuilder::on(root)
        .caption(format!("{method}: speed against accuracy"), (FONT, 24))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(80)
        .build_cartesian_2d((tmin..tmax).log_scale(), (floor..emax).log_scale())?;
    chart
        .configure_mesh()
        .label_style((FONT, 12))
        .axis_desc_style((FONT, 14))
        .x_desc("runtime per packing (s)")
        .y_desc("|φ_J − φ_ref|")
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .draw()?;
    let mut values: Vec<f64> = pts.iter().map(|p| p.value).collect();
    values.sort_by(f64::total_cmp);
    values.dedup();
    for (k, &v) in values.iter().enumerate() {
        let c = colour(k);
        chart
            .draw_series(
                pts.iter()
                    .filter(|p| p.value == v)
                    .map(|p| Circle::new((p.runtime_s, p.error.max(floor)), 6, c.filled())),
            )?
            .label(format!("{knob} = {v:e}"))
            .legend(move |(x, y)| Circle::new((x, y), 5, c.filled()));
    }
    draw_legend(&mut chart, SeriesLabelPosition::MiddleRight)?;
    Ok(())
}

fn phi_vs_knob<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    method: &str,
    knob: &str,
    refiner: Option<&str>,
    pts: &[SweepPoint],
) -> Res
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let (label, to_x) = knob_axis(knob, pts);
    let (lo, hi) = range(
        pts.iter()
            .flat_map(|p| std::iter::once(p.phi).chain(p.refined_phi)),
        0.15,
    );
    let xs: Vec<f64> = pts.iter().map(|p| to_x(p.value)).collect();
    let caption = format!("{method}: φ against {label}");
    let series = |refined: bool| -> Vec<(f64, f64)> {
        pts.iter()
            .filter_map(|p| Some((to_x(p.value), if refined { p.refined_phi? } else { p.phi })))
            .collect()
    };
    let names = [
        format!("{method} φ"),
        format!("after {}", refiner.unwrap_or_default()),
    ];
    let builder = |root| {
        let mut b = ChartBuilder::on(root);
        b.caption(&caption, (FONT, 24))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(80);
        b
    };
    // Log axis for positive knobs spanning a decade or more, linear otherwise; plotters types
    // the two differently, so the series are drawn by one generic function.
    let (xmin, xmax) = xs
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    if xmin > 0.0 && xmax >= 10.0 * xmin {
        let mut chart =
            builder(root).build_cartesian_2d((xmin / 2.0..xmax * 2.0).log_scale(), lo..hi)?;
        chart
            .configure_mesh()
            .label_style((FONT, 12))
            .axis_desc_style((FONT, 14))
            .x_desc(label.as_str())
            .y_desc("φ")
            .y_label_formatter(&|y| format!("{y:.4}"))
            .x_label_formatter(&|x| format!("{x:.0e}"))
            .draw()?;
        draw_phi_series(&mut chart, [series(false), series(true)], &names)
    } else {
        let (a, b) = range(xs.iter().copied(), 0.1);
        let mut chart = builder(root).build_cartesian_2d(a..b, lo..hi)?;
        chart
            .configure_mesh()
            .label_style((FONT, 12))
            .axis_desc_style((FONT, 14))
            .x_desc(label.as_str())
            .y_desc("φ")
            .y_label_formatter(&|y| format!("{y:.4}"))
            .draw()?;
        draw_phi_series(&mut chart, [series(false), series(true)], &names)
    }
}

/// Dots of φ (and of the refined φ, when there is any) with a legend if both are drawn.
fn draw_phi_series<
    'a,
    DB: DrawingBackend + 'a,
    X: plotters::coord::ranged1d::Ranged<ValueType = f64>,
>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, plotters::coord::types::RangedCoordf64>>,
    series: [Vec<(f64, f64)>; 2],
    names: &[String; 2],
) -> Res
where
    DB::ErrorType: 'static,
{
    let both = !series[1].is_empty();
    for (k, pts) in series.into_iter().enumerate() {
        if pts.is_empty() {
            continue;
        }
        let c = colour(k);
        let s = chart.draw_series(pts.into_iter().map(|p| Circle::new(p, 5, c.filled())))?;
        if both {
            s.label(names[k].as_str())
                .legend(move |(x, y)| Circle::new((x, y), 5, c.filled()));
        }
    }
    if both {
        draw_legend(chart, SeriesLabelPosition::UpperLeft)?;
    }
    Ok(())
}
