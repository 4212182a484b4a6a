//! The closest-jammed growth in its inequality form: each step solves, with clarabel,
//!
//! `min ‖y‖²  subject to  n_c·(y_j − y_i) ≥ D_c  for every contact c`
//!
//! (Baranau & Tallarek 2014 eqn 1 as an inequality), so a contact opens when steepest descent in the
//! "maximum density" landscape (Baranau & Tallarek 2014 App. B) says so, instead of staying bonded as in
//! [`crate::closest_jammed`]. Contacts whose constraint is active (positive dual) are the
//! bonds; they are projected back onto contact after each straight step, which ends at the next
//! new contact or after a relative growth `max_growth_step`. The packing is jammed when the QP
//! is infeasible: clarabel's certificate `z ≥ 0` with `Aᵀz = 0`, `zᵀb > 0` are the contact
//! forces, and a last projection in positions and `t` closes every force-bearing contact.
//!
//! The same steepest descent, solved as an active set on the integrator's sparse factor (every
//! bond whose multiplier turns tensile opens), is [`crate::closest_jammed`] with
//! `open_tensile_bonds`; it takes tens of times fewer steps, and the tests check that both come
//! back to the same jammed packing next to jamming.

use std::collections::HashSet;
use std::time::Instant;

use packbench_core::Packing;
use packbench_core::run::{Observer, Outcome, Progress, TraceRow};
use serde::{Deserialize, Serialize};
use serde_json::json;

use super::bonds::bond_count;
use crate::conic::{Program, Solution};
use crate::contacts::Key;
use crate::error::JammingError;
use crate::growth::{Growth, contact_time};
use crate::min_norm::Solver;
use crate::projection::project;
use crate::verdict::checked_termination;

/// Options of the QP form of the closest-jammed growth.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default)]
pub struct Params {
    /// Largest number of steps (one QP each).
    pub max_steps: u64,
    /// Largest relative growth `Δt/t` of one straight step between contacts.
    pub max_growth_step: f64,
    /// Candidate skin, in mean diameters.
    pub skin: f64,
    /// Pairs with relative gap `r/σ − 1` at most this are contacts (constrained in the QP).
    pub contact_tol: f64,
    /// Duals above `active_tol · max dual` mark a contact as an active bond.
    pub active_tol: f64,
    /// Tolerance given to clarabel.
    pub qp_tol: f64,
    /// Projection stops when every bond's relative gap is below this.
    pub projection_tol: f64,
    /// Bond counts up to this use the dense SVD pseudoinverse in projections.
    pub dense_max_bonds: usize,
    /// Largest relative overlap tolerated in the starting packing.
    pub overlap_tol: f64,
    /// Pass a snapshot to the observer every this many steps (0: never).
    pub save_interval: u64,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            max_steps: 1_000_000,
            max_growth_step: 1e-2,
            skin: 0.3,
            contact_tol: 1e-9,
            active_tol: 1e-7,
            qp_tol: 1e-11,
            projection_tol: 1e-14,
            dense_max_bonds: 48,
            overlap_tol: 1e-9,
            save_interval: 0,
        }
    }
}

impl Params {
    /// Checks every parameter; the error names the one out of range.
    pub fn validate(&self) -> Result<(), JammingError> {
        for (name, v) in [
            ("max_growth_step", self.max_growth_step),
            ("skin", self.skin),
            ("contact_tol", self.contact_tol),
            ("active_tol", self.active_tol),
            ("qp_tol", self.qp_tol),
            ("projection_tol", self.projection_tol),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(JammingError::Parameter(format!(
                    "{name} = {v} must be a positive number"
                )));
            }
        }
        if !(self.overlap_tol.is_finite() && self.overlap_tol >= 0.0) {
            return Err(JammingError::Parameter(format!(
                "overlap_tol = {} must be a non-negative number",
                self.overlap_tol
            )));
        }
        Ok(())
    }
}

/// Baranau & Tallarek 2014 App. B's steepest descent over `contacts`: `min ½‖y‖²` subject to
/// `n_c·(y_j − y_i) ≥ D_c`, solved by clarabel to `tol`; and the contacts it holds, those whose
/// dual exceeds `active_tol` times the largest, with their duals, in the order of `contacts`
/// (when the program is infeasible: the certificate's support and its forces). Errors:
/// clarabel's.
pub(super) fn steepest_descent(
    g: &Growth,
    contacts: &[Key],
    tol: f64,
    active_tol: f64,
) -> Result<(Solution, Vec<(Key, f64)>), String> {
    let (n, d) = (g.n, g.d);
    let mut qp = Program::new(vec![0.0; n * d], vec![1.0; n * d]);
    for l in g.links(contacts) {
        qp.at_least(l.terms(d), l.size);
    }
    let sol = qp.solve(tol, 200)?;
    let zmax = sol.z.iter().fold(0.0f64, |m, &z| m.max(z));
    let held = contacts
        .iter()
        .zip(&sol.z)
        .filter(|(_, z)| **z > active_tol * zmax)
        .map(|(k, z)| (*k, *z))
        .collect();
    Ok((sol, held))
}

/// Drives `start` to a jammed packing by the QP form of the closest-jammed growth.
///
/// Terminations: `jammed` (checked by the core's analysis, else `not_jammed`), `max_steps`,
/// `interrupted`. `extra` holds `bonds_opened` (active bonds whose constraint became
/// inactive), `bonds`, `non_rattler_bonds`, `n_dof`, `rattlers`, `qp_count`,
/// `projections_skipped` (steps whose held bonds no correction could close; see the loop) and
/// `final_bond_gap`.
///
/// # Errors
/// [`JammingError::InvalidPacking`] and [`JammingError::Overlap`] for a bad start,
/// [`JammingError::Parameter`] for bad options, [`JammingError::Solver`] when clarabel, a
/// factorisation or the final projection fails.
// Long because each step assembles and solves one QP (clarabel) over every contact and reads its
// duals back into the same bond bookkeeping; splitting it waits for the fix of its cycling.
pub fn run(
    start: &Packing,
    params: &Params,
    observer: &mut dyn Observer,
) -> Result<Outcome, JammingError> {
    params.validate()?;
    let clock = Instant::now();
    let phi0 = start.phi();
    let mut g = Growth::new(start, params.skin, params.overlap_tol)?;
    let solver = Solver::new(params.dense_max_bonds);
    let d = g.d;
    let mut trace = Vec::new();
    let mut steps = 0u64;
    let mut opened = 0u64;
    let mut projections_skipped = 0u64;
    let mut active: Vec<Key> = Vec::new();
    let mut last_report = Instant::now();
    let mut jam: Option<(Vec<Key>, Vec<f64>)> = None;
    let termination;
    loop {
        if observer.should_stop() {
            termination = "interrupted";
            break;
        }
        if steps >= params.max_steps {
            termination = "max_steps";
            break;
        }
        // Contacts: candidates at contact within the tolerance.
        let contacts: Vec<Key> = g
            .candidates
            .keys
            .iter()
            .filter(|k| g.link(k).rel_gap(g.t) <= params.contact_tol)
            .copied()
            .collect();
        let (sol, held) = steepest_descent(&g, &contacts, params.qp_tol, params.active_tol)
            .map_err(|e| JammingError::Solver(format!("closest-jammed QP: {e}")))?;
        steps += 1;
        if sol.infeasible {
            // The certificate's support and its forces, in the order of `contacts`.
            jam = Some(held.into_iter().unzip());
            termination = "jammed";
            break;
        }
        let now_active: Vec<Key> = held.into_iter().map(|(k, _)| k).collect();
        opened += active.iter().filter(|k| !now_active.contains(k)).count() as u64;
        active = now_active;
        // Project the active bonds onto contact, then take the straight step.
        let alinks = g.links(&active);
        if !alinks.is_empty() {
            let mn = solver
                .factor(&active, &alinks, &g, [].iter())
                .map_err(JammingError::Solver)?;
            let before = g.snapshot();
            match project(
                &mut g,
                &active,
                Some((&alinks, &mn)),
                None,
                params.projection_tol,
                &solver,
            ) {
                Ok(_) => {}
                // A held set dependent more than once (a crystallising 2D patch) can have gaps
                // no correction closes; the step goes on from the unprojected configuration,
                // whose bonds are within the contact tolerance, and the next QP sees them.
                Err(JammingError::Solver(_)) => {
                    g.restore(&before);
                    projections_skipped += 1;
                }
                Err(e) => return Err(e),
            }
        }
        let y = &sol.x;
        let vmax = y
            .chunks_exact(d)
            .map(|v| v.iter().map(|a| a * a).sum::<f64>().sqrt())
            .fold(0.0, f64::max);
        let mut tau = (params.max_growth_step * g.t).min(g.safe_step(vmax));
        // Every pair the QP did not constrain is checked, including one that the projection
        // has just moved to contact: it touches now (τ = 0) if it closes, and joins the next QP.
        let constrained: HashSet<Key> = contacts.iter().copied().collect();
        for (_, key) in g.candidates.within(tau * g.shrink_rate(vmax)) {
            if constrained.contains(key) {
                continue;
            }
            let l = g.link(key);
            if let Some(tc) = contact_time(&l, y, g.t, d) {
                tau = tau.min(tc);
            }
        }
        g.advance(y, tau);
        g.refresh();
        if params.save_interval > 0 && steps.is_multiple_of(params.save_interval) {
            observer.snapshot(steps, &g.packing());
        }
        if last_report.elapsed().as_secs_f64() > 0.25 {
            last_report = Instant::now();
            let phi = g.phi(phi0);
            observer.progress(&Progress {
                step: steps,
                phi,
                value: active.len() as f64,
                label: "bonds",
                fraction: None,
                more: Vec::new(),
            });
            trace.push(TraceRow {
                step: steps,
                time_s: clock.elapsed().as_secs_f64(),
                phi,
                values: vec![
                    ("bonds".into(), active.len() as f64),
                    ("bonds_opened".into(), opened as f64),
                ],
            });
        }
    }
    let mut final_gap = f64::NAN;
    let mut bonds = active.clone();
    if let Some((keys, forces)) = &jam {
        // The certificate's support is minimally dependent: drop one force-bearing bond from the
        // basis and let the projection close it through the growth factor.
        if let Some((last, rest)) = keys.split_last() {
            let links = g.links(rest);
            let mn = solver
                .factor(rest, &links, &g, [].iter())
                .map_err(JammingError::Solver)?;
            final_gap = project(
                &mut g,
                rest,
                Some((&links, &mn)),
                Some((last, forces)),
                params.projection_tol,
                &solver,
            )?;
        }
        bonds = keys.clone();
    }
    let phi = g.phi(phi0);
    trace.push(TraceRow {
        step: steps,
        time_s: clock.elapsed().as_secs_f64(),
        phi,
        values: vec![
            ("bonds".into(), bonds.len() as f64),
            ("bonds_opened".into(), opened as f64),
        ],
    });
    let (non_rattler_bonds, n_dof, n_rattlers) = bond_count(&g, &bonds, &[]);
    let mut extra = serde_json::Map::new();
    for (k, v) in [
        ("bonds_opened", json!(opened)),
        ("bonds", json!(bonds.len())),
        ("non_rattler_bonds", json!(non_rattler_bonds)),
        ("n_dof", json!(n_dof)),
        ("rattlers", json!(n_rattlers)),
        ("qp_count", json!(steps)),
        ("projections_skipped", json!(projections_skipped)),
        (
            "final_bond_gap",
            if final_gap.is_finite() {
                json!(final_gap)
            } else {
                json!(null)
            },
        ),
        ("growth_factor", json!(g.t)),
    ] {
        extra.insert(k.into(), v);
    }
    let packing = g.packing();
    let termination =
        checked_termination(termination, termination == "jammed", &packing, &mut extra)?;
    Ok(Outcome {
        packing,
        steps,
        termination,
        trace,
        extra,
    })
}
