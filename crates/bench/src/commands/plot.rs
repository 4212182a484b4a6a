//! `packbench plot`: draws one packing (2D to scale, or a slice), the g(r) of one or more
//! packings, or the traces of one or more runs (φ and a method quantity against steps).

use std::path::{Path, PathBuf};

use clap::Args;
use packbench_core::run::TraceRow;
use plotters::prelude::*;
use serde::Deserialize;

use super::Printed;
use crate::args::ContainerArgs;
use crate::error::{BenchError, usage};
use crate::figures::structure::{StructureKind, draw_structure};
use crate::figures::void_space::{
    VoidSpaceKind, VoidSpaceSeries, draw_void_space, histogram_points, pore_panels, voronoi_panels,
};
use crate::figures::{
    RunTrace, draw_gr, draw_packing, draw_traces, radial_distribution, trace_height,
};
use crate::outputs::read_input;
use packbench_core::analysis::structure::{StructureOptions, StructureReport, analyze_structure};
use packbench_core::analysis::void_space::{ChordOptions, PoreOptions, chords, pores, voronoi};

/// Flags of `packbench plot`.
#[derive(Args, Debug)]
pub struct PlotArgs {
    /// Packing files in plain text (`-` reads standard input); for `--kind trace` the runs'
    /// JSON outputs (or their packings, whose NAME.json is read). `packing` takes one file,
    /// `gr` and `trace` overlay several.
    #[arg(required = true)]
    pub files: Vec<String>,
    #[command(flatten)]
    pub container: ContainerArgs,
    /// Figure file; .png or .svg.
    #[arg(long, default_value = "packing.png")]
    pub output: PathBuf,
    /// packing (the particles and their contacts), gr (radial distribution function),
    /// trace (φ and --value against the step count of each run), sk (structure factor),
    /// forces (P(f/⟨f⟩)), gaps (g(h)), q6 (local bond-order histogram), voronoi (local φ
    /// histogram and local φ against diameter), pores (pore- and throat-size distributions) or
    /// chords (void and solid chord-length distributions, log–log).
    #[arg(long, default_value = "packing")]
    pub kind: String,
    /// For --kind trace: the traced quantity of the lower panel (default: the method's first,
    /// e.g. reduced_pressure for ls/mls, energy for adam, sqrt_gamma_minus_1 for calippso).
    #[arg(long)]
    pub value: Option<String>,
}

/// Draws into `path` (PNG, or SVG when it ends in .svg) at `size` with `draw`, which is
/// written once and instantiated for both backends.
macro_rules! draw_to {
    ($path:expr, $size:expr, $draw:expr) => {{
        let path: &Path = $path;
        let r: Result<(), Box<dyn std::error::Error>> =
            if path.extension().is_some_and(|e| e == "svg") {
                let root = SVGBackend::new(path, $size).into_drawing_area();
                $draw(&root).and_then(|_| Ok(root.present()?))
            } else {
                let root = BitMapBackend::new(path, $size).into_drawing_area();
                $draw(&root).and_then(|_| Ok(root.present()?))
            };
        r.map_err(|e| BenchError::Run(format!("drawing {}: {e}", path.display())))
    }};
}

/// The file name without folder and extension, as a legend entry.
fn stem(file: &str) -> String {
    Path::new(file)
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// Draws the figure.
pub fn run(args: &PlotArgs) -> Result<Printed, BenchError> {
    let out = args.output.as_path();
    match args.kind.as_str() {
        "packing" => {
            let [file] = args.files.as_slice() else {
                return Err(usage(format!(
                    "--kind packing draws one packing; {} files were given",
                    args.files.len()
                )));
            };
            let p = read_input(file, &args.container)?;
            draw_to!(out, (720, 720), |root| draw_packing(root, &p, &stem(file)))?;
        }
        "gr" => {
            let mut series = Vec::new();
            for file in &args.files {
                let p = read_input(file, &args.container)?;
                if !p.container.is_fully_periodic() {
                    return Err(usage(format!(
                        "{file}: g(r) is drawn for fully periodic packings only"
                    )));
                }
                series.push((stem(file), radial_distribution(&p, 200)));
            }
            draw_to!(out, (900, 520), |root| draw_gr(root, &series))?;
        }
        "trace" => {
            let runs = args
                .files
                .iter()
                .map(|f| read_trace(f, args.value.as_deref()))
                .collect::<Result<Vec<_>, _>>()?;
            draw_to!(out, (900, trace_height(&runs)), |root| {
                draw_traces(root, &runs)
            })?;
        }
        kind @ ("sk" | "forces" | "gaps" | "q6") => {
            let kind = match kind {
                "sk" => StructureKind::StructureFactor,
                "forces" => StructureKind::Forces,
                "gaps" => StructureKind::Gaps,
                _ => StructureKind::LocalOrder,
            };
            let reports = args
                .files
                .iter()
                .map(|f| {
                    let p = read_input(f, &args.container)?;
                    Ok((
                        stem(f),
                        analyze_structure(&p, &StructureOptions::default())?,
                    ))
                })
                .collect::<Result<Vec<_>, BenchError>>()?;
            let named: Vec<(String, &StructureReport)> =
                reports.iter().map(|(n, r)| (n.clone(), r)).collect();
            draw_to!(out, (900, 560), |root| draw_structure(
                root, kind, &named, false
            ))?;
        }
        kind @ ("voronoi" | "pores" | "chords") => {
            let kind = match kind {
                "voronoi" => VoidSpaceKind::Voronoi,
                "pores" => VoidSpaceKind::Pores,
                _ => VoidSpaceKind::Chords,
            };
            let series = args
                .files
                .iter()
                .map(|f| void_space_series(f, kind, &args.container))
                .collect::<Result<Vec<_>, BenchError>>()?;
            draw_to!(out, (1100, 480), |root| draw_void_space(
                root, kind, &series
            ))?;
        }
        other => {
            return Err(usage(format!(
                "unknown --kind `{other}`; use packing, gr, trace, sk, forces, gaps, q6, voronoi, pores or chords"
            )));
        }
    }
    Ok(Printed {
        stdout: String::new(),
        stderr: vec![format!("packbench plot: wrote {}", out.display())],
    })
}

/// The two panels of a void-space figure for the packing in `file`.
fn void_space_series(
    file: &str,
    kind: VoidSpaceKind,
    container: &ContainerArgs,
) -> Result<VoidSpaceSeries, BenchError> {
    let p = read_input(file, container)?;
    let panels = match kind {
        VoidSpaceKind::Voronoi => voronoi_panels(&voronoi(&p)?, &p),
        VoidSpaceKind::Pores => pore_panels(&pores(&p, &PoreOptions::default())?, &p),
        VoidSpaceKind::Chords => {
            if !p.container.is_fully_periodic() {
                return Err(usage(format!(
                    "{file}: chord lengths are drawn for fully periodic packings only"
                )));
            }
            let r = chords(&p, &ChordOptions::default())?;
            let unit = p.mean_diameter();
            [
                histogram_points(&r.void.distribution, unit, true),
                histogram_points(&r.solid.distribution, unit, true),
            ]
        }
    };
    Ok(VoidSpaceSeries {
        name: stem(file),
        panels,
    })
}

/// The part of a run's JSON output (`pack --output`) that a trace figure needs.
#[derive(Deserialize)]
struct RunOutput {
    method: Option<String>,
    trace: Vec<TraceRow>,
}

/// Reads the trace of the run whose JSON output is `file` (or sits beside the packing
/// `file`): `(step, φ, value)` per row, `value` being `wanted` or the first traced quantity.
fn read_trace(file: &str, wanted: Option<&str>) -> Result<RunTrace, BenchError> {
    let path = Path::new(file).with_extension("json");
    let text = std::fs::read_to_string(&path).map_err(|e| {
        usage(format!(
            "{}: {e} (--kind trace reads a run's JSON output, written by pack --output)",
            path.display()
        ))
    })?;
    let run: RunOutput = serde_json::from_str(&text)
        .map_err(|e| usage(format!("{}: not a run's JSON output: {e}", path.display())))?;
    let value = match wanted {
        Some(v) => v.to_string(),
        None => run
            .trace
            .first()
            .and_then(|r| r.values.first().map(|v| v.0.clone()))
            .unwrap_or_default(),
    };
    let points: Vec<(f64, f64, f64)> = run
        .trace
        .iter()
        .map(|row| {
            let v = row
                .values
                .iter()
                .find(|(name, _)| *name == value)
                .map_or(f64::NAN, |(_, v)| *v);
            (row.step as f64, row.phi, v)
        })
        .collect();
    if wanted.is_some() && points.iter().all(|p| p.2.is_nan()) {
        return Err(usage(format!(
            "{}: the trace has no quantity `{value}`",
            path.display()
        )));
    }
    let method = run.method.as_deref().unwrap_or("?");
    // The file's stem, with the method when the stem does not already say it.
    let name = match stem(file) {
        s if s == method => s,
        s => format!("{s} ({method})"),
    };
    Ok(RunTrace {
        name,
        method: method.to_string(),
        step_unit: crate::methods::find(method)
            .map_or("steps", |m| m.step_unit())
            .to_string(),
        value,
        points,
    })
}
