//! The surrogate-model optimiser of a design search (`--optimizer ego`, cargo feature `ego`):
//! efficient global optimisation over the `egobox-ego` crate — a Gaussian-process (Kriging)
//! model of the fitness over the unit cube of the free parameters, and the next candidates
//! where its infill criterion (expected improvement; several per generation by egobox's q-EI
//! with the Kriging believer) is best.
//!
//! # Ask and tell from the rows
//!
//! `egobox`'s service interface (`EgorServiceApi::suggest`) is stateless: given every point
//! evaluated so far and its fitness, it fits the model and returns the next points, with a
//! seeded generator. So [`ask`] rebuilds the surrogate from the history at every generation, as
//! `search::ask` replays CMA-ES: `--resume` needs nothing but the rows, and the same seed gives
//! the same history. Fitting a GP to a few dozen points takes milliseconds; a packing takes
//! seconds.
//!
//! The first generation is a Latin hypercube of the population's size, drawn here with the
//! search's seed, since the model needs data before it can suggest anything.
//!
//! egobox installs a global logger on first use that writes its own errors to stdout (level
//! set by `EGOBOX_LOG`, default `error`); packbench logs nothing itself, so nothing else is
//! routed there.

use egobox_ego::EgorServiceBuilder;
use ndarray::Array2;
use rand::rngs::StdRng;
use rand::seq::SliceRandom;
use rand::{RngExt, SeedableRng};

use super::objective::INFEASIBLE;
use crate::error::BenchError;

/// `n` points of a Latin hypercube in `[0, 1]^dim`: each axis cut into `n` equal strata, one
/// point in each, the strata of the axes paired at random.
pub fn latin_hypercube(dim: usize, n: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = StdRng::seed_from_u64(seed);
    let mut points = vec![vec![0.0; dim]; n];
    for k in 0..dim {
        let mut strata: Vec<usize> = (0..n).collect();
        strata.shuffle(&mut rng);
        for (p, s) in points.iter_mut().zip(strata) {
            p[k] = (s as f64 + rng.random::<f64>()) / n as f64;
        }
    }
    points
}

/// The fitness values the model is fitted to: those of candidates that made no packing or
/// broke a constraint ([`INFEASIBLE`] and above) are replaced by the worst measured one, so
/// that a penalty of 10⁶ does not flatten the model everywhere else.
fn tamed(values: &[f64]) -> Vec<f64> {
    let worst = values
        .iter()
        .copied()
        .filter(|v| *v < INFEASIBLE / 2.0)
        .fold(f64::NEG_INFINITY, f64::max);
    let worst = if worst.is_finite() { worst } else { 0.0 };
    values
        .iter()
        .map(|&v| if v < INFEASIBLE / 2.0 { v } else { worst })
        .collect()
}

/// The points (in the unit cube of the `dim` free parameters) of the generation after the
/// history: `points[g]` were evaluated with fitness `values[g]`. The first generation is a
/// Latin hypercube of `lambda` points; later ones are the `lambda` points (at most) the
/// surrogate suggests. `None` when it suggests none.
///
/// Errors: a run error when egobox refuses its configuration or the history's shape.
pub fn ask(
    dim: usize,
    lambda: usize,
    seed: u64,
    points: &[Vec<Vec<f64>>],
    values: &[Vec<f64>],
) -> Result<Option<Vec<Vec<f64>>>, BenchError> {
    if points.is_empty() {
        return Ok(Some(latin_hypercube(dim, lambda, seed)));
    }
    let xs: Vec<f64> = points
        .iter()
        .flatten()
        .flat_map(|p| p.iter().map(|v| v.clamp(0.0, 1.0)))
        .collect();
    let ys = tamed(&values.iter().flatten().copied().collect::<Vec<_>>());
    let n = ys.len();
    let err = |e: &dyn std::fmt::Display| BenchError::Run(format!("surrogate optimiser: {e}"));
    let x = Array2::from_shape_vec((n, dim), xs).map_err(|e| err(&e))?;
    let y = Array2::from_shape_vec((n, 1), ys).map_err(|e| err(&e))?;
    let unit = Array2::from_shape_fn((dim, 2), |(_, j)| j as f64);
    let ego = EgorServiceBuilder::optimize()
        .configure(|c| c.seed(seed).configure_qei(|q| q.batch(lambda)))
        .min_within(&unit)
        .map_err(|e| err(&e))?;
    let next = ego.suggest(&x, &y);
    if next.nrows() == 0 {
        return Ok(None);
    }
    Ok(Some(next.rows().into_iter().map(|r| r.to_vec()).collect()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_latin_hypercube_has_one_point_in_each_stratum_of_each_axis() {
        let p = latin_hypercube(3, 8, 4);
        for k in 0..3 {
            let mut strata: Vec<usize> = p.iter().map(|x| (x[k] * 8.0) as usize).collect();
            strata.sort_unstable();
            assert_eq!(strata, (0..8).collect::<Vec<_>>());
        }
        assert_eq!(p, latin_hypercube(3, 8, 4));
    }

    #[test]
    fn the_surrogate_moves_towards_the_minimum_and_repeats_itself() {
        // φ rising with the one parameter: the suggestions go to the upper bound.
        let f = |u: f64| -u;
        let mut points = vec![latin_hypercube(1, 4, 3)];
        let mut values = vec![points[0].iter().map(|p| f(p[0])).collect::<Vec<_>>()];
        for _ in 0..4 {
            let next = ask(1, 2, 3, &points, &values).unwrap().unwrap();
            assert_eq!(next, ask(1, 2, 3, &points, &values).unwrap().unwrap());
            values.push(next.iter().map(|p| f(p[0])).collect());
            points.push(next);
        }
        let best = points.iter().flatten().map(|p| p[0]).fold(0.0, f64::max);
        assert!(best > 0.97, "{points:?}");
    }
}
