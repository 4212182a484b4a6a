//! The figures of a comparison: φ per method, runtime against φ, φ histograms, and each
//! method's packing of the first seed drawn to scale.

use std::path::Path;

use packbench_core::Packing;
use packbench_core::analysis::structure::{StructureOptions, analyze_structure};
use plotters::coord::Shift;
use plotters::prelude::*;

use super::{
    FONT, Res, colour, draw_gr, draw_legend, draw_packing, group_label, groups_apart,
    panels_by_columns, radial_distribution, range,
};
use crate::error::BenchError;
use crate::records::RunsFile;

/// Every figure of a comparison; returns `(relative path, caption)` pairs.
pub fn comparison(
    out: &Path,
    file: &RunsFile,
    packing: impl Fn(&str, u64) -> Option<Packing>,
) -> Result<Vec<(String, String)>, BenchError> {
    let dir = out.join("figures");
    std::fs::create_dir_all(&dir)
        .map_err(|e| BenchError::Run(format!("creating {}: {e}", dir.display())))?;
    let methods = &file.config.methods;
    let mut figs = Vec::new();
    let points: Vec<(usize, f64, f64)> = file
        .runs
        .iter()
        .filter_map(|r| {
            Some((
                methods.iter().position(|m| m == &r.method)?,
                r.phi?,
                r.runtime_s,
            ))
        })
        .collect();
    if !points.is_empty() {
        // Room for each method's name under its column (closest-jammed-qp is 17 characters).
        let width = 900.max(200 + 125 * methods.len() as u32);
        both!(dir, "phi_by_method", (width, 520), |root: &DrawingArea<
            _,
            Shift,
        >| phi_strip(
            root, methods, &points
        ))?;
        figs.push((
            "figures/phi_by_method.png".into(),
            "φ_J of every run per method (dots), mean ± std (bars)".into(),
        ));
        both!(dir, "runtime_vs_phi", (900, 520), |root: &DrawingArea<
            _,
            Shift,
        >| {
            runtime_scatter(root, methods, &points)
        })?;
        figs.push((
            "figures/runtime_vs_phi.png".into(),
            "Runtime against φ_J: what each method buys with time".into(),
        ));
        both!(dir, "phi_histogram", (900, 520), |root: &DrawingArea<
            _,
            Shift,
        >| phi_histogram(
            root, methods, &points
        ))?;
        figs.push((
            "figures/phi_histogram.png".into(),
            "Histogram of φ_J over the ensemble, per method".into(),
        ));
    }
    let first = file.config.base_seed;
    let mut gr_series = Vec::new();
    let mut structures = Vec::new();
    for m in methods {
        if let Some(p) = packing(m, first) {
            both!(
                dir,
                format!("packing_{m}"),
                (720, 720),
                |root: &DrawingArea<_, Shift>| draw_packing(root, &p, m)
            )?;
            let what = if p.dim == 2 {
                "drawn to scale"
            } else {
                "a slice through the middle"
            };
            figs.push((
                format!("figures/packing_{m}.png"),
                format!("{m}, seed {first}: {what}; rattlers red, contacts black"),
            ));
            if p.container.is_fully_periodic() {
                gr_series.push((m.clone(), radial_distribution(&p, 200)));
            }
            structures.push((
                m.clone(),
                analyze_structure(&p, &StructureOptions::default())?,
            ));
        }
    }
    if !gr_series.is_empty() {
        both!(dir, "g_of_r", (900, 520), |root: &DrawingArea<_, Shift>| {
            draw_gr(root, &gr_series)
        })?;
        figs.push((
            "figures/g_of_r.png".into(),
            format!("Radial distribution g(r) of seed {first}, r in mean diameters"),
        ));
    }
    figs.extend(super::structure::comparison(&dir, &structures)?);
    Ok(figs)
}

/// φ apart, between the means of two methods, past which they get separate axes: a filling
/// method (seq-fill near 0.55) beside jammed ones (0.62–0.66) would squeeze the jammed ones'
/// spread of a few 10⁻³ into a thin band.
const SEPARATE_AXES_GAP: f64 = 0.03;

/// The methods (indices into `methods`) in groups whose mean φ lie within
/// [`SEPARATE_AXES_GAP`] of the next ([`groups_apart`]); methods without a point are left out.
fn phi_groups(methods: &[String], pts: &[(usize, f64, f64)]) -> Vec<Vec<usize>> {
    let means = (0..methods.len())
        .filter_map(|k| {
            let vals: Vec<f64> = pts.iter().filter(|p| p.0 == k).map(|p| p.1).collect();
            crate::records::mean_std(&vals).map(|(m, _)| (k, m))
        })
        .collect();
    groups_apart(means, |a, b| b - a > SEPARATE_AXES_GAP)
}

/// φ_J per method: every run a dot, the mean a bar with ± one std. Methods whose φ lie far
/// apart ([`phi_groups`]) get side-by-side panels with axes of their own.
fn phi_strip<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    methods: &[String],
    pts: &[(usize, f64, f64)],
) -> Res
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let groups = phi_groups(methods, pts);
    let caption = if groups.len() > 1 {
        "φ_J per method (separate φ axes: the groups lie far apart)"
    } else {
        "φ_J per method"
    };
    let (top, body) = root.split_vertically(45);
    top.titled(caption, (FONT, 22))?;
    for (area, g) in panels_by_columns(&body, &groups, 100.0).iter().zip(&groups) {
        method_column(area, methods, g, pts)?;
    }
    Ok(())
}

/// One panel of [`phi_strip`]: the methods `group` on their own φ axis.
fn method_column<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    methods: &[String],
    group: &[usize],
    pts: &[(usize, f64, f64)],
) -> Res
where
    DB::ErrorType: 'static,
{
    let mine = |k: usize| pts.iter().filter(move |p| p.0 == k).map(|p| p.1);
    let (lo, hi) = range(group.iter().flat_map(|&k| mine(k)), 0.15);
    let mut chart = ChartBuilder::on(area)
        .margin(15)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(-0.5f64..group.len() as f64 - 0.5, lo..hi)?;
    chart
        .configure_mesh()
        .label_style((FONT, 12))
        .axis_desc_style((FONT, 14))
        .disable_x_mesh()
        .x_labels(group.len().max(2))
        .x_label_formatter(&|x| group_label(*x, group, methods))
        .y_desc("φ_J")
        .y_label_formatter(&|y| format!("{y:.4}"))
        .draw()?;
    for (x, &k) in group.iter().enumerate() {
        let x = x as f64;
        let vals: Vec<f64> = mine(k).collect();
        let c = colour(k);
        let n = vals.len().max(1) as f64;
        chart.draw_series(vals.iter().enumerate().map(|(j, &v)| {
            let jitter = 0.25 * ((j as f64 + 0.5) / n - 0.5);
            Circle::new((x + jitter, v), 5, c.mix(0.7).filled())
        }))?;
        if let Some((m, s)) = crate::records::mean_std(&vals) {
            chart.draw_series(std::iter::once(PathElement::new(
                vec![(x - 0.3, m), (x + 0.3, m)],
                c.stroke_width(3),
            )))?;
            chart.draw_series(std::iter::once(PathElement::new(
                vec![(x, m - s), (x, m + s)],
                c.stroke_width(2),
            )))?;
        }
    }
    Ok(())
}

fn runtime_scatter<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    methods: &[String],
    pts: &[(usize, f64, f64)],
) -> Res
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let (lo, hi) = range(pts.iter().map(|p| p.1), 0.15);
    let tmin = pts
        .iter()
        .map(|p| p.2)
        .fold(f64::INFINITY, f64::min)
        .max(1e-4)
        * 0.5;
    let tmax = pts.iter().map(|p| p.2).fold(0.0, f64::max).max(tmin * 10.0) * 2.0;
    let mut chart = ChartBuilder::on(root)
        .caption("Runtime against φ_J", (FONT, 24))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d((tmin..tmax).log_scale(), lo..hi)?;
    chart
        .configure_mesh()
        .label_style((FONT, 12))
        .axis_desc_style((FONT, 14))
        .x_desc("runtime per packing (s, log scale)")
        .y_desc("φ_J")
        .y_label_formatter(&|y| format!("{y:.4}"))
        .draw()?;
    for (k, m) in methods.iter().enumerate() {
        let c = colour(k);
        chart
            .draw_series(
                pts.iter()
                    .filter(|p| p.0 == k)
                    .map(|p| Circle::new((p.2, p.1), 5, c.filled())),
            )?
            .label(m.as_str())
            .legend(move |(x, y)| Circle::new((x, y), 5, c.filled()));
    }
    draw_legend(&mut chart, SeriesLabelPosition::MiddleRight)?;
    Ok(())
}

fn phi_histogram<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    methods: &[String],
    pts: &[(usize, f64, f64)],
) -> Res
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let (lo, hi) = range(pts.iter().map(|p| p.1), 0.05);
    let bins = 20usize;
    let width = (hi - lo) / bins as f64;
    let counts: Vec<Vec<usize>> = (0..methods.len())
        .map(|k| {
            let mut c = vec![0usize; bins];
            for p in pts.iter().filter(|p| p.0 == k) {
                c[(((p.1 - lo) / width) as usize).min(bins - 1)] += 1;
            }
            c
        })
        .collect();
    let ymax = counts.iter().flatten().cloned().max().unwrap_or(1) as f64 + 1.0;
    let mut chart = ChartBuilder::on(root)
        .caption("Distribution of φ_J", (FONT, 24))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(50)
        .build_cartesian_2d(lo..hi, 0.0..ymax)?;
    chart
        .configure_mesh()
        .label_style((FONT, 12))
        .axis_desc_style((FONT, 14))
        .x_desc("φ_J")
        .y_desc("runs")
        .x_label_formatter(&|x| format!("{x:.4}"))
        .draw()?;
    let share = width / methods.len().max(1) as f64;
    for (k, m) in methods.iter().enumerate() {
        let c = colour(k);
        chart
            .draw_series(
                counts[k]
                    .iter()
                    .enumerate()
                    .filter(|(_, n)| **n > 0)
                    .map(|(b, &n)| {
                        let x0 = lo + b as f64 * width + k as f64 * share;
                        Rectangle::new([(x0, 0.0), (x0 + share, n as f64)], c.mix(0.8).filled())
                    }),
            )?
            .label(m.as_str())
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 10, y + 5)], c.filled()));
    }
    draw_legend(&mut chart, SeriesLabelPosition::MiddleRight)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// seq-fill's 0.55 beside jammed methods at 0.62–0.64 gets an axis of its own; methods
    /// 0.01 apart share one, in the methods' order.
    #[test]
    fn far_apart_methods_get_separate_axes() {
        let methods: Vec<String> = ["adam", "seq-fill", "mls"].map(String::from).to_vec();
        let pts = [
            (0, 0.630, 1.0),
            (0, 0.632, 1.0),
            (1, 0.550, 1.0),
            (2, 0.640, 1.0),
        ];
        assert_eq!(phi_groups(&methods, &pts), vec![vec![0, 2], vec![1]]);
        let close = [(0, 0.63, 1.0), (1, 0.62, 1.0), (2, 0.64, 1.0)];
        assert_eq!(phi_groups(&methods, &close), vec![vec![0, 1, 2]]);
    }
}
