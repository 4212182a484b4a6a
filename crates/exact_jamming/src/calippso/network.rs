//! The contact network of an LP's duals (contacts, forces, rattlers) and its exact closing
//! by a Newton projection after convergence.

use std::collections::BTreeSet;

use packbench_core::analysis::{Contact, ContactNetwork, rattlers};

use crate::contacts::{Key, Link};
use crate::growth::Growth;
use crate::min_norm::Solver;
use crate::projection::project;

use super::lp::LpStep;

/// The contact network of an LP (duals above `zero_force`), its rattlers, and per-particle
/// force imbalance relative to the mean force.
pub(super) struct Network {
    pub(super) rattler: Vec<bool>,
    /// Contacts among non-rattlers, with their forces ([`contact_force`]).
    pub(super) contacts: Vec<(Key, f64)>,
    pub(super) n_dof: usize,
    pub(super) imbalance: f64,
    /// Contact count per particle (all contacts).
    pub(super) degree: Vec<usize>,
    /// Keys of all contacts, to count how many change from one LP to the next.
    pub(super) keys: BTreeSet<Key>,
}

impl Network {
    /// Whether the network has at least n_dof contacts (and some), so that keeping its n_dof
    /// strongest can make it rigid: what the closure and the Newton finish need.
    pub(super) fn can_close(&self) -> bool {
        self.n_dof > 0 && self.contacts.len() >= self.n_dof
    }
}

pub(super) fn network(g: &Growth, step: &LpStep, zero_force: f64) -> Network {
    let (n, d) = (g.n, g.d);
    let mut net = ContactNetwork::default();
    let mut degree = vec![0usize; n];
    let mut kept = Vec::new();
    let mut keys = BTreeSet::new();
    for ((l, &z), &key) in step.links.iter().zip(&step.duals).zip(&step.keys) {
        if z > zero_force {
            keys.insert(key);
            net.contacts.push(Contact {
                i: l.i,
                j: l.j,
                wall: None,
                gap: 0.0,
            });
            degree[l.i] += 1;
            if let Some(j) = l.other() {
                degree[j] += 1;
            }
            kept.push((l, z, key));
        }
    }
    let rattler = rattlers(&net, n, d);
    let active = rattler.iter().filter(|&&r| !r).count();
    // Forces: the dual times the constraint's gradient magnitude, along the contact normal
    // (only directions matter for the balance test; the scale is divided out).
    let mut net_force = vec![0.0; n * d];
    let mut total = 0.0;
    let mut contacts = Vec::new();
    for &(l, z, key) in &kept {
        if rattler[l.i] || l.other().is_some_and(|j| rattler[j]) {
            continue;
        }
        let f = contact_force(l, z, g.t);
        contacts.push((key, f));
        total += f;
        l.add_transposed(f, &mut net_force, d);
    }
    let mut worst: f64 = 0.0;
    for i in 0..n {
        if !rattler[i] {
            let f2: f64 = net_force[i * d..(i + 1) * d].iter().map(|v| v * v).sum();
            worst = worst.max(f2.sqrt());
        }
    }
    let mean = if !contacts.is_empty() {
        total / contacts.len() as f64
    } else {
        1.0
    };
    Network {
        contacts,
        n_dof: if active == 0 {
            0
        } else {
            (d * active + 1).saturating_sub(g.container.rigid_motions())
        },
        imbalance: worst / mean,
        degree,
        rattler,
        keys,
    }
}

/// The force along the normal of a contact whose row has dual `z`, at growth factor `t`: the
/// constraints' u-gradients of `solve_lp` without their common factor R, 2|r|/σ² for a pair
/// and 1/ρ for a wall, with the actual σ and ρ (size·t). Taking the nominal sizes instead
/// scaled every wall force by 1/t, and walled runs reported force imbalances of 4 to 18 for
/// packings the core finds balanced to 1e-13.
pub(super) fn contact_force(l: &Link, z: f64, t: f64) -> f64 {
    let actual = l.size * t;
    z * match l.j {
        Some(_) => 2.0 * l.dist / (actual * actual),
        None => 1.0 / actual,
    }
}

/// Relative gap to which [`close_network`] closes the final contacts.
pub(super) const CLOSE_TOL: f64 = 1e-14;

/// Closes the non-rattler contacts of the last LP's network exactly. An LP makes its contacts
/// touch only to first order and to `lp_tol`, so a converged run leaves its weakest contacts
/// open by up to about `tol_s` (N = 4000, seed 81: 654 contacts with relative gaps of 1e-12 to
/// 1e-10 and one at 1.09e-9, which the core's count at contact tolerance 1e-9 missed). A Newton
/// projection of the positions and the growth factor together ([`project`], the network's
/// one dependency taking up the growth, as at the end of closest-jammed) closes them,
/// moving each particle by about that much. A near-degenerate last LP can carry more
/// contacts than n_dof; the weakest are left out. Returns the largest relative gap left, or
/// `None`, with nothing moved, when the network has fewer contacts than n_dof or the
/// projection does not converge.
pub(super) fn close_network(g: &mut Growth, net: &Network) -> Option<f64> {
    if !net.can_close() {
        return None;
    }
    let mut contacts = net.contacts.clone();
    contacts.sort_by(|a, b| b.1.total_cmp(&a.1));
    contacts.truncate(net.n_dof);
    // The strongest contact closes the dependency; `project` wants the forces of the basis
    // first, then of that contact.
    let (dependent, strongest) = contacts[0];
    let basis: Vec<Key> = contacts[1..].iter().map(|c| c.0).collect();
    let forces: Vec<f64> = contacts[1..]
        .iter()
        .map(|c| c.1)
        .chain([strongest])
        .collect();
    let solver = Solver::new(CLOSE_DENSE_MAX_BONDS);
    project(
        g,
        &basis,
        None,
        Some((&dependent, &forces)),
        CLOSE_TOL,
        &solver,
    )
    .ok()
}

/// Bond counts up to which [`close_network`] factorises densely (closest-jammed's default).
pub(super) const CLOSE_DENSE_MAX_BONDS: usize = 48;
