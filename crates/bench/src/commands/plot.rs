//! `packbench plot`: draws one packing (2D to scale, or a slice) or its g(r).

use std::path::PathBuf;

use clap::Args;
use plotters::prelude::*;

use super::Printed;
use crate::args::ContainerArgs;
use crate::error::{BenchError, usage};
use crate::figures::{draw_packing, radial_distribution};
use crate::outputs::read_input;

/// Flags of `packbench plot`.
#[derive(Args, Debug)]
pub struct PlotArgs {
    /// Packing file in plain text; `-` reads standard input.
    pub file: String,
    #[command(flatten)]
    pub container: ContainerArgs,
    /// Figure file; .png or .svg.
    #[arg(long, default_value = "packing.png")]
    pub output: PathBuf,
    /// packing (the particles and their contacts) or gr (radial distribution function).
    #[arg(long, default_value = "packing")]
    pub kind: String,
}

/// Draws the figure.
pub fn run(args: &PlotArgs) -> Result<Printed, BenchError> {
    let p = read_input(&args.file, &args.container)?;
    let title = std::path::Path::new(&args.file)
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let svg = args.output.extension().is_some_and(|e| e == "svg");
    let fail = |e: Box<dyn std::error::Error>| {
        BenchError::Run(format!("drawing {}: {e}", args.output.display()))
    };
    match args.kind.as_str() {
        "packing" => {
            if svg {
                let root = SVGBackend::new(&args.output, (720, 720)).into_drawing_area();
                draw_packing(&root, &p, &title)
                    .and_then(|_| Ok(root.present()?))
                    .map_err(fail)?;
            } else {
                let root = BitMapBackend::new(&args.output, (720, 720)).into_drawing_area();
                draw_packing(&root, &p, &title)
                    .and_then(|_| Ok(root.present()?))
                    .map_err(fail)?;
            }
        }
        "gr" => {
            if !p.container.is_fully_periodic() {
                return Err(usage("g(r) is drawn for fully periodic packings only"));
            }
            let series = vec![(title.clone(), radial_distribution(&p, 200))];
            if svg {
                let root = SVGBackend::new(&args.output, (900, 520)).into_drawing_area();
                crate::figures::draw_gr(&root, &series)
                    .and_then(|_| Ok(root.present()?))
                    .map_err(fail)?;
            } else {
                let root = BitMapBackend::new(&args.output, (900, 520)).into_drawing_area();
                crate::figures::draw_gr(&root, &series)
                    .and_then(|_| Ok(root.present()?))
                    .map_err(fail)?;
            }
        }
        other => {
            return Err(usage(format!(
                "unknown --kind `{other}`; use packing or gr"
            )));
        }
    }
    Ok(Printed {
        stdout: String::new(),
        stderr: vec![format!("packbench plot: wrote {}", args.output.display())],
    })
}
