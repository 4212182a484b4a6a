//! The analysis every method is judged by: φ, contacts at a tolerance, iterative rattler
//! removal, mean contact numbers, the isostatic count, the largest overlap and force balance.
//!
//! Definitions: a contact is a pair whose relative gap
//! `r_ij/σ_ij − 1` is at most `contact_tol` (overlapping pairs are contacts), or a particle
//! whose wall distance relative to its radius, `h/(D/2) − 1`, is at most `contact_tol`.

mod contacts;
mod force_balance;
mod jamming_verdict;
mod metrics_json;
mod rattlers;
pub mod structure;
pub mod void_space;

pub use contacts::{Contact, ContactNetwork, contact_network};
pub use force_balance::{BalancingForces, balancing_forces, force_balance};
pub use jamming_verdict::{JAMMED_FORCE_BALANCE, JAMMED_MAX_OVERLAP, not_jammed_because};
pub use rattlers::rattlers;

use serde::{Deserialize, Serialize};

use crate::distribution::Moments;
use crate::error::CoreError;
use crate::packing::Packing;

/// Options of [`analyze`].
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct AnalysisOptions {
    /// Largest relative gap `r/σ − 1` counted as a contact (default 1e-6).
    pub contact_tol: f64,
    /// Whether to solve for force balance (a conic program; skip it for quick looks).
    pub force_balance: bool,
}

impl Default for AnalysisOptions {
    fn default() -> Self {
        AnalysisOptions {
            contact_tol: 1e-6,
            force_balance: true,
        }
    }
}

/// The headline metrics of a packing; serialises to exactly the keys of `packbench analyze`,
/// with `z_nonrattler` and `iso_gap` as `null` when there are no non-rattlers
/// ([`Metrics::has_network`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(into = "metrics_json::MetricsJson", from = "metrics_json::MetricsJson")]
pub struct Metrics {
    /// Dimension.
    pub dim: usize,
    /// Number of particles.
    pub n: usize,
    /// Packing fraction.
    pub phi: f64,
    /// Number of contacts, particle pairs plus particle–wall contacts.
    pub contacts: usize,
    /// Mean contact number over all particles, (2·pair contacts + wall contacts)/N.
    pub z_mean: f64,
    /// Number of rattlers (removed iteratively: fewer than d+1 contacts).
    pub rattlers: usize,
    /// Mean contact number over the N' non-rattlers; undefined (0 here, `null` in JSON) when
    /// there are none.
    pub z_nonrattler: f64,
    /// Degrees of freedom d·N' − m + 1 (m: the container's rigid motions).
    pub n_dof: usize,
    /// Contacts among non-rattlers (wall contacts included) minus `n_dof`; undefined (0 here,
    /// `null` in JSON) when there are no non-rattlers: no network, so neither iso- nor
    /// hyperstatic.
    pub iso_gap: i64,
    /// `iso_gap == 0`.
    pub isostatic: bool,
    /// Largest relative overlap `1 − r/σ` (0 if none).
    pub max_overlap: f64,
    /// Relative residual ‖Σ f_c n_c‖ / Σ f_c of the best non-negative contact forces with mean 1;
    /// `None` when there are no non-rattlers or the check was not asked for.
    pub force_balance: Option<f64>,
    /// Polydispersity δ = std/mean of the diameters.
    pub polydispersity: f64,
    /// Skewness of the diameters.
    pub skewness: f64,
}

impl Metrics {
    /// Whether some particle is not a rattler: only then are `z_nonrattler` and `iso_gap`
    /// defined.
    pub fn has_network(&self) -> bool {
        self.rattlers < self.n
    }

    /// `iso_gap` where it is defined ([`Metrics::has_network`]).
    pub fn defined_iso_gap(&self) -> Option<i64> {
        self.has_network().then_some(self.iso_gap)
    }

    /// `z_nonrattler` where it is defined ([`Metrics::has_network`]).
    pub fn defined_z_nonrattler(&self) -> Option<f64> {
        self.has_network().then_some(self.z_nonrattler)
    }
}

/// Analyses `packing` with `options`. Errors: a negative or NaN tolerance, two particles at one
/// centre.
pub fn analyze(packing: &Packing, options: &AnalysisOptions) -> Result<Metrics, CoreError> {
    if !(options.contact_tol.is_finite() && options.contact_tol >= 0.0) {
        return Err(CoreError::Parameter(format!(
            "contact tolerance {} must be a non-negative number",
            options.contact_tol
        )));
    }
    // One rule for every command: `pack` refuses such a start, and no analysis can say which
    // way two coincident centres touch.
    if let Some((i, j)) = packing.coincident_centres() {
        return Err(CoreError::Packing(format!(
            "particles {} and {} have the same centre, so the direction of their contact (and the contacts, rattlers and forces that depend on it) is undefined; give distinct positions",
            i + 1,
            j + 1
        )));
    }
    let d = packing.dim;
    let n = packing.n();
    let net = contact_network(packing, options.contact_tol);
    let rattler = rattlers(&net, n, d);
    let n_active = rattler.iter().filter(|&&r| !r).count();
    let active_contacts = net
        .contacts
        .iter()
        .filter(|c| !rattler[c.i] && c.j.is_none_or(|j| !rattler[j]))
        .count();
    let ends: usize = net
        .contacts
        .iter()
        .map(|c| if c.j.is_some() { 2 } else { 1 })
        .sum();
    let active_ends: usize = net
        .contacts
        .iter()
        .filter(|c| !rattler[c.i] && c.j.is_none_or(|j| !rattler[j]))
        .map(|c| if c.j.is_some() { 2 } else { 1 })
        .sum();
    let n_dof = if n_active == 0 {
        0
    } else {
        (d * n_active + 1).saturating_sub(packing.container.rigid_motions())
    };
    let force_balance = if options.force_balance && n_active > 0 {
        Some(force_balance(&net, &rattler, d)?)
    } else {
        None
    };
    let moments = Moments::of(&packing.diameters);
    Ok(Metrics {
        dim: d,
        n,
        phi: packing.phi(),
        contacts: net.contacts.len(),
        z_mean: if n > 0 { ends as f64 / n as f64 } else { 0.0 },
        rattlers: n - n_active,
        z_nonrattler: if n_active > 0 {
            active_ends as f64 / n_active as f64
        } else {
            0.0
        },
        n_dof,
        iso_gap: active_contacts as i64 - n_dof as i64,
        isostatic: n_active > 0 && active_contacts == n_dof,
        max_overlap: net.max_overlap,
        force_balance,
        polydispersity: moments.polydispersity,
        skewness: moments.skewness,
    })
}

#[cfg(test)]
mod tests;
