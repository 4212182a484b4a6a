//! The cheap screen of a design search: φ_RCP predicted from a candidate's diameters
//! (`packbench predict`'s relations, [`packbench_core::rcp_prediction`]) decides whether the
//! candidate is worth packing.
//!
//! The predictors are biased for a given method, N and protocol (Desmond–Weeks is a fit to
//! other simulations; every packer's φ_J differs by protocol), so the screen calibrates them on
//! the search's own packed candidates: the corrected prediction is `predicted + bias`, the bias
//! the mean of `packed − predicted` over the candidates packed in earlier generations, and a
//! candidate is skipped only when even `corrected ± (margin + 2 × residual std)` cannot improve
//! on the best candidate packed so far. A skipped candidate's fitness is taken from its
//! corrected prediction, so the optimiser still learns from it.

use packbench_core::rcp_prediction::predict_rcp;
use serde::{Deserialize, Serialize};

use super::family::{Family, FamilyKind};
use super::objective::{Objective, SizeMeasures};
use crate::error::{BenchError, usage};

/// Candidates packed before the screen starts skipping: the calibration needs a few.
pub const MIN_CALIBRATION: usize = 3;

/// Which predictor screens candidates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Screen {
    /// Desmond & Weeks (2014): polydispersity and skewness (3D only).
    DesmondWeeks,
    /// Farr & Groot (2009): the diameters mapped to a 1D packing of rods (3D only).
    FarrGroot,
    /// Every candidate is packed.
    None,
}

impl Screen {
    /// The screen named `name` (`dw`, `fg`, `none`).
    ///
    /// Errors: a usage error for an unknown name.
    pub fn parse(name: &str) -> Result<Screen, BenchError> {
        match name {
            "dw" | "desmond-weeks" => Ok(Screen::DesmondWeeks),
            "fg" | "farr-groot" => Ok(Screen::FarrGroot),
            "none" => Ok(Screen::None),
            other => Err(usage(format!(
                "unknown screen `{other}`; use auto, dw (Desmond–Weeks), fg (Farr–Groot) or none"
            ))),
        }
    }

    /// The screen named `name` for `family`: as [`Screen::parse`], and `auto` picks Farr–Groot
    /// for the mixture, discrete and power-law families, whose broad distributions leave Desmond–Weeks'
    /// range, Desmond–Weeks otherwise (docs/BENCHMARKS.md, Design).
    ///
    /// Errors: a usage error for an unknown name.
    pub fn for_family(name: &str, family: &Family) -> Result<Screen, BenchError> {
        match (name, &family.kind) {
            (
                "auto",
                FamilyKind::Mixture { .. } | FamilyKind::Discrete { .. } | FamilyKind::Powerlaw,
            ) => Ok(Screen::FarrGroot),
            ("auto", _) => Ok(Screen::DesmondWeeks),
            (name, _) => Screen::parse(name),
        }
    }

    /// The prediction this screen uses out of both.
    pub fn pick(&self, p: &Predictions) -> Option<f64> {
        match self {
            Screen::DesmondWeeks => p.desmond_weeks,
            Screen::FarrGroot => p.farr_groot,
            Screen::None => None,
        }
    }
}

/// Both predictions of φ_RCP for a candidate's diameters (3D only; `None` elsewhere).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Predictions {
    pub desmond_weeks: Option<f64>,
    pub farr_groot: Option<f64>,
}

/// Both predictions for `diameters` in `dim` dimensions.
pub fn predictions(dim: usize, diameters: &[f64]) -> Predictions {
    let p = predict_rcp(dim, diameters);
    Predictions {
        desmond_weeks: p.desmond_weeks,
        farr_groot: p.farr_groot,
    }
}

/// The screen's calibration: pairs (predicted, packed mean φ_J) of earlier candidates.
#[derive(Clone, Debug, Default)]
pub struct Calibration {
    residuals: Vec<f64>,
}

impl Calibration {
    /// Adds a packed candidate.
    pub fn add(&mut self, predicted: f64, packed: f64) {
        self.residuals.push(packed - predicted);
    }

    /// Mean and standard deviation of `packed − predicted`, once there are
    /// [`MIN_CALIBRATION`] pairs.
    pub fn bias_and_spread(&self) -> Option<(f64, f64)> {
        if self.residuals.len() < MIN_CALIBRATION {
            return None;
        }
        crate::records::mean_std(&self.residuals)
    }
}

/// The screen's verdict on a candidate before it is packed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Verdict {
    /// Pack it.
    Pack,
    /// Skip it, with this corrected prediction as its φ_J for the optimiser.
    Skip { corrected: f64 },
}

/// Whether to pack a candidate with prediction `predicted` (`None`: no prediction, so pack)
/// and size measures `m`, given the calibration, the best fitness packed so far, the
/// objective and the margin (in φ).
pub fn verdict(
    objective: &Objective,
    predicted: Option<f64>,
    m: &SizeMeasures,
    calibration: &Calibration,
    best_fitness: Option<f64>,
    margin: f64,
) -> Verdict {
    let (Some(pred), Some((bias, spread)), Some(best)) =
        (predicted, calibration.bias_and_spread(), best_fitness)
    else {
        return Verdict::Pack;
    };
    let corrected = pred + bias;
    let slack = margin + 2.0 * spread;
    // The most favourable φ_J the candidate could plausibly have, for this objective.
    let optimistic = match objective.target() {
        Some(t) if matches!(objective, Objective::Target { .. }) => {
            if (corrected - t).abs() <= slack {
                t
            } else if corrected < t {
                corrected + slack
            } else {
                corrected - slack
            }
        }
        _ => corrected + slack,
    };
    if objective.fitness(Some(optimistic), m) > best {
        Verdict::Skip { corrected }
    } else {
        Verdict::Pack
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_screen_skips_only_what_cannot_win_after_calibration() {
        let o = Objective::MaxPhi;
        let m = SizeMeasures::default();
        let mut c = Calibration::default();
        assert_eq!(
            verdict(&o, Some(0.5), &m, &c, Some(-0.66), 0.01),
            Verdict::Pack
        );
        for (p, q) in [(0.65, 0.645), (0.66, 0.655), (0.67, 0.665)] {
            c.add(p, q);
        }
        let (bias, spread) = c.bias_and_spread().unwrap();
        assert!((bias + 0.005).abs() < 1e-12 && spread < 1e-12);
        // Best packed φ_J 0.66: a prediction of 0.63 (corrected 0.625) cannot reach it.
        assert!(matches!(
            verdict(&o, Some(0.63), &m, &c, Some(-0.66), 0.01),
            Verdict::Skip { .. }
        ));
        assert_eq!(
            verdict(&o, Some(0.66), &m, &c, Some(-0.66), 0.01),
            Verdict::Pack
        );
        assert_eq!(verdict(&o, None, &m, &c, Some(-0.66), 0.01), Verdict::Pack);
        let t = Objective::Target { target: 0.66 };
        assert_eq!(
            verdict(&t, Some(0.664), &m, &c, Some(0.002), 0.01),
            Verdict::Pack
        );
        assert!(matches!(
            verdict(&t, Some(0.70), &m, &c, Some(0.002), 0.01),
            Verdict::Skip { .. }
        ));
    }
}
