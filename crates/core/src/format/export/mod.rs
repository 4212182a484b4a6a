//! Exports for visualisation and simulation codes, one file per family: extended XYZ
//! ([`xyz`]), LAMMPS data and dump ([`lammps`]), VTK XML PolyData and legacy VTK ([`vtk`]).
//!
//! Every export carries positions, sizes, the box and which axes are periodic, as far as its
//! format can; numbers are written in Rust's shortest round-trip form, so each value reads back
//! as the same `f64`. These formats are three-dimensional: a 2D packing gets z = 0, marked as
//! 2D where the format can say so. Curved walls are not carried as geometry by any of them:
//! the box written is their bounding box, and a comment names the wall where the format has
//! room for one.

mod lammps;
mod vtk;
mod xyz;

use crate::container::Shape;
use crate::error::CoreError;
use crate::packing::Packing;

/// An export format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExportFormat {
    /// Extended XYZ (OVITO, ASE for 3D): `Lattice`, `pbc` and a radius column; a 2D packing
    /// has two position columns, which OVITO reads as a 2D cell.
    Xyz,
    /// LAMMPS data file, atom_style sphere, whose header comments give the `dimension`,
    /// `boundary` and `atom_style` lines of the input script that reads it.
    Lammps,
    /// LAMMPS dump (`ITEM: BOX BOUNDS` with pp/ff flags, `id type x y z radius`; no z column
    /// for a 2D packing), which OVITO reads with its boundary and dimension.
    LammpsDump,
    /// VTK XML PolyData of the particles (ParaView, OVITO, VTK): `Radius` and `Diameter`
    /// point arrays, the box as FieldData.
    Vtp,
    /// VTK XML PolyData of the box's edges, to show beside [`ExportFormat::Vtp`] in ParaView.
    VtpBox,
    /// Legacy VTK, an unstructured grid of vertices with the arrays and fields of
    /// [`ExportFormat::Vtp`] (VTK, ParaView, VisIt, meshio; OVITO cannot read it).
    Vtk,
}

impl ExportFormat {
    /// Every format with its name on the command line.
    pub const ALL: [(&'static str, ExportFormat); 6] = [
        ("xyz", Self::Xyz),
        ("lammps", Self::Lammps),
        ("lammps-dump", Self::LammpsDump),
        ("vtp", Self::Vtp),
        ("vtp-box", Self::VtpBox),
        ("vtk", Self::Vtk),
    ];
}

impl std::str::FromStr for ExportFormat {
    type Err = CoreError;
    fn from_str(s: &str) -> Result<Self, CoreError> {
        Self::ALL
            .iter()
            .find(|(name, _)| *name == s)
            .map(|&(_, f)| f)
            .ok_or_else(|| {
                let names: Vec<&str> = Self::ALL.iter().map(|(name, _)| *name).collect();
                CoreError::Parameter(format!(
                    "unknown export format `{s}`; use one of {}",
                    names.join(", ")
                ))
            })
    }
}

/// The packing in `format`. Fails for d > 3, which these formats cannot hold.
pub fn export(packing: &Packing, format: ExportFormat) -> Result<String, CoreError> {
    let d = packing.dim;
    if d > 3 {
        return Err(CoreError::Parameter(format!(
            "a {d}-dimensional packing cannot be exported: xyz, lammps and vtk files hold at most 3 coordinates"
        )));
    }
    let cell = Cell::of(packing);
    Ok(match format {
        ExportFormat::Xyz => xyz::write(packing, &cell),
        ExportFormat::Lammps => lammps::data(packing, &cell),
        ExportFormat::LammpsDump => lammps::dump(packing, &cell),
        ExportFormat::Vtp => vtk::vtp(packing, &cell),
        ExportFormat::VtpBox => vtk::vtp_box(&cell),
        ExportFormat::Vtk => vtk::legacy(packing, &cell),
    })
}

/// The container's box as a three-dimensional format holds it.
struct Cell {
    /// Dimension of the packing, 2 or 3.
    dim: usize,
    /// Lower corner: 0 on every axis of the packing. A 2D packing's z is a slab around z = 0
    /// as thick as its largest particle, at least 1, because LAMMPS wants the particles
    /// strictly inside it.
    lo: [f64; 3],
    /// Upper corner.
    hi: [f64; 3],
    /// Per axis: periodic, or bounded by walls. A 2D packing's z is periodic, as LAMMPS
    /// requires of 2D runs.
    periodic: [bool; 3],
    /// One line naming the packing and its container, for the formats that have a comment.
    title: String,
}

impl Cell {
    fn of(packing: &Packing) -> Self {
        let c = &packing.container;
        let mut lo = [0.0; 3];
        let mut hi = [0.0; 3];
        let mut periodic = [true; 3];
        let d = packing.dim;
        hi[..d].copy_from_slice(&c.lengths);
        periodic[..d].copy_from_slice(&c.periodic);
        if packing.dim == 2 {
            let thickness = packing.max_diameter().max(1.0);
            lo[2] = -0.5 * thickness;
            hi[2] = 0.5 * thickness;
        }
        let mut title = format!(
            "packbench packing: {}D, {} particles, {}",
            packing.dim,
            packing.n(),
            c.describe()
        );
        if c.shape != Shape::Box {
            title.push_str("; the curved wall is not carried, only its bounding box");
        }
        Cell {
            dim: packing.dim,
            lo,
            hi,
            periodic,
            title,
        }
    }

    /// Side length of axis `k`.
    fn length(&self, k: usize) -> f64 {
        self.hi[k] - self.lo[k]
    }
}

/// Position of particle `i` in three coordinates (z = 0 in 2D).
fn point3(packing: &Packing, i: usize) -> [f64; 3] {
    let p = packing.position(i);
    [p[0], p[1], if packing.dim == 3 { p[2] } else { 0.0 }]
}

/// Appends ` x y [z] r` and a newline: particle `i`'s coordinates on the packing's own axes,
/// then its radius.
fn push_coordinates_and_radius(s: &mut String, packing: &Packing, i: usize) {
    use std::fmt::Write as _;
    for x in packing.position(i) {
        let _ = write!(s, " {x:e}");
    }
    let _ = writeln!(s, " {:e}", 0.5 * packing.diameters[i]);
}

#[cfg(test)]
mod tests;
