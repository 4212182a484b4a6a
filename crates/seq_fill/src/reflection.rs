//! Method 1's total domain (Black & Cheviakov 2022 §2.2): BrickNumbers copies of the unit brick, each the
//! mirror image of its neighbours about their shared face, so spheres touching a face meet
//! their own reflections. Contacts inside a brick are copied; contacts across brick faces are
//! found with the core's cell list and recorded.

use packbench_core::Container;
use packbench_core::neighbor::CellList;

use crate::error::SeqFillError;
use crate::outcome::{Domain, wall_face_lists};
use crate::unit_brick::UnitBrick;

/// Multi-index of brick `b` (axis 0 fastest).
pub(crate) fn brick_index<const D: usize>(mut b: usize, numbers: &[usize]) -> [usize; D] {
    let mut idx = [0; D];
    for (a, &n) in numbers.iter().enumerate() {
        idx[a] = b % n;
        b /= n;
    }
    idx
}

/// The reflected domain of a filled Method 1 unit brick (or the brick itself, in its own
/// container, when every brick number is 1 — the hemisphere-cut domain).
pub(crate) fn reflect<const D: usize>(
    brick: &UnitBrick<'_, D>,
    numbers: &[usize],
) -> Result<Domain, SeqFillError> {
    let bed = &brick.bed;
    let n = bed.len();
    let bricks: usize = numbers.iter().product();
    let lengths = bed.lengths;
    let mut positions = Vec::with_capacity(n * bricks * D);
    let mut diameters = Vec::with_capacity(n * bricks);
    for b in 0..bricks {
        let idx = brick_index::<D>(b, numbers);
        for (c, &r) in bed.centres.iter().zip(&bed.radii) {
            for a in 0..D {
                let local = if idx[a].is_multiple_of(2) {
                    c[a]
                } else {
                    lengths[a] - c[a]
                };
                positions.push(idx[a] as f64 * lengths[a] + local);
            }
            diameters.push(2.0 * r);
        }
    }
    let container = if bricks == 1 {
        brick.container.clone()
    } else {
        let total: Vec<f64> = (0..D).map(|a| lengths[a] * numbers[a] as f64).collect();
        Container::with_flags(&total, &[true; D])?
    };
    let mut contacts: Vec<[usize; 2]> = Vec::with_capacity(bed.contacts.len() * bricks);
    for b in 0..bricks {
        let off = b * n;
        contacts.extend(
            bed.contacts
                .iter()
                .map(|&[i, j]| [off + i as usize, off + j as usize]),
        );
    }
    if bricks > 1 {
        let gap = bed.contact_gap;
        CellList::for_each_near_pair(&container, &positions, &diameters, gap, |i, j| {
            if i / n == j / n {
                return;
            }
            let r: f64 = (0..D)
                .map(|a| (positions[i * D + a] - positions[j * D + a]).powi(2))
                .sum::<f64>()
                .sqrt();
            if r - 0.5 * (diameters[i] + diameters[j]) <= gap {
                contacts.push([i.min(j), i.max(j)]);
            }
        });
    }
    contacts.sort_unstable();
    let faces = wall_face_lists(&container, &positions, &diameters, bed.contact_gap);
    Ok(Domain {
        positions,
        diameters,
        container,
        contacts,
        faces,
    })
}
