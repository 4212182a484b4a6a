//! The distribution P(f/⟨f⟩) of contact forces and its small-force exponent θ: P(f) ∝ f^θ,
//! θ > 0 (weak forces are rare). At jamming θ_e = 0.42311 for the extended forces and
//! θ_ℓ = 0.17462 for the forces of bucklers, non-rattlers with exactly d + 1 contacts that
//! buckle locally (Charbonneau, Corwin, Parisi & Zamponi, PRL 114, 125504 (2015), Fig. 1;
//! Charbonneau, Kurchan, Parisi, Urbani & Zamponi, Nat. Commun. 5, 3725 (2014)).
//!
//! The forces are the core's force-balance solution (non-negative, mean 1, best balancing every
//! non-rattler). For an isostatic, force-balanced packing they are unique, so they are the
//! forces any exact method finds (CALiPPSO's LP duals included) up to their scale, and only
//! then are extended and buckler forces told apart. Otherwise (a soft-sphere packing with
//! extra contacts at the tolerance) they are one solution of many, with exact zeros where
//! another solution has a force; θ is then fitted to the forces in its window and flagged.

use serde::{Deserialize, Serialize};

use super::histogram::Histogram;
use super::power_law::{ExponentFit, fit_truncated_power_law};
use crate::analysis::{ContactNetwork, JAMMED_FORCE_BALANCE, balancing_forces};
use crate::error::CoreError;

/// Fewest forces inside the fit window for θ: below it P(f) has too few small forces.
pub const MIN_FORCES_FOR_THETA: usize = 20;

/// P(f/⟨f⟩) and its fitted exponents.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ForceDistribution {
    /// Probability density of f/⟨f⟩ over 10⁻⁴ … 10 on log bins, normalised by every force.
    pub histogram: Histogram,
    /// Contacts carrying a force (non-rattler contacts).
    pub count: usize,
    /// θ of P(f) ∝ f^θ over every force, by maximum likelihood on `fit_window`.
    pub theta: Option<f64>,
    /// The standard error of `theta`.
    pub theta_error: Option<f64>,
    /// The window of f/⟨f⟩ the fits use.
    pub fit_window: [f64; 2],
    /// Forces inside the window.
    pub fit_samples: usize,
    /// Whether the forces are unique: the non-rattlers are isostatic and force-balanced (an
    /// exact packing). Only then are `extended` and `bucklers` fitted.
    pub unique: bool,
    /// Non-rattlers with exactly d + 1 contacts.
    pub bucklers: usize,
    /// θ_e of the forces between non-bucklers (unique forces only).
    pub extended: Option<ExponentFit>,
    /// θ_ℓ of the forces on bucklers (unique forces only).
    pub localised: Option<ExponentFit>,
    /// Why a θ is missing or to be read with care, in words; `None` when all fits stand.
    pub note: Option<String>,
    /// Relative force-balance residual of these forces (small for a stable packing).
    pub residual: f64,
}

/// Forces of the contact network `net` (rattlers marked in `rattler`) in dimension `d`, whose
/// non-rattlers have `n_dof` degrees of freedom, and their distribution. Errors when the
/// force-balance solver fails.
pub fn force_distribution(
    net: &ContactNetwork,
    rattler: &[bool],
    d: usize,
    n_dof: usize,
    window: [f64; 2],
) -> Result<ForceDistribution, CoreError> {
    let balanced = balancing_forces(net, rattler, d)?;
    // The contacts that can carry a force: between non-rattlers, not with a self-image.
    let carrying: Vec<(usize, Option<usize>, f64)> = net
        .contacts
        .iter()
        .zip(&balanced.forces)
        .filter(|(c, _)| !rattler[c.i] && c.j.is_none_or(|j| j != c.i && !rattler[j]))
        .map(|(c, &f)| (c.i, c.j, f))
        .collect();
    let mut contacts = vec![0usize; rattler.len()];
    for &(i, j, _) in &carrying {
        contacts[i] += 1;
        if let Some(j) = j {
            contacts[j] += 1;
        }
    }
    let buckler: Vec<bool> = (0..rattler.len())
        .map(|i| !rattler[i] && contacts[i] == d + 1)
        .collect();
    let unique = carrying.len() == n_dof && balanced.residual <= JAMMED_FORCE_BALANCE;
    let f: Vec<f64> = carrying.iter().map(|c| c.2).collect();
    let (on_bucklers, extended): (Vec<_>, Vec<_>) = carrying
        .iter()
        .partition(|(i, j, _)| buckler[*i] || j.is_some_and(|j| buckler[j]));
    let forces = |v: Vec<&(usize, Option<usize>, f64)>| v.iter().map(|c| c.2).collect::<Vec<_>>();
    let all = fit_truncated_power_law(&f, window, MIN_FORCES_FOR_THETA);
    let fit_split = |v: Vec<f64>| {
        unique
            .then(|| fit_truncated_power_law(&v, window, MIN_FORCES_FOR_THETA))
            .flatten()
    };
    let mut dist = ForceDistribution {
        histogram: Histogram::logarithmic(&f, 1e-4, 10.0, 50),
        count: f.len(),
        theta: all.as_ref().map(|x| x.exponent),
        theta_error: all.as_ref().map(|x| x.error),
        fit_window: window,
        fit_samples: f
            .iter()
            .filter(|&&x| window[0] <= x && x <= window[1])
            .count(),
        unique,
        bucklers: buckler.iter().filter(|&&b| b).count(),
        extended: fit_split(forces(extended)),
        localised: fit_split(forces(on_bucklers)),
        note: None,
        residual: balanced.residual,
    };
    dist.note = note(&dist);
    Ok(dist)
}

/// The note of a force distribution: too few small forces to fit, forces that are not unique.
fn note(f: &ForceDistribution) -> Option<String> {
    let [lo, hi] = f.fit_window;
    let mut words = Vec::new();
    if f.theta.is_none() {
        words.push(format!(
            "P(f) has too few small forces to fit θ: {} of {} forces lie in f/⟨f⟩ ∈ [{lo}, {hi}], and a fit needs {MIN_FORCES_FOR_THETA}",
            f.fit_samples, f.count
        ));
    }
    if !f.unique {
        words.push(
            "the forces are one solution of many (the non-rattlers are not isostatic and force-balanced), so θ describes that solution, not the packing; refine the packing with an exact method for θ_e and θ_ℓ"
                .to_string(),
        );
    } else if f.theta.is_some() && (f.extended.is_none() || f.localised.is_none()) {
        words.push(format!(
            "too few extended or buckler forces in the window for θ_e and θ_ℓ apart (a fit needs {MIN_FORCES_FOR_THETA} of each)"
        ));
    }
    (!words.is_empty()).then(|| words.join("; "))
}
