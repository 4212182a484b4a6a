//! Structure beyond φ, the same ruler for every method: g(r), the structure factor S(k) and
//! spectral density χ(k) with S(k→0), bond-orientational order (Q4, Q6, local q6, ψ6 in 2D,
//! crystal-like fraction), the contact-force distribution P(f) and gap distribution g(h) with
//! their small-value exponents θ and γ, and φ_RCP predicted from the size distribution.
//!
//! [`analyze_structure`] is the one entry point the command line, the reports and Python call.

mod bond_order;
mod force_distribution;
mod form_factor;
mod gap_distribution;
mod histogram;
mod neighbours;
mod pair_correlation;
mod power_law;
mod spherical_harmonics;
mod structure_factor;

pub use bond_order::{
    BondOrder, CRYSTAL_CUTOFF, CRYSTAL_PSI6_MIN, SOLID_BOND_DOT, SOLID_BONDS_MIN, bond_order,
};
pub use force_distribution::{ForceDistribution, force_distribution};
pub use gap_distribution::{GapDistribution, gap_distribution};
pub use histogram::Histogram;
pub use neighbours::{Bonds, Neighbours, bonds};
pub use pair_correlation::{PairCorrelation, pair_correlation};
pub use power_law::{PowerLawFit, fit_small_values};
pub use spherical_harmonics::{normalised_legendre, spherical_harmonics};
pub use structure_factor::{StructureFactor, StructureFactorOptions, structure_factor};

use serde::{Deserialize, Serialize};

use crate::analysis::{contact_network, rattlers};
use crate::error::CoreError;
use crate::packing::Packing;
use crate::rcp_prediction::{RcpPrediction, predict_rcp};

/// Options of [`analyze_structure`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct StructureOptions {
    /// Neighbours of Q4, Q6 and ψ6 (default: contacts at relative gap 1e-6).
    pub neighbours: Neighbours,
    /// Largest relative gap counted as a contact, for rattlers, forces and gaps (default 1e-6).
    pub contact_tol: f64,
    /// Bins of g(r) (default 200).
    pub gr_bins: usize,
    /// Wave vectors and fit window of S(k).
    pub structure_factor: StructureFactorOptions,
    /// Window of relative gaps h for γ (default [1e-5, 1e-2]).
    pub gap_window: [f64; 2],
    /// Window of f/⟨f⟩ for θ (default [0.01, 0.3]).
    pub force_window: [f64; 2],
    /// Whether to solve for contact forces (a conic program; default true).
    pub forces: bool,
}

impl Default for StructureOptions {
    fn default() -> Self {
        StructureOptions {
            neighbours: Neighbours::Contact { tol: 1e-6 },
            contact_tol: 1e-6,
            gr_bins: 200,
            structure_factor: StructureFactorOptions::default(),
            gap_window: [1e-5, 1e-2],
            force_window: [0.01, 0.3],
            forces: true,
        }
    }
}

/// Everything [`analyze_structure`] measures; serde-serialisable (the `structure` object of
/// `packbench analyze --structure`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StructureReport {
    /// Dimension.
    pub dim: usize,
    /// Number of particles.
    pub n: usize,
    /// Packing fraction.
    pub phi: f64,
    /// Bond-orientational order (keys `q4`, `q6`, `psi6`, `crystal_fraction`, …).
    #[serde(flatten)]
    pub bond_order: BondOrder,
    /// g(r) (fully periodic boxes only).
    pub pair_correlation: Option<PairCorrelation>,
    /// S(k), χ̃(k) and `s_k0` (fully periodic boxes only).
    pub structure_factor: Option<StructureFactor>,
    /// g(h) and γ.
    pub gaps: GapDistribution,
    /// P(f) and θ (when forces were asked for and there are non-rattlers).
    pub forces: Option<ForceDistribution>,
    /// φ_RCP predicted from the diameters.
    pub rcp_prediction: RcpPrediction,
}

/// The structure of `packing`. Errors on out-of-range options or a failing force solve.
pub fn analyze_structure(
    packing: &Packing,
    options: &StructureOptions,
) -> Result<StructureReport, CoreError> {
    let window_ok = |w: [f64; 2]| w[0].is_finite() && w[1].is_finite() && 0.0 < w[0] && w[0] < w[1];
    if !(options.contact_tol.is_finite()
        && options.contact_tol >= 0.0
        && window_ok(options.gap_window)
        && window_ok(options.force_window))
    {
        return Err(CoreError::Parameter(format!(
            "structure options: contact tolerance {} must be non-negative and the fit windows {:?}, {:?} positive and increasing",
            options.contact_tol, options.gap_window, options.force_window
        )));
    }
    match options.neighbours {
        Neighbours::Contact { tol } if !(tol.is_finite() && tol >= 0.0) => {
            return Err(CoreError::Parameter(format!(
                "neighbour contact tolerance {tol} must be a non-negative number"
            )));
        }
        Neighbours::Cutoff { factor } if !(factor.is_finite() && factor > 0.0) => {
            return Err(CoreError::Parameter(format!(
                "neighbour cut-off factor {factor} must be a positive number"
            )));
        }
        _ => {}
    }
    let d = packing.dim;
    let n = packing.n();
    let periodic = packing.container.is_fully_periodic();
    let net = contact_network(packing, options.contact_tol);
    let rattler = rattlers(&net, n, d);
    let forces = if options.forces && rattler.iter().any(|r| !r) {
        let active = rattler.iter().filter(|&&r| !r).count();
        let n_dof = (d * active + 1).saturating_sub(packing.container.rigid_motions());
        Some(force_distribution(
            &net,
            &rattler,
            d,
            n_dof,
            options.force_window,
        )?)
    } else {
        None
    };
    Ok(StructureReport {
        dim: d,
        n,
        phi: packing.phi(),
        bond_order: bond_order(packing, options.neighbours),
        pair_correlation: periodic.then(|| pair_correlation(packing, options.gr_bins)),
        structure_factor: if periodic {
            Some(structure_factor(packing, &options.structure_factor)?)
        } else {
            None
        },
        gaps: gap_distribution(packing, &rattler, options.contact_tol, options.gap_window),
        forces,
        rcp_prediction: predict_rcp(d, &packing.diameters),
    })
}

#[cfg(test)]
mod tests;
