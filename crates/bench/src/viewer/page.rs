//! The page itself: the data of every panel as one JSON block, and the HTML template with
//! the vendored three.js (module build and orbit controls, as `data:` modules in an import
//! map), the stylesheet and the viewer script inlined, so the file needs nothing but itself.

use base64::Engine;
use base64::engine::general_purpose::STANDARD;
use packbench_core::Container;
use packbench_core::run::TraceRow;
use serde::Serialize;

use super::frame::Frame;
use crate::error::BenchError;

const TEMPLATE: &str = include_str!("../../assets/viewer/viewer.html");
const STYLE: &str = include_str!("../../assets/viewer/viewer.css");
const SCRIPT: &str = include_str!("../../assets/viewer/viewer.js");
const THREE: &str = include_str!("../../assets/three/three.module.min.js");
const ORBIT_CONTROLS: &str = include_str!("../../assets/three/OrbitControls.js");

/// What the frames of a panel are: the states of one run over its steps, or the packings of
/// several starting seeds (a comparison).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FrameKind {
    /// Snapshots of a run in step order, its final packing last.
    Step,
    /// One packing per starting seed.
    Seed,
}

/// The method's trace for the plot under the timeline: φ and one method scalar per row.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Trace {
    /// Step of each row.
    pub step: Vec<u64>,
    /// Packing fraction of each row.
    pub phi: Vec<f64>,
    /// Name of the plotted scalar (`reduced_pressure`, `energy`, …), empty when none.
    pub label: String,
    /// Its value per row (NaN-free: rows without it are left out of `value` and `value_step`).
    pub value: Vec<f64>,
    /// Steps of the rows in `value`.
    pub value_step: Vec<u64>,
}

impl Trace {
    /// The trace of a run: φ per row, and the first scalar that names a pressure or an
    /// energy (else the first scalar).
    pub fn of(rows: &[TraceRow]) -> Trace {
        let label = rows
            .iter()
            .flat_map(|r| r.values.iter().map(|(k, _)| k.clone()))
            .find(|k| k.contains("pressure") || k.contains("energy"))
            .or_else(|| {
                rows.iter()
                    .find_map(|r| r.values.first().map(|v| v.0.clone()))
            })
            .unwrap_or_default();
        let mut t = Trace {
            label: label.clone(),
            ..Trace::default()
        };
        for r in rows.iter().filter(|r| r.phi.is_finite()) {
            t.step.push(r.step);
            t.phi.push(r.phi);
            if let Some((_, v)) = r.values.iter().find(|(k, v)| *k == label && v.is_finite()) {
                t.value.push(*v);
                t.value_step.push(r.step);
            }
        }
        t
    }
}

/// One panel of the page: a run or a method of a comparison.
#[derive(Clone, Debug, Serialize)]
pub struct Panel {
    /// Heading (method or file name).
    pub label: String,
    /// Method that made the packing, when known.
    pub method: Option<String>,
    /// Its parameters (JSON object), when known.
    pub parameters: serde_json::Value,
    /// Why the run stopped, when known.
    pub termination: Option<String>,
    /// Dimension.
    pub dim: usize,
    /// The container, as the core serialises it (lengths, periodic flags, curved shape).
    pub container: Container,
    /// The frames, at least one.
    pub frames: Vec<Frame>,
    /// The run's trace (empty for comparisons and foreign files).
    pub trace: Trace,
}

/// The whole page.
#[derive(Clone, Debug, Serialize)]
pub struct ViewerPage {
    /// Title of the page.
    pub title: String,
    /// What the frames are.
    pub frame_kind: FrameKind,
    /// The panels, side by side (cameras linked) when there are several.
    pub panels: Vec<Panel>,
}

/// A JavaScript module as a `data:` URL.
fn module_url(source: &str) -> String {
    format!(
        "data:text/javascript;base64,{}",
        STANDARD.encode(source.as_bytes())
    )
}

/// Text made safe inside an HTML `<script>` or `<title>`: no `</` and no raw `<`/`&`.
fn script_safe(text: &str) -> String {
    text.replace('<', "\\u003c")
        .replace('>', "\\u003e")
        .replace('&', "\\u0026")
}

fn html_escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The self-contained HTML of `page`. Errors: a panel without frames, or JSON encoding.
pub fn render(page: &ViewerPage) -> Result<String, BenchError> {
    if page.panels.is_empty() || page.panels.iter().any(|p| p.frames.is_empty()) {
        return Err(BenchError::Run(
            "nothing to show: a page needs at least one packing".into(),
        ));
    }
    let data = serde_json::to_string(page).map_err(|e| BenchError::Run(e.to_string()))?;
    let import_map = serde_json::json!({
        "imports": {
            "three": module_url(THREE),
            "three/addons/controls/OrbitControls.js": module_url(ORBIT_CONTROLS),
        }
    });
    Ok(TEMPLATE
        .replace("{{TITLE}}", &html_escape(&page.title))
        .replace("{{STYLE}}", STYLE)
        .replace("{{IMPORT_MAP}}", &import_map.to_string())
        .replace("{{SCRIPT}}", SCRIPT)
        .replace("{{DATA}}", &script_safe(&data)))
}
