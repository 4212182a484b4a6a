//! The closest-jammed growth in its inequality form: each step solves
//!
//! `min ‖y‖²  subject to  n_c·(y_j − y_i) ≥ D_c  for every contact c`
//!
//! (Baranau & Tallarek 2014 eqn 1 as an inequality), so a contact opens when steepest descent in the
//! "maximum density" landscape (Baranau & Tallarek 2014 App. B) says so, instead of staying bonded as in
//! [`crate::closest_jammed`]. Contacts whose constraint is active (positive dual) are the
//! bonds; those at contact are projected back onto it after each straight step, which ends at
//! the next new contact or after a relative growth `max_growth_step`. A pair constrained in one
//! QP stays constrained in the next while its gap is within `hold_band` (without that, contacts
//! opened by one large step near a fold left the QP and were closed again one step at a time:
//! docs/notes/closest-jammed-qp-cycling.md). Each QP is first solved by an active set (the last
//! step's bonds and the new contact, KKT-checked, [`QpRun::guess`]) and otherwise by clarabel.
//! The packing is jammed when the QP over the contacts is infeasible: clarabel's certificate
//! `z ≥ 0` with `Aᵀz = 0`, `zᵀb > 0` are the contact forces, and a last projection in positions
//! and `t` closes every force-bearing contact.
//!
//! The same steepest descent, solved as an active set on the integrator's sparse factor (every
//! bond whose multiplier turns tensile opens), is [`crate::closest_jammed`] with
//! `open_tensile_bonds`; the tests check that both come back to the same jammed packing next to
//! jamming.

use std::time::Instant;

use packbench_core::Packing;
use packbench_core::run::{Observer, Outcome, Progress, TraceRow};
use rustc_hash::FxHashSet;
use serde::{Deserialize, Serialize};
use serde_json::json;

use super::bonds::bond_count;
use crate::conic::{Program, Solution};
use crate::contacts::Key;
use crate::contacts::Link;
use crate::error::JammingError;
use crate::growth::{Growth, contact_time};
use crate::min_norm::{CgStats, MinNorm, Preconditioner, Solver};
use crate::projection::{project, project_to};
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
    /// A pair constrained in the last QP stays constrained while its relative gap is at most
    /// this (hysteresis on the contact set): a step with large velocities opens the contacts
    /// the QP left inactive by a little more than `contact_tol`, and without the band they
    /// dropped out of the next QP, whose velocities closed them again one step at a time
    /// (docs/notes/closest-jammed-qp-cycling.md).
    pub hold_band: f64,
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
            hold_band: 1e-5,
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
            ("hold_band", self.hold_band),
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
        if self.hold_band < self.contact_tol {
            return Err(JammingError::Parameter(format!(
                "hold_band = {} must be at least contact_tol = {}",
                self.hold_band, self.contact_tol
            )));
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

/// Active sets tried at one step before the QP goes to clarabel ([`QpRun::guess`]).
const ACTIVE_SET_ROUNDS: usize = 8;

/// The state of a QP-form run: the growth, the contacts constrained in the last QP, the bonds
/// it held, and the counts reported in `extra`.
struct QpRun<'p> {
    g: Growth,
    p: &'p Params,
    solver: Solver,
    constrained: FxHashSet<Key>,
    active: Vec<Key>,
    opened: u64,
    projections_skipped: u64,
    /// Steps whose QP was solved by clarabel (the others by the active set, [`QpRun::guess`]).
    by_clarabel: u64,
    /// Active sets tried ([`QpRun::kkt`] calls) over the run.
    active_set_rounds: std::cell::Cell<u64>,
    /// Conjugate-gradient counts of the changed active sets' solves ([`QpRun::changed`]).
    cg_stats: std::rc::Rc<CgStats>,
}

/// A step's QP solved: the velocities and the bonds it holds with their duals, and the factor
/// of those bonds when the active set made one.
struct Step {
    y: Vec<f64>,
    held: Vec<(Key, f64)>,
    factor: Option<MinNorm>,
}

impl QpRun<'_> {
    /// The pairs the next QP constrains: every candidate within `contact_tol` of contact, and
    /// those of the last QP still within `hold_band`.
    fn contacts(&self) -> Vec<Key> {
        let p = self.p;
        self.g
            .candidates
            .keys
            .iter()
            .filter(|k| {
                let gap = self.g.link(k).rel_gap(self.g.t);
                gap <= p.contact_tol || (gap <= p.hold_band && self.constrained.contains(k))
            })
            .copied()
            .collect()
    }

    /// The QP over `contacts` solved by an active set, when one proves optimal within
    /// [`ACTIVE_SET_ROUNDS`]: first the bonds held at the last step that are still constrained
    /// and the contacts new to this QP (the pair that ended the step), then, while that set
    /// misses the KKT conditions ([`QpRun::kkt`]), the same without its tensile bonds and with
    /// the rows its velocities violate. The QP is strictly convex, so a set that meets them
    /// gives its only solution. `None` when no set does (or its rows are dependent): clarabel
    /// solves the QP then.
    fn guess(&self, contacts: &[Key]) -> Option<Step> {
        let still: FxHashSet<Key> = contacts.iter().copied().collect();
        let mut set: Vec<Key> = (self.active.iter().filter(|k| still.contains(k)))
            .chain(contacts.iter().filter(|k| !self.constrained.contains(k)))
            .copied()
            .collect();
        // The last set tried with its factor: the next set, a few rows apart, is solved with it
        // ([`QpRun::changed`]) instead of a new factorisation.
        let mut earlier: Option<(Vec<Key>, MinNorm)> = None;
        for _ in 0..ACTIVE_SET_ROUNDS {
            match self.kkt(contacts, &set, earlier.take())? {
                Ok(step) => return Some(step),
                Err((next, factor)) => earlier = Some((std::mem::replace(&mut set, next), factor)),
            }
        }
        None
    }

    /// The rows `set` of the QP over `contacts` held at equality by the minimum-norm velocities
    /// `y = Aᵀλ`, `λ = (A Aᵀ)⁻¹ D`. `Ok` with the QP's solution when they meet its KKT
    /// conditions: every row of `set` at equality to `contact_tol` relative (after one refinement of `λ`), every multiplier
    /// non-negative to `active_tol` relative (the duals' own threshold), every other row
    /// satisfied to `qp_tol`; the bonds held are those of multiplier above `active_tol` times
    /// the largest. `Err` with the next set to try (without the tensile rows, with the
    /// violated ones, and this set's factor). `None` when the rows cannot be factorised or are
    /// dependent. `earlier` is the last set tried with its factor, used when `set` differs from
    /// it by a few rows.
    fn kkt(
        &self,
        contacts: &[Key],
        set: &[Key],
        earlier: Option<(Vec<Key>, MinNorm)>,
    ) -> Option<Result<Step, (Vec<Key>, MinNorm)>> {
        let (n, d, p) = (self.g.n, self.g.d, self.p);
        self.active_set_rounds.set(self.active_set_rounds.get() + 1);
        let links = self.g.links(set);
        let changed = earlier.and_then(|earlier| self.changed(earlier, set, &links));
        let factor = match changed {
            Some(factor) => factor,
            None => self.solver.factor(set, &links, &self.g, [].iter()).ok()?,
        };
        let mut lambda = factor.multipliers(&links, n, d);
        let transposed = |lambda: &[f64]| {
            let mut y = vec![0.0; n * d];
            for (l, &c) in links.iter().zip(lambda) {
                l.add_transposed(c, &mut y, d);
            }
            y
        };
        let mut y = transposed(&lambda);
        // One refinement: near a fold `A Aᵀ` is ill-conditioned, and the normal equations
        // lose what one correction with the same factor gives back.
        let residual: Vec<f64> = links.iter().map(|l| l.size - l.rate(&y, d)).collect();
        let correction = factor.gram_solve(&residual);
        lambda
            .iter_mut()
            .zip(&correction)
            .for_each(|(l, c)| *l += c);
        y = transposed(&lambda);
        let slack = |l: &Link| (l.rate(&y, d) - l.size) / l.size;
        let at_equality = links.iter().all(|l| slack(l).abs() <= p.contact_tol);
        if !(at_equality && y.iter().all(|v| v.is_finite())) {
            return None;
        }
        let lmax = lambda.iter().fold(0.0f64, |m, &l| m.max(l.abs()));
        let members: FxHashSet<Key> = set.iter().copied().collect();
        let violated = (contacts.iter().filter(|k| !members.contains(k)))
            .filter(|k| slack(&self.g.link(k)) < -p.qp_tol);
        let compressive = (set.iter().zip(&lambda)).filter(|(_, l)| **l >= -p.active_tol * lmax);
        let next: Vec<Key> = compressive
            .map(|(k, _)| *k)
            .chain(violated.copied())
            .collect();
        if next.len() != set.len() || next.iter().zip(set).any(|(a, b)| a != b) {
            return Some(Err((next, factor)));
        }
        let held: Vec<(Key, f64)> = (set.iter().zip(&lambda))
            .filter(|(_, l)| **l > p.active_tol * lmax)
            .map(|(k, l)| (*k, *l))
            .collect();
        let factor = (held.len() == set.len()).then_some(factor);
        Some(Ok(Step { y, held, factor }))
    }

    /// The factor `factor` of the active set `keys` changed to `set` (rows `links`, at the same
    /// configuration): conjugate gradients preconditioned by that factor bordered with the rows
    /// added and released ([`Preconditioner`]), which is `(A Aᵀ)⁻¹` of `set` itself here, so
    /// they stop after an iteration or two, where a new numeric factorisation costs about as
    /// much as 20. `None` when the factor is not a sparse one or the border would be too
    /// large; the caller then factorises `set`.
    fn changed(
        &self,
        (keys, factor): (Vec<Key>, MinNorm),
        set: &[Key],
        links: &[Link],
    ) -> Option<MinNorm> {
        let (n, d) = (self.g.n, self.g.d);
        let mut pre = Preconditioner::new(&std::rc::Rc::new(factor))?;
        let now: FxHashSet<Key> = set.iter().copied().collect();
        for k in keys.iter().filter(|k| !now.contains(k)) {
            pre = pre.release(k)?;
        }
        // The basis grows one added row at a time, the new row last, as `extend` takes it.
        let before: FxHashSet<Key> = keys.into_iter().collect();
        let (mut basis, mut rows): (Vec<Key>, Vec<Link>) = (set.iter().zip(links))
            .filter(|(k, _)| before.contains(k))
            .map(|(k, l)| (*k, *l))
            .unzip();
        for (k, l) in set.iter().zip(links).filter(|(k, _)| !before.contains(k)) {
            basis.push(*k);
            rows.push(*l);
            pre = pre.extend(&basis, &rows, n, d)?;
        }
        MinNorm::iterative(&std::rc::Rc::new(pre), set, links, n, d, &self.cg_stats)
    }

    /// Takes the bonds the QP holds as the active set and projects them, those within
    /// `contact_tol` of contact back onto it (with `factor` when the step has one of exactly
    /// those bonds, so most steps factorise once). A held pair still open within the hold band
    /// is projected back onto its own gap: the QP holds it at equality, and closing it here
    /// would move particles by that gap and push pairs that are no bonds into overlap (up to
    /// 8.6e-6 on a 16-sphere start with a band of 1e-5). A held set dependent more than once
    /// (a crystallising 2D patch) can have gaps no correction closes; the step then goes on
    /// from the unprojected configuration, whose bonds are within the contact tolerance, and
    /// the next QP sees them (`projections_skipped`).
    fn hold(&mut self, held: Vec<(Key, f64)>, factor: Option<MinNorm>) -> Result<(), JammingError> {
        let now_active: FxHashSet<Key> = held.iter().map(|(k, _)| *k).collect();
        self.opened += self
            .active
            .iter()
            .filter(|k| !now_active.contains(k))
            .count() as u64;
        self.active = held.into_iter().map(|(k, _)| k).collect();
        let links = self.g.links(&self.active);
        if links.is_empty() {
            return Ok(());
        }
        // Targets: contact for the bonds within `contact_tol`, its present gap for a bond open
        // within the hold band.
        let (t, contact_tol) = (self.g.t, self.p.contact_tol);
        let held_gaps: Vec<f64> = (links.iter())
            .map(|l| l.rel_gap(t))
            .map(|gap| if gap <= contact_tol { 0.0 } else { gap })
            .collect();
        let open = held_gaps.iter().any(|&gap| gap != 0.0);
        let mn = match factor {
            Some(mn) => mn,
            None => (self.solver)
                .factor(&self.active, &links, &self.g, [].iter())
                .map_err(JammingError::Solver)?,
        };
        let before = self.g.snapshot();
        let tol = self.p.projection_tol;
        let chord = Some((links.as_slice(), &mn));
        let held_gaps = open.then_some(held_gaps.as_slice());
        let active = &self.active;
        match project_to(
            &mut self.g,
            active,
            held_gaps,
            chord,
            None,
            tol,
            &self.solver,
        ) {
            Ok(_) => Ok(()),
            Err(JammingError::Solver(_)) => {
                self.g.restore(&before);
                self.projections_skipped += 1;
                Ok(())
            }
            Err(e) => Err(e),
        }
    }

    /// Whether a pair of `support` is open by more than `contact_tol`.
    fn open_in(&self, support: &[(Key, f64)]) -> bool {
        let g = &self.g;
        (support.iter()).any(|(k, _)| g.link(k).rel_gap(g.t) > self.p.contact_tol)
    }

    /// The straight step along the QP's velocities `y` to the first contact of a pair it did
    /// not constrain, or a relative growth `max_growth_step`. Every such pair is checked,
    /// including one the projection has just moved to contact: it touches now (τ = 0) if it
    /// closes, and joins the next QP.
    fn advance(&mut self, y: &[f64]) {
        let d = self.g.d;
        let g = &mut self.g;
        let vmax = y
            .chunks_exact(d)
            .map(|v| v.iter().map(|a| a * a).sum::<f64>().sqrt())
            .fold(0.0, f64::max);
        let mut tau = (self.p.max_growth_step * g.t).min(g.safe_step(vmax));
        for (_, key) in g.candidates.within(tau * g.shrink_rate(vmax)) {
            if self.constrained.contains(key) {
                continue;
            }
            if let Some(tc) = contact_time(&g.link(key), y, g.t, d) {
                tau = tau.min(tc);
            }
        }
        g.advance(y, tau);
        g.refresh();
    }

    /// Closes the jammed packing: the certificate's support `keys` is minimally dependent, so
    /// one force-bearing bond leaves the basis and the projection closes it through the
    /// growth factor. Returns the largest relative bond gap.
    fn close_jammed(&mut self, keys: &[Key], forces: &[f64]) -> Result<f64, JammingError> {
        let Some((last, rest)) = keys.split_last() else {
            return Ok(f64::NAN);
        };
        let links = self.g.links(rest);
        let mn = self
            .solver
            .factor(rest, &links, &self.g, [].iter())
            .map_err(JammingError::Solver)?;
        let chord = Some((links.as_slice(), &mn));
        let jam = Some((last, forces));
        project(
            &mut self.g,
            rest,
            chord,
            jam,
            self.p.projection_tol,
            &self.solver,
        )
    }

    /// The run's `extra` after `steps` QPs, with the final bonds and their largest gap.
    fn extra(
        &self,
        steps: u64,
        final_gap: f64,
        bonds: &[Key],
    ) -> serde_json::Map<String, serde_json::Value> {
        let (non_rattler_bonds, n_dof, n_rattlers) = bond_count(&self.g, bonds, &[]);
        let mut extra = serde_json::Map::new();
        for (k, v) in [
            ("bonds_opened", json!(self.opened)),
            ("bonds", json!(bonds.len())),
            ("non_rattler_bonds", json!(non_rattler_bonds)),
            ("n_dof", json!(n_dof)),
            ("rattlers", json!(n_rattlers)),
            ("qp_count", json!(steps)),
            ("qp_by_clarabel", json!(self.by_clarabel)),
            ("active_set_rounds", json!(self.active_set_rounds.get())),
            ("factorisations", json!(self.solver.numeric.get())),
            ("projections_skipped", json!(self.projections_skipped)),
            (
                "final_bond_gap",
                json!(final_gap.is_finite().then_some(final_gap)),
            ),
            ("growth_factor", json!(self.g.t)),
        ] {
            extra.insert(k.into(), v);
        }
        extra
    }

    fn trace_row(&self, step: u64, time_s: f64, phi: f64, bonds: usize) -> TraceRow {
        TraceRow {
            step,
            time_s,
            phi,
            values: vec![
                ("bonds".into(), bonds as f64),
                ("bonds_opened".into(), self.opened as f64),
            ],
        }
    }
}

/// Drives `start` to a jammed packing by the QP form of the closest-jammed growth.
///
/// Terminations: `jammed` (checked by the core's analysis, else `not_jammed`), `max_steps`,
/// `interrupted`. `extra` holds `bonds_opened` (active bonds whose constraint became
/// inactive), `bonds`, `non_rattler_bonds`, `n_dof`, `rattlers`, `qp_count`, `qp_by_clarabel`
/// (the QPs the active set did not solve), `projections_skipped` (steps whose held bonds no
/// correction could close) and `final_bond_gap`.
///
/// # Errors
/// [`JammingError::InvalidPacking`] and [`JammingError::Overlap`] for a bad start,
/// [`JammingError::Parameter`] for bad options, [`JammingError::Solver`] when clarabel, a
/// factorisation or the final projection fails.
pub fn run(
    start: &Packing,
    params: &Params,
    observer: &mut dyn Observer,
) -> Result<Outcome, JammingError> {
    params.validate()?;
    let clock = Instant::now();
    let phi0 = start.phi();
    let mut r = QpRun {
        g: Growth::new(start, params.skin, params.overlap_tol)?,
        p: params,
        solver: Solver::new(params.dense_max_bonds),
        constrained: FxHashSet::default(),
        active: Vec::new(),
        opened: 0,
        projections_skipped: 0,
        by_clarabel: 0,
        active_set_rounds: std::cell::Cell::new(0),
        cg_stats: Default::default(),
    };
    let mut trace = Vec::new();
    let mut steps = 0u64;
    let mut last_report = Instant::now();
    let mut jam: Option<(Vec<Key>, Vec<f64>)> = None;
    let termination = loop {
        if observer.should_stop() {
            break "interrupted";
        }
        if steps >= params.max_steps {
            break "max_steps";
        }
        let contacts = r.contacts();
        steps += 1;
        let step = match r.guess(&contacts) {
            Some(step) => step,
            None => {
                r.by_clarabel += 1;
                let (sol, held) =
                    steepest_descent(&r.g, &contacts, params.qp_tol, params.active_tol)
                        .map_err(|e| JammingError::Solver(format!("closest-jammed QP: {e}")))?;
                if sol.infeasible && r.open_in(&held) {
                    // A certificate that leans on pairs still open within the hold band is
                    // none: those pairs may close. The next QP holds the contacts only.
                    r.constrained.clear();
                    continue;
                }
                if sol.infeasible {
                    // The certificate's support and its forces, in the order of `contacts`.
                    jam = Some(held.into_iter().unzip());
                    break "jammed";
                }
                let y = sol.x;
                Step {
                    y,
                    held,
                    factor: None,
                }
            }
        };
        r.constrained = contacts.into_iter().collect();
        r.hold(step.held, step.factor)?;
        r.advance(&step.y);
        if params.save_interval > 0 && steps.is_multiple_of(params.save_interval) {
            observer.snapshot(steps, &r.g.packing());
        }
        if last_report.elapsed().as_secs_f64() > 0.25 {
            last_report = Instant::now();
            let phi = r.g.phi(phi0);
            observer.progress(&Progress {
                step: steps,
                phi,
                value: r.active.len() as f64,
                label: "bonds",
                fraction: None,
                more: Vec::new(),
            });
            let time_s = clock.elapsed().as_secs_f64();
            trace.push(r.trace_row(steps, time_s, phi, r.active.len()));
        }
    };
    let (final_gap, bonds) = match &jam {
        Some((keys, forces)) => (r.close_jammed(keys, forces)?, keys.clone()),
        None => (f64::NAN, r.active.clone()),
    };
    let phi = r.g.phi(phi0);
    trace.push(r.trace_row(steps, clock.elapsed().as_secs_f64(), phi, bonds.len()));
    let mut extra = r.extra(steps, final_gap, &bonds);
    let packing = r.g.packing();
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
