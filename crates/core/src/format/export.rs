//! Exports for visualisation and simulation codes: extended XYZ (OVITO), LAMMPS data
//! (atom_style sphere) and legacy VTK polydata with a diameter array (ParaView).
//! These formats are three-dimensional: 2D packings are written with z = 0.

use std::fmt::Write as _;

use crate::error::CoreError;
use crate::packing::Packing;

/// An export format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExportFormat {
    /// Extended XYZ with a `Lattice` for the box and a radius column.
    Xyz,
    /// LAMMPS data file, atom_style sphere.
    Lammps,
    /// Legacy VTK polydata with a `diameter` point array.
    Vtk,
}

impl std::str::FromStr for ExportFormat {
    type Err = CoreError;
    fn from_str(s: &str) -> Result<Self, CoreError> {
        match s {
            "xyz" => Ok(Self::Xyz),
            "lammps" => Ok(Self::Lammps),
            "vtk" => Ok(Self::Vtk),
            _ => Err(CoreError::Parameter(format!(
                "unknown export format `{s}`; use xyz, lammps or vtk"
            ))),
        }
    }
}

/// The packing in `format`. Fails for d > 3, which these formats cannot hold.
pub fn export(packing: &Packing, format: ExportFormat) -> Result<String, CoreError> {
    let d = packing.dim;
    if d > 3 {
        return Err(CoreError::Parameter(format!(
            "{d}-dimensional packings cannot be exported to xyz, lammps or vtk, which hold 3 coordinates"
        )));
    }
    let l = |k: usize| {
        if k < d {
            packing.container.lengths[k]
        } else {
            packing.max_diameter().max(1.0)
        }
    };
    let xyz = |i: usize| {
        let p = packing.position(i);
        [p[0], p[1], if d == 3 { p[2] } else { 0.0 }]
    };
    let mut s = String::new();
    match format {
        ExportFormat::Xyz => {
            let pbc = (0..3)
                .map(|k| {
                    if k < d && packing.container.periodic[k] {
                        "T"
                    } else {
                        "F"
                    }
                })
                .collect::<Vec<_>>()
                .join(" ");
            let _ = writeln!(s, "{}", packing.n());
            let _ = writeln!(
                s,
                "Lattice=\"{} 0 0 0 {} 0 0 0 {}\" Properties=species:S:1:pos:R:3:radius:R:1 pbc=\"{pbc}\"",
                l(0),
                l(1),
                l(2)
            );
            for i in 0..packing.n() {
                let p = xyz(i);
                let _ = writeln!(
                    s,
                    "P {:e} {:e} {:e} {:e}",
                    p[0],
                    p[1],
                    p[2],
                    0.5 * packing.diameters[i]
                );
            }
        }
        ExportFormat::Lammps => {
            let _ = writeln!(
                s,
                "# packbench packing, {d}D, {} particles (atom_style sphere)\n",
                packing.n()
            );
            let _ = writeln!(s, "{} atoms\n1 atom types\n", packing.n());
            for (k, ax) in ["x", "y", "z"].iter().enumerate() {
                let (lo, hi) = if k < d {
                    (0.0, l(k))
                } else {
                    (-0.5 * l(k), 0.5 * l(k))
                };
                let _ = writeln!(s, "{lo:e} {hi:e} {ax}lo {ax}hi");
            }
            let _ = writeln!(s, "\nAtoms # sphere\n");
            for i in 0..packing.n() {
                let p = xyz(i);
                let _ = writeln!(
                    s,
                    "{} 1 {:e} 1 {:e} {:e} {:e}",
                    i + 1,
                    packing.diameters[i],
                    p[0],
                    p[1],
                    p[2]
                );
            }
        }
        ExportFormat::Vtk => {
            let n = packing.n();
            let _ = writeln!(
                s,
                "# vtk DataFile Version 3.0\npackbench packing ({d}D)\nASCII\nDATASET POLYDATA"
            );
            let _ = writeln!(s, "POINTS {n} double");
            for i in 0..n {
                let p = xyz(i);
                let _ = writeln!(s, "{:e} {:e} {:e}", p[0], p[1], p[2]);
            }
            let _ = writeln!(s, "VERTICES {n} {}", 2 * n);
            for i in 0..n {
                let _ = writeln!(s, "1 {i}");
            }
            let _ = writeln!(
                s,
                "POINT_DATA {n}\nSCALARS diameter double 1\nLOOKUP_TABLE default"
            );
            for i in 0..n {
                let _ = writeln!(s, "{:e}", packing.diameters[i]);
            }
        }
    }
    Ok(s)
}
