//! Figures of a packing's structure (PNG or SVG, plotters): S(k), P(f/⟨f⟩) and g(h) on log
//! axes, and the histogram of the local bond order (q6 in 3D, |ψ6| in 2D). Several packings
//! overlay in one chart (`plot`) or get one panel each on the same axes (`compare`).

use std::path::Path;

use packbench_core::analysis::structure::StructureReport;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::{FONT, Res, labelled_line, panel};
use crate::error::BenchError;

/// What a structure figure shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StructureKind {
    /// S(k) against k·D̄, log–log.
    StructureFactor,
    /// P(f/⟨f⟩), log–log.
    Forces,
    /// g(h) of the relative gaps, log–log.
    Gaps,
    /// Histogram of the local q6 (3D) or |ψ6| (2D).
    LocalOrder,
}

impl StructureKind {
    /// Every kind, in the order `compare` draws them.
    pub const ALL: [StructureKind; 4] = [
        StructureKind::StructureFactor,
        StructureKind::LocalOrder,
        StructureKind::Forces,
        StructureKind::Gaps,
    ];

    /// File stem of the figure.
    pub fn stem(self) -> &'static str {
        match self {
            StructureKind::StructureFactor => "structure_factor",
            StructureKind::Forces => "force_distribution",
            StructureKind::Gaps => "gap_distribution",
            StructureKind::LocalOrder => "local_bond_order",
        }
    }

    /// Caption for a report.
    pub fn caption(self) -> &'static str {
        match self {
            StructureKind::StructureFactor => {
                "Structure factor S(k), log–log: S(k→0) → 0 for a hyperuniform packing"
            }
            StructureKind::Forces => {
                "Contact-force distribution P(f/<f>), log–log: P(f) ∝ f^θ at small f, θ > 0 (θ_e = 0.42 extended, θ_ℓ = 0.17 buckler forces at jamming, Charbonneau et al. 2015); legend: θ ± its standard error over f/<f> in [0.01, 0.3]"
            }
            StructureKind::Gaps => {
                "Gap distribution g(h) of near-contacts, log–log; small-gap slope −γ, γ ≈ 0.41 at jamming"
            }
            StructureKind::LocalOrder => {
                "Distribution of the local bond order (q6 in 3D, |ψ6| in 2D)"
            }
        }
    }

    fn labels(self) -> (&'static str, &'static str, bool) {
        match self {
            StructureKind::StructureFactor => (
                "log10 k·D̄ (wave number × mean diameter)",
                "log10 S(k)",
                true,
            ),
            // "<f>": the figures' monospace font has no ⟨ ⟩ glyphs.
            StructureKind::Forces => (
                "log10 f/<f> (force over mean force)",
                "log10 P(f/<f>)",
                true,
            ),
            StructureKind::Gaps => ("log10 h = r/σ − 1 (relative gap)", "log10 g(h)", true),
            StructureKind::LocalOrder => ("local q6 (3D) or |ψ6| (2D)", "density", false),
        }
    }

    /// The points of `r` this kind draws, on the drawn (log10 where logarithmic) axes.
    fn points(self, r: &StructureReport) -> Vec<(f64, f64)> {
        let raw: Vec<(f64, f64)> = match self {
            StructureKind::StructureFactor => r
                .structure_factor
                .as_ref()
                .map(|s| s.k.iter().cloned().zip(s.s.iter().cloned()).collect())
                .unwrap_or_default(),
            StructureKind::Forces => r
                .forces
                .as_ref()
                .map(|f| zip(&f.histogram.x, &f.histogram.density))
                .unwrap_or_default(),
            StructureKind::Gaps => zip(&r.gaps.histogram.x, &r.gaps.histogram.density),
            StructureKind::LocalOrder => zip(
                &r.bond_order.local_histogram.x,
                &r.bond_order.local_histogram.density,
            ),
        };
        if self.labels().2 {
            raw.into_iter()
                .filter(|&(x, y)| x > 0.0 && y > 0.0)
                .map(|(x, y)| (x.log10(), y.log10()))
                .collect()
        } else {
            raw
        }
    }
}

/// The legend entry of packing `name` in a figure of `kind`: for forces, with its θ.
fn legend(kind: StructureKind, name: &str, r: &StructureReport) -> String {
    match (kind, &r.forces) {
        (StructureKind::Forces, Some(f)) => match (f.theta, f.theta_error) {
            (Some(t), Some(e)) => format!("{name}: θ = {t:.2} ± {e:.2}"),
            _ => format!("{name}: θ — (too few small forces)"),
        },
        _ => name.to_string(),
    }
}

fn zip(x: &[f64], y: &[f64]) -> Vec<(f64, f64)> {
    x.iter().cloned().zip(y.iter().cloned()).collect()
}

/// Draws `kind` for the named reports: overlaid in one chart, or one panel each on the same
/// axes when `panels`.
pub fn draw_structure<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    kind: StructureKind,
    reports: &[(String, &StructureReport)],
    panels: bool,
) -> Res
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let series: Vec<(String, Vec<(f64, f64)>)> = reports
        .iter()
        .map(|(name, r)| (legend(kind, name, r), kind.points(r)))
        .collect();
    let all = || series.iter().flat_map(|s| s.1.iter());
    let (x0, x1) = span(all().map(|p| p.0));
    let (y0, y1) = span(all().map(|p| p.1));
    let (xdesc, ydesc, _) = kind.labels();
    let areas = if panels && series.len() > 1 {
        let cols = series.len().min(3);
        let rows = series.len().div_ceil(cols);
        root.split_evenly((rows, cols))
    } else {
        vec![root.clone()]
    };
    for (a, area) in areas.iter().enumerate() {
        let shown: Vec<usize> = if areas.len() > 1 {
            if a >= series.len() {
                continue;
            }
            vec![a]
        } else {
            (0..series.len()).collect()
        };
        let caption = if areas.len() > 1 {
            series[a].0.clone()
        } else {
            kind.caption()
                .split(':')
                .next()
                .unwrap_or_default()
                .to_owned()
        };
        let mut chart = panel(area, &caption, 18, 50, x0..x1, y0..y1, xdesc, ydesc)?;
        for &k in &shown {
            let c = Palette99::pick(k).to_rgba();
            let name = (areas.len() == 1).then_some(series[k].0.as_str());
            labelled_line(&mut chart, &series[k].1, c, name)?;
            chart.draw_series(series[k].1.iter().map(|&p| Circle::new(p, 2, c.filled())))?;
        }
        if areas.len() == 1 && !series.is_empty() {
            chart
                .configure_series_labels()
                .label_font((FONT, 12))
                .position(SeriesLabelPosition::UpperRight)
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .draw()?;
        }
    }
    Ok(())
}

/// Range of `values` padded by 5 %, or [0, 1] when there are none.
fn span(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
        (a.min(v), b.max(v))
    });
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let pad = 0.05 * (hi - lo).max(1e-6);
    (lo - pad, hi + pad)
}

/// The structure figures of a comparison, one panel per method on the same axes, written as
/// `<dir>/<stem>.png` and `.svg`; returns `(path relative to the report, caption)` pairs.
pub fn comparison(
    dir: &Path,
    reports: &[(String, StructureReport)],
) -> Result<Vec<(String, String)>, BenchError> {
    let named: Vec<(String, &StructureReport)> =
        reports.iter().map(|(m, r)| (m.clone(), r)).collect();
    let mut figs = Vec::new();
    if named.is_empty() {
        return Ok(figs);
    }
    let cols = named.len().min(3) as u32;
    let rows = named.len().div_ceil(3) as u32;
    let size = (360 * cols.max(2), 320 * rows);
    for kind in StructureKind::ALL {
        if named.iter().all(|(_, r)| kind.points(r).is_empty()) {
            continue;
        }
        for ext in ["png", "svg"] {
            let path = dir.join(format!("{}.{ext}", kind.stem()));
            let r: Res = if ext == "svg" {
                let root = SVGBackend::new(&path, size).into_drawing_area();
                draw_structure(&root, kind, &named, true).and_then(|_| Ok(root.present()?))
            } else {
                let root = BitMapBackend::new(&path, size).into_drawing_area();
                draw_structure(&root, kind, &named, true).and_then(|_| Ok(root.present()?))
            };
            r.map_err(|e| BenchError::Run(format!("drawing {}: {e}", path.display())))?;
        }
        figs.push((
            format!("figures/{}.png", kind.stem()),
            kind.caption().to_owned(),
        ));
    }
    Ok(figs)
}
