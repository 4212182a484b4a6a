//! Run traces: φ and one traced quantity against the step count.

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

/// φ (upper panel) and one traced quantity (lower panel) against the step count on a log
/// axis, one line per run. The quantity is drawn as log10 when it is positive and spans more
/// than two decades (pressures from 10 to 1e12), and as log10(1 + value) when it is a count
/// that reaches zero and exceeds 100 (calippso's `contacts_changed`, thousands down to none).
// Long because both panels share one plotters root area and the runs' colours; the split waits for
// the trace figure's rework.
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
    // Runs that trace different quantities share the lower axis; its label lists them and
    // the lower legend says which line is which.
    let name = match names.as_slice() {
        [one] => one.to_string(),
        _ => {
            let mut distinct = names.clone();
            distinct.sort_unstable();
            distinct.dedup();
            format!("each run's {}", distinct.join(" or "))
        }
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
        .x_desc(step_axis(runs))
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
            .label(run.name.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], c.stroke_width(2)));
        value_chart
            .draw_series(LineSeries::new(
                run.points
                    .iter()
                    .filter(on_axis)
                    .filter(|p| p.2.is_finite())
                    .map(|p| (p.0, shown(p.2))),
                c.stroke_width(1),
            ))?
            .label(format!("{}: {}", run.name, run.value))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], c.stroke_width(2)));
    }
    draw_legend(&mut phi_chart, SeriesLabelPosition::LowerRight)?;
    if names.len() > 1 {
        draw_legend(&mut value_chart, SeriesLabelPosition::UpperRight)?;
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
}
