//! How far a run is towards its method's own stopping rule, in [0, 1], from its progress
//! reports (the `progress` value and bar of the Python module). Each method states its rule
//! as [`StopMeasure`]s ([`super::Method::stop_measures`]); [`StopProgress`] turns reports into
//! a fraction that never goes back.

use packbench_core::run::Progress;
use serde_json::{Map, Value};

use super::Method;

/// Terminations that mean a method met its own stopping rule (its bar ends at 100 %).
const MET: [&str; 5] = [
    "converged",
    "jammed",
    "pressure_cap",
    "rate_final",
    "target_reached",
];

/// True when `termination` says the method met its stopping rule.
pub fn met_stopping_rule(termination: &str) -> bool {
    MET.contains(&termination)
}

/// One way to measure the way to a stopping rule.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StopMeasure {
    /// The fraction the method reports itself (`Progress::fraction`).
    Reported,
    /// A quantity that moves geometrically from `start` (else its first report) to `target`,
    /// measured on a log scale: the report entry `quantity` (of `Progress::more`), or the
    /// report's labelled value when `None`.
    LogTo {
        quantity: Option<&'static str>,
        start: Option<f64>,
        target: Option<f64>,
    },
    /// The ratio of two report entries (closest-jammed's non-rattler bonds over N_dof).
    Ratio {
        numerator: &'static str,
        denominator: &'static str,
    },
}

/// A number parameter of a parameter object (for the targets of a [`StopMeasure`]).
pub fn number(params: &Map<String, Value>, key: &str) -> Option<f64> {
    params.get(key).and_then(Value::as_f64)
}

/// The progress of one run towards its stopping rule.
pub struct StopProgress {
    measures: Vec<StopMeasure>,
    first: Option<f64>,
    best: f64,
}

impl StopProgress {
    /// For a run of `method` with the complete parameter object `params`.
    pub fn new(method: &dyn Method, params: &Map<String, Value>) -> Self {
        StopProgress {
            measures: method.stop_measures(params),
            first: None,
            best: 0.0,
        }
    }

    /// The fraction of a report by the first measure the report carries the quantity of,
    /// never below an earlier one (Δφ and γ are not monotonic within a reversal); `None`
    /// when no measure applies.
    pub fn fraction(&mut self, p: &Progress) -> Option<f64> {
        let more = |name: &str| p.more.iter().find(|(k, _)| *k == name).map(|(_, v)| *v);
        let f = self.measures.clone().into_iter().find_map(|m| match m {
            StopMeasure::Reported => Some(p.fraction),
            StopMeasure::LogTo {
                quantity,
                start,
                target,
            } => {
                let now = match quantity {
                    Some(q) => more(q)?,
                    None => p.value,
                };
                Some(self.log_fraction(now, start, target))
            }
            StopMeasure::Ratio {
                numerator,
                denominator,
            } => Some(match (more(numerator)?, more(denominator)?) {
                (b, n) if n > 0.0 => Some(b / n),
                _ => None,
            }),
        })??;
        self.best = self.best.max(f.clamp(0.0, 1.0));
        Some(self.best)
    }

    /// log(first/now) / log(first/target), for a quantity going from `first` (`start`, else
    /// the first value seen) to `target`.
    fn log_fraction(&mut self, now: f64, start: Option<f64>, target: Option<f64>) -> Option<f64> {
        let target = target?;
        if !(now > 0.0 && target > 0.0) {
            return None;
        }
        let first = *self.first.get_or_insert(start.unwrap_or(now));
        let span = (first / target).ln();
        (span.abs() > 0.0).then(|| (first / now).ln() / span)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::methods::find;

    fn report(value: f64, more: Vec<(&'static str, f64)>) -> Progress {
        Progress {
            step: 1,
            phi: 0.5,
            label: "value",
            value,
            fraction: Some(0.25),
            more,
        }
    }

    #[test]
    fn mls_goes_from_its_first_rate_to_rate_final_on_a_log_scale() {
        let mls = find("mls").unwrap();
        let mut params = mls.default_params();
        params.insert("rate_final".into(), 1e-4.into());
        let mut s = StopProgress::new(mls, &params);
        assert_eq!(s.fraction(&report(0.0, vec![("rate", 10.0)])), Some(0.0));
        let half = s
            .fraction(&report(0.0, vec![("rate", 10f64.powf(-1.5))]))
            .unwrap();
        assert!((half - 0.5).abs() < 1e-12);
        // γ back up within a reversal: the bar does not go back.
        assert_eq!(s.fraction(&report(0.0, vec![("rate", 1.0)])), Some(half));
        assert_eq!(s.fraction(&report(0.0, vec![])), None);
    }

    #[test]
    fn closest_jammed_counts_bonds_over_degrees_of_freedom() {
        let cj = find("closest-jammed").unwrap();
        let mut s = StopProgress::new(cj, &cj.default_params());
        let r = report(0.0, vec![("non_rattler_bonds", 30.0), ("n_dof", 120.0)]);
        assert_eq!(s.fraction(&r), Some(0.25));
    }

    #[test]
    fn adam_on_rcpgenerator_s_schedule_reports_its_own_fraction() {
        let adam = find("adam").unwrap();
        let mut s = StopProgress::new(adam, &adam.default_params());
        assert_eq!(s.fraction(&report(0.0, vec![("mu", 1e-3)])), Some(0.25));
    }
}
