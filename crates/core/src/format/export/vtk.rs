//! VTK: XML PolyData of the particles (`.vtp`) and of the box's edges, and a legacy `.vtk`.
//!
//! Both particle writers give each point `Radius` (OVITO's name for particle size, and
//! ParaView's Point Gaussian scale) and `Diameter` (the scale for ParaView's Glyph filter,
//! whose sphere has radius 0.5), and the box as FieldData: `BoxLengths` and `Periodic` (1 or 0)
//! with one value per axis of the packing, and `Dimension`.
//!
//! OVITO reads a `.vtp` as particles only in the shape Aspherix writes (its
//! `ParaViewVTPParticleImporter`): little-endian, uncompressed, vertices only, one vertex per
//! point, the points array named `Points`, sizes in `Radius`. It ignores FieldData, so it shows
//! no cell; the XYZ and LAMMPS dump exports carry the cell to OVITO.

use std::fmt::Write as _;

use super::{Cell, point3};
use crate::packing::Packing;

/// A VTK value type, spelled differently in the XML and the legacy format.
#[derive(Clone, Copy)]
enum Kind {
    Float,
    Int,
}

impl Kind {
    fn xml(self) -> &'static str {
        match self {
            Kind::Float => "Float64",
            Kind::Int => "Int32",
        }
    }
    fn legacy(self) -> &'static str {
        match self {
            Kind::Float => "double",
            Kind::Int => "int",
        }
    }
}

/// A named array of values, one tuple of `components` values per entry of `tuples`.
struct Array {
    name: &'static str,
    kind: Kind,
    components: usize,
    tuples: Vec<String>,
}

/// The box as field data: `BoxLengths`, `Periodic` and `Dimension`.
fn box_fields(cell: &Cell) -> [Array; 3] {
    let d = cell.dim;
    [
        Array {
            name: "BoxLengths",
            kind: Kind::Float,
            components: 1,
            tuples: (0..d).map(|k| format!("{}", cell.length(k))).collect(),
        },
        Array {
            name: "Periodic",
            kind: Kind::Int,
            components: 1,
            tuples: (0..d)
                .map(|k| u8::from(cell.periodic[k]).to_string())
                .collect(),
        },
        Array {
            name: "Dimension",
            kind: Kind::Int,
            components: 1,
            tuples: vec![d.to_string()],
        },
    ]
}

/// `Radius` and `Diameter` of every particle.
fn size_arrays(packing: &Packing) -> [Array; 2] {
    [
        Array {
            name: "Radius",
            kind: Kind::Float,
            components: 1,
            tuples: packing
                .diameters
                .iter()
                .map(|&d| format!("{:e}", 0.5 * d))
                .collect(),
        },
        Array {
            name: "Diameter",
            kind: Kind::Float,
            components: 1,
            tuples: packing.diameters.iter().map(|d| format!("{d:e}")).collect(),
        },
    ]
}

/// The particle centres, three coordinates each (z = 0 in 2D).
fn points(packing: &Packing) -> Array {
    Array {
        name: "Points",
        kind: Kind::Float,
        components: 3,
        tuples: (0..packing.n())
            .map(|i| {
                let p = point3(packing, i);
                format!("{:e} {:e} {:e}", p[0], p[1], p[2])
            })
            .collect(),
    }
}

/// Appends one ASCII `<DataArray>`, a tuple per line.
fn xml_array(s: &mut String, indent: &str, a: &Array) {
    let _ = writeln!(
        s,
        "{indent}<DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" NumberOfTuples=\"{}\" format=\"ascii\">",
        a.kind.xml(),
        a.name,
        a.components,
        a.tuples.len()
    );
    for t in &a.tuples {
        let _ = writeln!(s, "{indent}  {t}");
    }
    let _ = writeln!(s, "{indent}</DataArray>");
}

/// The cells of a piece: `tag` (`Verts` or `Lines`) of `size` points each, the points of
/// every cell one after the other in `connectivity`.
struct Cells<'a> {
    tag: &'static str,
    connectivity: &'a [usize],
    size: usize,
}

impl Cells<'_> {
    /// Number of cells of kind `tag`: all of them for their own tag, 0 for the other.
    fn count(&self, tag: &str) -> usize {
        if tag == self.tag {
            self.connectivity.len() / self.size
        } else {
            0
        }
    }

    /// Appends the cell block: `Int64` connectivity and offsets.
    fn write(&self, s: &mut String) {
        let join = |values: &[usize]| {
            values
                .iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
                .join(" ")
        };
        let offsets: Vec<usize> = (1..=self.count(self.tag)).map(|c| c * self.size).collect();
        let _ = writeln!(s, "      <{}>", self.tag);
        let _ = writeln!(
            s,
            "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">{}</DataArray>",
            join(self.connectivity)
        );
        let _ = writeln!(
            s,
            "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">{}</DataArray>",
            join(&offsets)
        );
        let _ = writeln!(s, "      </{}>", self.tag);
    }
}

/// A whole `.vtp` file: one piece of `points` with `point_data` and `cells`, then the box.
fn xml_file(cell: &Cell, points: &Array, point_data: &[Array], cells: &Cells) -> String {
    let n = points.tuples.len();
    let mut s = String::new();
    s.push_str("<?xml version=\"1.0\"?>\n");
    s.push_str(
        "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n",
    );
    let _ = writeln!(s, "  <!-- {} -->", cell.title);
    s.push_str("  <PolyData>\n");
    let _ = writeln!(
        s,
        "    <Piece NumberOfPoints=\"{n}\" NumberOfVerts=\"{}\" NumberOfLines=\"{}\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">",
        cells.count("Verts"),
        cells.count("Lines")
    );
    if let Some(first) = point_data.first() {
        let _ = writeln!(s, "      <PointData Scalars=\"{}\">", first.name);
        for a in point_data {
            xml_array(&mut s, "        ", a);
        }
        s.push_str("      </PointData>\n");
    }
    s.push_str("      <Points>\n");
    xml_array(&mut s, "        ", points);
    s.push_str("      </Points>\n");
    cells.write(&mut s);
    s.push_str("    </Piece>\n");
    // After the piece: OVITO's format detection walks to <Piece> and gives up at the first
    // element before it that holds text.
    s.push_str("    <FieldData>\n");
    for a in &box_fields(cell) {
        xml_array(&mut s, "      ", a);
    }
    s.push_str("    </FieldData>\n  </PolyData>\n</VTKFile>\n");
    s
}

/// The particles as VTK XML PolyData: one vertex per particle, `Radius` and `Diameter`.
pub(super) fn vtp(packing: &Packing, cell: &Cell) -> String {
    let vertices: Vec<usize> = (0..packing.n()).collect();
    xml_file(
        cell,
        &points(packing),
        &size_arrays(packing),
        &Cells {
            tag: "Verts",
            connectivity: &vertices,
            size: 1,
        },
    )
}

/// The box's edges as VTK XML PolyData lines: 12 in 3D, 4 in 2D (at z = 0).
pub(super) fn vtp_box(cell: &Cell) -> String {
    let d = cell.dim;
    // Corner c has the upper bound on axis k where bit k of c is set.
    let corners = Array {
        name: "Points",
        kind: Kind::Float,
        components: 3,
        tuples: (0..1usize << d)
            .map(|c| {
                let x = |k: usize| {
                    if k >= d {
                        0.0
                    } else if c >> k & 1 == 1 {
                        cell.hi[k]
                    } else {
                        cell.lo[k]
                    }
                };
                format!("{:e} {:e} {:e}", x(0), x(1), x(2))
            })
            .collect(),
    };
    let edges: Vec<usize> = (0..1usize << d)
        .flat_map(|c| {
            (0..d)
                .filter(move |k| c >> k & 1 == 0)
                .flat_map(move |k| [c, c | 1 << k])
        })
        .collect();
    let lines = Cells {
        tag: "Lines",
        connectivity: &edges,
        size: 2,
    };
    xml_file(cell, &corners, &[], &lines)
}

/// Legacy VTK: an unstructured grid of one vertex cell per particle (meshio reads no legacy
/// polydata), POINTS first, the box as dataset FIELD data after the cells, `Radius` and
/// `Diameter` as point FIELD data.
pub(super) fn legacy(packing: &Packing, cell: &Cell) -> String {
    let n = packing.n();
    let mut s = String::new();
    // The header line is limited to 256 characters by the format.
    let title: String = cell.title.chars().take(255).collect();
    let _ = writeln!(
        s,
        "# vtk DataFile Version 3.0\n{title}\nASCII\nDATASET UNSTRUCTURED_GRID"
    );
    // POINTS first: readers that take the geometry in the order the format lists it (OVITO)
    // stop at a dataset FIELD here; VTK reads the box FIELD after CELL_TYPES all the same.
    let _ = writeln!(s, "POINTS {n} double");
    for t in &points(packing).tuples {
        let _ = writeln!(s, "{t}");
    }
    let _ = writeln!(s, "CELLS {n} {}", 2 * n);
    for i in 0..n {
        let _ = writeln!(s, "1 {i}");
    }
    // 1 is VTK_VERTEX.
    let _ = writeln!(s, "CELL_TYPES {n}");
    for _ in 0..n {
        s.push_str("1\n");
    }
    legacy_field(&mut s, &box_fields(cell), " ");
    // Point data as a FIELD too: VTK's legacy readers keep only the first SCALARS unless
    // told to read them all.
    let _ = writeln!(s, "POINT_DATA {n}");
    legacy_field(&mut s, &size_arrays(packing), "\n");
    s
}

/// Appends a legacy `FIELD` block, the values of each array joined by `separator`.
fn legacy_field(s: &mut String, arrays: &[Array], separator: &str) {
    let _ = writeln!(s, "FIELD FieldData {}", arrays.len());
    for a in arrays {
        let _ = writeln!(
            s,
            "{} {} {} {}\n{}",
            a.name,
            a.components,
            a.tuples.len(),
            a.kind.legacy(),
            a.tuples.join(separator)
        );
    }
}
