//! Neighbour bonds for bond-orientational order: pairs in contact, or pairs closer than a
//! cut-off relative to their contact distance.

use serde::{Deserialize, Serialize};

use crate::MAX_DIM;
use crate::analysis::contact_network;
use crate::neighbor::CellList;
use crate::packing::Packing;

/// Which pairs count as neighbours.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "rule")]
pub enum Neighbours {
    /// Pairs whose relative gap `r/σ − 1` is at most `tol` (the contact network).
    Contact {
        /// Largest relative gap counted (default 1e-6, as the analysis).
        tol: f64,
    },
    /// Pairs with `r < factor·σ_ij`, `σ_ij = (D_i + D_j)/2`.
    Cutoff {
        /// Cut-off relative to the contact distance (e.g. 1.2: the first shell of FCC, HCP and
        /// both shells of BCC).
        factor: f64,
    },
}

impl Neighbours {
    /// One line saying what the rule is, for reports.
    pub fn describe(&self) -> String {
        match self {
            Neighbours::Contact { tol } => format!("contacts (r/σ − 1 ≤ {tol:e})"),
            Neighbours::Cutoff { factor } => format!("pairs with r < {factor}·σ_ij"),
        }
    }
}

/// Bonds of a packing: pair `(i, j)` and the unit vector from `i` to `j`, each pair once.
pub struct Bonds {
    /// Pairs, `i < j`.
    pub pairs: Vec<(usize, usize)>,
    /// Row-major unit vectors, `d` per pair, from `i` to `j`.
    pub directions: Vec<f64>,
}

/// The bonds of `packing` under `rule`. Wall contacts and contacts of a particle with its own
/// periodic image carry no pair direction and are left out.
pub fn bonds(packing: &Packing, rule: Neighbours) -> Bonds {
    let d = packing.dim;
    let mut out = Bonds {
        pairs: Vec::new(),
        directions: Vec::new(),
    };
    match rule {
        Neighbours::Contact { tol } => {
            let net = contact_network(packing, tol);
            for (c, ct) in net.contacts.iter().enumerate() {
                match ct.j {
                    Some(j) if j != ct.i => {
                        out.pairs.push((ct.i, j));
                        out.directions
                            .extend_from_slice(&net.normals[c * d..(c + 1) * d]);
                    }
                    _ => {}
                }
            }
        }
        Neighbours::Cutoff { factor } => {
            let c = &packing.container;
            let dia = &packing.diameters;
            let skin = (factor - 1.0).max(0.0) * packing.max_diameter();
            let mut delta = [0.0; MAX_DIM];
            CellList::for_each_near_pair(c, &packing.positions, dia, skin, |i, j| {
                c.separation(packing.position(i), packing.position(j), &mut delta[..d]);
                let r = delta[..d].iter().map(|v| v * v).sum::<f64>().sqrt();
                let sigma = 0.5 * (dia[i] + dia[j]);
                if r > 0.0 && r < factor * sigma {
                    let (a, b, s) = if i < j { (i, j, 1.0) } else { (j, i, -1.0) };
                    out.pairs.push((a, b));
                    out.directions.extend(delta[..d].iter().map(|v| s * v / r));
                }
            });
        }
    }
    out
}
