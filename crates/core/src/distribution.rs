//! Size distributions of diameters, with RCPGenerator's `InitializeParticles` parameter names,
//! sampled with `rand_distr`. Every parameter describes diameters.

use rand::{Rng, RngExt};
use rand_distr::{Distribution, Gamma, LogNormal, Normal, Weibull};
use serde::{Deserialize, Serialize};
use statrs::distribution::ContinuousCDF;

use crate::error::CoreError;

/// A distribution of particle diameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "dist", rename_all = "kebab-case")]
pub enum SizeDistribution {
    /// Every diameter equal to `d`.
    Mono { d: f64 },
    /// Diameter `d1` with probability `p`, else `d2`.
    Bidisperse { d1: f64, d2: f64, p: f64 },
    /// Normal with mean `mu` and standard deviation `sigma`, truncated to positive values.
    Gaussian { mu: f64, sigma: f64 },
    /// Normal(`mu1`, `sigma1`) with probability `p`, else Normal(`mu2`, `sigma2`); positive only.
    #[serde(rename = "biGaussian", alias = "bigaussian")]
    BiGaussian {
        mu1: f64,
        sigma1: f64,
        mu2: f64,
        sigma2: f64,
        p: f64,
    },
    /// ln D ~ Normal(`mu`, `sigma`).
    Lognormal { mu: f64, sigma: f64 },
    /// Log-normal with mean diameter 1 and standard deviation `sigma` of the diameters
    /// (Baranau & Tallarek's tables, Baranau & Tallarek 2014): polydispersity δ = `sigma`.
    LognormalMean1 { sigma: f64 },
    /// Uniform on `[d_min, d_max]`.
    Flat { d_min: f64, d_max: f64 },
    /// Density ∝ D^`exponent` on `[d_min, d_max]`.
    Powerlaw {
        d_min: f64,
        d_max: f64,
        exponent: f64,
    },
    /// Exponential density ∝ exp(−(D − d_min)/d_min) truncated to `[d_min, d_max]`
    /// (the scale is the smallest diameter).
    Exponential { d_min: f64, d_max: f64 },
    /// Weibull with scale λ = `scale` and shape k = `shape`.
    Weibull { scale: f64, shape: f64 },
    /// Gamma with shape k = `shape` and scale θ = `scale` (mean kθ).
    Gamma { shape: f64, scale: f64 },
    /// Diameters drawn uniformly from a list; N equal to the list length reproduces it.
    Custom { list: Vec<f64> },
}

/// Moments of a sample of diameters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Moments {
    /// Mean diameter.
    pub mean: f64,
    /// Polydispersity δ = standard deviation / mean.
    pub polydispersity: f64,
    /// Skewness E[(D − mean)³] / std³ (0 when std = 0).
    pub skewness: f64,
    /// Smallest diameter.
    pub min: f64,
    /// Largest diameter.
    pub max: f64,
}

impl Moments {
    /// Moments of `diameters` (population statistics).
    pub fn of(diameters: &[f64]) -> Moments {
        let n = diameters.len() as f64;
        if diameters.is_empty() {
            return Moments::default();
        }
        let mean = diameters.iter().sum::<f64>() / n;
        let m2 = diameters.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / n;
        let m3 = diameters.iter().map(|d| (d - mean).powi(3)).sum::<f64>() / n;
        let std = m2.sqrt();
        // Relative threshold: a sample of equal diameters has std at rounding level.
        let skewness = if std > 1e-12 * mean.abs() {
            m3 / (std * std * std)
        } else {
            0.0
        };
        let polydispersity = if std > 1e-12 * mean.abs() {
            std / mean
        } else {
            0.0
        };
        Moments {
            mean,
            polydispersity,
            skewness,
            min: diameters.iter().cloned().fold(f64::INFINITY, f64::min),
            max: diameters.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
        }
    }
}

fn positive(name: &str, v: f64) -> Result<(), CoreError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(CoreError::Distribution(format!(
            "{name} = {v} must be a positive finite number"
        )))
    }
}

fn nonneg(name: &str, v: f64) -> Result<(), CoreError> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(CoreError::Distribution(format!(
            "{name} = {v} must be a non-negative finite number"
        )))
    }
}

fn fraction(name: &str, v: f64) -> Result<(), CoreError> {
    if (0.0..=1.0).contains(&v) {
        Ok(())
    } else {
        Err(CoreError::Distribution(format!(
            "{name} = {v} must lie in [0, 1]"
        )))
    }
}

fn range(d_min: f64, d_max: f64) -> Result<(), CoreError> {
    positive("d_min", d_min)?;
    positive("d_max", d_max)?;
    if d_max < d_min {
        return Err(CoreError::Distribution(format!(
            "d_max = {d_max} is smaller than d_min = {d_min}"
        )));
    }
    Ok(())
}

/// Rejection bound for truncated normals: a distribution that puts almost no mass above zero
/// is an input error, not an infinite loop.
const MAX_REJECTIONS: usize = 10_000;

fn positive_normal(rng: &mut impl Rng, dist: &Normal<f64>) -> Result<f64, CoreError> {
    for _ in 0..MAX_REJECTIONS {
        let x = dist.sample(rng);
        if x > 0.0 {
            return Ok(x);
        }
    }
    Err(CoreError::Distribution(
        "the Gaussian puts almost no probability on positive diameters; raise mu or lower sigma"
            .into(),
    ))
}

impl SizeDistribution {
    /// RCPGenerator 1.0's broad benchmark: a power law D⁻³ on [1, 15].
    pub fn power_law_1_to_15() -> Self {
        Self::Powerlaw {
            d_min: 1.0,
            d_max: 15.0,
            exponent: -3.0,
        }
    }

    /// The distribution's name as used on the command line.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Mono { .. } => "mono",
            Self::Bidisperse { .. } => "bidisperse",
            Self::Gaussian { .. } => "gaussian",
            Self::BiGaussian { .. } => "biGaussian",
            Self::Lognormal { .. } => "lognormal",
            Self::LognormalMean1 { .. } => "lognormal-mean1",
            Self::Flat { .. } => "flat",
            Self::Powerlaw { .. } => "powerlaw",
            Self::Exponential { .. } => "exponential",
            Self::Weibull { .. } => "weibull",
            Self::Gamma { .. } => "gamma",
            Self::Custom { .. } => "custom",
        }
    }

    /// Checks the parameters.
    pub fn validate(&self) -> Result<(), CoreError> {
        match *self {
            Self::Mono { d } => positive("d", d),
            Self::Bidisperse { d1, d2, p } => {
                positive("d1", d1)?;
                positive("d2", d2)?;
                fraction("p", p)
            }
            Self::Gaussian { mu, sigma } => {
                positive("mu", mu)?;
                nonneg("sigma", sigma)
            }
            Self::BiGaussian {
                mu1,
                sigma1,
                mu2,
                sigma2,
                p,
            } => {
                positive("mu1", mu1)?;
                nonneg("sigma1", sigma1)?;
                positive("mu2", mu2)?;
                nonneg("sigma2", sigma2)?;
                fraction("p", p)
            }
            Self::Lognormal { mu, sigma } => {
                if !mu.is_finite() {
                    return Err(CoreError::Distribution(format!("mu = {mu} must be finite")));
                }
                nonneg("sigma", sigma)
            }
            Self::LognormalMean1 { sigma } => nonneg("sigma", sigma),
            Self::Flat { d_min, d_max } | Self::Exponential { d_min, d_max } => range(d_min, d_max),
            Self::Powerlaw {
                d_min,
                d_max,
                exponent,
            } => {
                range(d_min, d_max)?;
                if exponent.is_finite() {
                    Ok(())
                } else {
                    Err(CoreError::Distribution(format!(
                        "exponent = {exponent} must be finite"
                    )))
                }
            }
            Self::Weibull { scale, shape } => {
                positive("scale", scale)?;
                positive("shape", shape)
            }
            Self::Gamma { shape, scale } => {
                positive("shape", shape)?;
                positive("scale", scale)
            }
            Self::Custom { ref list } => {
                if list.is_empty() {
                    return Err(CoreError::Distribution("custom_list is empty".into()));
                }
                for &d in list {
                    positive("custom_list entry", d)?;
                }
                Ok(())
            }
        }
    }

    /// Draws `n` diameters.
    pub fn sample(&self, n: usize, rng: &mut impl Rng) -> Result<Vec<f64>, CoreError> {
        self.validate()?;
        let bad =
            |e: &dyn std::fmt::Display| CoreError::Distribution(format!("{}: {e}", self.name()));
        let mut out = Vec::with_capacity(n);
        match *self {
            Self::Mono { d } => out.resize(n, d),
            Self::Bidisperse { d1, d2, p } => {
                for _ in 0..n {
                    out.push(if rng.random::<f64>() < p { d1 } else { d2 });
                }
            }
            Self::Gaussian { mu, sigma } => {
                let g = Normal::new(mu, sigma).map_err(|e| bad(&e))?;
                for _ in 0..n {
                    out.push(positive_normal(rng, &g)?);
                }
            }
            Self::BiGaussian {
                mu1,
                sigma1,
                mu2,
                sigma2,
                p,
            } => {
                let g1 = Normal::new(mu1, sigma1).map_err(|e| bad(&e))?;
                let g2 = Normal::new(mu2, sigma2).map_err(|e| bad(&e))?;
                for _ in 0..n {
                    let g = if rng.random::<f64>() < p { &g1 } else { &g2 };
                    out.push(positive_normal(rng, g)?);
                }
            }
            Self::Lognormal { mu, sigma } => {
                let g = LogNormal::new(mu, sigma).map_err(|e| bad(&e))?;
                out.extend((0..n).map(|_| g.sample(rng)));
            }
            Self::LognormalMean1 { sigma } => {
                // Mean 1 and variance σ²: s² = ln(1 + σ²), m = −s²/2.
                let s2 = (1.0 + sigma * sigma).ln();
                let g = LogNormal::new(-0.5 * s2, s2.sqrt()).map_err(|e| bad(&e))?;
                out.extend((0..n).map(|_| g.sample(rng)));
            }
            Self::Flat { .. } | Self::Powerlaw { .. } | Self::Exponential { .. } => {
                out.extend((0..n).map(|_| self.inverse_cdf(rng.random::<f64>())));
            }
            Self::Weibull { scale, shape } => {
                let g = Weibull::new(scale, shape).map_err(|e| bad(&e))?;
                out.extend((0..n).map(|_| g.sample(rng)));
            }
            Self::Gamma { shape, scale } => {
                let g = Gamma::new(shape, scale).map_err(|e| bad(&e))?;
                out.extend((0..n).map(|_| g.sample(rng)));
            }
            Self::Custom { ref list } => {
                if n == list.len() {
                    out.extend_from_slice(list);
                } else {
                    out.extend((0..n).map(|_| list[rng.random_range(0..list.len())]));
                }
            }
        }
        self.checked(out)
    }

    fn checked(&self, diameters: Vec<f64>) -> Result<Vec<f64>, CoreError> {
        if let Some(bad) = diameters.iter().find(|d| !(d.is_finite() && **d > 0.0)) {
            return Err(CoreError::Distribution(format!(
                "{} produced the diameter {bad}; check its parameters",
                self.name()
            )));
        }
        Ok(diameters)
    }

    /// The `n` diameters at the mid-point quantiles u = (i + ½)/n, i = 0 … n − 1: a sample with
    /// no draw noise, the same for every seed, as rcptools draws its N diameters (Anzivino et
    /// al. 2023). A two-component distribution gives each component its share of the u (so
    /// round(N p) spheres of a bidisperse `d1`) and spreads them over its own quantiles; a
    /// custom list gives its sorted entries (itself, sorted, when `n` is its length).
    pub fn quantile_sample(&self, n: usize) -> Result<Vec<f64>, CoreError> {
        self.validate()?;
        let u = |i: usize| (i as f64 + 0.5) / n as f64;
        let out = match *self {
            Self::Bidisperse { d1, d2, p } => {
                (0..n).map(|i| if u(i) < p { d1 } else { d2 }).collect()
            }
            Self::BiGaussian {
                mu1,
                sigma1,
                mu2,
                sigma2,
                p,
            } => (0..n)
                .map(|i| {
                    let u = u(i);
                    if u < p {
                        positive_normal_quantile(mu1, sigma1, u / p)
                    } else {
                        positive_normal_quantile(mu2, sigma2, (u - p) / (1.0 - p))
                    }
                })
                .collect(),
            Self::Custom { ref list } => {
                let mut sorted = list.clone();
                sorted.sort_by(f64::total_cmp);
                (0..n)
                    .map(|i| sorted[((u(i) * sorted.len() as f64) as usize).min(sorted.len() - 1)])
                    .collect()
            }
            _ => (0..n).map(|i| self.inverse_cdf(u(i))).collect(),
        };
        self.checked(out)
    }

    /// The diameter below which a fraction `u` ∈ (0, 1) of a one-component distribution lies
    /// (not called for bidisperse, biGaussian or custom, which `quantile_sample` splits).
    fn inverse_cdf(&self, u: f64) -> f64 {
        match *self {
            Self::Mono { d } => d,
            Self::Gaussian { mu, sigma } => positive_normal_quantile(mu, sigma, u),
            Self::Lognormal { mu, sigma } => (mu + sigma * standard_normal_quantile(u)).exp(),
            Self::LognormalMean1 { sigma } => {
                let s2 = (1.0 + sigma * sigma).ln();
                (-0.5 * s2 + s2.sqrt() * standard_normal_quantile(u)).exp()
            }
            Self::Flat { d_min, d_max } => d_min + (d_max - d_min) * u,
            Self::Powerlaw {
                d_min,
                d_max,
                exponent,
            } => {
                // Inverse CDF of p(D) ∝ D^a on [d_min, d_max]; a = −1 is the logarithmic case.
                let a1 = exponent + 1.0;
                let d = if a1.abs() < 1e-12 {
                    d_min * (d_max / d_min).powf(u)
                } else {
                    let (lo, hi) = (d_min.powf(a1), d_max.powf(a1));
                    (lo + u * (hi - lo)).powf(1.0 / a1)
                };
                d.clamp(d_min, d_max)
            }
            Self::Exponential { d_min, d_max } => {
                // The exponential of scale d_min truncated to [d_min, d_max].
                let tail = 1.0 - (-(d_max - d_min) / d_min).exp();
                (d_min - d_min * (1.0 - u * tail).ln()).clamp(d_min, d_max)
            }
            Self::Weibull { scale, shape } => scale * (-(1.0 - u).ln()).powf(1.0 / shape),
            Self::Gamma { shape, scale } => statrs::distribution::Gamma::new(shape, 1.0 / scale)
                .map_or(f64::NAN, |g| g.inverse_cdf(u)),
            Self::Bidisperse { .. } | Self::BiGaussian { .. } | Self::Custom { .. } => {
                unreachable!("quantile_sample splits the two-component and custom distributions")
            }
        }
    }
}

/// Φ⁻¹(u) of the standard normal.
fn standard_normal_quantile(u: f64) -> f64 {
    statrs::distribution::Normal::standard().inverse_cdf(u)
}

/// The quantile u of Normal(`mu`, `sigma`) truncated to positive values.
fn positive_normal_quantile(mu: f64, sigma: f64, u: f64) -> f64 {
    truncated_normal_quantile(mu, sigma, (0.0, f64::INFINITY), u)
}

/// The quantile u ∈ (0, 1) of Normal(`mu`, `sigma`) truncated to [lo, hi] (`hi` may be
/// infinite): the inverse CDF of the untruncated normal at Φ(a) + u (Φ(b) − Φ(a)). A normal
/// whose mass on the interval underflows gives the end nearer its centre.
pub fn truncated_normal_quantile(mu: f64, sigma: f64, (lo, hi): (f64, f64), u: f64) -> f64 {
    if sigma == 0.0 {
        return mu.clamp(lo, hi);
    }
    let unit = statrs::distribution::Normal::standard();
    let (a, b) = (unit.cdf((lo - mu) / sigma), unit.cdf((hi - mu) / sigma));
    let x = mu + sigma * unit.inverse_cdf(a + u * (b - a));
    if x.is_finite() {
        x.clamp(lo, hi)
    } else if mu < lo {
        lo
    } else {
        hi
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use rand::SeedableRng;

    pub(crate) fn all() -> Vec<SizeDistribution> {
        use SizeDistribution::*;
        vec![
            Mono { d: 1.0 },
            Bidisperse {
                d1: 1.0,
                d2: 1.4,
                p: 0.5,
            },
            Gaussian {
                mu: 1.0,
                sigma: 0.1,
            },
            BiGaussian {
                mu1: 1.0,
                sigma1: 0.05,
                mu2: 2.0,
                sigma2: 0.1,
                p: 0.3,
            },
            Lognormal {
                mu: 0.0,
                sigma: 0.2,
            },
            LognormalMean1 { sigma: 0.3 },
            Flat {
                d_min: 1.0,
                d_max: 2.0,
            },
            Powerlaw {
                d_min: 1.0,
                d_max: 15.0,
                exponent: -3.0,
            },
            Exponential {
                d_min: 1.0,
                d_max: 5.0,
            },
            Weibull {
                scale: 31.4,
                shape: 3.55,
            },
            Gamma {
                shape: 2.0,
                scale: 14.0,
            },
            Custom {
                list: vec![1.0, 2.0, 3.0],
            },
        ]
    }

    #[test]
    fn every_distribution_samples_positive_finite_diameters_in_range() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(7);
        for dist in all() {
            let s = dist.sample(20_000, &mut rng).unwrap();
            assert_eq!(s.len(), 20_000);
            assert!(
                s.iter().all(|d| d.is_finite() && *d > 0.0),
                "{}",
                dist.name()
            );
            let m = Moments::of(&s);
            match dist {
                SizeDistribution::Powerlaw { d_min, d_max, .. }
                | SizeDistribution::Flat { d_min, d_max }
                | SizeDistribution::Exponential { d_min, d_max } => {
                    assert!(m.min >= d_min && m.max <= d_max, "{}", dist.name())
                }
                _ => {}
            }
        }
    }

    #[test]
    fn sampled_moments_match_the_distributions() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(11);
        let m = Moments::of(
            &SizeDistribution::LognormalMean1 { sigma: 0.3 }
                .sample(200_000, &mut rng)
                .unwrap(),
        );
        assert!(
            (m.mean - 1.0).abs() < 0.005 && (m.polydispersity - 0.3).abs() < 0.005,
            "{m:?}"
        );
        // Log-normal skewness (e^{s²}+2)√(e^{s²}−1) with s² = ln 1.09.
        let e = 1.09f64;
        assert!(
            (m.skewness - (e + 2.0) * (e - 1.0).sqrt()).abs() < 0.05,
            "{m:?}"
        );
        let m = Moments::of(
            &SizeDistribution::Gamma {
                shape: 2.0,
                scale: 7.0,
            }
            .sample(200_000, &mut rng)
            .unwrap(),
        );
        assert!(
            (m.mean - 14.0).abs() < 0.1 && (m.polydispersity - 0.5f64.sqrt()).abs() < 0.01,
            "{m:?}"
        );
        let m = Moments::of(
            &SizeDistribution::Mono { d: 2.0 }
                .sample(10, &mut rng)
                .unwrap(),
        );
        assert_eq!((m.mean, m.polydispersity, m.skewness), (2.0, 0.0, 0.0));
        let m = Moments::of(
            &SizeDistribution::Bidisperse {
                d1: 1.0,
                d2: 1.4,
                p: 0.5,
            }
            .sample(100_000, &mut rng)
            .unwrap(),
        );
        assert!((m.mean - 1.2).abs() < 0.005, "{m:?}");
    }

    #[test]
    fn quantile_samples_follow_the_random_draws() {
        // rand_distr's samplers are independent of the inverse CDFs: a 20 000-draw sample and
        // the 2 000 mid-point quantiles must agree within the KS test's 0.1 % critical value
        // 1.95/√20 000 ≈ 0.014 (plus 1/4 000 for the quantiles' grid); band 0.02.
        let mut rng = rand::rngs::StdRng::seed_from_u64(5);
        for dist in all() {
            let q = dist.quantile_sample(2000).unwrap();
            let r = dist.sample(20_000, &mut rng).unwrap();
            let ks = crate::ks::two_sample_ks(&q, &r).d;
            assert!(ks < 0.02, "{}: KS distance {ks}", dist.name());
        }
    }

    #[test]
    fn quantile_samples_have_the_exact_shares_and_spreads() {
        // Exactly round(N p) spheres of d1, for every seed.
        let bi = SizeDistribution::Bidisperse {
            d1: 1.0,
            d2: 1.4,
            p: 0.3,
        };
        let q = bi.quantile_sample(1000).unwrap();
        assert_eq!(q.iter().filter(|d| **d == 1.0).count(), 300);
        // ln D of the log-normal: mean 0 by symmetry, std below σ only by the grid's missing
        // tails; rcptools' N = 1000 quantiles give 0.2998 at σ = 0.3 (Anzivino et al. 2023).
        let q = SizeDistribution::Lognormal {
            mu: 0.0,
            sigma: 0.3,
        }
        .quantile_sample(1000)
        .unwrap();
        let ln: Vec<f64> = q.iter().map(|d| d.ln()).collect();
        let mean = ln.iter().sum::<f64>() / 1000.0;
        let std = (ln.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / 1000.0).sqrt();
        assert!(
            mean.abs() < 1e-12 && (std - 0.2998).abs() < 0.0005,
            "{mean} {std}"
        );
        // Gamma(k = 2, θ = 7): mean kθ = 14, δ = 1/√k.
        let m = Moments::of(
            &SizeDistribution::Gamma {
                shape: 2.0,
                scale: 7.0,
            }
            .quantile_sample(10_000)
            .unwrap(),
        );
        assert!(
            (m.mean - 14.0).abs() < 0.02 && (m.polydispersity - 0.5f64.sqrt()).abs() < 0.005,
            "{m:?}"
        );
        let list = vec![3.0, 1.0, 2.0];
        let q = SizeDistribution::Custom { list }
            .quantile_sample(3)
            .unwrap();
        assert_eq!(q, vec![1.0, 2.0, 3.0]);
    }

    #[test]
    fn bad_parameters_say_which() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(1);
        let e = SizeDistribution::Mono { d: -1.0 }
            .sample(3, &mut rng)
            .unwrap_err()
            .to_string();
        assert!(e.contains("d = -1"), "{e}");
        let e = SizeDistribution::Flat {
            d_min: 2.0,
            d_max: 1.0,
        }
        .validate()
        .unwrap_err()
        .to_string();
        assert!(e.contains("d_max"), "{e}");
        let e = SizeDistribution::Bidisperse {
            d1: 1.0,
            d2: 1.0,
            p: 1.5,
        }
        .validate()
        .unwrap_err()
        .to_string();
        assert!(e.contains("p = 1.5"), "{e}");
        assert!(
            SizeDistribution::Custom { list: vec![] }
                .validate()
                .is_err()
        );
        assert!(
            SizeDistribution::Gaussian {
                mu: 1.0,
                sigma: f64::NAN
            }
            .validate()
            .is_err()
        );
    }
}
