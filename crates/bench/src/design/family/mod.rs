//! Families of size distributions with named, bounded parameters: what `packbench design`
//! searches over. A candidate is a value for every parameter; it becomes the diameters of one
//! packing through [`Family::diameters`]: its mid-point quantiles, the same for every seed
//! (`--draw quantile`, the default), or a random draw with the packing's own seed (`--draw
//! random`); either way the diameters searched are exactly the diameters packed.
//!
//! Every parameter is dimensionless: sizes are ratios to the smallest (or typical) diameter,
//! because φ_J does not depend on the overall scale.

use packbench_core::SizeDistribution;
use packbench_core::distribution::truncated_normal_quantile;
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
    /// `components` sizes on [1, `max_ratio`], as rcptools' discrete (delta) components:
    /// d1 = 1 and `d<i>` (i ≥ 2) free, with shares by stick-breaking of `x<i>` ∈ [0, 1]
    /// (i < components): component 1 takes x1 of the whole, component 2 takes x2 of what is
    /// left, …, the last the rest. Every point of the box is then a valid mixture (nothing to
    /// normalise, nothing that can sum to zero), and for two components x1 is directly the
    /// share of the small spheres. The shares are volume or number fractions (`fractions`;
    /// volume needs the dimension `dim`); the counts are N times the number fractions, rounded
    /// by largest remainder, so the diameters are the same for every seed.
    Discrete {
        components: usize,
        max_ratio: f64,
        dim: usize,
        fractions: Fractions,
    },
}

/// What the shares of a discrete mixture count.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Fractions {
    /// Fractions of the spheres' volume (how mixtures are specified in the laboratory).
    #[default]
    Volume,
    /// Fractions of the number of spheres.
    Number,
}

impl Fractions {
    /// `volume` or `number`.
    ///
    /// Errors: a usage error for another name.
    pub fn parse(name: &str) -> Result<Fractions, BenchError> {
        match name {
            "volume" => Ok(Fractions::Volume),
            "number" => Ok(Fractions::Number),
            other => Err(usage(format!("--fractions {other}: use volume or number"))),
        }
    }
}

/// What shapes a family beyond its name: a mixture's components and support, the dimension
/// and fractions of a discrete mixture.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shape {
    /// Components of a mixture or discrete mixture.
    pub components: usize,
    /// Support [1, max_ratio] of a mixture; the default upper bound of a ratio.
    pub max_ratio: Option<f64>,
    /// Dimension of the packings (converts a discrete mixture's volume fractions to numbers).
    pub dim: usize,
    /// What a discrete mixture's shares count.
    pub fractions: Fractions,
    /// How a packing's diameters are drawn.
    pub draw: Draw,
}

impl Default for Shape {
    fn default() -> Shape {
        Shape {
            components: 2,
            max_ratio: None,
            dim: 3,
            fractions: Fractions::Volume,
            draw: Draw::Quantile,
        }
    }
}

/// How the N diameters of a packing are drawn from a candidate's distribution (a discrete
/// mixture has the same diameters either way).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Draw {
    /// The N mid-point quantiles (i + ½)/N: the same diameters for every seed, as rcptools
    /// draws them (Anzivino et al. 2023), so a candidate's φ_J varies between seeds only by
    /// the positions. Searches for a target φ_J need this: with random draws the diameters'
    /// own noise (about 0.001 in φ_J at N = 10³) moves the answer.
    Quantile,
    /// N independent draws with the packing's seed: a candidate's φ_J averages over the
    /// sample's fluctuations as well, as a laboratory batch of N grains would.
    Random,
}

impl Draw {
    /// `quantile` or `random`.
    ///
    /// Errors: a usage error for another name.
    pub fn parse(name: &str) -> Result<Draw, BenchError> {
        match name {
            "quantile" => Ok(Draw::Quantile),
            "random" => Ok(Draw::Random),
            other => Err(usage(format!("--draw {other}: use quantile or random"))),
        }
    }

    /// Design files written before the draw could be chosen drew at random.
    fn before_the_choice() -> Draw {
        Draw::Random
    }
}

/// A family and the bounds of its parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Family {
    pub kind: FamilyKind,
    /// Every parameter of the family, free or fixed, in the family's order.
    pub params: Vec<Param>,
    /// How a packing's diameters are drawn.
    #[serde(default = "Draw::before_the_choice")]
    pub draw: Draw,
}

/// The family names `--family` accepts.
pub const FAMILY_NAMES: &str =
    "lognormal, powerlaw, bidisperse, weibull, gamma, mixture or discrete";

impl Family {
    /// The family `name` with its default bounds; `shape` shapes a mixture or discrete mixture
    /// (the others use only its `max_ratio`, as the default upper bound of a ratio).
    ///
    /// Errors: a usage error for an unknown name, a mixture of 0 or more than
    /// [`MAX_COMPONENTS`] components, or a `max_ratio` that is not a finite number > 1.
    pub fn with_defaults(name: &str, shape: &Shape) -> Result<Family, BenchError> {
        let Shape {
            components,
            max_ratio,
            dim,
            fractions,
            draw,
        } = *shape;
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
            "mixture" | "discrete" if components == 0 || components > MAX_COMPONENTS => {
                return Err(usage(format!(
                    "--components {components}: a mixture has 1 to {MAX_COMPONENTS} components"
                )));
            }
            "discrete" if components < 2 => {
                return Err(usage(format!(
                    "--components {components}: a discrete mixture has 2 to {MAX_COMPONENTS} \
                     sizes (one size is monodisperse: nothing to search)"
                )));
            }
            "discrete" => {
                let r = max_ratio.unwrap_or(10.0);
                let mut params = Vec::new();
                for i in 2..=components {
                    params.push(Param::new(&format!("d{i}"), 1.0, r));
                }
                for i in 1..components {
                    params.push(Param::new(&format!("x{i}"), 0.0, 1.0));
                }
                (
                    FamilyKind::Discrete {
                        components,
                        max_ratio: r,
                        dim,
                        fractions,
                    },
                    params,
                )
            }
            "mixture" => {
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
        Ok(Family { kind, params, draw })
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
            FamilyKind::Discrete { .. } => "discrete",
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
            _ if name.starts_with('d') => lo >= 1.0,
            _ if name.starts_with('x') => lo >= 0.0 && hi <= 1.0,
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
            FamilyKind::Mixture { .. } | FamilyKind::Discrete { .. } => None,
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
            FamilyKind::Mixture { .. } | FamilyKind::Discrete { .. } => None,
        }
    }

    /// The distribution a packing of `values` uses: the core's when it draws at random, or
    /// else the `n` diameters [`Family::diameters`] gives for `seed` as a custom list (which
    /// the core reproduces exactly when asked for `n` diameters).
    ///
    /// Errors: a run error when the values make no valid distribution (e.g. zero weights).
    pub fn scene_distribution(
        &self,
        values: &[f64],
        n: usize,
        seed: u64,
    ) -> Result<SizeDistribution, BenchError> {
        match self.distribution(values) {
            Some(d) if self.draw == Draw::Random => Ok(d),
            _ => Ok(SizeDistribution::Custom {
                list: self.diameters(values, n, seed)?,
            }),
        }
    }

    /// The `n` diameters a packing with `seed` gets. Drawn at random, they are the same draw
    /// `packbench-core`'s initial packing makes (a fresh `StdRng` seeded with `seed`), before
    /// its scaling to the initial φ; as quantiles, `seed` plays no part.
    ///
    /// Errors: a run error when the values make no valid distribution.
    pub fn diameters(&self, values: &[f64], n: usize, seed: u64) -> Result<Vec<f64>, BenchError> {
        let mut rng = StdRng::seed_from_u64(seed);
        if let Some(d) = self.distribution(values) {
            return Ok(match self.draw {
                Draw::Quantile => d.quantile_sample(n)?,
                Draw::Random => d.sample(n, &mut rng)?,
            });
        }
        match self.kind {
            FamilyKind::Mixture {
                components,
                max_ratio,
            } => self.mixture_diameters(values, components, max_ratio, n, &mut rng),
            FamilyKind::Discrete {
                components,
                dim,
                fractions,
                ..
            } => self.discrete_diameters(values, (components, dim, fractions), n),
            _ => unreachable!("the other families have a core distribution"),
        }
    }

    /// The `n` diameters of a discrete mixture (the same for every seed): each component's count
    /// N × its number fraction, rounded by largest remainder.
    ///
    /// Errors: a run error when the sizes are not finite numbers ≥ 1.
    fn discrete_diameters(
        &self,
        values: &[f64],
        (components, dim, fractions): (usize, usize, Fractions),
        n: usize,
    ) -> Result<Vec<f64>, BenchError> {
        let mut sizes = vec![1.0];
        sizes.extend((2..=components).map(|i| self.value(values, &format!("d{i}"))));
        if let Some(bad) = sizes.iter().find(|d| !(d.is_finite() && **d >= 1.0)) {
            return Err(BenchError::Run(format!(
                "a discrete mixture's sizes must be finite numbers ≥ 1, not {bad}"
            )));
        }
        let mut left = 1.0;
        let mut shares = Vec::with_capacity(components);
        for i in 1..components {
            let x = self.value(values, &format!("x{i}")).clamp(0.0, 1.0);
            shares.push(left * x);
            left *= 1.0 - x;
        }
        shares.push(left);
        let weights: Vec<f64> = match fractions {
            Fractions::Number => shares,
            Fractions::Volume => shares
                .iter()
                .zip(&sizes)
                .map(|(v, d)| v / d.powi(dim as i32))
                .collect(),
        };
        let total: f64 = weights.iter().sum();
        let exact: Vec<f64> = weights.iter().map(|w| w / total * n as f64).collect();
        let mut counts: Vec<usize> = exact.iter().map(|e| e.floor() as usize).collect();
        let mut order: Vec<usize> = (0..components).collect();
        order.sort_by(|&a, &b| {
            (exact[b] - exact[b].floor()).total_cmp(&(exact[a] - exact[a].floor()))
        });
        let short = n.saturating_sub(counts.iter().sum());
        for &i in order.iter().cycle().take(short) {
            counts[i] += 1;
        }
        Ok(sizes
            .iter()
            .zip(&counts)
            .flat_map(|(&d, &c)| std::iter::repeat_n(d, c))
            .collect())
    }

    /// The `n` diameters of a mixture of truncated log-Gaussians: its quantiles, each component
    /// taking its weight's share of them, or drawn with `rng`.
    ///
    /// Errors: a run error when the weights sum to zero (no distribution).
    fn mixture_diameters(
        &self,
        values: &[f64],
        components: usize,
        max_ratio: f64,
        n: usize,
        rng: &mut StdRng,
    ) -> Result<Vec<f64>, BenchError> {
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
        // The component a fraction u of the way through the weights falls in, and how far
        // through that component's own weight it lies.
        let component = |u: f64| {
            let mut u = u * total;
            let mut k = 0;
            while k + 1 < comps.len() && u >= comps[k].0 {
                u -= comps[k].0;
                k += 1;
            }
            let w = comps[k].0;
            (
                k,
                if w > 0.0 {
                    (u / w).clamp(0.0, 1.0)
                } else {
                    0.5
                },
            )
        };
        if self.draw == Draw::Quantile {
            return Ok((0..n)
                .map(|i| {
                    let (k, v) = component((i as f64 + 0.5) / n as f64);
                    let (_, c, s) = comps[k];
                    truncated_normal_quantile(c, s, (0.0, ln_r), v).exp()
                })
                .collect());
        }
        let mut out = Vec::with_capacity(n);
        for _ in 0..n {
            let (k, _) = component(rng.random::<f64>());
            let (_, c, s) = comps[k];
            let g = Normal::new(c, s).map_err(|e| BenchError::Run(format!("mixture: {e}")))?;
            // Truncation to the support [1, max_ratio] by rejection; a component centred far
            // outside falls back to the nearest end after many tries.
            let mut x = f64::NAN;
            for _ in 0..1000 {
                let t = g.sample(rng);
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
        _ if name.starts_with('d') => "diameter ≥ 1 (the smallest)",
        _ if name.starts_with('x') => "0 ≤ share ≤ 1",
        _ if name.starts_with('c') => "0 ≤ centre ≤ 1",
        _ if name.starts_with('s') => "width > 0",
        _ => "any finite number",
    }
}

#[cfg(test)]
mod tests;
