//! CALiPPSO: jamming by iterated linear programming (CALiPPSO.jl).
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
//! duals (`warm_start`): 9–13 interior-point iterations per LP instead of 20.
//! After convergence the final network's contacts are closed exactly by a Newton projection
//! ([`close_network`]), which the LPs leave open by up to `tol_s`.
//!
//! Cut-off and bound schedule (in units of the mean radius R): while √Γ−1 ≥ 5e-4 the cut-off
//! gap is `(ℓ0 − 2)R` and `s_bound = gap/(4√d)`; below 5e-4 the gap is at most `R` and
//! `s_bound ≤ 0.1R`; below 1e-5 the gap is at most `R/2` and `s_bound = s_bound_final·R`.
//! With `bound_schedule = trust-region` the cut-off follows the same schedule and the bound is
//! a trust region ([`BoundSchedule::TrustRegion`]).
//!
//! Where each part lives: `params.rs` (the options), `lp.rs` (one LP: its rows, lazy rows and
//! warm start), `iteration.rs` (one iteration: the schedule, the LP, the update, what it
//! records; and the fine-tuning LP), `network.rs` (the duals' contact network and its exact
//! closing), `trust_region.rs`, `held_coordinates.rs`, `curved_walls.rs`, and [`run`], the loop
//! over iterations, here.

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
mod iteration;
mod lp;
mod network;
mod newton_finish;
mod params;
#[cfg(test)]
mod tests;
mod trust_region;

pub use params::{BoundSchedule, Params};

use iteration::{Iteration, LpRecord};
use network::close_network;
use newton_finish::{FinishSchedule, Finished};

/// Jams `start` by CALiPPSO's iterated linear programming (CALiPPSO.jl).
///
/// Terminations: `converged` (√Γ−1 < tol_gamma and non-rattler max |s| < tol_s),
/// `max_iters`, `interrupted`. `extra` holds `lp_count`, `sqrt_gamma_minus_1`, `max_s`,
/// `contacts` and `n_dof` of the dual network, `rattlers`, `force_imbalance_lp` (the last LP's)
/// and `force_imbalance` (the smaller of it and the fine-tuning LP's), `fine_tuned` (whether
/// the fine-tuning LP's network was the better balanced), `fine_tuning_skipped` (present when
/// that LP failed: why; the fine-tuning LP is never handed to clarabel), `max_overlap` of the final check,
/// `lp_iterations` (interior-point iterations over all LPs), `lp_solves` (one per LP plus one
/// per round of lazy rows), `lp_unconverged` (solves that stopped short of `lp_tol`; their
/// last iterate is used), `lp_clarabel` (solves handed to clarabel because the normal
/// equations had no factor), `wall_limited_lps` (LPs whose Γ a curved wall capped),
/// `overlap_repairs` and `largest_repaired_overlap` (checks during the run that found overlaps
/// beyond `tol_overlap` and shrank the diameters to clear them), `closed_gap` (the largest
/// relative gap of the final network after [`close_network`]; null when it did not run or was
/// undone) and `closure_undone_overlap` (the overlap for which a closure was undone, else
/// null). The trace has one row per LP: `sqrt_gamma_minus_1`, `max_s`,
/// `contacts`, `n_dof`, `contacts_changed` (contacts of the dual network made or lost since the
/// previous LP) and `rattlers`.
///
/// # Errors
/// [`JammingError::InvalidPacking`] and [`JammingError::Overlap`] for a bad start,
/// [`JammingError::OverlapDuringRun`] for an overlap the final check finds,
/// [`JammingError::Parameter`] for bad options, [`JammingError::Solver`] when an LP's normal
/// equations cannot be factorised.
// Long because the LP iterations, their bound schedule, the stop tests and the trace form one loop
// over the same state; the named steps are in iteration.rs and lp.rs.
pub fn run(
    start: &Packing,
    params: &Params,
    observer: &mut dyn Observer,
) -> Result<Outcome, JammingError> {
    params.validate()?;
    let clock = Instant::now();
    let phi0 = start.phi();
    let mut it = Iteration::new(Growth::new(start, 0.5, params.tol_overlap)?, params);
    let stop = observer.stop_flag();
    let mut trace = Vec::new();
    // The finish closes its network; a run asked to leave the LPs' network open runs none.
    let below = if params.close_network {
        params.newton_finish_below
    } else {
        0.0
    };
    let mut schedule = FinishSchedule::new(below);
    let mut finished: Option<Finished> = None;
    let termination = loop {
        if observer.should_stop() {
            break "interrupted";
        }
        if it.lps >= params.max_iters {
            break "max_iters";
        }
        let Some(lp) = it.lp(stop)? else {
            break "interrupted";
        };
        let phi = it.g.phi(phi0);
        report(observer, &it, &lp, phi, params.max_iters);
        trace.push(trace_row(&it, &lp, phi, clock.elapsed().as_secs_f64()));
        if params.save_interval > 0 && it.lps.is_multiple_of(params.save_interval) {
            observer.snapshot(it.lps, &it.g.packing());
        }
        if it.converged() {
            break "converged";
        }
        if let Some((_, net)) = &it.last
            && let Some(done) = schedule.try_after(&mut it.g, net, it.sqrt_gamma - 1.0)
        {
            finished = Some(done);
            break "converged";
        }
    };
    let mut extra = serde_json::Map::new();
    extra.insert("closure_undone_overlap".into(), json!(null));
    extra.insert("newton_finish".into(), schedule.to_json(finished.as_ref()));
    let closed_gap = match &it.last {
        // The Newton finish has closed its own network.
        _ if finished.is_some() => finished.as_ref().map(|done| done.gap),
        Some((_, net)) if params.close_network && termination == "converged" => {
            let unclosed = (it.g.x.clone(), it.g.t);
            let gap = close_network(&mut it.g, net);
            // The closure keeps n_dof contacts; moving them shut can push a weak contact it
            // left out into overlap (3D mono N = 4000, ADAM start seed 1: 2.2e-8, and the run
            // failed its final check). Such a closure is undone: the converged packing stands,
            // its weakest contacts open by up to about tol_s.
            let (overlap, _, _) = worst_overlap(&it.g);
            if gap.is_some() && overlap > params.tol_overlap {
                extra.insert("closure_undone_overlap".into(), json!(overlap));
                (it.g.x, it.g.t) = unclosed;
                None
            } else {
                gap
            }
        }
        _ => None,
    };
    extra.insert("closed_gap".into(), json!(closed_gap));
    match &finished {
        Some(done) => it.finished_network(done, &mut extra),
        None => it.final_network(stop, &mut extra),
    }
    let max_overlap = check_overlaps(&it.g, params.tol_overlap, it.lps)?;
    extra.insert("lp_count".into(), json!(it.lps));
    it.counts.insert_into(&mut extra);
    extra.insert("sqrt_gamma_minus_1".into(), json!(it.sqrt_gamma - 1.0));
    extra.insert(
        "max_s".into(),
        if it.max_s_active.is_finite() {
            json!(it.max_s_active)
        } else {
            json!(null)
        },
    );
    extra.insert("max_overlap".into(), json!(max_overlap));
    let packing = it.g.packing();
    let termination = checked_termination(
        termination,
        termination == "converged",
        &packing,
        &mut extra,
    )?;
    Ok(Outcome {
        packing,
        steps: it.lps,
        termination,
        trace,
        extra,
    })
}

/// The progress line of one LP.
fn report(observer: &mut dyn Observer, it: &Iteration, lp: &LpRecord, phi: f64, max_iters: u64) {
    observer.progress(&Progress {
        step: it.lps,
        phi,
        value: it.sqrt_gamma - 1.0,
        label: "sqrt(Γ)−1",
        fraction: Some(it.lps as f64 / max_iters as f64),
        more: vec![
            ("max_s_over_d", it.max_s_active),
            ("contacts_changed", lp.changed as f64),
            ("ipm_iterations", f64::from(lp.ipm_iterations)),
        ],
    });
}

/// The trace row of one LP (the columns of [`run`]'s doc).
fn trace_row(it: &Iteration, lp: &LpRecord, phi: f64, time_s: f64) -> TraceRow {
    TraceRow {
        step: it.lps,
        time_s,
        phi,
        values: vec![
            ("sqrt_gamma_minus_1".into(), it.sqrt_gamma - 1.0),
            ("max_s".into(), it.max_s_active),
            ("contacts".into(), lp.contacts as f64),
            ("n_dof".into(), lp.n_dof as f64),
            ("contacts_changed".into(), lp.changed as f64),
            ("rattlers".into(), lp.rattlers as f64),
            ("bound_over_r".into(), lp.bound_over_r),
            ("max_s_over_bound".into(), lp.max_s_over_bound),
            ("binds".into(), lp.binds),
            ("model_agreement".into(), lp.agreement),
            ("ipm_iterations".into(), f64::from(lp.ipm_iterations)),
        ],
    }
}

/// The largest relative overlap `1 − r/σ` over every pair and wall, and its pair.
fn worst_overlap(g: &Growth) -> (f64, usize, usize) {
    let skin = 1e-3 * g.t * g.diameters.iter().fold(0.0f64, |m, &v| m.max(v));
    let cands = Candidates::build(&g.container, &g.x, &g.diameters, g.t, skin);
    contacts::worst_overlap(&g.container, &g.x, &g.diameters, g.t, &cands.keys)
}

/// CALiPPSO.jl's overlap check: the largest relative overlap over all near pairs and walls; an
/// error when it exceeds `tol`.
fn check_overlaps(g: &Growth, tol: f64, iteration: u64) -> Result<f64, JammingError> {
    let (ov, i, j) = worst_overlap(g);
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
