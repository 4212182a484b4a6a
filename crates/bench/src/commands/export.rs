//! `packbench export`: a packing file to extended XYZ, LAMMPS data or dump, or VTK, with its
//! box, periodic and walled axes and dimension as far as each format holds them.

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
    /// xyz, lammps, lammps-dump, vtp, vtp-box or vtk (see --help for what each carries).
    ///
    /// xyz: extended XYZ for OVITO (ASE too in 3D): the box as Lattice, pbc flags (F on walled
    /// axes), a radius column; a 2D packing has two position columns, which OVITO reads as 2D.
    ///
    /// lammps: LAMMPS data file, atom_style sphere; its comments give the `dimension`,
    /// `boundary` (f on walled axes) and `atom_style` input lines that read it. A 2D packing
    /// keeps z = 0 inside a thin periodic z slab, as LAMMPS's `dimension 2` wants.
    ///
    /// lammps-dump: LAMMPS dump, `ITEM: BOX BOUNDS` with pp/ff flags and `id type x y z
    /// radius` (no z column in 2D): OVITO reads it with its walls and as 2D.
    ///
    /// vtp: VTK XML PolyData of the particles for ParaView and OVITO: Radius and Diameter point
    /// arrays, the box lengths, periodic flags and dimension as FieldData (which ParaView and
    /// VTK read; OVITO reads the particles but shows no cell: use xyz or lammps-dump there).
    ///
    /// vtp-box: the box's edges as VTK XML PolyData lines, to show beside a vtp in ParaView.
    ///
    /// vtk: legacy VTK, an unstructured grid of vertices with the same arrays and fields, for
    /// older VTK readers and meshio; OVITO cannot read it, use vtp.
    ///
    /// No format carries a curved wall (--walls -t, --shell, --hemispheres) as geometry: the box
    /// written is its bounding box, and lammps, vtp and vtk name the wall in a comment, xyz in
    /// a `container` key.
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
