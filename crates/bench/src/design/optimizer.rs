//! Which optimiser proposes a design search's candidates: CMA-ES (the `cmaes` crate, always
//! built), a bracketing search for one parameter and a target ([`super::bracket`]), or
//! efficient global optimisation over a Kriging surrogate (`egobox-ego`, only in a build with
//! the `ego` cargo feature). Each is asked for a generation from the rows alone, so
//! `--resume`, `--shard` and the seed rules hold for any.

use serde::{Deserialize, Serialize};

use crate::error::{BenchError, usage};

/// The sentence that refuses `--optimizer ego` in a build without the `ego` feature.
pub const EGO_NOT_BUILT: &str = "--optimizer ego needs the `ego` cargo feature, which this \
     build of packbench lacks; build it with `cargo build --release --features ego -p packbench`";

/// The optimiser of a design search.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Optimizer {
    /// CMA-ES (Hansen's defaults) with IPOP restarts, replayed from the recorded fitness values.
    #[default]
    Cmaes,
    /// Efficient global optimisation: a Latin hypercube, then the points of best expected
    /// improvement of a Kriging model fitted to every evaluated point (q-EI for a batch).
    Ego,
    /// Bisection with a local line fit on the signed residual φ_J − target, for one free
    /// parameter and an objective with a target.
    Bracket,
}

impl Optimizer {
    /// The optimiser named `name` for a search of `free` parameters, with or without a target
    /// φ_J: `auto` is the bracket for one free parameter and a target (it is told the signed
    /// residual, where CMA-ES sees only its size; docs/notes/design-search.md) and CMA-ES
    /// otherwise.
    ///
    /// Errors: as [`Optimizer::parse`].
    pub fn for_search(name: &str, free: usize, target: bool) -> Result<Optimizer, BenchError> {
        match name {
            "auto" if free == 1 && target => Ok(Optimizer::Bracket),
            "auto" => Ok(Optimizer::Cmaes),
            _ => Optimizer::parse(name),
        }
    }

    /// The optimiser named `name` (`cmaes`, `bracket` or `ego`).
    ///
    /// Errors: a usage error for an unknown name, and for `ego` in a build without the `ego`
    /// feature ([`EGO_NOT_BUILT`]).
    pub fn parse(name: &str) -> Result<Optimizer, BenchError> {
        let o = match name {
            "cmaes" | "cma-es" => Optimizer::Cmaes,
            "ego" => Optimizer::Ego,
            "bracket" => Optimizer::Bracket,
            other => {
                return Err(usage(format!(
                    "unknown optimizer `{other}`; use auto, cmaes, bracket or ego"
                )));
            }
        };
        o.check()?;
        Ok(o)
    }

    /// Whether this build can run the optimiser.
    ///
    /// Errors: [`EGO_NOT_BUILT`] for `ego` without the `ego` feature.
    pub fn check(self) -> Result<(), BenchError> {
        if self == Optimizer::Ego && !cfg!(feature = "ego") {
            return Err(usage(EGO_NOT_BUILT));
        }
        Ok(())
    }

    /// Its name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Optimizer::Cmaes => "cmaes",
            Optimizer::Ego => "ego",
            Optimizer::Bracket => "bracket",
        }
    }

    /// The fewest candidates per generation it works with: CMA-ES needs two to rank, the
    /// bracket two to bracket, EGO works one point at a time.
    pub fn min_population(self) -> usize {
        match self {
            Optimizer::Cmaes | Optimizer::Bracket => 2,
            Optimizer::Ego => 1,
        }
    }

    /// The points (unit cube of the `dim` free parameters, 0 = lower bound) of the generation
    /// after the history: `points[g]` were asked for at generation g and scored
    /// `values[g]` (fitness, smaller is better) and `residuals[g]` (φ_J − target, `None` when
    /// not packed or without a target); a CMA-ES restart asks for more points than λ. `None`
    /// when the optimiser stops on its own (CMA-ES's last restart converged, EGO suggests
    /// nothing, the bracket's root lies beyond a bound). CMA-ES needs only the values, the
    /// bracket only the residuals.
    ///
    /// Errors: a run error when the optimiser refuses its options; [`EGO_NOT_BUILT`] for
    /// `ego` in a build without the feature.
    pub fn ask(
        self,
        dim: usize,
        lambda: usize,
        seed: u64,
        points: &[Vec<Vec<f64>>],
        values: &[Vec<f64>],
        residuals: &[Vec<Option<f64>>],
    ) -> Result<Option<Vec<Vec<f64>>>, BenchError> {
        match self {
            Optimizer::Cmaes => Ok(super::cma::ask(dim, lambda, seed, values)?.map(|(p, _)| p)),
            Optimizer::Bracket => Ok(super::bracket::ask(lambda, points, residuals)),
            #[cfg(feature = "ego")]
            Optimizer::Ego => super::surrogate::ask(dim, lambda, seed, points, values),
            #[cfg(not(feature = "ego"))]
            Optimizer::Ego => {
                let _ = points;
                Err(usage(EGO_NOT_BUILT))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_and_ego_needs_its_feature() {
        assert_eq!(Optimizer::parse("cmaes").unwrap(), Optimizer::Cmaes);
        assert_eq!(Optimizer::default(), Optimizer::Cmaes);
        assert!(Optimizer::parse("nelder-mead").is_err());
        assert_eq!(Optimizer::parse("bracket").unwrap(), Optimizer::Bracket);
        let auto = |free, target| Optimizer::for_search("auto", free, target).unwrap();
        assert_eq!(auto(1, true), Optimizer::Bracket);
        assert_eq!(auto(1, false), Optimizer::Cmaes);
        assert_eq!(auto(2, true), Optimizer::Cmaes);
        assert_eq!(
            Optimizer::for_search("cmaes", 1, true).unwrap(),
            Optimizer::Cmaes
        );
        let ego = Optimizer::parse("ego");
        if cfg!(feature = "ego") {
            assert_eq!(ego.unwrap(), Optimizer::Ego);
        } else {
            let e = ego.unwrap_err().to_string();
            assert!(e.contains("--features ego"), "{e}");
        }
    }
}
