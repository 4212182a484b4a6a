//! Figures with plotters, each written as PNG and SVG: φ per method, runtime against φ, the
//! speed–accuracy curve of a sweep, φ histograms, g(r), and a packing drawn to scale (2D) or
//! as a slice (3D and up) with rattlers marked and the contact network, and run traces.

use std::path::Path;

use packbench_core::Packing;
use packbench_core::analysis::structure::{StructureOptions, analyze_structure, pair_correlation};
use packbench_core::analysis::{contact_network, rattlers};
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::compare::RunsFile;

/// Font family of every label. Plotters' bitmap text drops the part of a glyph left of its
/// origin, and in proportional fonts 'j' and 'J' start there (they vanished from "φ_J" and
/// "closest-jammed"); monospace glyphs never do, and every fontconfig system has one.
const FONT: &str = "monospace";
use crate::error::BenchError;

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
        both!(dir, "phi_by_method", (900, 520), |root: &DrawingArea<
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
    figs.extend(crate::figures_structure::comparison(&dir, &structures)?);
    Ok(figs)
}

fn phi_strip<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    methods: &[String],
    pts: &[(usize, f64, f64)],
) -> Res
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let (lo, hi) = range(pts.iter().map(|p| p.1), 0.15);
    let mut chart = ChartBuilder::on(root)
        .caption("φ_J per method", (FONT, 24))
        .margin(15)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(-0.5f64..methods.len() as f64 - 0.5, lo..hi)?;
    chart
        .configure_mesh()
        .label_style((FONT, 12))
        .axis_desc_style((FONT, 14))
        .disable_x_mesh()
        .x_labels(methods.len().max(2))
        .x_label_formatter(&|x| {
            let i = x.round();
            if (x - i).abs() < 1e-6 && i >= 0.0 {
                methods.get(i as usize).cloned().unwrap_or_default()
            } else {
                String::new()
            }
        })
        .y_desc("φ_J")
        .y_label_formatter(&|y| format!("{y:.4}"))
        .draw()?;
    for (k, _) in methods.iter().enumerate() {
        let vals: Vec<f64> = pts.iter().filter(|p| p.0 == k).map(|p| p.1).collect();
        let c = colour(k);
        let n = vals.len().max(1) as f64;
        chart.draw_series(vals.iter().enumerate().map(|(j, &v)| {
            let jitter = 0.25 * ((j as f64 + 0.5) / n - 0.5);
            Circle::new((k as f64 + jitter, v), 5, c.mix(0.7).filled())
        }))?;
        if let Some((m, s)) = crate::report::mean_std(&vals) {
            chart.draw_series(std::iter::once(PathElement::new(
                vec![(k as f64 - 0.3, m), (k as f64 + 0.3, m)],
                c.stroke_width(3),
            )))?;
            chart.draw_series(std::iter::once(PathElement::new(
                vec![(k as f64, m - s), (k as f64, m + s)],
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

/// One run's trace for `draw_traces`: legend name, the traced quantity's name, and
/// `(step, φ, value)` rows.
pub struct RunTrace {
    pub name: String,
    pub value: String,
    pub points: Vec<(f64, f64, f64)>,
}

/// φ (upper panel) and one traced quantity (lower panel) against the step count on a log
/// axis, one line per run. The quantity is drawn as log10 when it is positive and spans more
/// than two decades (pressures from 10 to 1e12), and as log10(1 + value) when it is a count
/// that reaches zero and exceeds 100 (calippso's `contacts_changed`, thousands down to none).
pub fn draw_traces<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, runs: &[RunTrace]) -> Res
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let steps = runs.iter().flat_map(|r| r.points.iter().map(|p| p.0));
    let x_lo = steps
        .clone()
        .filter(|&s| s > 0.0)
        .fold(f64::INFINITY, f64::min);
    let x_hi = steps.fold(1.0, f64::max);
    let x_lo = if x_lo.is_finite() {
        x_lo.min(x_hi / 10.0)
    } else {
        1.0
    };
    let values = || {
        runs.iter()
            .flat_map(|r| r.points.iter().map(|p| p.2))
            .filter(|v| v.is_finite())
    };
    let (v_lo, v_hi) = values().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
        (a.min(v), b.max(v))
    });
    // Offset added before the log10, if the values are drawn on a log scale.
    let log_offset = if v_lo > 0.0 && v_hi > 100.0 * v_lo {
        Some(0.0)
    } else if v_lo == 0.0 && v_hi > 100.0 {
        Some(1.0)
    } else {
        None
    };
    let shown = |v: f64| log_offset.map_or(v, |o| (o + v).log10());
    let mut names: Vec<&str> = runs.iter().map(|r| r.value.as_str()).collect();
    names.dedup();
    let name = match names.as_slice() {
        [one] => one.to_string(),
        _ => "value".to_string(),
    };
    let value_desc = match log_offset {
        None => name,
        Some(0.0) => format!("log10 {name}"),
        Some(_) => format!("log10(1 + {name})"),
    };
    let (upper, lower) = root.split_vertically(360);
    let x_range = || (x_lo..x_hi * 1.2).log_scale();
    let (p_lo, p_hi) = range(runs.iter().flat_map(|r| r.points.iter().map(|p| p.1)), 0.05);
    let mut phi_chart = ChartBuilder::on(&upper)
        .caption("Run traces", (FONT, 24))
        .margin(15)
        .x_label_area_size(30)
        .y_label_area_size(60)
        .build_cartesian_2d(x_range(), p_lo..p_hi)?;
    phi_chart
        .configure_mesh()
        .label_style((FONT, 12))
        .axis_desc_style((FONT, 14))
        .x_label_formatter(&|x| format!("{x:.0e}"))
        .y_desc("φ")
        .draw()?;
    let (y_lo, y_hi) = range(values().map(shown), 0.05);
    let mut value_chart = ChartBuilder::on(&lower)
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(x_range(), y_lo..y_hi)?;
    value_chart
        .configure_mesh()
        .label_style((FONT, 12))
        .axis_desc_style((FONT, 14))
        .x_label_formatter(&|x| format!("{x:.0e}"))
        .x_desc("step (collisions for ls and mls, LPs for calippso)")
        .y_desc(value_desc)
        .draw()?;
    for (k, run) in runs.iter().enumerate() {
        let c = colour(k);
        let on_axis = |p: &&(f64, f64, f64)| p.0 >= x_lo;
        phi_chart
            .draw_series(LineSeries::new(
                run.points.iter().filter(on_axis).map(|p| (p.0, p.1)),
                c.stroke_width(2),
            ))?
            .label(if names.len() > 1 {
                format!("{}: {}", run.name, run.value)
            } else {
                run.name.clone()
            })
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], c.stroke_width(2)));
        value_chart.draw_series(LineSeries::new(
            run.points
                .iter()
                .filter(on_axis)
                .filter(|p| p.2.is_finite())
                .map(|p| (p.0, shown(p.2))),
            c.stroke_width(1),
        ))?;
    }
    draw_legend(&mut phi_chart, SeriesLabelPosition::LowerRight)?;
    Ok(())
}

/// A packing to scale: 2D disks, or for d ≥ 3 the disks where spheres cut the plane through
/// the middle of axes 3…d. Rattlers are red, contacts between drawn particles are lines.
pub fn draw_packing<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    p: &Packing,
    title: &str,
) -> Res
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let (w, h) = root.dim_in_pixel();
    let margin = 40.0;
    let (lx, ly) = (p.container.lengths[0], p.container.lengths[1]);
    let scale = ((w as f64 - 2.0 * margin) / lx).min((h as f64 - 2.0 * margin) / ly);
    let px = |x: f64, y: f64| {
        (
            (margin + x * scale) as i32,
            (h as f64 - margin - y * scale) as i32,
        )
    };
    let net = contact_network(p, 1e-6);
    let rattler = rattlers(&net, p.n(), p.dim);
    // In-plane radius of each particle (None when it does not cut the drawing plane).
    let cut: Vec<Option<f64>> = (0..p.n())
        .map(|i| {
            let x = p.position(i);
            let off2: f64 = (2..p.dim)
                .map(|k| (x[k] - 0.5 * p.container.lengths[k]).powi(2))
                .sum();
            let r2 = 0.25 * p.diameters[i] * p.diameters[i] - off2;
            (r2 > 0.0).then(|| r2.sqrt())
        })
        .collect();
    let images = |k: usize| {
        if p.container.periodic[k] {
            vec![-1.0, 0.0, 1.0]
        } else {
            vec![0.0]
        }
    };
    for i in 0..p.n() {
        let Some(r) = cut[i] else { continue };
        let x = p.position(i);
        let fill = if rattler[i] {
            RGBColor(220, 60, 60)
        } else {
            RGBColor(120, 160, 210)
        };
        for sx in images(0) {
            for sy in images(1) {
                let (cx, cy) = (x[0] + sx * lx, x[1] + sy * ly);
                if cx + r < 0.0 || cx - r > lx || cy + r < 0.0 || cy - r > ly {
                    continue;
                }
                let radius = ((r * scale) as i32).max(1);
                root.draw(&Circle::new(px(cx, cy), radius, fill.mix(0.75).filled()))?;
                root.draw(&Circle::new(px(cx, cy), radius, BLACK.stroke_width(1)))?;
            }
        }
    }
    for (c, ct) in net.contacts.iter().enumerate() {
        let Some(j) = ct.j else { continue };
        if cut[ct.i].is_none() || cut[j].is_none() {
            continue;
        }
        let xi = p.position(ct.i);
        let n = &net.normals[c * p.dim..(c + 1) * p.dim];
        let r = 0.5 * (p.diameters[ct.i] + p.diameters[j]);
        let end = (xi[0] + n[0] * r, xi[1] + n[1] * r);
        root.draw(&PathElement::new(
            vec![px(xi[0], xi[1]), px(end.0, end.1)],
            BLACK.stroke_width(2),
        ))?;
    }
    // Periodic images spill over the box edge: mask the margins, then draw frame and title.
    let (x0, y0) = px(0.0, ly);
    let (x1, y1) = px(lx, 0.0);
    let (wi, hi) = (w as i32, h as i32);
    for r in [
        [(0, 0), (wi, y0)],
        [(0, y1), (wi, hi)],
        [(0, 0), (x0, hi)],
        [(x1, 0), (wi, hi)],
    ] {
        root.draw(&Rectangle::new(r, WHITE.filled()))?;
    }
    root.draw(&Rectangle::new([(x0, y0), (x1, y1)], BLACK.stroke_width(1)))?;
    if let packbench_core::Shape::Ball { .. } = p.container.shape {
        let c = px(0.5 * lx, 0.5 * lx);
        root.draw(&Circle::new(
            c,
            (0.5 * lx * scale) as i32,
            BLACK.stroke_width(2),
        ))?;
    }
    let slice = if p.dim > 2 {
        " (slice through the middle)"
    } else {
        ""
    };
    root.draw(&Text::new(
        format!("{title}: N = {}, φ = {:.4}{slice}", p.n(), p.phi()),
        (10, 10),
        (FONT, 18),
    ))?;
    Ok(())
}

/// One run of a sweep, for the speed–accuracy figures.
pub struct SweepPoint {
    pub value: f64,
    pub runtime_s: f64,
    pub phi: f64,
    /// |φ_J − φ_ref|.
    pub error: f64,
    pub iso_gap: f64,
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
/// time, as in seed 001 Fig. 2 (slow compressions to the right); other knobs as they are.
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

/// Histogram of the radii a fill placed and discarded against the target density (a seeded
/// sample of 10^5 draws from the requested distribution), as a PNG.
pub fn radius_histogram(
    path: &Path,
    placed: &[f64],
    discarded: &[f64],
    target: &packbench_core::SizeDistribution,
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
