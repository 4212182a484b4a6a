//! Extended XYZ as OVITO and ASE read it: the box as `Lattice`, periodicity as `pbc`, one line
//! per particle with its radius.

use std::fmt::Write as _;

use super::{Cell, push_coordinates_and_radius};
use crate::packing::Packing;

/// The packing as extended XYZ. A 2D packing has two position columns (`pos:R:2`), which
/// OVITO reads as a 2D cell; a curved wall is named in a `container` key.
pub(super) fn write(packing: &Packing, cell: &Cell) -> String {
    let d = cell.dim;
    let pbc: Vec<&str> = cell
        .periodic
        .iter()
        .map(|&p| if p { "T" } else { "F" })
        .collect();
    let mut s = String::new();
    let _ = writeln!(s, "{}", packing.n());
    let _ = write!(
        s,
        "Lattice=\"{} 0 0 0 {} 0 0 0 {}\" Properties=species:S:1:pos:R:{d}:radius:R:1 pbc=\"{}\"",
        cell.length(0),
        cell.length(1),
        cell.length(2),
        pbc.join(" ")
    );
    if packing.container.shape != crate::container::Shape::Box {
        // The quotes delimit the value; the description has none of its own.
        let _ = write!(s, " container=\"{}\"", packing.container.describe());
    }
    s.push('\n');
    for i in 0..packing.n() {
        s.push('P');
        push_coordinates_and_radius(&mut s, packing, i);
    }
    s
}
