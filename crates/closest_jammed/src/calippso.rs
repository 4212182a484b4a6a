//! CALiPPSO: jamming by iterated linear programming (seed 002).
//!
//! Each iteration solves the LP in the inflation factor Γ and the displacements
//! s: maximise Γ subject to the linearised non-overlap constraints
//! `|r_ij|² + 2 r_ij·(s_j − s_i) ≥ Γ σ_ij²` for every pair (and periodic image) within the
//! cut-off ℓ, and `|s_iμ| ≤ s_bound`; then `r ← r + s`, `σ ← √Γ σ`. The linearisation drops
//! `|s_j − s_i|² ≥ 0`, so an LP solution never creates an overlap among listed pairs; the cut-off,
//! the bound and a cap on Γ keep unlisted pairs apart. Walls (not in CALiPPSO, which is periodic
//! only) enter as `h − n·s_i ≥ ρ_i (1 + Γ)/2`, which implies `h' ≥ √Γ ρ_i` since
//! `(1+Γ)/2 ≥ √Γ`, and is exact at convergence. A curved wall (ball, cylinder) enters by its
//! tangent plane at the particle's projection, and Γ is then capped by the exact wall distances
//! after the step ([`curved_wall_gamma`]).
//!
//! Variables are scaled (`s = R u`, `Γ = 1 + g`, constraints divided by σ²) so the LP sees
//! numbers of order one and the tiny gaps near jamming are not lost against `|r|²`. The duals
//! of the pair constraints sum to one (stationarity in g) and are the contact forces; contacts
//! are the constraints whose dual exceeds `zero_force`, rattlers are removed recursively from
//! that network before the displacement test. Each rigid motion the container allows is held
//! by one coordinate fixed at zero ([`held_coordinates`]): the periodic coordinates of the
//! best-connected particle of the previous LP (translations), and for a ball or cylindrical
//! shell coordinates of non-rattlers far from the centre (rotations).
//!
//! Rows that cannot bind are left out of each LP: a pair with `|r|² − 2|r|·2√d s_bound ≥ Γ_cap σ²`
//! satisfies its constraint for every admissible step. After the first LP, Γ is also capped at
//! `(1 + 4(√Γ_prev − 1))²`, which seldom binds and drops most of the cut-off shell; both keep
//! the factorisation (≈ 90% of the run time) sparse. Of the rows left, an LP
//! first lists those within a relative gap of 5% and every row of a particle that would be held
//! by d rows or fewer, and adds the rows its solution violates until none is (lazy rows): the
//! result is an optimum of the LP over all rows, at a fraction of the rows in the wide shell of
//! the first LPs. The LPs are solved by this crate's primal–dual interior point over the normal
//! equations ([`crate::interior_point`], faer's sparse Cholesky, METIS ordering): about three
//! times faster per LP than clarabel at N = 1000 and 10⁴ in 3D, on the same LP path at N = 1000
//! (docs/notes/calippso-lp-solver.md). Near jamming each LP starts from the previous one's
//! duals (`warm_start`, issue 49): 9–13 interior-point iterations per LP instead of 20.
//! After convergence the final network's contacts are closed exactly by a Newton projection
//! ([`close_network`]), which the LPs leave open by up to `tol_s`.
//!
//! Cut-off and bound schedule (in units of the mean radius R): while √Γ−1 ≥ 5e-4 the cut-off
//! gap is `(ℓ0 − 2)R` and `s_bound = gap/(4√d)`; below 5e-4 the gap is at most `R` and
//! `s_bound ≤ 0.1R`; below 1e-5 the gap is at most `R/2` and `s_bound = s_bound_final·R`.
//! With `bound_schedule = trust-region` the cut-off follows the same schedule and the bound is
//! a trust region ([`BoundSchedule::TrustRegion`], issue 49).

use std::collections::{BTreeSet, HashMap};
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use packbench_core::analysis::{Contact, ContactNetwork, rattlers};
use packbench_core::run::{Observer, Outcome, Progress, TraceRow};
use packbench_core::{Packing, Shape};
use serde::{Deserialize, Serialize};
use serde_json::json;

use crate::contacts::{self, Candidates, Key, Link};
use crate::error::JammingError;
use crate::growth::Growth;
use crate::interior_point::{InequalityLp, LpSolution};
use crate::min_norm::Solver;
use crate::projection::project;
use crate::verdict::checked_termination;

/// CALiPPSO's options, with its defaults (seed 002 and issue 5).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default)]
pub struct Params {
    /// Convergence when `√Γ − 1 < tol_gamma` (`--tol-gamma`).
    pub tol_gamma: f64,
    /// … and the largest non-rattler displacement `max |s_iμ|` is below `tol_s` mean
    /// diameters (`--tol-s`).
    pub tol_s: f64,
    /// Largest number of LPs (`--max-iters`).
    pub max_iters: u64,
    /// Largest relative overlap `1 − r/σ` tolerated by the overlap checks (`--tol-overlap`).
    pub tol_overlap: f64,
    /// Duals (contact forces, normalised to sum to one) above this are contacts.
    pub zero_force: f64,
    /// Largest net force on a non-rattler, relative to the mean contact force, before the
    /// fine-tuning LP is run.
    pub tol_mechanical_equilibrium: f64,
    /// Initial cut-off distance ℓ0, in mean radii (pairs closer than ℓ0 − 2R in gap are listed).
    pub ell0: f64,
    /// √Γ assumed before the first LP (selects the first schedule phase).
    pub sqrt_gamma0: f64,
    /// `s_bound` near convergence (√Γ − 1 < 1e-5), in mean radii.
    pub s_bound_final: f64,
    /// Tolerance (gap and feasibility) of each LP's interior-point solve.
    pub lp_tol: f64,
    /// Interior-point iterations per LP solve at most.
    pub lp_max_iter: u32,
    /// The overlap check runs every LP for the first `initial_overlaps_check` LPs and every
    /// `interval_overlaps_check` LPs after, and always at the end.
    pub initial_overlaps_check: u64,
    /// See `initial_overlaps_check`.
    pub interval_overlaps_check: u64,
    /// Pass a snapshot to the observer every this many LPs (0: never).
    pub save_interval: u64,
    /// How `s_bound` is chosen from LP to LP (`--bound-schedule`).
    pub bound_schedule: BoundSchedule,
    /// Start each LP's interior point from the previous LP's duals of the same rows (about half
    /// the iterations per LP near jamming); a warm solve that stops short of `lp_tol` is redone
    /// from the cold start.
    pub warm_start: bool,
    /// After convergence, close the final network's contacts exactly ([`close_network`]).
    pub close_network: bool,
}

/// How the displacement bound `s_bound` is chosen (issue 49).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BoundSchedule {
    /// Seed 002's schedule by √Γ − 1 (see the module): `gap/(4√d)`, then 0.1 R below 5e-4,
    /// then `s_bound_final` R below 1e-5.
    #[default]
    Seed,
    /// A trust region: the first LP takes the seed's bound; after each LP the bound doubles
    /// when the linear model agreed with the exact non-overlap (ratio > 0.75) and the bound was
    /// binding (max |s| of non-rattlers ≥ 0.99 s_bound), and halves when the agreement is poor
    /// (< 0.25); it never exceeds the cut-off's `gap/(4√d)`.
    TrustRegion,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            tol_gamma: 1e-12,
            tol_s: 1e-9,
            max_iters: 1000,
            tol_overlap: 1e-8,
            zero_force: 1e-10,
            tol_mechanical_equilibrium: 1e-12,
            ell0: 4.0,
            sqrt_gamma0: 1.01,
            s_bound_final: 0.01,
            lp_tol: 1e-12,
            lp_max_iter: 400,
            initial_overlaps_check: 10,
            interval_overlaps_check: 10,
            save_interval: 0,
            bound_schedule: BoundSchedule::Seed,
            warm_start: true,
            close_network: true,
        }
    }
}

impl Params {
    /// Checks every parameter; the error names the one out of range.
    pub fn validate(&self) -> Result<(), JammingError> {
        for (name, v) in [
            ("tol_gamma", self.tol_gamma),
            ("tol_s", self.tol_s),
            ("tol_overlap", self.tol_overlap),
            ("zero_force", self.zero_force),
            (
                "tol_mechanical_equilibrium",
                self.tol_mechanical_equilibrium,
            ),
            ("s_bound_final", self.s_bound_final),
            ("lp_tol", self.lp_tol),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(JammingError::Parameter(format!(
                    "{name} = {v} must be a positive number"
                )));
            }
        }
        if !(self.ell0.is_finite() && self.ell0 > 2.0) {
            return Err(JammingError::Parameter(format!(
                "ell0 = {} must exceed 2 radii (the contact distance)",
                self.ell0
            )));
        }
        if !(self.sqrt_gamma0.is_finite() && self.sqrt_gamma0 >= 1.0) {
            return Err(JammingError::Parameter(format!(
                "sqrt_gamma0 = {} must be at least 1",
                self.sqrt_gamma0
            )));
        }
        if self.max_iters == 0 {
            return Err(JammingError::Parameter(
                "max_iters must be at least 1".into(),
            ));
        }
        Ok(())
    }
}

/// One LP's results.
struct LpStep {
    /// Γ − 1.
    g: f64,
    /// Displacements (length units), N·d.
    s: Vec<f64>,
    /// Constraint links, their candidate keys, and their duals (forces, summing to about one).
    links: Vec<Link>,
    keys: Vec<Key>,
    duals: Vec<f64>,
    /// Interior-point iterations, over all its solves.
    iterations: u32,
    /// Solves (one, plus one per round of lazy rows added).
    solves: u32,
    /// Solves that stopped (iteration limit, stalled steps or an overflowing direction) before
    /// meeting `lp_tol`.
    unconverged: u32,
    /// Solves handed to clarabel because the normal equations had no factor.
    by_clarabel: u32,
    /// Duals of the rows after the links: the cap on Γ, then the bound rows (+, − per
    /// coordinate), the warm start of the next LP.
    tail_duals: Vec<f64>,
    /// Sum of the duals of the bound rows `|u_iμ| ≤ s_bound/R`: how fast g = Γ − 1 would grow
    /// with the bound (in units of R); zero when the bound does not bind.
    bound_dual: f64,
}

/// Relative gap of the rows an LP starts from; rows beyond it join when a solution violates
/// them. Near jamming a step closes gaps of at most a few `s_bound` (1e-2 R), so the rows
/// within 5% are all that bind; the first LP's wide shell (ℓ0 = 4R) holds about five times
/// as many rows, nearly all slack (21 469 against 3951 at N = 1000 from a near-jammed start).
const LAZY_GAP: f64 = 0.05;

/// An LP is warm-started (`Params::warm_start`) only when the previous one made or broke at
/// most this fraction of its contacts …
const WARM_MAX_CHANGED: f64 = 0.05;

/// … and left √Γ − 1 at least this large.
const WARM_MIN_EXCESS: f64 = 1e-9;

/// Which rows an LP lists and how far its particles may move.
#[derive(Clone, Copy)]
struct LpScope {
    /// Pairs with a gap below this (length units) are candidates.
    cutoff_gap: f64,
    /// `|s_iμ| ≤ s_bound`; `None` leaves the displacements free (the fine-tuning LP of seed
    /// 002's final packing).
    s_bound: Option<f64>,
    /// Cap on √Γ − 1 (a few times the previous LP's), which drops rows that cannot bind.
    excess_cap: Option<f64>,
    /// Relative gap of the rows of the first solve (see [`LAZY_GAP`]).
    working_gap: f64,
}

/// Builds and solves one LP around the current configuration, each solve warm-started from the
/// duals of `warm` (the previous LP) when given. `Ok(None)` when `stop` ended the solve.
fn solve_lp(
    g: &Growth,
    scope: &LpScope,
    held: &[usize],
    p: &Params,
    stop: Option<&'static AtomicBool>,
    warm: Option<&LpStep>,
) -> Result<Option<LpStep>, JammingError> {
    let (n, d, t) = (g.n, g.d, g.t);
    let LpScope {
        cutoff_gap,
        s_bound,
        excess_cap,
        working_gap,
    } = *scope;
    let r_unit = 0.5 * t * g.diameters.iter().sum::<f64>() / n as f64;
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
    let rows: Vec<Row> = cands
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
    // Lazy rows: solve over the rows within `working_gap`, then add every row the solution
    // violates (and widen the gap) until none is violated. The last solution is feasible for
    // every row and optimal for a subset of them, so it is an optimum of the whole LP, and the
    // left-out rows have zero duals.
    let mut in_lp: Vec<bool> = rows.iter().map(|r| r.rel_gap < working_gap).collect();
    // A particle held by d rows or fewer may move as far as the bound allows (an interior
    // point centres it in its free directions) and meet any neighbour: all its rows go in.
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

/// One LP row in the scaled variables (u = s/R, g = Γ − 1), divided by σ² (pairs) or ρ
/// (walls): `constant + coef·(a·u) ≥ g_coef·g`, with `a·u` the link's rate (n·(u_j − u_i) for a
/// pair, −n·u_i for a wall).
struct Row {
    key: Key,
    link: Link,
    rel_gap: f64,
    constant: f64,
    coef: f64,
    g_coef: f64,
}

impl Row {
    fn new(key: Key, link: Link, t: f64, r_unit: f64) -> Self {
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
    fn slack(&self, u: &[f64], g: f64, d: usize) -> f64 {
        self.constant + self.coef * self.link.rate(u, d) - self.g_coef * g
    }
}

/// Solves the LP over the rows `listed` of `rows`, with the cap `g ≤ Γ_cap − 1`, the bounds
/// `|s_iμ| ≤ s_bound`, and the coordinates `held` (indices into s) fixed at zero.
#[allow(clippy::too_many_arguments)]
fn solve_rows(
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
) -> Result<LpSolution, JammingError> {
    let (n, d) = (g.n, g.d);
    // Variables: [g, u_0 … u_{Nd−1}], s = R u.
    let mut q = vec![0.0; 1 + n * d];
    q[0] = -1.0;
    let mut lp = InequalityLp::new(q);
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
    // The normal equations may have no factor (issue 43: a 3D start at N = 200); clarabel
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
            lp.solve_by_clarabel(p.lp_tol, p.lp_max_iter)
                .map_err(|c| format!("{e}, and clarabel failed too ({c})"))
        })
        .map_err(|e| JammingError::Solver(format!("CALiPPSO LP: {e}")))
}

/// The contact network of an LP (duals above `zero_force`), its rattlers, and per-particle
/// force imbalance relative to the mean force.
struct Network {
    rattler: Vec<bool>,
    /// Contacts among non-rattlers, with their forces ([`contact_force`]).
    contacts: Vec<(Key, f64)>,
    n_dof: usize,
    imbalance: f64,
    /// Contact count per particle (all contacts).
    degree: Vec<usize>,
    /// Keys of all contacts, to count how many change from one LP to the next.
    keys: BTreeSet<Key>,
}

fn network(g: &Growth, step: &LpStep, zero_force: f64) -> Network {
    let (n, d) = (g.n, g.d);
    let mut net = ContactNetwork::default();
    let mut degree = vec![0usize; n];
    let mut kept = Vec::new();
    let mut keys = BTreeSet::new();
    for ((l, &z), &key) in step.links.iter().zip(&step.duals).zip(&step.keys) {
        if z > zero_force {
            keys.insert(key);
            net.contacts.push(Contact {
                i: l.i,
                j: l.j,
                wall: None,
                gap: 0.0,
            });
            degree[l.i] += 1;
            if let Some(j) = l.other() {
                degree[j] += 1;
            }
            kept.push((l, z, key));
        }
    }
    let rattler = rattlers(&net, n, d);
    let active = rattler.iter().filter(|&&r| !r).count();
    // Forces: the dual times the constraint's gradient magnitude, along the contact normal
    // (only directions matter for the balance test; the scale is divided out).
    let mut net_force = vec![0.0; n * d];
    let mut total = 0.0;
    let mut contacts = Vec::new();
    for &(l, z, key) in &kept {
        if rattler[l.i] || l.other().is_some_and(|j| rattler[j]) {
            continue;
        }
        let f = contact_force(l, z, g.t);
        contacts.push((key, f));
        total += f;
        l.add_transposed(f, &mut net_force, d);
    }
    let mut worst: f64 = 0.0;
    for i in 0..n {
        if !rattler[i] {
            let f2: f64 = net_force[i * d..(i + 1) * d].iter().map(|v| v * v).sum();
            worst = worst.max(f2.sqrt());
        }
    }
    let mean = if !contacts.is_empty() {
        total / contacts.len() as f64
    } else {
        1.0
    };
    Network {
        contacts,
        n_dof: if active == 0 {
            0
        } else {
            (d * active + 1).saturating_sub(g.container.rigid_motions())
        },
        imbalance: worst / mean,
        degree,
        rattler,
        keys,
    }
}

/// The force along the normal of a contact whose row has dual `z`, at growth factor `t`: the
/// constraints' u-gradients of `solve_lp` without their common factor R, 2|r|/σ² for a pair
/// and 1/ρ for a wall, with the actual σ and ρ (size·t). Taking the nominal sizes instead
/// scaled every wall force by 1/t, and walled runs reported force imbalances of 4 to 18 for
/// packings the core finds balanced to 1e-13.
fn contact_force(l: &Link, z: f64, t: f64) -> f64 {
    let actual = l.size * t;
    z * match l.j {
        Some(_) => 2.0 * l.dist / (actual * actual),
        None => 1.0 / actual,
    }
}

/// Relative gap to which [`close_network`] closes the final contacts.
const CLOSE_TOL: f64 = 1e-14;

/// Closes the non-rattler contacts of the last LP's network exactly. An LP makes its contacts
/// touch only to first order and to `lp_tol`, so a converged run leaves its weakest contacts
/// open by up to about `tol_s` (N = 4000, seed 81: 654 contacts with relative gaps of 1e-12 to
/// 1e-10 and one at 1.09e-9, which the core's count at contact tolerance 1e-9 missed). A Newton
/// projection of the positions and the growth factor together ([`project`], the network's
/// one dependency taking up the growth, as at the end of closest-jammed) closes them,
/// moving each particle by about that much. A near-degenerate last LP can carry more
/// contacts than n_dof; the weakest are left out. Returns the largest relative gap left, or
/// `None`, with nothing moved, when the network has fewer contacts than n_dof or the
/// projection does not converge.
fn close_network(g: &mut Growth, net: &Network) -> Option<f64> {
    let mut contacts = net.contacts.clone();
    if net.n_dof == 0 || contacts.len() < net.n_dof {
        return None;
    }
    contacts.sort_by(|a, b| b.1.total_cmp(&a.1));
    contacts.truncate(net.n_dof);
    // The strongest contact closes the dependency; `project` wants the forces of the basis
    // first, then of that contact.
    let (dependent, strongest) = contacts[0];
    let basis: Vec<Key> = contacts[1..].iter().map(|c| c.0).collect();
    let forces: Vec<f64> = contacts[1..]
        .iter()
        .map(|c| c.1)
        .chain([strongest])
        .collect();
    let solver = Solver::new(CLOSE_DENSE_MAX_BONDS);
    project(
        g,
        &basis,
        None,
        Some((&dependent, &forces)),
        CLOSE_TOL,
        &solver,
    )
    .ok()
}

/// Bond counts up to which [`close_network`] factorises densely (closest-jammed's default).
const CLOSE_DENSE_MAX_BONDS: usize = 48;

/// Jams `start` by CALiPPSO's iterated linear programming (seed 002).
///
/// Terminations: `converged` (√Γ−1 < tol_gamma and non-rattler max |s| < tol_s),
/// `max_iters`, `interrupted`. `extra` holds `lp_count`, `sqrt_gamma_minus_1`, `max_s`,
/// `contacts` and `n_dof` of the dual network, `rattlers`, `force_imbalance_lp` (the last LP's)
/// and `force_imbalance` (the smaller of it and the fine-tuning LP's), `fine_tuned` (whether
/// the fine-tuning LP's network was the better balanced), `max_overlap` of the final check,
/// `lp_iterations` (interior-point iterations over all LPs), `lp_solves` (one per LP plus one
/// per round of lazy rows), `lp_unconverged` (solves that stopped short of `lp_tol`; their
/// last iterate is used), `lp_clarabel` (solves handed to clarabel because the normal
/// equations had no factor), `wall_limited_lps` (LPs whose Γ a curved wall capped) and
/// `closed_gap` (the largest relative gap of the final network after [`close_network`]; null
/// when it did not run). The trace has one row per LP: `sqrt_gamma_minus_1`, `max_s`,
/// `contacts`, `n_dof`, `contacts_changed` (contacts of the dual network made or lost since the
/// previous LP) and `rattlers`.
///
/// # Errors
/// [`JammingError::InvalidPacking`] and [`JammingError::Overlap`] for a bad start or an
/// overlap found by a check, [`JammingError::Parameter`] for bad options,
/// [`JammingError::Solver`] when an LP's normal equations cannot be factorised.
pub fn run(
    start: &Packing,
    params: &Params,
    observer: &mut dyn Observer,
) -> Result<Outcome, JammingError> {
    params.validate()?;
    let clock = Instant::now();
    let phi0 = start.phi();
    let mut g = Growth::new(start, 0.5, params.tol_overlap)?;
    let (n, d) = (g.n, g.d);
    let sqrt_d = (d as f64).sqrt();
    let mut sqrt_gamma = params.sqrt_gamma0;
    let mut held = held_coordinates(&g, 0, None);
    let mut trace = Vec::new();
    let mut iters = 0u64;
    let mut last: Option<(LpStep, Network)> = None;
    // Contacts the last LP made or broke, as a fraction of its contacts.
    let mut changed_fraction = 1.0;
    let mut max_s_active = f64::INFINITY;
    let mut lp_iterations = 0u64;
    let mut lp_solves = 0u64;
    let mut lp_unconverged = 0u64;
    let mut lp_clarabel = 0u64;
    let mut wall_limited = 0u64;
    // The trust region's bound in mean radii (none before the first LP).
    let mut trust_bound: Option<f64> = None;
    let mut bound_switches = 0u64;
    let mut bound_bound_prev = false;
    let stop = observer.stop_flag();
    let termination;
    loop {
        if observer.should_stop() {
            termination = "interrupted";
            break;
        }
        if iters >= params.max_iters {
            termination = "max_iters";
            break;
        }
        let r_mean = 0.5 * g.t * g.diameters.iter().sum::<f64>() / n as f64;
        let excess = sqrt_gamma - 1.0;
        let base_gap = (params.ell0 - 2.0) * r_mean;
        let (gap, seed_sb) = if excess >= 5e-4 {
            (base_gap, base_gap / (4.0 * sqrt_d))
        } else if excess >= 1e-5 {
            let gap = base_gap.min(r_mean);
            (gap, (0.1 * r_mean).min(gap / (4.0 * sqrt_d)))
        } else {
            let gap = base_gap.min(0.5 * r_mean);
            (
                gap,
                (params.s_bound_final * r_mean).min(gap / (4.0 * sqrt_d)),
            )
        };
        // After the first LP, Γ is capped at (1 + 4(√Γ_prev − 1))², which rarely binds (Γ
        // falls from LP to LP) and lets the far part of the cut-off shell drop out.
        let sb = match (params.bound_schedule, trust_bound) {
            (BoundSchedule::TrustRegion, Some(b)) => (b * r_mean).min(gap / (4.0 * sqrt_d)),
            _ => seed_sb,
        };
        let excess_cap = (iters > 0).then(|| (4.0 * excess).max(1e-5));
        let scope = LpScope {
            cutoff_gap: gap,
            s_bound: Some(sb),
            excess_cap,
            working_gap: LAZY_GAP,
        };
        // Warm starts pay where the active set barely changes (near jamming); far from it the
        // old duals are no guide. At the very end a warm start's displacements carry noise of
        // ~1e-8 D (N = 4000: 300 LPs with 1e-8 < max |s| < 5e-8 after √Γ − 1 had reached
        // 1e-13), which `tol_s` = 1e-9 does not accept, so the last LPs start cold.
        let warm = last.as_ref().map(|l| &l.0).filter(|_| {
            params.warm_start && changed_fraction <= WARM_MAX_CHANGED && excess >= WARM_MIN_EXCESS
        });
        let Some(step) = solve_lp(&g, &scope, &held, params, stop, warm)? else {
            termination = "interrupted";
            break;
        };
        lp_iterations += u64::from(step.iterations);
        lp_solves += u64::from(step.solves);
        lp_unconverged += u64::from(step.unconverged);
        lp_clarabel += u64::from(step.by_clarabel);
        // Update r ← r + s, σ ← √Γ σ, with Γ no larger than the curved walls allow.
        g.x.iter_mut().zip(&step.s).for_each(|(x, s)| *x += s);
        let agreement = model_agreement(&g, &step);
        let gamma_walls = curved_wall_gamma(&g);
        if gamma_walls < 1.0 + step.g {
            wall_limited += 1;
        }
        let gamma = (1.0 + step.g).min(gamma_walls);
        sqrt_gamma = gamma.max(0.0).sqrt();
        g.t *= sqrt_gamma;
        iters += 1;
        let net = network(&g, &step, params.zero_force);
        // Contacts made or lost since the previous LP: near jamming the network settles and
        // this falls to zero; while it stays high the packing is still rearranging.
        let changed = last.as_ref().map_or(net.keys.len(), |(_, prev)| {
            prev.keys.symmetric_difference(&net.keys).count()
        });
        changed_fraction = changed as f64 / net.keys.len().max(1) as f64;
        let d_mean = 2.0 * r_mean;
        max_s_active = (0..n)
            .filter(|&i| !net.rattler[i])
            .flat_map(|i| step.s[i * d..(i + 1) * d].iter().map(|v| v.abs()))
            .fold(0.0, f64::max)
            / d_mean;
        // What limited this LP: the bound binds when its rows carry a dual, non-overlap when
        // the pair and wall rows do (their duals sum to one unless the cap on Γ binds).
        let bound_binds = step.bound_dual > params.zero_force;
        let overlap_binds = step.duals.iter().sum::<f64>() > 0.5;
        let binds = match (bound_binds, overlap_binds) {
            (false, true) => 1.0,
            (true, false) => 2.0,
            (true, true) => 3.0,
            (false, false) => 0.0,
        };
        if iters > 1 && bound_binds != bound_bound_prev {
            bound_switches += 1;
        }
        bound_bound_prev = bound_binds;
        let s_over_bound = max_s_active * d_mean / sb;
        trust_bound = Some(trust_update(sb / r_mean, agreement, s_over_bound));
        let anchor = (0..n)
            .max_by_key(|&i| (net.degree[i], std::cmp::Reverse(i)))
            .unwrap_or(0);
        held = held_coordinates(&g, anchor, Some(&net.rattler));
        if iters <= params.initial_overlaps_check
            || (params.interval_overlaps_check > 0
                && iters.is_multiple_of(params.interval_overlaps_check))
        {
            check_overlaps(&g, params.tol_overlap, iters)?;
        }
        let phi = g.phi(phi0);
        observer.progress(&Progress {
            step: iters,
            phi,
            value: sqrt_gamma - 1.0,
            label: "sqrt(Γ)−1",
            fraction: Some(iters as f64 / params.max_iters as f64),
            more: vec![
                ("max_s_over_d", max_s_active),
                ("contacts_changed", changed as f64),
                ("ipm_iterations", f64::from(step.iterations)),
            ],
        });
        trace.push(TraceRow {
            step: iters,
            time_s: clock.elapsed().as_secs_f64(),
            phi,
            values: vec![
                ("sqrt_gamma_minus_1".into(), sqrt_gamma - 1.0),
                ("max_s".into(), max_s_active),
                ("contacts".into(), net.contacts.len() as f64),
                ("n_dof".into(), net.n_dof as f64),
                ("contacts_changed".into(), changed as f64),
                (
                    "rattlers".into(),
                    net.rattler.iter().filter(|&&r| r).count() as f64,
                ),
                ("bound_over_r".into(), sb / r_mean),
                ("max_s_over_bound".into(), s_over_bound),
                ("binds".into(), binds),
                ("model_agreement".into(), agreement),
                ("ipm_iterations".into(), f64::from(step.iterations)),
            ],
        });
        if params.save_interval > 0 && iters.is_multiple_of(params.save_interval) {
            observer.snapshot(iters, &g.packing());
        }
        let converged = sqrt_gamma - 1.0 < params.tol_gamma && max_s_active < params.tol_s;
        last = Some((step, net));
        if converged {
            termination = "converged";
            break;
        }
    }
    let closed_gap = match &last {
        Some((_, net)) if params.close_network && termination == "converged" => {
            close_network(&mut g, net)
        }
        _ => None,
    };
    // Final packing: force balance of the last LP's duals, fine-tuned if needed.
    let mut extra = serde_json::Map::new();
    extra.insert("closed_gap".into(), json!(closed_gap));
    if let Some((_, net)) = &last {
        let mut imbalance = net.imbalance;
        extra.insert("force_imbalance_lp".into(), json!(imbalance));
        let mut fine_tuned = false;
        let mut net_final = None;
        if imbalance > params.tol_mechanical_equilibrium {
            let r_mean = 0.5 * g.t * g.diameters.iter().sum::<f64>() / n as f64;
            // A stop request skips it: the last LP's network stands.
            let scope = LpScope {
                cutoff_gap: 0.5 * r_mean,
                s_bound: None,
                excess_cap: None,
                working_gap: LAZY_GAP,
            };
            if let Some(tuned) = solve_lp(&g, &scope, &held, params, stop, None)? {
                lp_iterations += u64::from(tuned.iterations);
                lp_solves += u64::from(tuned.solves);
                lp_unconverged += u64::from(tuned.unconverged);
                lp_clarabel += u64::from(tuned.by_clarabel);
                // Its duals come from an unbounded LP solved to the same `lp_tol` and are not
                // always better balanced (N = 4000, seed 82 run again: 8.9e-7 against the last
                // LP's 3.0e-8), so the better network is kept.
                let tn = network(&g, &tuned, params.zero_force);
                if tn.imbalance < imbalance {
                    imbalance = tn.imbalance;
                    fine_tuned = true;
                    net_final = Some(tn);
                }
            }
        }
        let net = net_final.as_ref().unwrap_or(net);
        extra.insert("force_imbalance".into(), json!(imbalance));
        extra.insert("fine_tuned".into(), json!(fine_tuned));
        extra.insert("contacts".into(), json!(net.contacts.len()));
        extra.insert("n_dof".into(), json!(net.n_dof));
        extra.insert(
            "rattlers".into(),
            json!(net.rattler.iter().filter(|&&r| r).count()),
        );
    }
    let max_overlap = check_overlaps(&g, params.tol_overlap, iters)?;
    extra.insert("lp_count".into(), json!(iters));
    extra.insert("lp_iterations".into(), json!(lp_iterations));
    extra.insert("lp_solves".into(), json!(lp_solves));
    extra.insert("lp_unconverged".into(), json!(lp_unconverged));
    extra.insert("lp_clarabel".into(), json!(lp_clarabel));
    extra.insert("wall_limited_lps".into(), json!(wall_limited));
    extra.insert("bound_switches".into(), json!(bound_switches));
    extra.insert("sqrt_gamma_minus_1".into(), json!(sqrt_gamma - 1.0));
    extra.insert(
        "max_s".into(),
        json!(if max_s_active.is_finite() {
            json!(max_s_active)
        } else {
            json!(null)
        }),
    );
    extra.insert("max_overlap".into(), json!(max_overlap));
    let packing = g.packing();
    let termination = checked_termination(
        termination,
        termination == "converged",
        &packing,
        &mut extra,
    )?;
    Ok(Outcome {
        packing,
        steps: iters,
        termination,
        trace,
        extra,
    })
}

/// Agreement of the LP's linear model with the exact non-overlap at the new positions: with
/// `p = √Γ_LP − 1` (what the LP promised) and `a = √Γ_exact − 1` (the largest inflation the
/// exact distances of the LP's pairs and walls allow after the step), `min(p, a)/max(p, a)`,
/// 1 when they agree. The linearisation drops `|s_j − s_i|²`, so `a ≥ p` for pairs and flat
/// walls: a step long against the gaps it closes makes `a ≫ p`. A curved wall can make
/// `a < p`. Called after `g.x` has moved and before `g.t` has grown.
fn model_agreement(g: &Growth, step: &LpStep) -> f64 {
    let exact = step
        .keys
        .iter()
        .map(|k| {
            // Pairs: |r|² ≥ Γσ²; walls: h ≥ √Γ ρ (the row's ρ(1 + Γ)/2, exactly).
            let l = g.link(k);
            let ratio = (l.dist / (l.size * g.t)).max(0.0);
            ratio * ratio
        })
        .fold(curved_wall_gamma(g), f64::min);
    let p = (1.0 + step.g).max(0.0).sqrt() - 1.0;
    let a = exact.sqrt() - 1.0;
    let (lo, hi) = (p.min(a), p.max(a));
    if hi <= 0.0 { 1.0 } else { (lo / hi).max(0.0) }
}

/// The trust region's next bound (mean radii) after an LP with bound `bound`, model agreement
/// `agreement` and largest non-rattler displacement `s_over_bound` times the bound.
fn trust_update(bound: f64, agreement: f64, s_over_bound: f64) -> f64 {
    if agreement < 0.25 {
        (0.5 * bound).max(TRUST_MIN)
    } else if agreement > 0.75 && s_over_bound >= 0.99 {
        2.0 * bound
    } else {
        bound
    }
}

/// The smallest trust-region bound, in mean radii.
const TRUST_MIN: f64 = 1e-6;

/// Coordinates (indices into s) held at zero in an LP, one for each rigid motion of the
/// container, so that no direction of the LP is free. Along a free direction the interior
/// point stops at the centre of the optimal face, not at zero: the packing would drift LP after
/// LP, never meeting `tol_s`, and a rotation along a curved wall would let [`curved_wall_gamma`]
/// shrink it. Translations: the periodic coordinates of `anchor`. Rotations of a ball over t
/// axes (or of a cylindrical shell, t = 2) in the planes (k, l), k < l < t: a rotation by ω
/// moves coordinate l of a particle at p by ω p_k, so coordinates l > k of the non-rattler
/// farthest from the centre along k are held.
fn held_coordinates(g: &Growth, anchor: usize, rattler: Option<&[bool]>) -> Vec<usize> {
    let d = g.d;
    let mut held: Vec<usize> = (0..d)
        .filter(|&k| g.container.periodic[k])
        .map(|k| anchor * d + k)
        .collect();
    let axes = match g.container.shape {
        Shape::Ball { axes } => axes,
        Shape::CylindricalShell { .. } => 2,
        _ => 0,
    };
    let centre = 0.5 * g.container.lengths[0];
    for k in 0..axes.saturating_sub(1) {
        let far = (0..g.n)
            .filter(|&i| rattler.is_none_or(|r| !r[i]))
            .max_by(|&i, &j| {
                let off = |p: usize| (g.x[p * d + k] - centre).abs();
                off(i).total_cmp(&off(j))
            });
        if let Some(a) = far {
            held.extend((k + 1..axes).map(|l| a * d + l));
        }
    }
    held.sort_unstable();
    held.dedup();
    held
}

/// The largest Γ the curved wall of the container allows at the current positions,
/// `min_i (h_i/ρ_i)²` with `h_i` the exact distance of particle i to its nearest wall and `ρ_i`
/// its radius before inflation; `+∞` for a box, whose flat walls the LP's rows describe exactly.
///
/// The LP's wall row is the tangent plane at the particle's projection on the wall. The inside
/// of a ball or cylinder curves towards the particle, so a step `s` along the wall brings it
/// closer by up to `|s_⊥|²/(2|p|)` than the row says (|p| the distance from the axis), and the
/// LP's Γ may overlap the wall; capping Γ here keeps every update overlap-free. At convergence
/// `s → 0` and the cap meets the LP's Γ.
fn curved_wall_gamma(g: &Growth) -> f64 {
    if matches!(g.container.shape, Shape::Box) {
        return f64::INFINITY;
    }
    let d = g.d;
    (0..g.n)
        .map(|i| {
            let h = g.container.wall_clearance(&g.x[i * d..(i + 1) * d]);
            let rho = 0.5 * g.diameters[i] * g.t;
            let ratio = (h / rho).max(0.0);
            ratio * ratio
        })
        .fold(f64::INFINITY, f64::min)
}

/// Seed 002's overlap check: the largest relative overlap over all near pairs and walls; an
/// error when it exceeds `tol`.
fn check_overlaps(g: &Growth, tol: f64, iteration: u64) -> Result<f64, JammingError> {
    let skin = 1e-3 * g.t * g.diameters.iter().fold(0.0f64, |m, &v| m.max(v));
    let cands = Candidates::build(&g.container, &g.x, &g.diameters, g.t, skin);
    let (ov, i, j) = contacts::worst_overlap(&g.container, &g.x, &g.diameters, g.t, &cands.keys);
    if ov > tol {
        return Err(JammingError::OverlapDuringRun {
            i,
            j,
            overlap: ov,
            iteration,
        });
    }
    Ok(ov)
}

#[cfg(test)]
mod tests {
    use super::*;
    use packbench_core::init::initial_packing;
    use packbench_core::scene::{Placement, Scene};
    use packbench_core::{Container, SizeDistribution};

    /// Asserts that the core finds `p` exactly jammed at contact tolerance 1e-9: isostatic, no
    /// overlap above 1e-9, force balance within 1e-8.
    fn assert_exactly_jammed(p: &Packing, what: &str) {
        use packbench_core::analysis::{AnalysisOptions, analyze};
        let m = analyze(
            p,
            &AnalysisOptions {
                contact_tol: 1e-9,
                force_balance: true,
            },
        )
        .unwrap();
        assert!(m.max_overlap <= 1e-9, "{what}: {m:?}");
        assert_eq!(m.iso_gap, 0, "{what}: {m:?}");
        assert!(m.force_balance.unwrap() <= 1e-8, "{what}: {m:?}");
    }

    /// A random placement (the core's initializer, which lets spheres overlap) of `n`
    /// monodisperse spheres at packing fraction `phi` in `container`.
    fn random_mono(container: Container, n: usize, phi: f64, seed: u64) -> Packing {
        let scene = Scene {
            n,
            distribution: SizeDistribution::Mono { d: 1.0 },
            container,
            phi,
            seed: Some(seed),
            placement: Placement::Random,
        };
        initial_packing(&scene, seed).unwrap()
    }

    /// [`random_mono`] shrunk until overlap-free (relative clearance 1e-3).
    fn overlap_free_mono(container: Container, n: usize, phi: f64, seed: u64) -> Packing {
        crate::shrink_to_overlap_free(&random_mono(container, n, phi, seed), 1e-3).unwrap()
    }

    fn unit_cube() -> Container {
        Container::periodic_box(&[1.0; 3]).unwrap()
    }

    /// The state after `max_iters` LPs from a random start of `n` monodisperse spheres
    /// (φ 0.3, shrunk until overlap-free) in a periodic unit cube.
    fn after_lps(n: usize, seed: u64, max_iters: u64) -> Growth {
        let start = overlap_free_mono(unit_cube(), n, 0.3, seed);
        let few = Params {
            max_iters,
            ..Params::default()
        };
        let out = run(&start, &few, &mut packbench_core::run::NullObserver).unwrap();
        Growth::new(&out.packing, 0.5, 1e-9).unwrap()
    }

    fn solve(g: &Growth, scope: &LpScope) -> LpStep {
        solve_lp(g, scope, &[0, 1, 2], &Params::default(), None, None)
            .unwrap()
            .unwrap()
    }

    fn assert_same_gamma(step: &LpStep, full: &LpStep) {
        assert!(
            (step.g - full.g).abs() <= 1e-9 * full.g.abs().max(1e-3),
            "{} vs {}",
            step.g,
            full.g
        );
    }

    /// Curved walls (issue 43): in a cylinder periodic along its axis and in a sphere the run
    /// converges to a packing the core finds jammed, with every sphere inside the wall.
    #[test]
    fn jams_inside_a_cylinder_and_a_sphere() {
        for walls in [[-2, 0, 0], [-3, 0, 0]] {
            let container = Container::from_rcp_flags(&[1.0; 3], &walls).unwrap();
            let start = overlap_free_mono(container.clone(), 50, 0.3, 1);
            let out = run(
                &start,
                &Params::default(),
                &mut packbench_core::run::NullObserver,
            )
            .unwrap();
            assert_eq!(out.termination, "converged", "walls {walls:?}");
            let p = &out.packing;
            for (x, dia) in p.positions.chunks_exact(3).zip(&p.diameters) {
                assert!(
                    container.contains(x, 0.5 * dia, 1e-9 * dia),
                    "walls {walls:?}: outside"
                );
            }
            assert_exactly_jammed(p, &format!("walls {walls:?}"));
        }
    }

    /// `pack --method calippso --N 200 --Ndim 3 --seed 5` (issue 43 item 11b): an LP of this
    /// start met a negative pivot in its normal equations and the run failed. It converges, and
    /// the core finds its output exactly jammed.
    #[test]
    fn a_start_with_a_negative_pivot_converges_jammed() {
        use packbench_core::analysis::contact_network;
        let raw = random_mono(unit_cube(), 200, 0.05, 5);
        let start = if contact_network(&raw, 0.0).max_overlap > 1e-12 {
            crate::shrink_to_overlap_free(&raw, 1e-3).unwrap()
        } else {
            raw
        };
        let out = run(
            &start,
            &Params::default(),
            &mut packbench_core::run::NullObserver,
        )
        .unwrap();
        assert_eq!(out.termination, "converged");
        assert_exactly_jammed(&out.packing, "N = 200, seed 5");
    }

    /// The final network is closed to rounding: every contact of the output touches to 1e-13
    /// and no other pair comes within 1e-9, so the core counts the same isostatic network at
    /// any contact tolerance between. The same run left open (`close_network = false`) ends at
    /// the same φ to 1e-12, with contacts open by more than that.
    #[test]
    fn the_final_network_is_closed_to_rounding() {
        use packbench_core::analysis::{AnalysisOptions, analyze, contact_network};
        let start = overlap_free_mono(unit_cube(), 300, 0.5, 2);
        let jam = |close_network| {
            let params = Params {
                close_network,
                ..Params::default()
            };
            let out = run(&start, &params, &mut packbench_core::run::NullObserver).unwrap();
            assert_eq!(out.termination, "converged");
            out
        };
        let (closed, open) = (jam(true), jam(false));
        let gap = closed.extra["closed_gap"].as_f64().unwrap();
        assert!(gap <= CLOSE_TOL, "closed to {gap}");
        assert!(open.extra["closed_gap"].is_null());
        let iso_gap = |p: &Packing, contact_tol| {
            let options = AnalysisOptions {
                contact_tol,
                force_balance: false,
            };
            analyze(p, &options).unwrap().iso_gap
        };
        for tol in [1e-13, 1e-11, 1e-9] {
            assert_eq!(iso_gap(&closed.packing, tol), 0, "contact tolerance {tol}");
        }
        assert!(contact_network(&closed.packing, 0.0).max_overlap <= 1e-13);
        let widest = |p: &Packing| {
            contact_network(p, 1e-9)
                .contacts
                .iter()
                .map(|c| c.gap.abs())
                .fold(0.0, f64::max)
        };
        assert!(widest(&closed.packing) <= 1e-13);
        assert!(widest(&open.packing) > 1e-13, "{}", widest(&open.packing));
        assert!((closed.packing.phi() - open.packing.phi()).abs() <= 1e-12);
        // The reported network is the better balanced of the last LP's and the fine-tuning's.
        let imbalance = |key: &str| closed.extra[key].as_f64().unwrap();
        assert!(imbalance("force_imbalance") <= imbalance("force_imbalance_lp"));
    }

    /// Issue 49: from a random start of 300 spheres (φ 0.5, seed 1) the seed's schedule has
    /// the bound binding and not binding in turn (15 switches); the trust region grows the
    /// bound while it binds and the model agrees, and switches far less (1). Both outputs are
    /// exactly jammed. The LP counts are not compared: the seed schedule's path here is
    /// chaotic in rounding (130 LPs on one machine, 87 on the CI machine, against the trust
    /// region's 100 on both), and at N = 1000 the trust region takes more LPs (BENCHMARKS).
    #[test]
    fn the_trust_region_switches_less_than_the_seed_schedule() {
        let start = overlap_free_mono(unit_cube(), 300, 0.5, 1);
        let [seed, trust] = [BoundSchedule::Seed, BoundSchedule::TrustRegion].map(|schedule| {
            let p = Params {
                bound_schedule: schedule,
                ..Params::default()
            };
            let out = run(&start, &p, &mut packbench_core::run::NullObserver).unwrap();
            assert_eq!(out.termination, "converged", "{schedule:?}");
            assert_exactly_jammed(&out.packing, &format!("{schedule:?}"));
            out.extra["bound_switches"].as_u64().unwrap()
        });
        assert!(trust < seed, "switches: trust region {trust}, seed {seed}");
    }

    /// Issue 49: near jamming, an LP warm-started from the previous LP's duals reaches the
    /// optimum the cold start reaches, in far fewer interior-point iterations. The start is
    /// near-jammed as an ADAM packing is: a jammed packing of 200 spheres with every centre
    /// moved by up to 2·10⁻³ D, shrunk until overlap-free; two LPs bring it to the creep.
    #[test]
    fn a_warm_started_lp_reaches_the_cold_optimum_in_fewer_iterations() {
        use rand::rngs::StdRng;
        use rand::{RngExt, SeedableRng};
        let jammed = run(
            &overlap_free_mono(unit_cube(), 200, 0.55, 4),
            &Params::default(),
            &mut packbench_core::run::NullObserver,
        )
        .unwrap()
        .packing;
        let mut moved = jammed.clone();
        let step = 2e-3 * jammed.diameters[0];
        let mut rng = StdRng::seed_from_u64(4);
        moved
            .positions
            .iter_mut()
            .for_each(|x| *x += rng.random_range(-step..step));
        let start = crate::shrink_to_overlap_free(&moved, 1e-3).unwrap();
        let mut g = Growth::new(&start, 0.5, 1e-9).unwrap();
        let r = 0.5 * g.t * g.diameters[0];
        let scope = LpScope {
            cutoff_gap: 0.5 * r,
            s_bound: Some(0.01 * r),
            excess_cap: None,
            working_gap: LAZY_GAP,
        };
        let p = Params::default();
        let lp = |g: &Growth, warm: Option<&LpStep>| {
            solve_lp(g, &scope, &[0, 1, 2], &p, None, warm)
                .unwrap()
                .unwrap()
        };
        let mut last = lp(&g, None);
        for _ in 0..2 {
            g.x.iter_mut().zip(&last.s).for_each(|(x, s)| *x += s);
            g.t *= (1.0 + last.g).sqrt();
            last = lp(&g, Some(&last));
        }
        g.x.iter_mut().zip(&last.s).for_each(|(x, s)| *x += s);
        g.t *= (1.0 + last.g).sqrt();
        let (cold, warm) = (lp(&g, None), lp(&g, Some(&last)));
        assert_same_gamma(&warm, &cold);
        assert!(
            f64::from(warm.iterations) <= 0.7 * f64::from(cold.iterations),
            "iterations: warm {}, cold {}",
            warm.iterations,
            cold.iterations
        );
    }

    /// Leaving out rows that cannot bind, and a Γ cap that does not bind, change no LP optimum.
    #[test]
    fn dropping_rows_that_cannot_bind_keeps_the_lp_optimum() {
        // A few LPs in, near jamming, where the cap drops most of the shell.
        let g = after_lps(40, 7, 8);
        let r = 0.5 * g.diameters[0];
        let every_row = LpScope {
            cutoff_gap: r,
            s_bound: Some(0.02 * r),
            excess_cap: None,
            working_gap: f64::INFINITY,
        };
        let full = solve(&g, &every_row);
        let capped = solve(
            &g,
            &LpScope {
                excess_cap: Some(4.0 * full.g),
                ..every_row
            },
        );
        assert!(capped.links.len() < full.links.len());
        assert_same_gamma(&capped, &full);
    }

    /// Lazy rows: an LP started from the nearest rows, with the rows its solutions violate
    /// added, reaches the optimum of the LP over every row, in the wide first shell (ℓ0 = 4R,
    /// free to move far) as near jamming.
    #[test]
    fn lazy_rows_reach_the_optimum_of_every_row() {
        // After 14 LPs (√Γ − 1 ≈ 5e-2, where the rows must be added in several rounds) and
        // after 25 (√Γ − 1 ≈ 2e-3).
        for max_iters in [14, 25] {
            let g = after_lps(60, 3, max_iters);
            let r = 0.5 * g.diameters[0];
            let every_row = LpScope {
                cutoff_gap: 2.0 * r,
                s_bound: Some(2.0 * r / (4.0 * 3f64.sqrt())),
                excess_cap: None,
                working_gap: f64::INFINITY,
            };
            let full = solve(&g, &every_row);
            let lazy = solve(
                &g,
                &LpScope {
                    working_gap: LAZY_GAP,
                    ..every_row
                },
            );
            assert!(lazy.links.len() < full.links.len());
            assert_same_gamma(&lazy, &full);
            // The lazy solution satisfies every row of the full LP.
            let rows = full
                .keys
                .iter()
                .zip(&full.links)
                .map(|(&k, &l)| Row::new(k, l, g.t, r));
            let u: Vec<f64> = lazy.s.iter().map(|v| v / r).collect();
            let worst = rows
                .map(|row| row.slack(&u, lazy.g, 3))
                .fold(f64::INFINITY, f64::min);
            assert!(worst >= -1e-9, "a left-out row is violated by {worst:e}");
        }
    }
}
