//! Run traces: φ and each traced quantity against the step count.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{FONT, Res, colour, draw_legend, range};

/// One run's trace for `draw_traces`: legend name, the method and what its steps are
/// ([`crate::methods::Method::step_unit`]), the traced quantity's name, and `(step, φ, value)`
/// rows.
pub struct RunTrace {
    pub name: String,
    pub method: String,
    pub step_unit: String,
    pub value: String,
    pub points: Vec<(f64, f64, f64)>,
}

/// The step axis's label: "step (collisions)" when every run counts the same unit, else each
/// unit with its methods ("step (collisions for ls, mls; LPs for calippso)").
fn step_axis(runs: &[RunTrace]) -> String {
    let mut units: Vec<(&str, Vec<&str>)> = Vec::new();
    for r in runs {
        match units.iter_mut().find(|(u, _)| *u == r.step_unit) {
            Some((_, methods)) if !methods.contains(&r.method.as_str()) => methods.push(&r.method),
            Some(_) => {}
            None => units.push((&r.step_unit, vec![&r.method])),
        }
    }
    match units.as_slice() {
        [] => "step".into(),
        [(unit, _)] => format!("step ({unit})"),
        _ => {
            let each: Vec<String> = units
                .iter()
                .map(|(u, m)| format!("{u} for {}", m.join(", ")))
                .collect();
            format!("step ({})", each.join("; "))
        }
    }
}

/// How a traced quantity is drawn: log10 when it is positive and spans more than two decades
/// (pressures from 10 to 1e12), log10(1 + value) when it is a count that reaches zero and
/// exceeds 100 (calippso's `contacts_changed`, thousands down to none), else as it is.
#[derive(Clone, Copy, Debug, PartialEq)]
enum ValueScale {
    Linear,
    Log,
    LogOnePlus,
}

impl ValueScale {
    fn of(values: impl Iterator<Item = f64>) -> Self {
        let (lo, hi) = values
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            });
        if lo > 0.0 && hi > 100.0 * lo {
            ValueScale::Log
        } else if lo == 0.0 && hi > 100.0 {
            ValueScale::LogOnePlus
        } else {
            ValueScale::Linear
        }
    }

    fn shown(self, v: f64) -> f64 {
        match self {
            ValueScale::Linear => v,
            ValueScale::Log => v.log10(),
            ValueScale::LogOnePlus => (1.0 + v).log10(),
        }
    }

    fn axis(self, name: &str) -> String {
        match self {
            ValueScale::Linear => name.to_string(),
            ValueScale::Log => format!("log10 {name}"),
            ValueScale::LogOnePlus => format!("log10(1 + {name})"),
        }
    }
}

/// The traced quantities, each once, in the runs' order.
fn quantities(runs: &[RunTrace]) -> Vec<&str> {
    let mut names: Vec<&str> = Vec::new();
    for r in runs {
        if !names.contains(&r.value.as_str()) {
            names.push(&r.value);
        }
    }
    names
}

/// The step range of the runs' traces, for a log axis: from the smallest positive step (at
/// most a decade below the largest) to the largest.
fn step_range(runs: &[RunTrace]) -> (f64, f64) {
    let steps = runs.iter().flat_map(|r| r.points.iter().map(|p| p.0));
    let lo = steps
        .clone()
        .filter(|&s| s > 0.0)
        .fold(f64::INFINITY, f64::min);
    let hi = steps.fold(1.0, f64::max);
    (
        if lo.is_finite() {
            lo.min(hi / 10.0)
        } else {
            1.0
        },
        hi,
    )
}

/// The height of a trace figure of `runs` at width 900: the φ panel and one panel per
/// traced quantity.
pub fn trace_height(runs: &[RunTrace]) -> u32 {
    380 + 260 * quantities(runs).len().max(1) as u32
}

/// φ (upper panel) and each traced quantity (a panel of its own: energy and pressure do not
/// share an axis) against the step count on a log axis, one line and colour per run.
pub fn draw_traces<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, runs: &[RunTrace]) -> Res
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let (x_lo, x_hi) = step_range(runs);
    let names = quantities(runs);
    let (upper, lower) = root.split_vertically(380);
    let x_range = || (x_lo..x_hi * 1.2).log_scale();
    let on_axis = |p: &&(f64, f64, f64)| p.0 >= x_lo;
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
    for (k, run) in runs.iter().enumerate() {
        let c = colour(k);
        phi_chart
            .draw_series(LineSeries::new(
                run.points.iter().filter(on_axis).map(|p| (p.0, p.1)),
                c.stroke_width(2),
            ))?
            .label(run.name.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], c.stroke_width(2)));
    }
    draw_legend(&mut phi_chart, SeriesLabelPosition::LowerRight)?;
    let panels = lower.split_evenly((names.len().max(1), 1));
    for (q, (area, name)) in panels.iter().zip(&names).enumerate() {
        let last = q + 1 == names.len();
        let mine = || runs.iter().enumerate().filter(|(_, r)| r.value == *name);
        let scale = ValueScale::of(mine().flat_map(|(_, r)| r.points.iter().map(|p| p.2)));
        let values = mine().flat_map(|(_, r)| r.points.iter().map(|p| p.2));
        let (y_lo, y_hi) = range(
            values.filter(|v| v.is_finite()).map(|v| scale.shown(v)),
            0.05,
        );
        let mut chart = ChartBuilder::on(area)
            .margin(15)
            .x_label_area_size(if last { 45 } else { 25 })
            .y_label_area_size(60)
            .build_cartesian_2d(x_range(), y_lo..y_hi)?;
        let mut mesh = chart.configure_mesh();
        mesh.label_style((FONT, 12))
            .axis_desc_style((FONT, 14))
            .x_label_formatter(&|x| format!("{x:.0e}"))
            .y_desc(scale.axis(name));
        if last {
            mesh.x_desc(step_axis(runs));
        }
        mesh.draw()?;
        for (k, run) in mine() {
            let c = colour(k);
            chart
                .draw_series(LineSeries::new(
                    run.points
                        .iter()
                        .filter(on_axis)
                        .filter(|p| p.2.is_finite())
                        .map(|p| (p.0, scale.shown(p.2))),
                    c.stroke_width(1),
                ))?
                .label(run.name.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 15, y)], c.stroke_width(2))
                });
        }
        draw_legend(&mut chart, SeriesLabelPosition::UpperRight)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(method: &str, unit: &str) -> RunTrace {
        RunTrace {
            name: method.into(),
            method: method.into(),
            step_unit: unit.into(),
            value: "pressure".into(),
            points: Vec::new(),
        }
    }

    #[test]
    fn the_step_axis_names_each_unit_with_its_methods() {
        assert_eq!(step_axis(&[run("mls", "collisions")]), "step (collisions)");
        let mixed = [
            run("ls", "collisions"),
            run("mls", "collisions"),
            run("mls", "collisions"),
            run("calippso", "LPs"),
        ];
        assert_eq!(
            step_axis(&mixed),
            "step (collisions for ls, mls; LPs for calippso)"
        );
    }

    /// Energy (adam) and reduced pressure (mls) get a panel each, each on its own scale.
    #[test]
    fn each_quantity_has_its_own_panel_and_scale() {
        let mut adam = run("adam", "steps");
        adam.value = "energy".into();
        adam.points = vec![(1.0, 0.6, 1e-2), (10.0, 0.62, 1e-8)];
        let mut mls = run("mls", "collisions");
        mls.points = vec![(1.0, 0.5, 10.0), (10.0, 0.6, 1e12)];
        let mut ls = run("ls", "collisions");
        ls.points = vec![(1.0, 0.5, 20.0), (10.0, 0.6, 40.0)];
        let runs = [adam, mls, ls];
        assert_eq!(quantities(&runs), vec!["energy", "pressure"]);
        assert_eq!(trace_height(&runs), 380 + 2 * 260);
        let scale = |r: &RunTrace| ValueScale::of(r.points.iter().map(|p| p.2));
        assert_eq!(scale(&runs[0]), ValueScale::Log);
        assert_eq!(scale(&runs[2]), ValueScale::Linear);
        let counts = [(1.0, 0.6, 0.0), (2.0, 0.6, 3000.0)];
        assert_eq!(
            ValueScale::of(counts.iter().map(|p| p.2)),
            ValueScale::LogOnePlus
        );
    }
}
