//! Method 2's total domain (Black & Cheviakov 2022 §3): the unit brick has identical opposite faces, so
//! bricks are joined by plain copying. The unit brick is a periodic cell whose face spheres are
//! centred on the faces x_a = 0 (≡ L_a); the domain is the periodic box of BrickNumbers copies,
//! each face sphere stored once, and every contact of the cell (found by minimum image) is
//! carried to the copy of its partner in the neighbouring brick.

use packbench_core::Container;

use crate::error::SeqFillError;
use crate::outcome::{Domain, FaceList, face_name};
use crate::reflection::brick_index;
use crate::unit_brick::UnitBrick;

/// The tiled periodic domain of a filled Method 2 unit brick.
pub(crate) fn tile<const D: usize>(
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
            positions.extend((0..D).map(|a| idx[a] as f64 * lengths[a] + c[a]));
            diameters.push(2.0 * r);
        }
    }
    let total: Vec<f64> = (0..D).map(|a| lengths[a] * numbers[a] as f64).collect();
    let container = Container::periodic_box(&total)?;
    let mut contacts = Vec::with_capacity(bed.contacts.len() * bricks);
    let mut stride = [1usize; D];
    for a in 1..D {
        stride[a] = stride[a - 1] * numbers[a - 1];
    }
    for &[i, j] in &bed.contacts {
        let (ci, cj) = (bed.centres[i as usize], bed.centres[j as usize]);
        let v = bed.separation(&ci, &cj);
        // Which brick, relative to i's, holds the image of j that i touches.
        let mut shift = [0i64; D];
        for a in 0..D {
            shift[a] = ((ci[a] + v[a] - cj[a]) / lengths[a]).round() as i64;
        }
        for b in 0..bricks {
            let idx = brick_index::<D>(b, numbers);
            let partner: usize = (0..D)
                .map(|a| {
                    (idx[a] as i64 + shift[a]).rem_euclid(numbers[a] as i64) as usize * stride[a]
                })
                .sum();
            let (p, q) = (b * n + i as usize, partner * n + j as usize);
            contacts.push([p.min(q), p.max(q)]);
        }
    }
    contacts.sort_unstable();
    contacts.dedup();
    let mut faces = Vec::with_capacity(2 * D);
    for a in 0..D {
        // Centres on x_a = 0, which the periodic domain identifies with x_a = n_a L_a.
        let on: Vec<usize> = (0..n * bricks)
            .filter(|&s| positions[s * D + a] == 0.0)
            .collect();
        for wall in [2 * a, 2 * a + 1] {
            faces.push(FaceList {
                name: face_name(D, wall),
                wall,
                spheres: on.clone(),
            });
        }
    }
    Ok(Domain {
        positions,
        diameters,
        container,
        contacts,
        faces,
    })
}
