//! Figures with plotters, each written as PNG and SVG, one module per kind of figure. They
//! read records and packings only; they run nothing.

use plotters::prelude::*;

/// Font family of every label. Plotters' bitmap text drops the part of a glyph left of its
/// origin, and in proportional fonts 'j' and 'J' start there (they vanished from "φ_J" and
/// "closest-jammed"); monospace glyphs never do, and every fontconfig system has one.
const FONT: &str = "monospace";

/// What a drawing returns: plotters' errors differ by backend.
type Res = Result<(), Box<dyn std::error::Error>>;

/// Colour of series `i`.
fn colour(i: usize) -> RGBColor {
    const C: [RGBColor; 8] = [
        RGBColor(31, 119, 180),
        RGBColor(255, 127, 14),
        RGBColor(44, 160, 44),
        RGBColor(214, 39, 40),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
        RGBColor(23, 190, 207),
    ];
    C[i % C.len()]
}

/// Draws with `draw` into `<dir>/<stem>.png` and `.svg`; returns the PNG's path relative to
/// the report.
macro_rules! both {
    ($dir:expr, $stem:expr, $size:expr, $draw:expr) => {{
        let png = $dir.join(format!("{}.png", $stem));
        let svg = $dir.join(format!("{}.svg", $stem));
        let r1: Res = (|| {
            let root = BitMapBackend::new(&png, $size).into_drawing_area();
            $draw(&root)?;
            root.present()?;
            Ok(())
        })();
        let r2: Res = (|| {
            let root = SVGBackend::new(&svg, $size).into_drawing_area();
            $draw(&root)?;
            root.present()?;
            Ok(())
        })();
        r1.and(r2)
            .map_err(|e| BenchError::Run(format!("drawing {}: {e}", png.display())))
    }};
}

/// Draws the legend of `chart` at `position`: the figures' font on a light, framed box.
fn draw_legend<'a, DB, CT>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
) -> Res
where
    DB: DrawingBackend + 'a,
    DB::ErrorType: 'static,
    CT: plotters::coord::CoordTranslate,
{
    chart
        .configure_series_labels()
        .label_font((FONT, 13))
        .position(position)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()?;
    Ok(())
}

/// The 2D chart of one panel on `area`: caption, the figures' margins, a mesh with the axis
/// labels `xdesc` and `ydesc`, and the axis ranges `x` and `y`.
#[allow(clippy::too_many_arguments)]
fn panel<'a, 'b, DB>(
    area: &'a DrawingArea<DB, plotters::coord::Shift>,
    caption: &str,
    caption_size: u32,
    y_label_area: u32,
    x: std::ops::Range<f64>,
    y: std::ops::Range<f64>,
    xdesc: &str,
    ydesc: &str,
) -> Result<
    ChartContext<
        'a,
        DB,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
    Box<dyn std::error::Error>,
>
where
    DB: DrawingBackend + 'a,
    DB::ErrorType: 'static,
{
    let mut chart = ChartBuilder::on(area)
        .caption(caption, (FONT, caption_size))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(y_label_area)
        .build_cartesian_2d(x, y)?;
    chart
        .configure_mesh()
        .label_style((FONT, 11))
        .axis_desc_style((FONT, 12))
        .x_desc(xdesc)
        .y_desc(ydesc)
        .draw()?;
    Ok(chart)
}

/// Draws `points` as a line of colour `c`, two pixels wide, with a legend entry `name`.
fn labelled_line<'a, DB>(
    chart: &mut ChartContext<
        'a,
        DB,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
    points: &[(f64, f64)],
    c: RGBAColor,
    name: Option<&str>,
) -> Res
where
    DB: DrawingBackend + 'a,
    DB::ErrorType: 'static,
{
    let line = chart.draw_series(LineSeries::new(points.iter().cloned(), c.stroke_width(2)))?;
    if let Some(name) = name {
        line.label(name)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], c.stroke_width(2)));
    }
    Ok(())
}

/// The range of `values` widened by `pad` of its span on each side ((0, 1) when empty).
fn range(values: impl Iterator<Item = f64>, pad: f64) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
        (a.min(v), b.max(v))
    });
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let span = (hi - lo).max(1e-6 * hi.abs().max(1e-12));
    (lo - pad * span, hi + pad * span)
}

/// Indices of `values` in groups whose values lie close together: sorted by value, a new group
/// starts where `apart(previous, next)`; each group in index order, the groups in the order
/// of their first index. Figures give each group an axis of its own, so that values far
/// apart (seq-fill beside jammed methods, 2D beside 3D) do not squeeze each other's spread.
fn groups_apart(
    mut values: Vec<(usize, f64)>,
    apart: impl Fn(f64, f64) -> bool,
) -> Vec<Vec<usize>> {
    values.sort_by(|a, b| a.1.total_cmp(&b.1));
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for (i, &(k, v)) in values.iter().enumerate() {
        match groups.last_mut() {
            Some(g) if !apart(values[i - 1].1, v) => g.push(k),
            _ => groups.push(vec![k]),
        }
    }
    for g in &mut groups {
        g.sort_unstable();
    }
    groups.sort_by_key(|g| g[0]);
    groups
}

/// The label under column `x` of a panel of `group` (indices into `names`): the name at a
/// whole column, nothing between columns.
fn group_label(x: f64, group: &[usize], names: &[String]) -> String {
    let i = x.round();
    if (x - i).abs() < 1e-6 && i >= 0.0 {
        group
            .get(i as usize)
            .map_or(String::new(), |&k| names[k].clone())
    } else {
        String::new()
    }
}

/// `area` cut into side-by-side panels, one per group, each `frame` pixels (its axis labels
/// and margins) plus a share of the rest by its number of columns.
fn panels_by_columns<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    groups: &[Vec<usize>],
    frame: f64,
) -> Vec<DrawingArea<DB, plotters::coord::Shift>> {
    let width = area.dim_in_pixel().0 as f64 - frame * groups.len() as f64;
    let columns: usize = groups.iter().map(Vec::len).sum::<usize>().max(1);
    let mut rest = area.clone();
    let mut panels = Vec::new();
    for (i, g) in groups.iter().enumerate() {
        if i + 1 == groups.len() {
            panels.push(rest.clone());
        } else {
            let cut = (frame + width * g.len() as f64 / columns as f64).round() as i32;
            let (left, right) = rest.split_horizontally(cut);
            panels.push(left);
            rest = right;
        }
    }
    panels
}

mod comparison;
mod design;
mod packing;
mod pair_correlation;
mod radius_histogram;
mod reproduce;
pub mod structure;
mod sweep;
mod trace;
pub mod void_space;

pub use comparison::comparison;
pub use design::{DesignPoint, design_figures};
pub use packing::draw_packing;
pub use pair_correlation::{draw_gr, radial_distribution};
pub use radius_histogram::radius_histogram;
pub use reproduce::{ReproducePoint, reproduce_figure};
pub use sweep::{SweepPoint, sweep};
pub use trace::{RunTrace, draw_traces, trace_height};
