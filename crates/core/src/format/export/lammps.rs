//! LAMMPS: a data file (atom_style sphere) and a dump file, both with the box; the data
//! file's comments give the input lines that read it with the right boundary and dimension,
//! the dump carries the boundary in its `BOX BOUNDS` flags.

use std::fmt::Write as _;

use super::{Cell, point3, push_coordinates_and_radius};
use crate::packing::Packing;

const AXES: [&str; 3] = ["x", "y", "z"];

/// LAMMPS's boundary letter of each axis: `p` periodic, `f` fixed (non-periodic).
fn boundary(cell: &Cell) -> [&'static str; 3] {
    cell.periodic.map(|p| if p { "p" } else { "f" })
}

/// The data file: a title and comments with the input-script lines (a data file has no
/// place for the boundary or the dimension), then the header and `Atoms # sphere` lines
/// `id type diameter density x y z` with density 1.
pub(super) fn data(packing: &Packing, cell: &Cell) -> String {
    let n = packing.n();
    let b = boundary(cell);
    let mut s = String::new();
    let _ = writeln!(s, "# {}", cell.title);
    let _ = writeln!(
        s,
        "# Read it with these input lines (f: packbench's hard walls at lo and hi; a run keeps \
         particles inside them only with a wall fix such as wall/gran):"
    );
    let _ = writeln!(s, "#   dimension {}", cell.dim);
    let _ = writeln!(s, "#   boundary {} {} {}", b[0], b[1], b[2]);
    let _ = writeln!(s, "#   atom_style sphere");
    let _ = writeln!(s, "#   read_data FILE\n");
    let _ = writeln!(s, "{n} atoms\n1 atom types\n");
    for (k, ax) in AXES.iter().enumerate() {
        let _ = writeln!(s, "{:e} {:e} {ax}lo {ax}hi", cell.lo[k], cell.hi[k]);
    }
    let _ = writeln!(s, "\nAtoms # sphere\n");
    for i in 0..n {
        let p = point3(packing, i);
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
    s
}

/// One dump frame (timestep 0): `ITEM: BOX BOUNDS` with each axis's boundary flags (`pp` or
/// `ff`), then `id type x y z radius`; a 2D packing has no z column, which OVITO reads as a
/// 2D cell (LAMMPS's own 2D dumps keep z = 0).
pub(super) fn dump(packing: &Packing, cell: &Cell) -> String {
    let n = packing.n();
    let b = boundary(cell);
    let mut s = String::new();
    let _ = writeln!(s, "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n{n}");
    let _ = writeln!(s, "ITEM: BOX BOUNDS {0}{0} {1}{1} {2}{2}", b[0], b[1], b[2]);
    for k in 0..3 {
        let _ = writeln!(s, "{:e} {:e}", cell.lo[k], cell.hi[k]);
    }
    let columns = AXES[..cell.dim].join(" ");
    let _ = writeln!(s, "ITEM: ATOMS id type {columns} radius");
    for i in 0..n {
        let _ = write!(s, "{} 1", i + 1);
        push_coordinates_and_radius(&mut s, packing, i);
    }
    s
}
