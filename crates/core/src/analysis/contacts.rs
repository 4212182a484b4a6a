//! The contact network at a relative tolerance, with unit normals for force balance.

use crate::MAX_DIM;
use crate::neighbor::{CellList, for_each_image_pair, needs_images};
use crate::packing::Packing;

/// One contact: particle `i` with particle `j`, or with wall `wall` when `j` is `None`.
#[derive(Clone, Debug, PartialEq)]
pub struct Contact {
    /// First particle.
    pub i: usize,
    /// Second particle, or `None` for a wall contact.
    pub j: Option<usize>,
    /// The wall's id within its container (see `Container::for_each_wall`) for wall contacts.
    pub wall: Option<usize>,
    /// Relative gap `r/σ − 1` (negative when overlapping).
    pub gap: f64,
}

/// All contacts of a packing and their unit normals.
#[derive(Clone, Debug, Default)]
pub struct ContactNetwork {
    /// The contacts.
    pub contacts: Vec<Contact>,
    /// Row-major unit normals, `d` per contact, pointing from `i` to `j` (or into the wall).
    pub normals: Vec<f64>,
    /// Largest relative overlap `1 − r/σ` over pairs and walls (0 if none).
    pub max_overlap: f64,
}

/// Contacts of `packing` whose relative gap is at most `tol`. In a periodic box shorter than
/// twice the reach `D_max(1 + tol)`, every image is searched: a pair may then touch more than
/// once (one contact per image) and a particle may touch its own image (`j == Some(i)`).
pub fn contact_network(packing: &Packing, tol: f64) -> ContactNetwork {
    let d = packing.dim;
    let c = &packing.container;
    let x = &packing.positions;
    let dia = &packing.diameters;
    let mut net = ContactNetwork::default();
    // Any pair within tol·σ of contact has σ ≤ D_max, so this skin finds all of them.
    let skin = tol * packing.max_diameter() * (1.0 + 1e-12);
    let mut delta = [0.0; MAX_DIM];
    if needs_images(c, packing.max_diameter() + skin) {
        for_each_image_pair(c, x, dia, skin, |i, j, shift| {
            for k in 0..d {
                delta[k] = x[j * d + k] - x[i * d + k] + shift[k] as f64 * c.lengths[k];
            }
            net.add_pair(i, j, &delta[..d], 0.5 * (dia[i] + dia[j]), tol);
        });
    } else {
        CellList::for_each_near_pair(c, x, dia, skin, |i, j| {
            c.separation(
                &x[i * d..(i + 1) * d],
                &x[j * d..(j + 1) * d],
                &mut delta[..d],
            );
            net.add_pair(i, j, &delta[..d], 0.5 * (dia[i] + dia[j]), tol);
        });
    }
    if c.has_walls() {
        for i in 0..packing.n() {
            let radius = 0.5 * dia[i];
            c.for_each_wall(&x[i * d..(i + 1) * d], radius * (1.0 + tol), |w| {
                let gap = w.distance / radius - 1.0;
                net.max_overlap = net.max_overlap.max(-gap);
                if gap <= tol {
                    net.contacts.push(Contact {
                        i,
                        j: None,
                        wall: Some(w.id),
                        gap,
                    });
                    net.normals.extend_from_slice(w.normal);
                }
            });
        }
    }
    net
}

impl ContactNetwork {
    /// Records the pair `i`, `j` at separation `delta` (from `i` to `j`) if its relative gap is
    /// at most `tol`, and its overlap in any case.
    fn add_pair(&mut self, i: usize, j: usize, delta: &[f64], sigma: f64, tol: f64) {
        let r = delta.iter().map(|v| v * v).sum::<f64>().sqrt();
        let gap = r / sigma - 1.0;
        self.max_overlap = self.max_overlap.max(-gap);
        if gap > tol {
            return;
        }
        self.contacts.push(Contact {
            i: i.min(j),
            j: Some(i.max(j)),
            wall: None,
            gap,
        });
        let sign = if i <= j { 1.0 } else { -1.0 };
        // Coincident centres have no direction; any unit vector will do for counting.
        if r > 0.0 {
            self.normals.extend(delta.iter().map(|v| sign * v / r));
        } else {
            self.normals
                .extend((0..delta.len()).map(|k| if k == 0 { 1.0 } else { 0.0 }));
        }
    }
}
