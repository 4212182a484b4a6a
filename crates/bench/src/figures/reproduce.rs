//! The figure of a reproduction: one panel per quantity, the published value of each case
//! (open squares) beside the recomputed one (dots with ± one standard error).

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{FONT, Res, colour, group_label, groups_apart, panels_by_columns, range};
use crate::error::BenchError;

/// One cell of a reproduction, for the figure.
pub struct ReproducePoint {
    /// Index of the case (the x position).
    pub case: usize,
    /// Index of the quantity (the panel).
    pub quantity: usize,
    pub published: Option<f64>,
    /// The recomputed value and its standard error.
    pub recomputed: Option<(f64, Option<f64>)>,
}

/// Draws `figures/reproduce.png` and `.svg` into `out`; returns `(relative path, caption)`.
pub fn reproduce_figure(
    out: &Path,
    title: &str,
    axis: &str,
    cases: &[String],
    quantities: &[String],
    pts: &[ReproducePoint],
) -> Result<Vec<(String, String)>, BenchError> {
    let dir = out.join("figures");
    std::fs::create_dir_all(&dir)
        .map_err(|e| BenchError::Run(format!("creating {}: {e}", dir.display())))?;
    let height = 120 + 300 * quantities.len() as u32;
    both!(dir, "reproduce", (900, height), |root: &DrawingArea<
        _,
        Shift,
    >| panels(
        root, title, axis, cases, quantities, pts
    ))?;
    Ok(vec![(
        "figures/reproduce.png".into(),
        "Published values (open squares) and recomputed ones (dots, ± one standard error) per \
         case"
            .into(),
    )])
}

/// The title, then one panel per quantity.
fn panels<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    axis: &str,
    cases: &[String],
    quantities: &[String],
    pts: &[ReproducePoint],
) -> Res
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let (top, rest) = root.split_vertically(50);
    top.draw_text(title, &(FONT, 20).into_text_style(&top), (15, 15))?;
    // One key for every panel, in the title bar, where it hides no point.
    let key = (FONT, 14).into_text_style(&top);
    top.draw(&Rectangle::new(
        [(560, 14), (572, 26)],
        colour(0).stroke_width(2),
    ))?;
    top.draw_text("published", &key, (580, 13))?;
    top.draw(&Circle::new((716, 20), 6, colour(1).filled()))?;
    top.draw_text("recomputed ± SE", &key, (728, 13))?;
    for (q, panel) in rest.split_evenly((quantities.len(), 1)).iter().enumerate() {
        let mine: Vec<&ReproducePoint> = pts.iter().filter(|p| p.quantity == q).collect();
        quantity_panel(panel, &quantities[q], axis, cases, &mine)?;
    }
    Ok(())
}

/// Decimals that tell apart ticks about a fifth of `[lo, hi]` apart: z from 4 to 6 reads
/// "4.5", not "4.5000"; φ from 0.62 to 0.64 keeps four.
fn tick_digits(lo: f64, hi: f64) -> usize {
    let step = (hi - lo) / 5.0;
    if !(step.is_finite() && step > 0.0) {
        return 4;
    }
    (-step.log10()).ceil().clamp(0.0, 6.0) as usize
}

/// Cases whose values differ by more than this fraction get axes of their own: 2D disks (φ_J
/// 0.84) beside 3D spheres (0.64) on one axis would hide a gap of several standard errors.
const SEPARATE_AXES_RELATIVE_GAP: f64 = 0.03;

/// One quantity: the cases in groups of close values ([`groups_apart`]), each group a panel
/// with its own axis, under one caption.
fn quantity_panel<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    quantity: &str,
    axis: &str,
    cases: &[String],
    pts: &[&ReproducePoint],
) -> Res
where
    DB::ErrorType: 'static,
{
    let (top, body) = root.split_vertically(26);
    top.titled(quantity, (FONT, 16))?;
    let values = (0..cases.len())
        .filter_map(|c| {
            let p = pts.iter().find(|p| p.case == c)?;
            let v = p.published.or(p.recomputed.map(|r| r.0))?;
            v.is_finite().then_some((c, v))
        })
        .collect();
    let groups = groups_apart(values, |a, b| {
        (b - a).abs() > SEPARATE_AXES_RELATIVE_GAP * a.abs().max(b.abs())
    });
    for (area, group) in panels_by_columns(&body, &groups, 110.0).iter().zip(&groups) {
        let mine: Vec<&ReproducePoint> = pts
            .iter()
            .filter(|p| group.contains(&p.case))
            .copied()
            .collect();
        case_column(area, axis, cases, group, &mine)?;
    }
    Ok(())
}

/// The cases `group` of one quantity on one axis: published values as open squares,
/// recomputed ones as dots with ± one standard error.
fn case_column<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    axis: &str,
    cases: &[String],
    group: &[usize],
    pts: &[&ReproducePoint],
) -> Res
where
    DB::ErrorType: 'static,
{
    let values = pts.iter().flat_map(|p| {
        let (v, se) = p.recomputed.unwrap_or((f64::NAN, None));
        let se = se.unwrap_or(0.0);
        [p.published, Some(v - se), Some(v + se)]
            .into_iter()
            .flatten()
            .filter(|x| x.is_finite())
    });
    let (lo, hi) = range(values, 0.15);
    let digits = tick_digits(lo, hi);
    let x_of = |case: usize| group.iter().position(|&c| c == case).unwrap_or(0) as f64;
    let mut chart = ChartBuilder::on(root)
        .margin(10)
        .x_label_area_size(45)
        .y_label_area_size(80)
        .build_cartesian_2d(-0.5f64..group.len() as f64 - 0.5, lo..hi)?;
    chart
        .configure_mesh()
        .label_style((FONT, 12))
        .axis_desc_style((FONT, 13))
        .x_desc(axis)
        .disable_x_mesh()
        .x_labels(group.len().max(2))
        .x_label_formatter(&|x| group_label(*x, group, cases))
        // At most six labels, the spacing `tick_digits` assumes (with more, neighbours at
        // that many decimals read alike: 0.844, 0.844, 0.843).
        .y_labels(6)
        .y_label_formatter(&|y| format!("{y:.digits$}"))
        .draw()?;
    let (published, recomputed) = (colour(0), colour(1));
    chart.draw_series(pts.iter().filter_map(|p| {
        let y = p.published?;
        Some(
            EmptyElement::at((x_of(p.case) - 0.1, y))
                + Rectangle::new([(-6, -6), (6, 6)], published.stroke_width(2)),
        )
    }))?;
    chart.draw_series(pts.iter().filter_map(|p| {
        let (v, _) = p.recomputed?;
        Some(Circle::new((x_of(p.case) + 0.1, v), 5, recomputed.filled()))
    }))?;
    chart.draw_series(pts.iter().filter_map(|p| {
        let (v, se) = p.recomputed?;
        let se = se?;
        let x = x_of(p.case) + 0.1;
        Some(PathElement::new(
            vec![(x, v - se), (x, v + se)],
            recomputed.stroke_width(2),
        ))
    }))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::groups_apart;
    use super::{SEPARATE_AXES_RELATIVE_GAP, tick_digits};

    /// O'Hern's 2D disks (φ_J 0.84, z 4) and 3D spheres (0.64, 6) get an axis each; the
    /// Baranau table's φ from 0.64 to 0.67 over σ share one.
    #[test]
    fn cases_far_apart_get_axes_of_their_own() {
        let apart = |a: f64, b: f64| (b - a).abs() > SEPARATE_AXES_RELATIVE_GAP * a.max(b);
        assert_eq!(
            groups_apart(vec![(0, 0.842), (1, 0.639)], apart),
            vec![vec![0], vec![1]]
        );
        assert_eq!(groups_apart(vec![(0, 4.0), (1, 6.0)], apart).len(), 2);
        let sigma = vec![(0, 0.640), (1, 0.645), (2, 0.652), (3, 0.660), (4, 0.668)];
        assert_eq!(groups_apart(sigma, apart), vec![vec![0, 1, 2, 3, 4]]);
    }

    #[test]
    fn ticks_carry_the_decimals_their_spacing_needs() {
        assert_eq!(tick_digits(4.0, 6.0), 1);
        assert_eq!(tick_digits(0.62, 0.64), 3);
        assert_eq!(tick_digits(0.60, 0.87), 2);
        assert_eq!(tick_digits(1.0, 1.0), 4);
    }
}
