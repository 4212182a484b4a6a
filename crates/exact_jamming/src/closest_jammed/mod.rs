//! The closest-jammed integrator (Baranau & Tallarek 2014, Appendix C, eqns 1–4).
//!
//! Diameters grow as `t·D_i`. Bonded pairs stay exactly in contact, and the velocities are the
//! minimum-norm solution `y = A⁺b` of `n_k·(y_j − y_i) = D_k` for every bond k (eqn 1 divided by
//! |x_ij| = D_k t; eqn 2). Eqn 3 is integrated with straight steps that end exactly at the next
//! new contact (the pair-gap root, [`crate::growth::contact_time`]) or after a relative growth
//! `max_growth_step`; after each step the bonds are projected back onto contact (a
//! minimum-norm Newton correction), which removes the second-order drift of straight steps.
//!
//! A new bond whose row is independent of the others joins the factorised basis. A dependent
//! bond either agrees with the others (a redundant contact, as in a crystal) or makes `A y = b`
//! unsolvable. In that case the left null vector `f` of A (`Aᵀf = 0`, normalised to `fᵀb > 0`) is
//! the set of contact forces: if every `f_k ≥ 0` no growth is possible (Farkas), the packing is
//! jammed, and a last projection in positions *and* `t` makes every bond touch exactly. If some
//! `f_k < 0` that bond wants to open: one such bond, chosen by [`ReleaseRule`], is released and
//! the growth continues (counted in `extra.bonds_released`). The equality form never opens
//! bonds otherwise; the QP form ([`qp_form`]) does.
//!
//! Linear algebra per step (`A Aᵀ λ = b`, `y = Aᵀλ`): consecutive steps differ by a small motion
//! and one bond, so the velocities and the projection are solved by conjugate gradients
//! preconditioned with the sparse Cholesky factor of an earlier step, bordered with the rows of
//! the bonds added since (`min_norm::Preconditioner`), and refactorised (symbolic pattern
//! reused, see the `min_norm` module) once a solve needs more than `refactor_iterations`, after
//! a bond is released, and when the bordering is full. With `factor_updates` the factor is kept
//! by CHOLMOD row updates instead of a border, and a release needs no refactorisation. So the
//! decisions that depend on signs or near-zero values at a new bond (its dependence and
//! residual, the forces) are solved with a preconditioner of their own basis a few steps'
//! motion away, where the preconditioned matrix is nearly the identity and the forward error is
//! that of a direct solve; the forces at a fold and the final projection use an exact factor.

use std::cell::RefCell;
use std::rc::Rc;
use std::time::Instant;

use packbench_core::Packing;
use packbench_core::run::{Observer, Outcome, Progress};
use rustc_hash::FxHashSet;
use serde_json::json;

use crate::contacts::Key;
use crate::error::JammingError;
use crate::growth::Growth;
use crate::min_norm::{CgStats, Solver};
use crate::verdict::{checked_termination, stalled_termination};

mod bonds;
mod cycles;
mod integrator;
mod params;
pub mod qp_form;

use bonds::bond_count;

use integrator::{GrowthProgress, Integrator, STALL_GROWTH, STALL_STEPS, StepCounts, StepOutcome};
pub use params::{Params, ReleaseRule};

/// Drives `start` to its closest jammed configuration (Baranau & Tallarek 2014 App. C).
///
/// Returns the jammed packing (termination `jammed`), or the packing reached when `max_steps`,
/// an interrupt or a run without progress stopped it (`max_steps`, `interrupted`, `stalled`:
/// `t` grew by no more than 1e-14 relative in 10 000 steps, `extra.stall` says so; every 500
/// steps without growth the bond set is first chosen afresh, [`cycles`]). `extra`
/// holds `bonds`, `bonds_redundant`, `bonds_released`, `non_rattler_bonds`, `n_dof`, `rattlers`,
/// `total_velocity_max` (eqn 12), `min_force_ratio`, `final_bond_gap`, `growth_factor` and
/// `step_counts` (what the steps did: contact events, capped steps, admissions, releases at
/// admission and at folds, numeric and symbolic factorisations, conjugate-gradient solves).
///
/// # Errors
/// [`JammingError::InvalidPacking`] and [`JammingError::Overlap`] for a bad start,
/// [`JammingError::Parameter`] for bad options, [`JammingError::Solver`] when the bond matrix
/// cannot be factorised.
// Long because the integrator's loop (steps, stalls, cycles, the verdict, snapshots and
// interrupts) keeps one state; its steps are in integrator.rs, bonds.rs and cycles.rs.
pub fn run(
    start: &Packing,
    params: &Params,
    observer: &mut dyn Observer,
) -> Result<Outcome, JammingError> {
    params.validate()?;
    let clock = Instant::now();
    let phi0 = start.phi();
    let g = Growth::new(start, params.skin, params.overlap_tol)?;
    let mut it = Integrator {
        g,
        p: params,
        basis: Vec::new(),
        redundant: Vec::new(),
        bonded: FxHashSet::default(),
        released: 0,
        counts: StepCounts::default(),
        solver: Solver::new(params.dense_max_bonds),
        cached: RefCell::new(None),
        preconditioner: RefCell::new(None),
        cg: Rc::new(CgStats::default()),
        total_velocity: 0.0,
        next_velocities: None,
        pending: Vec::new(),
        admitting: None,
        zero_step_event: None,
    };
    // Contacts of the starting packing, closest first.
    let mut pending: Vec<(f64, Key)> =
        it.g.candidates
            .keys
            .iter()
            .map(|k| (it.g.link(k).rel_gap(1.0), *k))
            .filter(|(gap, _)| *gap <= params.contact_tol)
            .collect();
    pending.sort_by(|a, b| b.0.total_cmp(&a.0));
    it.pending = pending.into_iter().map(|(_, k)| k).collect();

    let mut trace = Vec::new();
    let mut steps = 0u64;
    let mut last_report = Instant::now();
    let mut jam_forces: Option<(Key, Vec<f64>)> = None;
    let mut progress = GrowthProgress { t: it.g.t, step: 0 };
    let mut cycle_left_at = 0;
    let termination = loop {
        // A run stops only between steps, with every contact admitted: the contact that ended
        // the last step may overlap by up to `EVENT_OVERSHOOT` until its admission closes it.
        // Before the first step no contact overshoots, and an interrupt is heeded between the
        // admissions of the start's contacts (at N = 10⁴ from a start at contact they take
        // many minutes).
        if (it.pending.is_empty() || steps == 0) && observer.should_stop() {
            break "interrupted";
        }
        if it.pending.is_empty() {
            if steps >= params.max_steps {
                break "max_steps";
            }
            if progress.stalled(it.g.t, steps) {
                break "stalled";
            }
            if progress.cycling(steps, cycle_left_at) {
                cycle_left_at = steps;
                it.leave_cycle()?;
            }
        }
        match it.step()? {
            StepOutcome::Jammed(key, forces) => {
                jam_forces = Some((key, forces));
                break "jammed";
            }
            StepOutcome::Admitted | StepOutcome::BondReleased => {}
            StepOutcome::Advanced => {
                steps += 1;
                if params.save_interval > 0 && steps.is_multiple_of(params.save_interval) {
                    observer.snapshot(steps, &it.g.packing());
                }
                if last_report.elapsed().as_secs_f64() > 0.25 {
                    last_report = Instant::now();
                    let phi = it.g.phi(phi0);
                    let (non_rattler_bonds, n_dof, _) = bond_count(&it.g, &it.basis, &it.redundant);
                    observer.progress(&Progress {
                        step: steps,
                        phi,
                        value: it.basis.len() as f64,
                        label: "bonds",
                        fraction: None,
                        more: vec![
                            ("non_rattler_bonds", non_rattler_bonds as f64),
                            ("n_dof", n_dof as f64),
                        ],
                    });
                    trace.push(it.trace_row(steps, clock.elapsed().as_secs_f64(), phi));
                }
            }
        }
    };
    let mut final_gap = f64::NAN;
    let mut min_force_ratio = f64::NAN;
    if let Some((key, forces)) = &jam_forces {
        final_gap = it.close_jammed(key, forces);
        min_force_ratio = bonds::min_force_ratio(forces);
    } else if !it.basis.is_empty() {
        // A stopped run: bonds admitted since the last step's projection (they may overlap by
        // up to `EVENT_OVERSHOOT`) are closed too, so the packing returned is overlap-free.
        // A failed projection, or one that jumped past the candidate skin, leaves the
        // configuration as it was.
        let before = it.g.snapshot();
        if it.project_exact(None).is_err() || !it.g.candidates_cover_contacts() {
            it.g.restore(&before);
        }
    }
    let phi = it.g.phi(phi0);
    trace.push(it.trace_row(steps, clock.elapsed().as_secs_f64(), phi));
    it.counts.factorisations = it.solver.numeric.get();
    it.counts.patterns = it.solver.symbolic.get();
    it.counts.dense_fallbacks = it.solver.dense_fallbacks.get();
    it.counts.factor_row_updates = it.solver.row_updates.get();
    it.counts.factorisation_seconds = it.solver.seconds.get();
    it.counts.cg_solves = it.cg.solves.get();
    it.counts.cg_iterations = it.cg.iterations.get();
    it.counts.cg_failures = it.cg.failures.get();
    let (non_rattler_bonds, n_dof, n_rattlers) = bond_count(&it.g, &it.basis, &it.redundant);
    let mut extra = serde_json::Map::new();
    for (k, v) in [
        ("bonds", json!(it.basis.len() + it.redundant.len())),
        ("bonds_redundant", json!(it.redundant.len())),
        ("bonds_released", json!(it.released)),
        ("non_rattler_bonds", json!(non_rattler_bonds)),
        ("n_dof", json!(n_dof)),
        ("rattlers", json!(n_rattlers)),
        ("total_velocity_max", json!(it.total_velocity)),
        ("min_force_ratio", json!(finite_or_null(min_force_ratio))),
        ("final_bond_gap", json!(finite_or_null(final_gap))),
        ("growth_factor", json!(it.g.t)),
        ("step_counts", json!(it.counts)),
        (
            "stall",
            match termination {
                "stalled" => json!(format!(
                    "the growth factor grew by less than {STALL_GROWTH:e} relative in the last {STALL_STEPS} steps ({} bonds, {non_rattler_bonds} among non-rattlers, n_dof {n_dof})",
                    it.basis.len() + it.redundant.len()
                )),
                _ => serde_json::Value::Null,
            },
        ),
    ] {
        extra.insert(k.into(), v);
    }
    let packing = it.g.packing();
    let termination = match termination {
        "stalled" => stalled_termination(&packing, &mut extra)?,
        _ => termination,
    };
    let termination = checked_termination(termination, jam_forces.is_some(), &packing, &mut extra)?;
    Ok(Outcome {
        packing,
        steps,
        termination,
        trace,
        extra,
    })
}

fn finite_or_null(v: f64) -> serde_json::Value {
    if v.is_finite() {
        json!(v)
    } else {
        serde_json::Value::Null
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Growth resets the count; growth below `STALL_GROWTH` does not; the run stalls exactly
    /// `STALL_STEPS` steps after the last real growth.
    #[test]
    fn a_run_stalls_after_stall_steps_without_growth() {
        let mut p = GrowthProgress { t: 1.0, step: 0 };
        assert!(!p.stalled(1.5, 10));
        let flat = 1.5 * (1.0 + STALL_GROWTH / 2.0);
        assert!(!p.stalled(flat, 10 + STALL_STEPS - 1));
        assert!(p.stalled(flat, 10 + STALL_STEPS));
        assert!(!p.stalled(1.6, 10 + STALL_STEPS + 1));
        assert!(!p.stalled(1.6, 10 + 2 * STALL_STEPS));
        assert!(p.stalled(1.6, 11 + 2 * STALL_STEPS));
    }
}
