//! What a fill returns besides the packing (Black & Cheviakov 2022 §2.3 outputs): the contact list, the
//! spheres touching each domain face, the achieved face and body fractions and the drawn radii;
//! and the writers of the contact list and face lists.

use std::io::Write;

use packbench_core::Container;
use packbench_core::run::Outcome;
use serde::{Deserialize, Serialize};

use crate::error::SeqFillError;

/// The spheres touching one face of the total domain (ListXmin … ListZmax).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FaceList {
    /// `xmin`, `xmax`, `ymin`, …, `x4min` … in d > 3, `hemisphere_xmin`/`hemisphere_xmax` for
    /// the curved walls of Example 3.
    pub name: String,
    /// The core's wall id (`2·axis + high side`; `2d`, `2d + 1` for the hemispheres).
    pub wall: usize,
    /// Indices into the packing, ascending.
    pub spheres: Vec<usize>,
}

/// The result of [`crate::run`].
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SeqFillOutcome {
    /// The core outcome: the packing of the total domain (Method 1: a walled box, or the
    /// hemisphere-cut brick; Method 2: a periodic box whose face spheres sit on x_a = 0), the
    /// number of radii drawn as `steps`, the termination (`goals_reached`, `nothing_fits` or
    /// `interrupted`), a trace of the unit-brick fill and the extra results as JSON.
    pub outcome: Outcome,
    /// Pairs `[i, j]`, `i < j`, of spheres whose surface gap is at most ε·r̄, ascending.
    pub contacts: Vec<[usize; 2]>,
    /// Spheres touching each face of the total domain. Method 1 and Example 3: surface within
    /// ε·r̄ of the wall. Method 2: centre on the face (opposite faces list the same spheres).
    pub faces: Vec<FaceList>,
    /// Achieved fraction of each unit-brick face covered by the projections of the spheres
    /// touching it, indexed by wall id (xmin, xmax, ymin, …).
    pub face_fractions: Vec<f64>,
    /// Achieved volume fraction of the unit brick (of the hemisphere-cut domain in Example 3).
    pub body_fraction: f64,
    /// Spheres in one unit brick (Method 2: each face sphere once).
    pub unit_brick_spheres: usize,
    /// The mean radius r̄ that ε, δ and the corner spheres refer to (estimated from 2^16 draws).
    pub mean_radius: f64,
    /// Radii drawn and placed in the unit brick, in order (the 2^d or 1 corner spheres of
    /// radius r̄ are not drawn and not listed).
    pub radii_placed: Vec<f64>,
    /// Radii drawn and discarded because they fitted nowhere, in order.
    pub radii_discarded: Vec<f64>,
}

/// The total domain assembled from the unit brick.
pub(crate) struct Domain {
    pub positions: Vec<f64>,
    pub diameters: Vec<f64>,
    pub container: Container,
    pub contacts: Vec<[usize; 2]>,
    pub faces: Vec<FaceList>,
}

/// Name of wall `wall` of a d-dimensional domain: `xmin`, `xmax`, `ymin`, … (`x4min` on the
/// fourth axis and beyond), `hemisphere_xmin`/`hemisphere_xmax` for ids `2d`, `2d + 1`.
pub fn face_name(d: usize, wall: usize) -> String {
    let side = if wall.is_multiple_of(2) { "min" } else { "max" };
    let axis = wall / 2;
    if axis >= d {
        return format!("hemisphere_x{side}");
    }
    match axis {
        0 => format!("x{side}"),
        1 => format!("y{side}"),
        2 => format!("z{side}"),
        _ => format!("x{}{side}", axis + 1),
    }
}

/// Face lists of a walled container: spheres whose surface lies within `gap` of each wall.
pub(crate) fn wall_face_lists(
    container: &Container,
    positions: &[f64],
    diameters: &[f64],
    gap: f64,
) -> Vec<FaceList> {
    let d = container.dim();
    let walls = match container.shape {
        packbench_core::Shape::HemisphereCutBrick { .. } => 2 * d + 2,
        _ => 2 * d,
    };
    let mut faces: Vec<FaceList> = (0..walls)
        .map(|w| FaceList {
            name: face_name(d, w),
            wall: w,
            spheres: Vec::new(),
        })
        .collect();
    for (i, &dia) in diameters.iter().enumerate() {
        let r = 0.5 * dia;
        container.for_each_wall(&positions[i * d..(i + 1) * d], r + gap + 1e-12 * r, |w| {
            if w.distance - r <= gap {
                faces[w.id].spheres.push(i);
            }
        });
    }
    faces
}

fn io(context: &str) -> impl FnOnce(std::io::Error) -> SeqFillError + '_ {
    move |source| SeqFillError::Io {
        context: context.into(),
        source,
    }
}

/// Writes the contact list as CSV: a header `i,j` and one 0-based index pair per line.
pub fn write_contacts_csv(
    contacts: &[[usize; 2]],
    out: &mut impl Write,
) -> Result<(), SeqFillError> {
    let mut s = String::with_capacity(16 * contacts.len() + 4);
    s.push_str("i,j\n");
    for [i, j] in contacts {
        s.push_str(&format!("{i},{j}\n"));
    }
    out.write_all(s.as_bytes())
        .map_err(io("writing the contact list"))
}

/// Writes the face lists as CSV: a header `face,sphere` and one line per sphere touching a face
/// (`xmin,17`), faces in wall-id order.
pub fn write_face_lists_csv(faces: &[FaceList], out: &mut impl Write) -> Result<(), SeqFillError> {
    let mut s = String::from("face,sphere\n");
    for f in faces {
        for i in &f.spheres {
            s.push_str(&format!("{},{i}\n", f.name));
        }
    }
    out.write_all(s.as_bytes())
        .map_err(io("writing the face lists"))
}
