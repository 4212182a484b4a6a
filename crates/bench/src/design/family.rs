//! Families of size distributions with named, bounded parameters: what `packbench design`
//! searches over. A candidate is a value for every parameter; it becomes the diameters of one
//! packing through [`Family::diameters`], drawn with the packing's own seed so that the
//! diameters searched are exactly the diameters packed.
//!
//! Every parameter is dimensionless: sizes are ratios to the smallest (or typical) diameter,
//! because φ_J does not depend on the overall scale.

use packbench_core::SizeDistribution;
use rand::rngs::StdRng;
use rand::{RngExt, SeedableRng};
use rand_distr::{Distribution, Normal};
use serde::{Deserialize, Serialize};

use crate::error::{BenchError, usage};

/// Largest number of components of a [`FamilyKind::Mixture`].
pub const MAX_COMPONENTS: usize = 6;

/// One parameter of a family with its search interval `[lo, hi]`; `lo == hi` fixes it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Param {
    /// Name as given on the command line (`sigma`, `ratio`, `w1`, …).
    pub name: String,
    /// Lower bound.
    pub lo: f64,
    /// Upper bound (≥ `lo`).
    pub hi: f64,
}

impl Param {
    fn new(name: &str, lo: f64, hi: f64) -> Param {
        Param {
            name: name.to_string(),
            lo,
            hi,
        }
    }

    /// Whether the search varies it (`hi > lo`).
    pub fn is_free(&self) -> bool {
        self.hi > self.lo
    }
}

/// The kinds of family. Sizes are in units of the smallest diameter (bidisperse, power law,
/// mixture) or of the scale (log-normal, Weibull, gamma).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FamilyKind {
    /// ln D ~ Normal(0, `sigma`): one parameter, the log-standard deviation.
    Lognormal,
    /// Density ∝ D^`exponent` on [1, `ratio`].
    Powerlaw,
    /// Diameter 1 with number fraction `p`, else `ratio`.
    Bidisperse,
    /// Weibull of scale 1 and shape `shape`.
    Weibull,
    /// Gamma of scale 1 and shape `shape`.
    Gamma,
    /// `components` Gaussians in ln D on the support [1, `max_ratio`] (truncated to it), each
    /// with weight `w<i>` (normalised over the components), centre `c<i>` (0 = ln 1,
    /// 1 = ln max_ratio) and width `s<i>` (standard deviation in units of ln max_ratio): the
    /// free-form family, in the spirit of RCPGenerator's rcptools "universal" mixture.
    Mixture { components: usize, max_ratio: f64 },
}

/// A family and the bounds of its parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Family {
    pub kind: FamilyKind,
    /// Every parameter of the family, free or fixed, in the family's order.
    pub params: Vec<Param>,
}

/// The family names `--family` accepts.
pub const FAMILY_NAMES: &str = "lognormal, powerlaw, bidisperse, weibull, gamma or mixture";

impl Family {
    /// The family `name` with its default bounds; `components` and `max_ratio` shape a mixture
    /// (the others ignore them).
    ///
    /// Errors: a usage error for an unknown name, a mixture of 0 or more than
    /// [`MAX_COMPONENTS`] components, or a `max_ratio` that is not a finite number > 1.
    pub fn with_defaults(
        name: &str,
        components: usize,
        max_ratio: Option<f64>,
    ) -> Result<Family, BenchError> {
        let (kind, params) = match name {
            "lognormal" => (FamilyKind::Lognormal, vec![Param::new("sigma", 0.0, 0.4)]),
            "powerlaw" => (
                FamilyKind::Powerlaw,
                vec![
                    Param::new("ratio", 1.0, max_ratio.unwrap_or(10.0)),
                    Param::new("exponent", -4.0, 0.0),
                ],
            ),
            "bidisperse" => (
                FamilyKind::Bidisperse,
                vec![
                    Param::new("ratio", 1.0, max_ratio.unwrap_or(2.0)),
                    Param::new("p", 0.0, 1.0),
                ],
            ),
            "weibull" => (FamilyKind::Weibull, vec![Param::new("shape", 2.0, 20.0)]),
            "gamma" => (FamilyKind::Gamma, vec![Param::new("shape", 4.0, 100.0)]),
            "mixture" => {
                if components == 0 || components > MAX_COMPONENTS {
                    return Err(usage(format!(
                        "--components {components}: a mixture has 1 to {MAX_COMPONENTS} components"
                    )));
                }
                let r = max_ratio.unwrap_or(10.0);
                let mut params = Vec::new();
                for i in 1..=components {
                    params.push(Param::new(&format!("w{i}"), 0.0, 1.0));
                    params.push(Param::new(&format!("c{i}"), 0.0, 1.0));
                    params.push(Param::new(&format!("s{i}"), 0.01, 0.3));
                }
                (
                    FamilyKind::Mixture {
                        components,
                        max_ratio: r,
                    },
                    params,
                )
            }
            other => {
                return Err(usage(format!(
                    "unknown family `{other}`; use {FAMILY_NAMES}"
                )));
            }
        };
        if let Some(r) = max_ratio
            && !(r.is_finite() && r > 1.0)
        {
            return Err(usage(format!(
                "--max-ratio {r} must be a finite number above 1"
            )));
        }
        Ok(Family { kind, params })
    }

    /// The family's name on the command line.
    pub fn name(&self) -> &'static str {
        match self.kind {
            FamilyKind::Lognormal => "lognormal",
            FamilyKind::Powerlaw => "powerlaw",
            FamilyKind::Bidisperse => "bidisperse",
            FamilyKind::Weibull => "weibull",
            FamilyKind::Gamma => "gamma",
            FamilyKind::Mixture { .. } => "mixture",
        }
    }

    /// Sets the bounds of parameter `name` from `spec`: `lo:hi` to search the interval, or one
    /// number to fix it (the command line's `--param NAME=SPEC`).
    ///
    /// Errors: as [`Family::set_range`], and a usage error for a value that is not a number;
    /// each sentence starts with `--param NAME=SPEC`.
    pub fn set_bounds(&mut self, name: &str, spec: &str) -> Result<(), BenchError> {
        let flag = format!("--param {name}={spec}");
        let num = |s: &str| {
            s.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| usage(format!("{flag}: `{s}` is not a finite number")))
        };
        self.check_name(name)?;
        let (lo, hi) = match spec.split_once(':') {
            Some((a, b)) => (num(a)?, num(b)?),
            None => {
                let v = num(spec)?;
                (v, v)
            }
        };
        self.set_range(name, lo, hi).map_err(|e| match e {
            BenchError::Usage(m) => usage(format!("{flag}: {m}")),
            e => e,
        })
    }

    /// Errors with a usage error naming the family's parameters when it has no `name`.
    fn check_name(&self, name: &str) -> Result<(), BenchError> {
        if self.params.iter().any(|p| p.name == name) {
            return Ok(());
        }
        let known: Vec<&str> = self.params.iter().map(|p| p.name.as_str()).collect();
        Err(usage(format!(
            "the {} family has no parameter `{name}`; its parameters are {}",
            self.name(),
            known.join(", ")
        )))
    }

    /// Searches parameter `name` over `[lo, hi]` (`lo == hi` fixes it).
    ///
    /// Errors: a usage error for a parameter the family does not have (a sentence of its own),
    /// and for bounds that are not finite, reversed, or outside the parameter's domain (a
    /// clause the caller puts after the way the user gave them).
    pub fn set_range(&mut self, name: &str, lo: f64, hi: f64) -> Result<(), BenchError> {
        self.check_name(name)?;
        if !(lo.is_finite() && hi.is_finite()) {
            return Err(usage("the bounds must be finite numbers"));
        }
        if lo > hi {
            return Err(usage(format!(
                "the bounds are reversed (lower {lo} > upper {hi})"
            )));
        }
        let domain_ok = match name {
            "sigma" => lo >= 0.0,
            "exponent" => true,
            "ratio" => lo >= 1.0,
            "p" => lo >= 0.0 && hi <= 1.0,
            "shape" => lo > 0.0,
            _ if name.starts_with('w') => lo >= 0.0,
            _ if name.starts_with('c') => lo >= 0.0 && hi <= 1.0,
            _ if name.starts_with('s') => lo > 0.0,
            _ => true,
        };
        if !domain_ok {
            return Err(usage(format!(
                "the bounds leave the parameter's domain ({})",
                domain(name)
            )));
        }
        if let Some(p) = self.params.iter_mut().find(|p| p.name == name) {
            p.lo = lo;
            p.hi = hi;
        }
        Ok(())
    }

    /// The D_max/D_min bound on packed diameters that a search of this family checks: none for
    /// a mixture, whose support `[1, max_ratio]` already bounds it.
    pub fn ratio_constraint(&self, max_ratio: Option<f64>) -> Option<f64> {
        match self.kind {
            FamilyKind::Mixture { .. } => None,
            _ => max_ratio,
        }
    }

    /// Checks that the family has something to search.
    ///
    /// Errors: a usage error when every parameter is fixed, or when a mixture's weights are all
    /// fixed at 0.
    pub fn validate(&self) -> Result<(), BenchError> {
        if !self.params.iter().any(Param::is_free) {
            return Err(usage(format!(
                "the {} family has every parameter fixed: give at least one a range lo:hi with \
                 --param",
                self.name()
            )));
        }
        if matches!(self.kind, FamilyKind::Mixture { .. })
            && self
                .params
                .iter()
                .filter(|p| p.name.starts_with('w'))
                .all(|p| p.hi <= 0.0)
        {
            return Err(usage(
                "every weight of the mixture is fixed at 0: it describes no distribution",
            ));
        }
        Ok(())
    }

    /// The free parameters, in order: the coordinates of the search.
    pub fn free(&self) -> Vec<&Param> {
        self.params.iter().filter(|p| p.is_free()).collect()
    }

    /// Every parameter's value from the free ones' values in `[0, 1]` (0 = lower bound).
    pub fn values_from_unit(&self, unit: &[f64]) -> Vec<f64> {
        let mut it = unit.iter();
        self.params
            .iter()
            .map(|p| {
                if p.is_free() {
                    let u = it.next().copied().unwrap_or(0.5).clamp(0.0, 1.0);
                    p.lo + (p.hi - p.lo) * u
                } else {
                    p.lo
                }
            })
            .collect()
    }

    fn value(&self, values: &[f64], name: &str) -> f64 {
        self.params
            .iter()
            .position(|p| p.name == name)
            .map_or(f64::NAN, |i| values[i])
    }

    /// The core's distribution for `values` (every parameter, in the family's order), or
    /// `None` for a mixture, which the core has no distribution for ([`Family::diameters`]
    /// draws it).
    pub fn distribution(&self, values: &[f64]) -> Option<SizeDistribution> {
        let v = |n: &str| self.value(values, n);
        match self.kind {
            FamilyKind::Lognormal => Some(SizeDistribution::Lognormal {
                mu: 0.0,
                sigma: v("sigma"),
            }),
            FamilyKind::Powerlaw => Some(SizeDistribution::Powerlaw {
                d_min: 1.0,
                d_max: v("ratio"),
                exponent: v("exponent"),
            }),
            FamilyKind::Bidisperse => Some(SizeDistribution::Bidisperse {
                d1: 1.0,
                d2: v("ratio"),
                p: v("p"),
            }),
            FamilyKind::Weibull => Some(SizeDistribution::Weibull {
                scale: 1.0,
                shape: v("shape"),
            }),
            FamilyKind::Gamma => Some(SizeDistribution::Gamma {
                shape: v("shape"),
                scale: 1.0,
            }),
            FamilyKind::Mixture { .. } => None,
        }
    }

    /// The distribution a packing of `values` uses: the core's, or for a mixture the `n`
    /// diameters drawn with `seed` as a custom list (which the core reproduces exactly when
    /// asked for `n` diameters).
    ///
    /// Errors: a run error when the values make no valid distribution (e.g. zero weights).
    pub fn scene_distribution(
        &self,
        values: &[f64],
        n: usize,
        seed: u64,
    ) -> Result<SizeDistribution, BenchError> {
        match self.distribution(values) {
            Some(d) => Ok(d),
            None => Ok(SizeDistribution::Custom {
                list: self.diameters(values, n, seed)?,
            }),
        }
    }

    /// The `n` diameters a packing with `seed` gets: the same draw `packbench-core`'s initial
    /// packing makes (a fresh `StdRng` seeded with `seed`), before its scaling to the initial φ.
    ///
    /// Errors: a run error when the values make no valid distribution.
    pub fn diameters(&self, values: &[f64], n: usize, seed: u64) -> Result<Vec<f64>, BenchError> {
        let mut rng = StdRng::seed_from_u64(seed);
        if let Some(d) = self.distribution(values) {
            return Ok(d.sample(n, &mut rng)?);
        }
        let FamilyKind::Mixture {
            components,
            max_ratio,
        } = self.kind
        else {
            unreachable!("only the mixture has no core distribution")
        };
        let ln_r = max_ratio.ln();
        let comps: Vec<(f64, f64, f64)> = (1..=components)
            .map(|i| {
                (
                    self.value(values, &format!("w{i}")).max(0.0),
                    self.value(values, &format!("c{i}")) * ln_r,
                    (self.value(values, &format!("s{i}")) * ln_r).max(1e-9),
                )
            })
            .collect();
        let total: f64 = comps.iter().map(|c| c.0).sum();
        if !(total > 0.0 && total.is_finite()) {
            return Err(BenchError::Run(
                "the mixture's weights sum to zero: it describes no distribution".into(),
            ));
        }
        let mut out = Vec::with_capacity(n);
        for _ in 0..n {
            let mut u = rng.random::<f64>() * total;
            let mut k = 0;
            while k + 1 < comps.len() && u >= comps[k].0 {
                u -= comps[k].0;
                k += 1;
            }
            let (_, c, s) = comps[k];
            let g = Normal::new(c, s).map_err(|e| BenchError::Run(format!("mixture: {e}")))?;
            // Truncation to the support [1, max_ratio] by rejection; a component centred far
            // outside falls back to the nearest end after many tries.
            let mut x = f64::NAN;
            for _ in 0..1000 {
                let t = g.sample(&mut rng);
                if (0.0..=ln_r).contains(&t) {
                    x = t;
                    break;
                }
            }
            if x.is_nan() {
                x = c.clamp(0.0, ln_r);
            }
            out.push(x.exp());
        }
        Ok(out)
    }

    /// The values as `name=value` pairs, for messages and reports.
    pub fn describe(&self, values: &[f64]) -> String {
        self.params
            .iter()
            .zip(values)
            .map(|(p, v)| format!("{}={}", p.name, short(*v)))
            .collect::<Vec<_>>()
            .join(" ")
    }
}

/// A number in at most 6 significant digits, without trailing zeros.
pub fn short(v: f64) -> String {
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_string()
}

fn domain(name: &str) -> &'static str {
    match name {
        "sigma" => "sigma ≥ 0",
        "ratio" => "ratio ≥ 1",
        "p" => "0 ≤ p ≤ 1",
        "shape" => "shape > 0",
        _ if name.starts_with('w') => "weights ≥ 0",
        _ if name.starts_with('c') => "0 ≤ centre ≤ 1",
        _ if name.starts_with('s') => "width > 0",
        _ => "any finite number",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use packbench_core::distribution::Moments;

    #[test]
    fn the_diameters_are_those_the_initial_packing_draws() {
        let f = Family::with_defaults("lognormal", 0, None).unwrap();
        let values = f.values_from_unit(&[0.5]);
        let d = f.diameters(&values, 50, 9).unwrap();
        let dist = f.distribution(&values).unwrap();
        let again = dist.sample(50, &mut StdRng::seed_from_u64(9)).unwrap();
        assert_eq!(d, again);
    }

    #[test]
    fn a_mixture_stays_on_its_support_and_follows_its_weights() {
        let f = Family::with_defaults("mixture", 2, Some(10.0)).unwrap();
        // Component 1 at ln 1 (weight 3), component 2 at ln 10 (weight 1), both narrow.
        let values = vec![3.0, 0.0, 0.02, 1.0, 1.0, 0.02];
        let d = f.diameters(&values, 4000, 1).unwrap();
        assert!(d.iter().all(|&x| (1.0..=10.0).contains(&x)));
        let large = d.iter().filter(|&&x| x > 3.0).count() as f64 / d.len() as f64;
        assert!((large - 0.25).abs() < 0.03, "{large}");
        let m = Moments::of(&d);
        assert!(m.max / m.min <= 10.0);
    }

    #[test]
    fn bad_bounds_and_unknown_parameters_are_usage_errors() {
        let mut f = Family::with_defaults("bidisperse", 0, None).unwrap();
        assert_eq!(f.set_bounds("ratio", "1.4:1.0").unwrap_err().exit_code(), 2);
        assert_eq!(f.set_bounds("sigma", "0:1").unwrap_err().exit_code(), 2);
        assert_eq!(f.set_bounds("p", "0.5:1.5").unwrap_err().exit_code(), 2);
        assert_eq!(f.set_bounds("ratio", "x").unwrap_err().exit_code(), 2);
        f.set_bounds("ratio", "1.4").unwrap();
        f.set_bounds("p", "0.5").unwrap();
        assert_eq!(f.validate().unwrap_err().exit_code(), 2);
        assert!(Family::with_defaults("cauchy", 0, None).is_err());
        assert!(Family::with_defaults("mixture", 0, None).is_err());
        assert!(Family::with_defaults("mixture", 2, Some(0.5)).is_err());
    }
}
