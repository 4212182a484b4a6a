//! `packbench view`: packings, runs and comparisons as one self-contained HTML page.

use std::path::{Path, PathBuf};

use clap::Args;
use packbench_core::format::write_atomic;

use super::Printed;
use crate::error::{BenchError, usage};
use crate::outputs::load_packing;
use crate::records::RunsFile;
use crate::viewer::{
    Frame, FrameKind, FrameOptions, Panel, RunFiles, Trace, ViewerPage, read_run, render, thin,
};

/// Whether `method` (a name from a sidecar or a comparison) is an exact jamming method, so its
/// contact forces mean something: the page colours their contact network by the core's
/// balancing forces.
fn is_exact(method: &str) -> bool {
    crate::methods::find(method).is_ok_and(|m| m.is_exact())
}

/// Flags of `packbench view`.
#[derive(Args, Debug)]
pub struct ViewArgs {
    /// Packings (`NAME.txt`), runs (`NAME.json`, with their `--save-interval` snapshots as a
    /// timeline) or one `compare` output folder. Several runs are shown side by side.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// The page to write (default: NAME.html beside a run, viewer.html in a comparison folder).
    #[arg(long)]
    pub output: Option<PathBuf>,
    /// Largest relative gap r/σ − 1 counted as a contact.
    #[arg(long = "contact-tol", default_value_t = 1e-6)]
    pub contact_tol: f64,
    /// Skip the force-balance solve in the metrics (about 3 s at N = 10⁴ and 25 s at N = 10⁵
    /// in 3D).
    #[arg(long = "no-force-balance")]
    pub no_force_balance: bool,
    /// Colour the contact network by the core's balancing forces for every method, not only
    /// the exact ones (closest-jammed, calippso).
    #[arg(long)]
    pub forces: bool,
    /// Most frames of a run kept on the timeline (evenly spread, the final packing always).
    #[arg(long = "max-frames", default_value_t = 120)]
    pub max_frames: usize,
}

impl ViewArgs {
    fn options(&self, method: Option<&str>) -> FrameOptions {
        FrameOptions {
            contact_tol: self.contact_tol,
            metrics: true,
            force_balance: !self.no_force_balance,
            forces: self.forces || method.is_some_and(is_exact),
        }
    }
}

/// The panel of one run: its snapshots (contacts only) then its final packing (with metrics
/// and, for exact methods, forces).
pub fn run_panel(
    run: RunFiles,
    options: &FrameOptions,
    max_frames: usize,
) -> Result<Panel, BenchError> {
    let snapshot_options = FrameOptions {
        metrics: false,
        forces: false,
        ..*options
    };
    let mut frames = Vec::new();
    let snapshots = thin(run.snapshots, max_frames.saturating_sub(1));
    for (step, p) in &snapshots {
        frames.push(Frame::of(
            p,
            format!("step {step}"),
            Some(*step),
            &snapshot_options,
        )?);
    }
    let sidecar = run.sidecar.as_ref();
    frames.push(Frame::of(
        &run.packing,
        "final",
        sidecar.map(|s| s.steps),
        options,
    )?);
    Ok(Panel {
        label: match sidecar {
            Some(s) => format!("{} ({})", run.name, s.method),
            None => run.name.clone(),
        },
        method: sidecar.map(|s| s.method.clone()),
        parameters: sidecar
            .map(|s| s.parameters.clone())
            .unwrap_or(serde_json::Value::Null),
        termination: sidecar.map(|s| s.termination.clone()),
        dim: run.packing.dim,
        container: run.packing.container.clone(),
        frames,
        trace: sidecar.map(|s| Trace::of(&s.trace)).unwrap_or_default(),
    })
}

/// The page of a `compare` folder: one panel per method with a saved packing, one frame per
/// starting seed. `options.forces` asks for forces for every method (exact methods always get
/// them). Errors: no readable `runs.json`, or a failed analysis.
pub fn compare_page(dir: &Path, options: &FrameOptions) -> Result<ViewerPage, BenchError> {
    let path = dir.join("runs.json");
    let text = std::fs::read_to_string(&path)
        .map_err(|e| usage(format!("cannot read {}: {e}", path.display())))?;
    let file: RunsFile = serde_json::from_str(&text)
        .map_err(|e| usage(format!("{}: not a runs.json: {e}", path.display())))?;
    let mut panels = Vec::new();
    for method in &file.config.methods {
        let options = FrameOptions {
            forces: options.forces || is_exact(method),
            ..*options
        };
        let mut frames = Vec::new();
        let mut container = None;
        for rec in file.runs.iter().filter(|r| &r.method == method) {
            if let Some(p) = load_packing(dir, method, rec.seed) {
                frames.push(Frame::of(
                    &p,
                    format!("seed {}", rec.seed),
                    Some(rec.seed),
                    &options,
                )?);
                container.get_or_insert(p.container);
            }
        }
        if let Some(container) = container {
            panels.push(Panel {
                label: method.clone(),
                method: Some(method.clone()),
                parameters: serde_json::Value::Null,
                termination: None,
                dim: container.dim(),
                container,
                frames,
                trace: Trace::default(),
            });
        }
    }
    Ok(ViewerPage {
        title: format!("packbench compare: {}", dir.display()),
        frame_kind: FrameKind::Seed,
        panels,
    })
}

/// Writes `viewer.html` into a comparison folder (called by `compare` and `merge`), with the
/// default analysis options; nothing when no run left a packing. Errors: as [`compare_page`],
/// or the file cannot be written.
pub fn write_compare_page(dir: &Path) -> Result<Option<PathBuf>, BenchError> {
    let options = FrameOptions {
        contact_tol: 1e-6,
        metrics: true,
        force_balance: true,
        forces: false,
    };
    let page = compare_page(dir, &options)?;
    if page.panels.is_empty() {
        return Ok(None);
    }
    let out = dir.join("viewer.html");
    write_atomic(&out, render(&page)?.as_bytes())?;
    Ok(Some(out))
}

/// `packbench view`.
pub fn run(args: &ViewArgs) -> Result<Printed, BenchError> {
    if args.max_frames == 0 {
        return Err(usage("--max-frames must be at least 1"));
    }
    let (page, default_out) = if args.files.len() == 1 && args.files[0].is_dir() {
        let dir = &args.files[0];
        let page = compare_page(dir, &args.options(None))?;
        if page.panels.is_empty() {
            return Err(usage(format!(
                "{} holds no packings to show (every run failed?)",
                dir.display()
            )));
        }
        (page, dir.join("viewer.html"))
    } else {
        let mut panels = Vec::new();
        for f in &args.files {
            if f.is_dir() {
                return Err(usage(format!(
                    "{} is a folder: give a comparison folder alone, or packing files",
                    f.display()
                )));
            }
            let run = read_run(f)?;
            let options = args.options(run.sidecar.as_ref().map(|s| s.method.as_str()));
            panels.push(run_panel(run, &options, args.max_frames)?);
        }
        let title = panels
            .iter()
            .map(|p| p.label.as_str())
            .collect::<Vec<_>>()
            .join(" | ");
        (
            ViewerPage {
                title: format!("packbench view: {title}"),
                frame_kind: FrameKind::Step,
                panels,
            },
            args.files[0].with_extension("html"),
        )
    };
    let out = args.output.clone().unwrap_or(default_out);
    let html = render(&page)?;
    write_atomic(&out, html.as_bytes())?;
    Ok(Printed {
        stdout: String::new(),
        stderr: vec![format!(
            "packbench view: {} panel(s), {} frame(s), {:.1} MB -> {}",
            page.panels.len(),
            page.panels.iter().map(|p| p.frames.len()).sum::<usize>(),
            html.len() as f64 / 1e6,
            out.display()
        )],
    })
}
