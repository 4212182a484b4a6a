//! The distribution g(h) of the relative gaps h = r/σ − 1 of near-contacts among the
//! non-rattlers, and its small-gap exponent γ: g(h) ∝ h^{−γ}, γ ≈ 0.41 at jamming
//! (Charbonneau, Kurchan, Parisi, Urbani & Zamponi, Nat. Commun. 5, 3725 (2014): γ = 0.41269).

use serde::{Deserialize, Serialize};

use super::histogram::Histogram;
use super::power_law::fit_small_values;
use crate::MAX_DIM;
use crate::neighbor::CellList;
use crate::packing::Packing;

/// g(h) and its fitted exponent.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct GapDistribution {
    /// Probability density of h over 10⁻⁹ … 1 on log bins, normalised by the gaps counted.
    pub histogram: Histogram,
    /// Gaps counted: pairs of non-rattlers with contact_tol < h ≤ 1.
    pub count: usize,
    /// γ of g(h) ∝ h^{−γ}, from the cumulative count over `fit_window` (`None` with fewer
    /// than 5 gaps there).
    pub gamma: Option<f64>,
    /// The window of h the fit used.
    pub fit_window: [f64; 2],
    /// Gaps inside the window.
    pub fit_samples: usize,
}

/// Gaps of `packing` between non-rattlers (`rattler[i]` false) with `contact_tol < h ≤ 1`.
pub fn gap_distribution(
    packing: &Packing,
    rattler: &[bool],
    contact_tol: f64,
    window: [f64; 2],
) -> GapDistribution {
    let d = packing.dim;
    let c = &packing.container;
    let dia = &packing.diameters;
    let mut gaps = Vec::new();
    let mut delta = [0.0; MAX_DIM];
    // h ≤ 1 means r ≤ 2σ_ij, i.e. r < σ_ij + D_max.
    CellList::for_each_near_pair(
        c,
        &packing.positions,
        dia,
        packing.max_diameter(),
        |i, j| {
            if rattler[i] || rattler[j] {
                return;
            }
            c.separation(packing.position(i), packing.position(j), &mut delta[..d]);
            let r = delta[..d].iter().map(|v| v * v).sum::<f64>().sqrt();
            let h = r / (0.5 * (dia[i] + dia[j])) - 1.0;
            if h > contact_tol && h <= 1.0 {
                gaps.push(h);
            }
        },
    );
    gaps.sort_by(f64::total_cmp);
    let fit = fit_small_values(&gaps, window);
    GapDistribution {
        histogram: Histogram::logarithmic(&gaps, 1e-9, 1.0, 45),
        count: gaps.len(),
        gamma: fit.as_ref().map(|f| -f.exponent),
        fit_window: window,
        fit_samples: fit.map_or(0, |f| f.samples),
    }
}
