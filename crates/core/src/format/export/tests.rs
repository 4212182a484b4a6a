//! The writers' output read back by hand: exact values, boundary flags, 2D marking, walls.

use super::*;
use crate::container::Container;

/// Values with all of their mantissa in use, so only a round-trip representation survives.
fn packing(walls: &[i64], lengths: &[f64]) -> Packing {
    let d = lengths.len();
    let x: Vec<f64> = (0..2 * d)
        .map(|k| lengths[k % d] * (0.3 + (k as f64) / 10.0 + 1.0 / 3e3))
        .collect();
    let container = Container::from_rcp_flags(lengths, walls).unwrap();
    Packing::new(x, vec![0.1 + 0.2, 1.0 / 7.0], container).unwrap()
}

/// Numbers of a line, parsed.
fn numbers(line: &str) -> Vec<f64> {
    line.split_whitespace()
        .map(|t| t.parse().unwrap())
        .collect()
}

/// Whitespace-separated values of the XML `<DataArray Name="name">`.
fn xml_array(text: &str, name: &str) -> Vec<String> {
    let start = text.find(&format!("Name=\"{name}\"")).unwrap();
    let body = &text[start..];
    let open = body.find('>').unwrap() + 1;
    let close = body.find("</DataArray>").unwrap();
    body[open..close]
        .split_whitespace()
        .map(str::to_string)
        .collect()
}

fn floats(values: &[String]) -> Vec<f64> {
    values.iter().map(|v| v.parse().unwrap()).collect()
}

/// The lines after the line that starts with `marker`.
fn after<'a>(text: &'a str, marker: &str) -> Vec<&'a str> {
    text.lines()
        .skip_while(|l| !l.starts_with(marker))
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .collect()
}

#[test]
fn every_format_writes_the_exact_values() {
    let p = packing(&[], &[1.5, 2.0, 2.5]);
    let radii: Vec<f64> = p.diameters.iter().map(|d| 0.5 * d).collect();

    let xyz = export(&p, ExportFormat::Xyz).unwrap();
    let dump = export(&p, ExportFormat::LammpsDump).unwrap();
    for rows in [
        xyz.lines()
            .skip(2)
            .map(|l| numbers(&l[2..]))
            .collect::<Vec<_>>(),
        after(&dump, "ITEM: ATOMS")
            .iter()
            .map(|l| numbers(l)[2..].to_vec())
            .collect(),
    ] {
        assert_eq!(rows.len(), 2);
        for (i, row) in rows.iter().enumerate() {
            assert_eq!(&row[..3], p.position(i));
            assert_eq!(row[3], radii[i]);
        }
    }

    let data = export(&p, ExportFormat::Lammps).unwrap();
    let atoms = after(&data, "Atoms # sphere");
    assert_eq!(atoms.len(), 2);
    for (i, line) in atoms.iter().enumerate() {
        let row = numbers(line);
        assert_eq!(row[..4], [(i + 1) as f64, 1.0, p.diameters[i], 1.0]);
        assert_eq!(&row[4..], p.position(i));
    }

    let vtp = export(&p, ExportFormat::Vtp).unwrap();
    assert_eq!(floats(&xml_array(&vtp, "Points")), p.positions);
    assert_eq!(floats(&xml_array(&vtp, "Radius")), radii);
    assert_eq!(floats(&xml_array(&vtp, "Diameter")), p.diameters);

    let vtk = export(&p, ExportFormat::Vtk).unwrap();
    assert!(vtk.contains("CELLS 2 4\n1 0\n1 1\nCELL_TYPES 2\n1\n1\n"));
    // The geometry starts right after the dataset line, as OVITO's reader requires.
    let dataset = vtk
        .lines()
        .position(|l| l == "DATASET UNSTRUCTURED_GRID")
        .unwrap();
    assert_eq!(
        vtk.lines().nth(dataset + 1),
        Some("POINTS 2 double"),
        "{vtk}"
    );
    let points: Vec<f64> = after(&vtk, "POINTS 2 double")[..2]
        .iter()
        .flat_map(|l| numbers(l))
        .collect();
    assert_eq!(points, p.positions);
    assert_eq!(
        after(&vtk, "Diameter 1 2 double")[..2]
            .iter()
            .flat_map(|l| numbers(l))
            .collect::<Vec<_>>(),
        p.diameters
    );
}

#[test]
fn a_periodic_3d_box_is_periodic_everywhere() {
    let p = packing(&[], &[1.5, 2.0, 2.5]);
    let xyz = export(&p, ExportFormat::Xyz).unwrap();
    assert!(xyz.lines().nth(1).unwrap().starts_with(
        "Lattice=\"1.5 0 0 0 2 0 0 0 2.5\" Properties=species:S:1:pos:R:3:radius:R:1 pbc=\"T T T\""
    ));
    let data = export(&p, ExportFormat::Lammps).unwrap();
    assert!(data.contains("#   dimension 3\n#   boundary p p p\n"));
    assert!(data.contains("0e0 1.5e0 xlo xhi\n0e0 2e0 ylo yhi\n0e0 2.5e0 zlo zhi\n"));
    let dump = export(&p, ExportFormat::LammpsDump).unwrap();
    assert!(dump.contains("ITEM: BOX BOUNDS pp pp pp\n0e0 1.5e0\n0e0 2e0\n0e0 2.5e0\n"));
    assert!(dump.contains("ITEM: ATOMS id type x y z radius\n"));
    let vtp = export(&p, ExportFormat::Vtp).unwrap();
    assert_eq!(xml_array(&vtp, "BoxLengths"), ["1.5", "2", "2.5"]);
    assert_eq!(xml_array(&vtp, "Periodic"), ["1", "1", "1"]);
    assert_eq!(xml_array(&vtp, "Dimension"), ["3"]);
}

#[test]
fn walls_are_marked_non_periodic_in_every_format() {
    let p = packing(&[1, 0, 1], &[1.5, 2.0, 2.5]);
    let xyz = export(&p, ExportFormat::Xyz).unwrap();
    assert!(xyz.lines().nth(1).unwrap().ends_with("pbc=\"F T F\""));
    let data = export(&p, ExportFormat::Lammps).unwrap();
    assert!(data.contains("#   boundary f p f\n"));
    let dump = export(&p, ExportFormat::LammpsDump).unwrap();
    assert!(dump.contains("ITEM: BOX BOUNDS ff pp ff\n"));
    let vtp = export(&p, ExportFormat::Vtp).unwrap();
    assert_eq!(xml_array(&vtp, "Periodic"), ["0", "1", "0"]);
    let vtk = export(&p, ExportFormat::Vtk).unwrap();
    assert!(vtk.contains("FIELD FieldData 3\nBoxLengths 1 3 double\n1.5 2 2.5\nPeriodic 1 3 int\n0 1 0\nDimension 1 1 int\n3\n"));
}

#[test]
fn a_2d_packing_is_marked_2d_where_the_format_can_say_so() {
    let p = packing(&[0, 1], &[1.5, 2.0]);
    let xyz = export(&p, ExportFormat::Xyz).unwrap();
    let header = xyz.lines().nth(1).unwrap();
    assert!(header.contains("pos:R:2"), "{header}");
    assert!(header.ends_with("pbc=\"T F T\""), "{header}");
    assert_eq!(numbers(&xyz.lines().nth(2).unwrap()[2..]).len(), 3);

    // LAMMPS wants z periodic in 2D and the particles (at z = 0) strictly inside its slab.
    let data = export(&p, ExportFormat::Lammps).unwrap();
    assert!(data.contains("#   dimension 2\n#   boundary p f p\n"));
    assert!(data.contains("-5e-1 5e-1 zlo zhi\n"));
    for line in after(&data, "Atoms # sphere") {
        assert_eq!(numbers(line)[6], 0.0);
    }
    let dump = export(&p, ExportFormat::LammpsDump).unwrap();
    assert!(dump.contains("ITEM: BOX BOUNDS pp ff pp\n0e0 1.5e0\n0e0 2e0\n-5e-1 5e-1\n"));
    assert!(dump.contains("ITEM: ATOMS id type x y radius\n"));

    let vtp = export(&p, ExportFormat::Vtp).unwrap();
    assert_eq!(xml_array(&vtp, "Dimension"), ["2"]);
    assert_eq!(xml_array(&vtp, "BoxLengths"), ["1.5", "2"]);
    assert_eq!(xml_array(&vtp, "Periodic"), ["1", "0"]);
    let points = floats(&xml_array(&vtp, "Points"));
    assert_eq!(points[2], 0.0);
    assert_eq!(points[5], 0.0);
}

#[test]
fn the_box_outline_has_every_edge_once() {
    for (lengths, corners, edges) in [(vec![1.5, 2.0, 2.5], 8, 12), (vec![1.5, 2.0], 4, 4)] {
        let p = packing(&[], &lengths);
        let text = export(&p, ExportFormat::VtpBox).unwrap();
        assert!(text.contains(&format!(
            "NumberOfPoints=\"{corners}\" NumberOfVerts=\"0\" NumberOfLines=\"{edges}\""
        )));
        let points: Vec<[f64; 3]> = floats(&xml_array(&text, "Points"))
            .chunks(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect();
        let ends: Vec<usize> = xml_array(&text, "connectivity")
            .iter()
            .map(|v| v.parse().unwrap())
            .collect();
        assert_eq!(ends.len(), 2 * edges);
        let mut seen = std::collections::BTreeSet::new();
        for e in ends.chunks(2) {
            let (a, b) = (points[e[0]], points[e[1]]);
            let differ: Vec<usize> = (0..3).filter(|&k| a[k] != b[k]).collect();
            assert_eq!(differ.len(), 1, "an edge runs along one axis");
            assert_eq!((b[differ[0]] - a[differ[0]]).abs(), lengths[differ[0]]);
            assert!(seen.insert((e[0].min(e[1]), e[0].max(e[1]))));
        }
    }
}

#[test]
fn a_curved_wall_is_named_and_said_not_to_be_carried() {
    let container = Container::from_rcp_flags(&[2.0, 2.0, 2.0], &[-3, 0, 0]).unwrap();
    let p = Packing::new(vec![1.0, 1.0, 1.0], vec![0.5], container).unwrap();
    let note =
        "ball over 3 axes, diameter 2 [www]; the curved wall is not carried, only its bounding box";
    for format in [ExportFormat::Lammps, ExportFormat::Vtp, ExportFormat::Vtk] {
        assert!(export(&p, format).unwrap().contains(note), "{format:?}");
    }
    let xyz = export(&p, ExportFormat::Xyz).unwrap();
    assert!(xyz.contains("pbc=\"F F F\" container=\"ball over 3 axes, diameter 2 [www]\"\n"));
    assert!(
        export(&p, ExportFormat::Lammps)
            .unwrap()
            .contains("#   boundary f f f\n")
    );
}

#[test]
fn refusals_say_what_was_wrong() {
    let p = packing(&[], &[1.0; 4]);
    let e = export(&p, ExportFormat::Vtp).unwrap_err().to_string();
    assert!(
        e.contains("a 4-dimensional packing cannot be exported"),
        "{e}"
    );
    let e = "pdb".parse::<ExportFormat>().unwrap_err().to_string();
    assert!(
        e.contains(
            "unknown export format `pdb`; use one of xyz, lammps, lammps-dump, vtp, vtp-box, vtk"
        ),
        "{e}"
    );
    for (name, format) in ExportFormat::ALL {
        assert_eq!(name.parse::<ExportFormat>().unwrap(), format);
    }
}
