//! `packbench export`: a packing file to extended XYZ, LAMMPS data or legacy VTK.

use std::path::PathBuf;

use clap::Args;
use packbench_core::format::{ExportFormat, export, write_atomic};

use super::Printed;
use crate::args::ContainerArgs;
use crate::error::BenchError;
use crate::outputs::read_input;

/// Flags of `packbench export`.
#[derive(Args, Debug)]
pub struct ExportArgs {
    /// Packing file in plain text; `-` reads standard input.
    pub file: String,
    /// xyz (OVITO), lammps (LAMMPS data, atom_style sphere) or vtk (ParaView).
    #[arg(long)]
    pub format: String,
    #[command(flatten)]
    pub container: ContainerArgs,
    /// Output file (default: standard output).
    #[arg(long)]
    pub output: Option<PathBuf>,
}

/// Converts the packing.
pub fn run(args: &ExportArgs) -> Result<Printed, BenchError> {
    let format: ExportFormat = args.format.parse()?;
    let packing = read_input(&args.file, &args.container)?;
    let text = export(&packing, format)?;
    match &args.output {
        Some(path) => {
            write_atomic(path, text.as_bytes())?;
            Ok(Printed {
                stdout: String::new(),
                stderr: vec![format!("packbench export: wrote {}", path.display())],
            })
        }
        None => Ok(Printed {
            stdout: text,
            stderr: vec![],
        }),
    }
}
