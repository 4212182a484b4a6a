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
//!
//! Where each part lives: `params.rs` (the options), `lp.rs` (one LP: its rows, lazy rows and
//! warm start), `network.rs` (the duals' contact network and its exact closing),
//! `trust_region.rs`, `held_coordinates.rs`, `curved_walls.rs`, and the iteration itself,
//! [`run`], here.

use std::time::Instant;

use packbench_core::Packing;
use packbench_core::run::{Observer, Outcome, Progress, TraceRow};
use serde_json::json;

use crate::contacts::{self, Candidates};
use crate::error::JammingError;
use crate::growth::Growth;
use crate::verdict::checked_termination;

mod curved_walls;
mod held_coordinates;
mod lp;
mod network;
mod params;
#[cfg(test)]
mod tests;
mod trust_region;

pub use params::{BoundSchedule, Params};

use curved_walls::curved_wall_gamma;
use held_coordinates::held_coordinates;
use lp::{LAZY_GAP, LpScope, LpStep, WARM_MAX_CHANGED, WARM_MIN_EXCESS, solve_lp};
use network::{Network, close_network, network};
use trust_region::{model_agreement, trust_update};

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
