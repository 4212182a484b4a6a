//! Projection of bonded pairs back onto exact contact.
//!
//! Straight steps keep bonds in contact only to first order; a Newton iteration with the
//! minimum-norm correction `δx = A⁺(−g)` (g: bond gaps) restores them. It first runs as a
//! Newton–chord iteration with the factorisation of the step's start; if that stalls (near-
//! singular bond networks close to jamming) it restarts as a full Newton iteration that
//! refactorises at every iterate. At jamming the bonds are dependent and `A δx = −g` has no
//! solution in general; the growth factor then moves too: with the forces f (`Aᵀf = 0`),
//! `δt = fᵀg / fᵀD` makes `A δx = −g + D δt` solvable, so every bond of the jammed network
//! touches exactly.

use crate::contacts::{Key, Link};
use crate::error::JammingError;
use crate::growth::{Growth, max_or_nan};
use crate::min_norm::{MinNorm, Solver};

/// Iterations of each of the two phases.
const MAX_ITERATIONS: usize = 16;

/// Relative residual to which a chord correction is solved when the chord factorisation is
/// iterative. The chord is already a stale Jacobian (the rows of the step's start), so the
/// outer iteration converges linearly anyway; solving each correction to 1e-3 instead of full
/// accuracy leaves its rate almost unchanged (measured on an N = 1000 exchange phase: 31 % fewer
/// conjugate-gradient iterations, 6 % less CPU, the same φ and release solves).
const CHORD_SOLVE_TOL: f64 = 1e-3;

/// Projects the bonds `basis` onto contact. `chord` is a factorisation of the basis rows at a
/// nearby configuration to try first. `jam = Some((key, forces))` adds the dependent bond `key`
/// and lets `t` move, with `forces` over `basis` then `key`. Returns the largest remaining
/// relative gap.
///
/// # Errors
/// [`JammingError::Solver`] when even the full Newton iteration diverges or a factorisation
/// fails; the configuration is then left where the chord phase started.
pub(crate) fn project(
    g: &mut Growth,
    basis: &[Key],
    chord: Option<(&[Link], &MinNorm)>,
    jam: Option<(&Key, &[f64])>,
    tol: f64,
    solver: &Solver,
) -> Result<f64, JammingError> {
    project_to(g, basis, None, chord, jam, tol, solver)
}

/// [`project`] onto the relative gaps `held_gaps` (one per bond of `basis`, `r/σ − 1`; `None`:
/// every bond onto contact) instead of contact: a pair the QP form holds at equality while it
/// is still open keeps its gap, and the step's factor of all its bonds serves the projection.
pub(crate) fn project_to(
    g: &mut Growth,
    basis: &[Key],
    held_gaps: Option<&[f64]>,
    chord: Option<(&[Link], &MinNorm)>,
    jam: Option<(&Key, &[f64])>,
    tol: f64,
    solver: &Solver,
) -> Result<f64, JammingError> {
    let start = g.snapshot();
    if let Some((links, mn)) = chord
        && let Some(worst) = newton(g, basis, held_gaps, Some((links, mn)), jam, tol, solver)?
    {
        return Ok(worst);
    }
    g.restore(&start);
    match newton(g, basis, held_gaps, None, jam, tol, solver)? {
        Some(worst) => Ok(worst),
        None => {
            g.restore(&start);
            Err(JammingError::Solver(
                "projecting the bonds onto contact diverged; the bond network is degenerate".into(),
            ))
        }
    }
}

/// One Newton phase: with `chord` fixed, or refactorising every iterate. `None` when it
/// diverged (the worst gap grew tenfold) or did not reach `tol`.
fn newton(
    g: &mut Growth,
    basis: &[Key],
    held_gaps: Option<&[f64]>,
    chord: Option<(&[Link], &MinNorm)>,
    jam: Option<(&Key, &[f64])>,
    tol: f64,
    solver: &Solver,
) -> Result<Option<f64>, JammingError> {
    let (n, d) = (g.n, g.d);
    // Bond k's distance from its target: contact, or its held relative gap.
    let off = |k: usize, l: &Link, t: f64| l.gap(t) - held_gaps.map_or(0.0, |h| h[k]) * l.size * t;
    let mut first = f64::NAN;
    for _ in 0..MAX_ITERATIONS {
        let now = g.links(basis);
        let mut gaps: Vec<f64> = (now.iter().enumerate())
            .map(|(k, l)| off(k, l, g.t))
            .collect();
        let mut sizes: Vec<f64> = now.iter().map(|l| l.size).collect();
        if let Some((key, _)) = jam {
            let lk = g.link(key);
            gaps.push(lk.gap(g.t));
            sizes.push(lk.size);
        }
        let worst = max_or_nan(
            gaps.iter()
                .zip(&sizes)
                .map(|(gap, s)| gap.abs() / (s * g.t)),
        );
        if worst <= tol {
            return Ok(Some(worst));
        }
        if first.is_nan() {
            first = worst;
        } else if worst.is_nan() || worst > 10.0 * first.max(1e-8) {
            return Ok(None);
        }
        let dt = match jam {
            Some((_, f)) => {
                let fg: f64 = f.iter().zip(&gaps).map(|(a, b)| a * b).sum();
                let fs: f64 = f.iter().zip(&sizes).map(|(a, b)| a * b).sum();
                fg / fs
            }
            None => 0.0,
        };
        let rhs: Vec<f64> = (0..now.len()).map(|k| -gaps[k] + sizes[k] * dt).collect();
        let dx = match chord {
            Some((links, mn)) => mn.solve_to(links, &rhs, n, d, CHORD_SOLVE_TOL),
            None => solver
                .factor(basis, &now, g, [].iter())
                .map_err(JammingError::Solver)?
                .solve(&now, &rhs, n, d),
        };
        // A solve that failed (its basis singular here, the conjugate gradients and the exact
        // factor both given up) returns NaN: the phase has diverged.
        if dx.iter().any(|v| !v.is_finite()) {
            return Ok(None);
        }
        g.displace(&dx);
        g.grow(dt);
    }
    // Not converged to `tol` but not diverging either: accept only a small remainder.
    let now = g.links(basis);
    let worst =
        max_or_nan((now.iter().enumerate()).map(|(k, l)| off(k, l, g.t).abs() / (l.size * g.t)));
    Ok((worst <= 1e3 * tol).then_some(worst))
}
