//! The distribution P(f/⟨f⟩) of contact forces and its small-force exponent θ: P(f) ∝ f^θ,
//! θ ≈ 0.42 for the extended forces at jamming (Charbonneau, Kurchan, Parisi, Urbani & Zamponi,
//! Nat. Commun. 5, 3725 (2014): θ = 0.42311).
//!
//! The forces are the core's force-balance solution (non-negative, mean 1, best balancing every
//! non-rattler). For an isostatic packing they are unique, so they are the forces any exact
//! method finds (CALiPPSO's LP duals included) up to their scale.

use serde::{Deserialize, Serialize};

use super::histogram::Histogram;
use super::power_law::fit_small_values;
use crate::analysis::{ContactNetwork, balancing_forces};
use crate::error::CoreError;

/// P(f/⟨f⟩) and its fitted exponent.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ForceDistribution {
    /// Probability density of f/⟨f⟩ over 10⁻⁴ … 10 on log bins, normalised by every force.
    pub histogram: Histogram,
    /// Contacts carrying a force (non-rattler contacts).
    pub count: usize,
    /// θ of P(f) ∝ f^θ from the cumulative count over `fit_window` (`None` with fewer than 5
    /// forces there).
    pub theta: Option<f64>,
    /// The window of f/⟨f⟩ the fit used.
    pub fit_window: [f64; 2],
    /// Forces inside the window.
    pub fit_samples: usize,
    /// Relative force-balance residual of these forces (small for a stable packing).
    pub residual: f64,
}

/// Forces of the contact network `net` (rattlers marked in `rattler`) and their distribution.
/// Errors when the force-balance solver fails.
pub fn force_distribution(
    net: &ContactNetwork,
    rattler: &[bool],
    d: usize,
    window: [f64; 2],
) -> Result<ForceDistribution, CoreError> {
    let balanced = balancing_forces(net, rattler, d)?;
    // The contacts that can carry a force: between non-rattlers, not with a self-image.
    let mut f: Vec<f64> = net
        .contacts
        .iter()
        .zip(&balanced.forces)
        .filter(|(c, _)| !rattler[c.i] && c.j.is_none_or(|j| j != c.i && !rattler[j]))
        .map(|(_, &f)| f)
        .collect();
    f.sort_by(f64::total_cmp);
    let fit = fit_small_values(&f, window);
    Ok(ForceDistribution {
        histogram: Histogram::logarithmic(&f, 1e-4, 10.0, 50),
        count: f.len(),
        theta: fit.as_ref().map(|x| x.exponent),
        fit_window: window,
        fit_samples: fit.map_or(0, |x| x.samples),
        residual: balanced.residual,
    })
}
