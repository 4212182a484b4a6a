//! CMA-ES with IPOP restarts, asked one generation at a time over the `cmaes` crate.
//!
//! # Ask and tell by replay
//!
//! `cmaes` drives the objective function itself (`CMAES::next` samples λ points and evaluates
//! them), which does not fit evaluations that are packings spread over threads, files and
//! restarts. Its state is a pure function of its seed and the objective values it has been
//! told, so [`ask`] rebuilds it: a fresh `CMAES` with the search's seed is told the recorded
//! values of every finished generation, in order, and the points it then asks for are the next
//! generation. Replaying is microseconds per generation for the few parameters a family has;
//! in exchange `--resume` needs nothing but the rows, and the same seed gives the same history.
//!
//! # Restarts with growing populations (IPOP)
//!
//! When a run stops on one of its own criteria (its steps below [`TOL_X`], its fitness flat
//! within [`TOL_FUN`], or stagnant), the next generation is the first of a new run from the
//! centre of the cube with twice the population and the next seed (Auger & Hansen 2005, IPOP-
//! CMA-ES, §2). A restart is recognised on replay by the same criteria, so the generations of
//! every run are in one history and `--resume` continues whichever run was under way.
//!
//! # Bounds
//!
//! CMA-ES searches the unit cube of the free parameters (0 = lower bound, 1 = upper). The search
//! evaluates a point outside at its projection onto the cube and raises its fitness by a
//! multiple of the squared distance (Hansen's repair-and-penalise rule), so a best candidate on
//! a bound sits exactly on it.

use cmaes::{CMAES, CMAESOptions, DVector, ObjectiveFunction};

use crate::error::BenchError;

/// Initial step size of CMA-ES in the unit cube: a third of each interval.
pub const SIGMA0: f64 = 0.3;

/// A run has converged when its steps are below this in every coordinate of the unit cube: a
/// thousandth of each parameter's interval, finer than φ_J's seed noise can tell apart.
pub const TOL_X: f64 = 1e-3;

/// A run has converged when its fitness values stay within this of each other: far below the
/// seed-to-seed spread of φ_J (about 10⁻³ at N = 10³).
pub const TOL_FUN: f64 = 1e-5;

/// Most restarts of a search; the population is then λ·2^MAX_RESTARTS (Auger & Hansen 2005
/// stop at nine).
pub const MAX_RESTARTS: usize = 9;

/// An objective function for `cmaes` that returns recorded values in call order and, past
/// them, records the points it is asked about.
struct Replay {
    told: Vec<f64>,
    calls: usize,
    asked: Vec<Vec<f64>>,
}

impl ObjectiveFunction for Replay {
    fn evaluate(&mut self, x: &DVector<f64>) -> f64 {
        let v = self.told.get(self.calls).copied();
        self.calls += 1;
        match v {
            Some(v) => v,
            None => {
                self.asked.push(x.iter().copied().collect());
                0.0
            }
        }
    }
}

/// A fresh run of `dim` parameters with population `lambda` and `seed`, to be told `told`.
fn new_run(
    dim: usize,
    lambda: usize,
    seed: u64,
    told: &[Vec<f64>],
) -> Result<CMAES<Replay>, BenchError> {
    let replay = Replay {
        told: told.iter().flatten().copied().collect(),
        calls: 0,
        asked: Vec::new(),
    };
    CMAESOptions::new(vec![0.5; dim], SIGMA0)
        .population_size(lambda)
        .seed(seed)
        .tol_x(TOL_X)
        .tol_fun(TOL_FUN)
        .build(replay)
        .map_err(|e| BenchError::Run(format!("CMA-ES options: {e:?}")))
}

/// A generation's points in the unit cube and the restart they belong to.
pub type Generation = (Vec<Vec<f64>>, usize);

/// The next generation of an IPOP-CMA-ES search after `history` (the fitness values of every
/// earlier generation, in the order their points were asked): its points in the unit cube and
/// the restart they belong to (0 for the first run). `None` after [`MAX_RESTARTS`] restarts
/// have converged.
///
/// Errors: a run error when `cmaes` refuses the options, or when a generation of the history
/// does not have the population of its run (the history comes from another search).
pub fn ask(
    dim: usize,
    lambda: usize,
    seed: u64,
    history: &[Vec<f64>],
) -> Result<Option<Generation>, BenchError> {
    let mut restart = 0;
    let mut start = 0;
    loop {
        let pop = lambda << restart;
        let run_seed = seed.wrapping_add(restart as u64);
        let mut cma = new_run(dim, pop, run_seed, &history[start..])?;
        let mut converged_at = None;
        for (i, generation) in history[start..].iter().enumerate() {
            if generation.len() != pop {
                return Err(BenchError::Run(format!(
                    "CMA-ES replay: generation {} has {} values where its run asks for {pop}",
                    start + i,
                    generation.len()
                )));
            }
            if cma.next().is_some() {
                converged_at = Some(start + i + 1);
                break;
            }
        }
        match converged_at {
            Some(next) if restart < MAX_RESTARTS => {
                restart += 1;
                start = next;
            }
            Some(_) => return Ok(None),
            None => {
                // The values of this last generation are placeholders; its state is thrown away.
                let _ = cma.next();
                return Ok(Some((cma.into_objective_function().asked, restart)));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn asking_again_after_the_same_values_gives_the_same_points() {
        let (first, r) = ask(2, 6, 7, &[]).unwrap().unwrap();
        assert_eq!((first.len(), r), (6, 0));
        assert_eq!(first, ask(2, 6, 7, &[]).unwrap().unwrap().0);
        assert_ne!(first, ask(2, 6, 8, &[]).unwrap().unwrap().0);
        // Told that the points near (1, 1) are better, the mean moves there.
        let told: Vec<f64> = first
            .iter()
            .map(|p| (p[0] - 1.0).powi(2) + (p[1] - 1.0).powi(2))
            .collect();
        let second = ask(2, 6, 7, std::slice::from_ref(&told)).unwrap().unwrap();
        assert_eq!(second, ask(2, 6, 7, &[told]).unwrap().unwrap());
        let mean = |ps: &[Vec<f64>]| ps.iter().map(|p| p[0] + p[1]).sum::<f64>() / 6.0;
        assert!(mean(&second.0) > mean(&first) - 0.5);
    }

    #[test]
    fn a_flat_run_restarts_with_twice_the_population() {
        // A constant fitness stops a run by its fitness tolerance; the next generation belongs
        // to a restart with population 2λ.
        let mut told: Vec<Vec<f64>> = Vec::new();
        let mut restarts = Vec::new();
        for _ in 0..60 {
            let Some((pts, r)) = ask(2, 4, 3, &told).unwrap() else {
                break;
            };
            assert_eq!(pts.len(), 4 << r);
            restarts.push(r);
            told.push(vec![1.0; pts.len()]);
        }
        assert_eq!(restarts[0], 0);
        assert!(restarts.iter().any(|&r| r >= 1), "{restarts:?}");
        // A history whose generation sizes do not fit the runs is refused.
        assert!(ask(2, 4, 3, &[vec![1.0; 3]]).is_err());
    }

    #[test]
    fn cma_es_in_the_unit_cube_finds_a_corner() {
        // φ rising with the one parameter: the best point sits on the upper bound.
        let mut told: Vec<Vec<f64>> = Vec::new();
        let mut best = f64::INFINITY;
        let mut best_u = 0.0;
        for _ in 0..15 {
            let (pts, _) = ask(1, 4, 3, &told).unwrap().unwrap();
            let f: Vec<f64> = pts
                .iter()
                .map(|p| {
                    let u = p[0].clamp(0.0, 1.0);
                    let v = -u + 1e-3 * (p[0] - u).powi(2);
                    if v < best {
                        best = v;
                        best_u = u;
                    }
                    v
                })
                .collect();
            told.push(f);
        }
        assert_eq!(best_u, 1.0);
    }
}
