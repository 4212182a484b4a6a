//! `_repr_html_` of `Packing` and `Result`: the page `packbench view` writes (the bench's
//! viewer, three.js embedded), inline in Jupyter as an `<iframe srcdoc>` so that its import
//! map and scripts run in a document of their own.

use packbench::error::BenchError;
use packbench::viewer::{Frame, FrameKind, FrameOptions, Panel, Trace, ViewerPage, render};
use packbench_core::Packing;
use packbench_core::run::TraceRow;

/// Height of the inline viewer in pixels.
const HEIGHT_PX: u32 = 520;

/// What a run adds to its packing's panel: method, parameters, termination, steps and trace.
pub struct RunInfo<'a> {
    pub method: &'a str,
    pub parameters: serde_json::Value,
    pub termination: &'a str,
    pub steps: u64,
    pub trace: &'a [TraceRow],
}

/// The viewer page of `packing` (and of the run that made it), wrapped in an iframe. The
/// metrics skip the force-balance solve, so the page is quick at any N; contact forces are
/// drawn for the exact-jamming methods, as `packbench view` does.
pub fn packing_html(packing: &Packing, run: Option<RunInfo<'_>>) -> Result<String, BenchError> {
    let options = FrameOptions {
        contact_tol: 1e-6,
        metrics: true,
        force_balance: false,
        forces: run
            .as_ref()
            .is_some_and(|r| packbench::methods::find(r.method).is_ok_and(|m| m.is_exact())),
    };
    let frame = Frame::of(packing, "final", run.as_ref().map(|r| r.steps), &options)?;
    let label = run
        .as_ref()
        .map_or("packing".to_string(), |r| r.method.to_string());
    let panel = Panel {
        label: label.clone(),
        method: run.as_ref().map(|r| r.method.to_string()),
        parameters: run
            .as_ref()
            .map_or(serde_json::Value::Null, |r| r.parameters.clone()),
        termination: run.as_ref().map(|r| r.termination.to_string()),
        dim: packing.dim,
        container: packing.container.clone(),
        frames: vec![frame],
        trace: run.as_ref().map(|r| Trace::of(r.trace)).unwrap_or_default(),
    };
    let page = render(&ViewerPage {
        title: format!("packbench: {label}"),
        frame_kind: FrameKind::Step,
        panels: vec![panel],
    })?;
    let srcdoc = page.replace('&', "&amp;").replace('"', "&quot;");
    Ok(format!(
        "<iframe class=\"packbench-view\" srcdoc=\"{srcdoc}\" style=\"width:100%;height:{HEIGHT_PX}px;border:0\" sandbox=\"allow-scripts\"></iframe>"
    ))
}
