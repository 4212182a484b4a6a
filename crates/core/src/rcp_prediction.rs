//! φ_RCP predicted from the size distribution alone, to set beside a measured φ_J.
//!
//! Desmond & Weeks, "Influence of particle size distribution on random close packing of
//! spheres", Phys. Rev. E 90, 022204 (2014), arXiv:1303.4627: an empirical fit to their
//! simulated 3D packings in the polydispersity δ = std/mean and the skewness S of the radii
//! (the same for diameters),
//!
//!   φ_RCP = φ*_RCP + c₁ δ + c₂ S δ²,   φ*_RCP = 0.634, c₁ = 0.0658, c₂ = 0.0857.
//!
//! Range: 3D spheres, δ ≤ 0.4 ([`DW_MAX_POLYDISPERSITY`]); beyond it
//! [`RcpPrediction::desmond_weeks_in_range`] is false and the value is an extrapolation. Other
//! dimensions get no value. Provenance of the numbers: the paper's text could not be opened
//! here (the stored copies give its abstract only, which announces "a simple empirical formula"
//! without its coefficients); the form, the three numbers and the range δ ≤ 0.4 agree with the
//! one other public statement of them that was found (a public repository quoting
//! Phys. Rev. E 90 022204), which is a second-hand source. They are unchanged, and still to be
//! checked against the paper's equation (docs/notes/structure.md).
//!
//! Beside it, [`farr_groot`]: the Farr & Groot (J. Chem. Phys. 131, 244104 (2009)) mapping of
//! the actual diameters onto a one-dimensional packing of rods, calibrated to φ = 0.6435 for
//! equal spheres, for 3D spheres of any size distribution.

pub mod farr_groot;

use serde::{Deserialize, Serialize};

use crate::distribution::Moments;

/// Desmond–Weeks φ*_RCP: the monodisperse limit.
pub const DW_PHI_STAR: f64 = 0.634;
/// Desmond–Weeks coefficient of δ.
pub const DW_C1: f64 = 0.0658;
/// Desmond–Weeks coefficient of S·δ².
pub const DW_C2: f64 = 0.0857;
/// Largest polydispersity inside the range the Desmond–Weeks fit was made on.
pub const DW_MAX_POLYDISPERSITY: f64 = 0.4;

/// The predicted φ_RCP of a size distribution.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RcpPrediction {
    /// Dimension the prediction is for.
    pub dim: usize,
    /// Polydispersity δ = std/mean of the diameters.
    pub polydispersity: f64,
    /// Skewness S of the diameters.
    pub skewness: f64,
    /// Desmond–Weeks φ_RCP (3D only).
    pub desmond_weeks: Option<f64>,
    /// Whether δ lies inside the range the Desmond–Weeks fit was made on (3D, δ ≤ 0.4).
    pub desmond_weeks_in_range: bool,
    /// The range the Desmond–Weeks relation was fitted on, in words.
    pub desmond_weeks_range: String,
    /// Farr–Groot φ_RCP from the diameters themselves (3D only).
    pub farr_groot: Option<f64>,
    /// The range the Farr–Groot mapping is stated for, in words.
    pub farr_groot_range: String,
}

/// [`RcpPrediction::farr_groot_range`].
pub const FG_RANGE: &str = "3D spheres of any size distribution, calibrated to 0.6435 for equal spheres; checked by its authors on bidisperse, tridisperse and log-normal packings and exact at large size ratios (J. Chem. Phys. 131, 244104)";

/// [`RcpPrediction::desmond_weeks_range`].
pub const DW_RANGE: &str = "3D spheres, polydispersity of the radii δ ≤ 0.4, skewness of either sign (Phys. Rev. E 90, 022204)";

/// φ_RCP predicted for spheres in dimension `dim` with diameters `diameters`.
pub fn predict_rcp(dim: usize, diameters: &[f64]) -> RcpPrediction {
    let m = Moments::of(diameters);
    let (delta, s) = (m.polydispersity, m.skewness);
    RcpPrediction {
        dim,
        polydispersity: delta,
        skewness: s,
        desmond_weeks: (dim == 3)
            .then_some(DW_PHI_STAR + DW_C1 * delta + DW_C2 * s * delta * delta),
        desmond_weeks_in_range: dim == 3 && delta <= DW_MAX_POLYDISPERSITY,
        desmond_weeks_range: DW_RANGE.to_owned(),
        farr_groot: if dim == 3 {
            farr_groot::farr_groot(diameters)
        } else {
            None
        },
        farr_groot_range: FG_RANGE.to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn monodisperse_gives_phi_star_and_skew_raises_it() {
        let p = predict_rcp(3, &[1.0; 10]);
        assert_eq!(p.desmond_weeks, Some(DW_PHI_STAR));
        // Bidisperse 1 : 2 at equal numbers: δ = 1/3, S = 0.
        let b = predict_rcp(3, &[1.0, 2.0, 1.0, 2.0]);
        assert!((b.desmond_weeks.unwrap() - (0.634 + 0.0658 / 3.0)).abs() < 1e-12);
        // One large among three small: positive skew, higher than the symmetric value of the
        // same δ.
        let s = predict_rcp(3, &[1.0, 1.0, 1.0, 2.0]);
        assert!(s.skewness > 0.0);
        assert!(s.desmond_weeks.unwrap() > 0.634 + 0.0658 * s.polydispersity);
        assert!((p.farr_groot.unwrap() - farr_groot::FG_PHI_MONO).abs() < 1e-12);
        // Farr–Groot raises φ for the symmetric bidisperse mixture too.
        assert!(b.farr_groot.unwrap() > farr_groot::FG_PHI_MONO + 0.005);
        let disks = predict_rcp(2, &[1.0, 1.4]);
        assert!(disks.desmond_weeks.is_none() && disks.farr_groot.is_none());
    }
}
