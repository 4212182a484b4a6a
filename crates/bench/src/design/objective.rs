//! What a design search optimises, as one number to minimise per candidate (the CMA-ES
//! fitness), from the candidate's packed φ_J (mean over its seeds) and its size measures.

use serde::{Deserialize, Serialize};

use crate::error::{BenchError, usage};

/// Fitness of a candidate whose packings all failed, or that broke a constraint: worse than
/// any candidate that was measured.
pub const INFEASIBLE: f64 = 1e6;

/// Penalty per unit of φ_J a candidate falls short of the target in the constrained
/// objectives: a shortfall of 0.001 costs as much as 1 in size ratio.
pub const SHORTFALL_WEIGHT: f64 = 1e3;

/// Offset that puts every candidate short of the target behind every candidate that reaches
/// it in the constrained objectives.
pub const SHORTFALL_OFFSET: f64 = 1e3;

/// Offset that puts every candidate that breaks a constraint behind every candidate that keeps
/// it, and ahead of the infeasible ones.
pub const CONSTRAINT_OFFSET: f64 = 1e4;

/// Penalty per unit of the constrained measure above its limit, so that the optimiser is led
/// back towards the limit.
pub const CONSTRAINT_WEIGHT: f64 = 1e4;

/// Constraints on a candidate's packings beside the objective: questions of the packed
/// structure, not of φ_J alone.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Constraints {
    /// Largest mean fraction of rattlers (spheres with fewer than d + 1 contacts, not part of
    /// the rigid backbone) in the method's packings.
    #[serde(default)]
    pub max_rattlers: Option<f64>,
}

impl Constraints {
    /// The constraints with `--max-rattlers` `max_rattlers`.
    ///
    /// Errors: a usage error for a fraction outside [0, 1].
    pub fn new(max_rattlers: Option<f64>) -> Result<Constraints, BenchError> {
        if let Some(r) = max_rattlers
            && !(0.0..=1.0).contains(&r)
        {
            return Err(usage(format!(
                "--max-rattlers {r} must be a fraction of the spheres between 0 and 1"
            )));
        }
        Ok(Constraints { max_rattlers })
    }

    /// The penalty added to the fitness of a candidate whose packings have a mean rattler
    /// fraction `rattlers` (`None`: not measured, which breaks a rattler constraint).
    pub fn penalty(&self, rattlers: Option<f64>) -> f64 {
        match (self.max_rattlers, rattlers) {
            (None, _) => 0.0,
            (Some(_), None) => CONSTRAINT_OFFSET + CONSTRAINT_WEIGHT,
            (Some(limit), Some(r)) if r > limit => {
                CONSTRAINT_OFFSET + CONSTRAINT_WEIGHT * (r - limit)
            }
            (Some(_), Some(_)) => 0.0,
        }
    }

    /// The constraints in words, for reports (empty when there are none).
    pub fn describe(&self) -> String {
        match self.max_rattlers {
            Some(r) => format!("at most {:.1} % rattlers", 100.0 * r),
            None => String::new(),
        }
    }
}

/// The objective of a search.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "objective")]
pub enum Objective {
    /// The highest φ_J.
    MaxPhi,
    /// φ_J as close as possible to `target`.
    Target { target: f64 },
    /// The smallest size ratio D_max/D_min of the packed diameters with φ_J ≥ `target`.
    MinRatio { target: f64 },
    /// The smallest polydispersity δ = std/mean of the packed diameters with φ_J ≥ `target`.
    MinPolydispersity { target: f64 },
}

/// The size measures of a candidate's diameters (those of its first packing).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SizeMeasures {
    /// D_max / D_min.
    pub size_ratio: f64,
    /// std / mean.
    pub polydispersity: f64,
}

impl Objective {
    /// The objective named `name` (`max-phi`, `target`, `min-ratio`, `min-polydispersity`)
    /// with `target` for those that need one, in `dim` dimensions.
    ///
    /// Errors: a usage error for an unknown name, a missing target, a target given to
    /// `max-phi`, or a target outside 0 < φ < 0.95 (no jammed packing of these families comes
    /// near 0.95).
    pub fn parse(name: &str, target: Option<f64>) -> Result<Objective, BenchError> {
        let need = || {
            let t =
                target.ok_or_else(|| usage(format!("--objective {name} needs --target φ_J")))?;
            if !(t > 0.0 && t < 0.95) {
                return Err(usage(format!(
                    "--target {t} is impossible: a jammed packing's φ lies between 0 and 1, and \
                     the families searched here stay below 0.95"
                )));
            }
            Ok(t)
        };
        let o = match name {
            "max-phi" | "max" => Objective::MaxPhi,
            "target" => Objective::Target { target: need()? },
            "min-ratio" => Objective::MinRatio { target: need()? },
            "min-polydispersity" => Objective::MinPolydispersity { target: need()? },
            other => {
                return Err(usage(format!(
                    "unknown objective `{other}`; use max-phi, target, min-ratio or \
                     min-polydispersity"
                )));
            }
        };
        if o == Objective::MaxPhi && target.is_some() {
            return Err(usage(
                "--target has no meaning with --objective max-phi; use --objective target",
            ));
        }
        Ok(o)
    }

    /// The target φ_J, if the objective has one.
    pub fn target(&self) -> Option<f64> {
        match *self {
            Objective::MaxPhi => None,
            Objective::Target { target }
            | Objective::MinRatio { target }
            | Objective::MinPolydispersity { target } => Some(target),
        }
    }

    /// The fitness (smaller is better) of a candidate with mean φ_J `phi` (`None`: no packing
    /// of it succeeded) and size measures `m`.
    pub fn fitness(&self, phi: Option<f64>, m: &SizeMeasures) -> f64 {
        let Some(phi) = phi else {
            return INFEASIBLE;
        };
        let constrained = |measure: f64, target: f64| {
            if phi >= target {
                measure
            } else {
                SHORTFALL_OFFSET + SHORTFALL_WEIGHT * (target - phi)
            }
        };
        match *self {
            Objective::MaxPhi => -phi,
            Objective::Target { target } => (phi - target).abs(),
            Objective::MinRatio { target } => constrained(m.size_ratio, target),
            Objective::MinPolydispersity { target } => constrained(m.polydispersity, target),
        }
    }

    /// The objective in words, for reports.
    pub fn describe(&self) -> String {
        match *self {
            Objective::MaxPhi => "maximise φ_J".into(),
            Objective::Target { target } => format!("reach φ_J = {target}"),
            Objective::MinRatio { target } => {
                format!("smallest size ratio D_max/D_min with φ_J ≥ {target}")
            }
            Objective::MinPolydispersity { target } => {
                format!("smallest polydispersity with φ_J ≥ {target}")
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_broken_rattler_constraint_ranks_behind_every_kept_one() {
        let c = Constraints::new(Some(0.02)).unwrap();
        let o = Objective::MaxPhi;
        let m = SizeMeasures::default();
        let kept = o.fitness(Some(0.60), &m) + c.penalty(Some(0.019));
        let broken = o.fitness(Some(0.70), &m) + c.penalty(Some(0.021));
        let worse = o.fitness(Some(0.70), &m) + c.penalty(Some(0.05));
        assert!(kept < broken && broken < worse && worse < INFEASIBLE);
        assert_eq!(Constraints::default().penalty(None), 0.0);
        assert!(Constraints::new(Some(1.5)).is_err());
    }

    #[test]
    fn feasible_candidates_beat_infeasible_ones_and_targets_are_checked() {
        let o = Objective::parse("min-ratio", Some(0.66)).unwrap();
        let small = SizeMeasures {
            size_ratio: 2.0,
            polydispersity: 0.2,
        };
        let large = SizeMeasures {
            size_ratio: 9.0,
            polydispersity: 0.5,
        };
        assert!(o.fitness(Some(0.661), &large) < o.fitness(Some(0.659), &small));
        assert!(o.fitness(Some(0.67), &small) < o.fitness(Some(0.67), &large));
        assert!(o.fitness(Some(0.65), &small) < o.fitness(Some(0.64), &small));
        assert_eq!(o.fitness(None, &small), INFEASIBLE);
        let t = Objective::parse("target", Some(0.66)).unwrap();
        assert!(t.fitness(Some(0.659), &small) < t.fitness(Some(0.665), &small));
        assert!(
            Objective::parse("max-phi", None)
                .unwrap()
                .fitness(Some(0.7), &small)
                < -0.69
        );
        for bad in [
            Objective::parse("target", None),
            Objective::parse("target", Some(1.2)),
            Objective::parse("min-ratio", Some(0.0)),
            Objective::parse("max-phi", Some(0.6)),
            Objective::parse("densest", None),
        ] {
            assert_eq!(bad.unwrap_err().exit_code(), 2);
        }
    }
}
