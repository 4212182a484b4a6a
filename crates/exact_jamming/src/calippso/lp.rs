//! One LP of CALiPPSO: its rows (pairs and walls within the cut-off, the bound on each
//! displacement), the rows left out because they cannot bind, lazy rows added while the
//! solution violates them, and the warm start from the previous LP's duals.

use std::collections::HashMap;
use std::sync::atomic::AtomicBool;

use crate::contacts::{self, Candidates, Key, Link};
use crate::error::JammingError;
use crate::growth::Growth;
use crate::interior_point::{InequalityLp, LpSolution};

use super::params::Params;

/// One LP's results.
pub(super) struct LpStep {
    /// Γ − 1.
    pub(super) g: f64,
    /// Displacements (length units), N·d.
    pub(super) s: Vec<f64>,
    /// Constraint links, their candidate keys, and their duals (forces, summing to about one).
    pub(super) links: Vec<Link>,
    pub(super) keys: Vec<Key>,
    pub(super) duals: Vec<f64>,
    /// Interior-point iterations, over all its solves.
    pub(super) iterations: u32,
    /// Solves (one, plus one per round of lazy rows added).
    pub(super) solves: u32,
    /// Solves that stopped (iteration limit, stalled steps or an overflowing direction) before
    /// meeting `lp_tol`.
    pub(super) unconverged: u32,
    /// The last solve, whose solution this is, met `lp_tol`.
    pub(super) converged: bool,
    /// Solves handed to clarabel because the normal equations had no factor.
    pub(super) by_clarabel: u32,
    /// Duals of the rows after the links: the cap on Γ, then the bound rows (+, − per
    /// coordinate), the warm start of the next LP.
    pub(super) tail_duals: Vec<f64>,
    /// Sum of the duals of the bound rows `|u_iμ| ≤ s_bound/R`: how fast g = Γ − 1 would grow
    /// with the bound (in units of R); zero when the bound does not bind.
    pub(super) bound_dual: f64,
}

/// Relative gap of the rows an LP starts from; rows beyond it join when a solution violates
/// them. Near jamming a step closes gaps of at most a few `s_bound` (1e-2 R), so the rows
/// within 5% are all that bind; the first LP's wide shell (ℓ0 = 4R) holds about five times
/// as many rows, nearly all slack (21 469 against 3951 at N = 1000 from a near-jammed start).
pub(super) const LAZY_GAP: f64 = 0.05;

/// An LP is warm-started (`Params::warm_start`) only when the previous one made or broke at
/// most this fraction of its contacts …
pub(super) const WARM_MAX_CHANGED: f64 = 0.05;

/// … and left √Γ − 1 at least this large …
pub(super) const WARM_MIN_EXCESS: f64 = 1e-9;

/// … or moved a non-rattler by at least this many mean diameters: a warm start's displacements
/// carry noise of about 1e-8 D, harmless while the LPs still move the packing by a hundred
/// times that (the creep keeps √Γ − 1 near 1e-10 while moving 1e-4 D per LP), fatal to the
/// last LPs, which must bring max |s| under `tol_s`.
pub(super) const WARM_MIN_MOVE: f64 = 1e-6;

/// Which rows an LP lists and how far its particles may move.
#[derive(Clone, Copy)]
pub(super) struct LpScope {
    /// Pairs with a gap below this (length units) are candidates.
    pub(super) cutoff_gap: f64,
    /// `|s_iμ| ≤ s_bound`; `None` leaves the displacements free (the fine-tuning LP of
    /// CALiPPSO.jl's final packing).
    pub(super) s_bound: Option<f64>,
    /// Cap on √Γ − 1 (a few times the previous LP's), which drops rows that cannot bind.
    pub(super) excess_cap: Option<f64>,
    /// Relative gap of the rows of the first solve (see [`LAZY_GAP`]).
    pub(super) working_gap: f64,
    /// Hand the LP to clarabel when its normal equations have no factor (otherwise that is an
    /// error): every LP of the iteration needs its step, the fine-tuning LP does not.
    pub(super) clarabel_fallback: bool,
}

/// Builds and solves one LP around the current configuration, each solve warm-started from the
/// duals of `warm` (the previous LP) when given. `Ok(None)` when `stop` ended the solve.
pub(super) fn solve_lp(
    g: &Growth,
    scope: &LpScope,
    held: &[usize],
    p: &Params,
    stop: Option<&'static AtomicBool>,
    warm: Option<&LpStep>,
) -> Result<Option<LpStep>, JammingError> {
    let (n, d, t) = (g.n, g.d, g.t);
    let LpScope {
        s_bound,
        working_gap,
        clarabel_fallback,
        ..
    } = *scope;
    let r_unit = 0.5 * t * g.diameters.iter().sum::<f64>() / n as f64;
    let (rows, gamma_cap) = candidate_rows(g, scope, r_unit);
    let mut in_lp = first_rows(&rows, working_gap, n, d);
    let mut gap = working_gap;
    let mut solves = 0;
    let mut iterations = 0;
    let mut unconverged = 0;
    let mut by_clarabel = 0;
    // The previous LP's duals by row identity, for the warm start of each solve below.
    let warm = warm.map(|w| {
        let by_key: HashMap<Key, f64> = w
            .keys
            .iter()
            .copied()
            .zip(w.duals.iter().copied())
            .collect();
        (by_key, &w.tail_duals)
    });
    let (sol, listed) = loop {
        let listed: Vec<usize> = (0..rows.len()).filter(|&k| in_lp[k]).collect();
        // The listed rows' previous duals (0 for rows the previous LP did not list), then
        // those of the Γ cap and of the bound rows, which every LP lists in the same order.
        let z0 = warm.as_ref().map(|(by_key, tail)| {
            let mut z: Vec<f64> = listed
                .iter()
                .map(|&k| by_key.get(&rows[k].key).copied().unwrap_or(0.0))
                .collect();
            z.extend(tail.iter());
            z
        });
        let sol = solve_rows(
            g,
            &rows,
            &listed,
            gamma_cap,
            s_bound,
            held,
            r_unit,
            p,
            stop,
            z0.as_deref(),
            clarabel_fallback,
        )?;
        solves += 1;
        iterations += sol.iterations;
        unconverged += u32::from(!sol.converged);
        by_clarabel += u32::from(sol.by_clarabel);
        if sol.interrupted {
            return Ok(None);
        }
        gap *= 2.0;
        let mut violated = false;
        for (k, row) in rows.iter().enumerate() {
            if !in_lp[k] && row.slack(&sol.x[1..], sol.x[0], d) < -p.lp_tol {
                violated = true;
                in_lp[k] = true;
            }
        }
        if !violated {
            break (sol, listed);
        }
        for (k, row) in rows.iter().enumerate() {
            in_lp[k] |= row.rel_gap < gap;
        }
    };
    let s: Vec<f64> = sol.x[1..].iter().map(|&u| u * r_unit).collect();
    // Rows: the listed ones, the cap on Γ, then the bound rows.
    let tail_duals = sol.z[listed.len()..].to_vec();
    let bound_dual = tail_duals.get(1..).map_or(0.0, |z| z.iter().sum());
    Ok(Some(LpStep {
        tail_duals,
        bound_dual,
        converged: sol.converged,
        g: sol.x[0],
        s,
        duals: sol.z[..listed.len()].to_vec(),
        iterations,
        solves,
        unconverged,
        by_clarabel,
        links: listed.iter().map(|&k| rows[k].link).collect(),
        keys: listed.iter().map(|&k| rows[k].key).collect(),
    }))
}

/// The rows an LP may list, around the configuration of `g` within `scope`'s cut-off (pair
/// and wall links in the scaled variables, lengths in units of `r_unit`), and the cap on Γ
/// that keeps pairs beyond the cut-off apart.
fn candidate_rows(g: &Growth, scope: &LpScope, r_unit: f64) -> (Vec<Row>, f64) {
    let (d, t) = (g.d, g.t);
    let LpScope {
        cutoff_gap,
        s_bound,
        excess_cap,
        ..
    } = *scope;
    let sigma_max = t * g.diameters.iter().fold(0.0f64, |m, &v| m.max(v));
    // Cap on Γ so that pairs beyond the cut-off cannot meet: √Γ − 1 ≤ (gap − 2√d s_b)/σ_max,
    // tightened to `excess_cap` (a few times the previous LP's √Γ − 1) when given.
    let reach = match s_bound {
        Some(sb) => 2.0 * (d as f64).sqrt() * sb,
        None => 0.0,
    };
    let sqrt_cap = (1.0 + ((cutoff_gap - reach) / sigma_max).max(0.0))
        .min(excess_cap.map_or(f64::INFINITY, |e| 1.0 + e));
    let gamma_cap = sqrt_cap * sqrt_cap;
    let cands = Candidates::build(&g.container, &g.x, &g.diameters, t, cutoff_gap);
    // A pair whose constraint holds for every admissible (s, Γ), |r|² − 2|r|·reach ≥ Γ_cap σ²
    // (|n·(s_j − s_i)| ≤ 2√d s_bound = reach), cannot bind: leaving its row out changes no LP
    // solution and keeps the KKT factorisation sparse (most of the cut-off shell, in 3D).
    let rows = cands
        .keys
        .iter()
        .map(|k| (*k, contacts::link(&g.container, &g.x, &g.diameters, k)))
        .filter(|(_, l)| match l.j {
            Some(j) if j != l.i && s_bound.is_some() => {
                let sigma = l.size * t;
                l.dist * (l.dist - 2.0 * reach) < gamma_cap * sigma * sigma * (1.0 + 1e-9)
            }
            _ => true,
        })
        .map(|(key, l)| Row::new(key, l, t, r_unit))
        .collect();
    (rows, gamma_cap)
}

/// Which of `rows` the first solve lists. Lazy rows: the solve is over the rows within
/// `working_gap`, then every row the solution violates joins (and the gap widens) until none is
/// violated; the last solution is feasible for every row and optimal for a subset of them, so
/// it is an optimum of the whole LP, and the left-out rows have zero duals. A particle held by
/// `d` rows or fewer may move as far as the bound allows (an interior point centres it in its
/// free directions) and meet any neighbour: all its rows go in.
fn first_rows(rows: &[Row], working_gap: f64, n: usize, d: usize) -> Vec<bool> {
    let mut in_lp: Vec<bool> = rows.iter().map(|r| r.rel_gap < working_gap).collect();
    let mut rows_of = vec![0usize; n];
    for row in rows.iter().zip(&in_lp).filter(|p| *p.1).map(|p| p.0) {
        rows_of[row.link.i] += 1;
        if let Some(j) = row.link.other() {
            rows_of[j] += 1;
        }
    }
    for (row, listed) in rows.iter().zip(in_lp.iter_mut()) {
        let loose = |i: usize| rows_of[i] <= d;
        *listed |= loose(row.link.i) || row.link.other().is_some_and(loose);
    }
    in_lp
}

/// One LP row in the scaled variables (u = s/R, g = Γ − 1), divided by σ² (pairs) or ρ
/// (walls): `constant + coef·(a·u) ≥ g_coef·g`, with `a·u` the link's rate (n·(u_j − u_i) for a
/// pair, −n·u_i for a wall).
pub(super) struct Row {
    pub(super) key: Key,
    pub(super) link: Link,
    pub(super) rel_gap: f64,
    pub(super) constant: f64,
    pub(super) coef: f64,
    pub(super) g_coef: f64,
}

impl Row {
    pub(super) fn new(key: Key, link: Link, t: f64, r_unit: f64) -> Self {
        let size = link.size * t;
        let (constant, coef, g_coef) = match link.j {
            // |r|² + 2|r| n·(s_j − s_i) ≥ Γσ²: (|r|²/σ² − 1) + (2R|r|/σ²) n·(u_j − u_i) ≥ g.
            Some(_) => (
                (link.dist / size).powi(2) - 1.0,
                2.0 * r_unit * link.dist / (size * size),
                1.0,
            ),
            // h − n·s_i ≥ ρ(1 + Γ)/2: (h/ρ − 1) − (R/ρ) n·u_i ≥ g/2.
            None => (link.dist / size - 1.0, r_unit / size, 0.5),
        };
        Row {
            rel_gap: link.rel_gap(t),
            key,
            link,
            constant,
            coef,
            g_coef,
        }
    }

    /// How far the constraint is from binding at `(u, g)` (negative: violated).
    pub(super) fn slack(&self, u: &[f64], g: f64, d: usize) -> f64 {
        self.constant + self.coef * self.link.rate(u, d) - self.g_coef * g
    }
}

/// Solves the LP over the rows `listed` of `rows`, with the cap `g ≤ Γ_cap − 1`, the bounds
/// `|s_iμ| ≤ s_bound`, and the coordinates `held` (indices into s) fixed at zero; by clarabel
/// when the normal equations have no factor and `clarabel_fallback` allows it.
#[allow(clippy::too_many_arguments)]
pub(super) fn solve_rows(
    g: &Growth,
    rows: &[Row],
    listed: &[usize],
    gamma_cap: f64,
    s_bound: Option<f64>,
    held: &[usize],
    r_unit: f64,
    p: &Params,
    stop: Option<&'static AtomicBool>,
    warm: Option<&[f64]>,
    clarabel_fallback: bool,
) -> Result<LpSolution, JammingError> {
    let (n, d) = (g.n, g.d);
    // Variables: [g, u_0 … u_{Nd−1}], s = R u.
    let mut q = vec![0.0; 1 + n * d];
    q[0] = -1.0;
    let mut lp = InequalityLp::new(q);
    lp.factorise_in_parallel(p.parallel_factorisation);
    for &v in held {
        lp.fix_at_zero(1 + v);
    }
    for row in listed.iter().map(|&k| &rows[k]) {
        let rate = row
            .link
            .terms(d)
            .into_iter()
            .map(|(c, a)| (1 + c, row.coef * a));
        lp.at_least(std::iter::once((0, -row.g_coef)).chain(rate), -row.constant);
    }
    lp.at_least([(0usize, -1.0)], 1.0 - gamma_cap);
    if let Some(sb) = s_bound {
        let ub = sb / r_unit;
        for v in 1..=n * d {
            lp.at_least([(v, 1.0)], -ub);
            lp.at_least([(v, -1.0)], -ub);
        }
    }
    // The normal equations may have no factor (a 3D start at N = 200); clarabel
    // then solves this LP.
    // A warm solve that stops short of `lp_tol` (its start far from the new central path) is
    // redone cold, so that a warm start never costs a step of lower accuracy.
    let warm = warm.filter(|z| z.len() == lp.rows());
    lp.solve(p.lp_tol, p.lp_max_iter, stop, warm)
        .and_then(|sol| match warm {
            Some(_) if !sol.converged && !sol.interrupted => lp
                .solve(p.lp_tol, p.lp_max_iter, stop, None)
                .map(|cold| LpSolution {
                    iterations: cold.iterations + sol.iterations,
                    ..cold
                }),
            _ => Ok(sol),
        })
        .or_else(|e| {
            if !clarabel_fallback {
                return Err(e);
            }
            lp.solve_by_clarabel(p.lp_tol, p.lp_max_iter)
                .map_err(|c| format!("{e}, and clarabel failed too ({c})"))
        })
        .map_err(|e| JammingError::Solver(format!("CALiPPSO LP: {e}")))
}
