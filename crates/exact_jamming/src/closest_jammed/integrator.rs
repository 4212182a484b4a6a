//! The integrator of Baranau & Tallarek's closest-jammed dynamics (Baranau & Tallarek 2014, App. C): the
//! state of a run, one growth step with bonds held in contact, contact events, folds of the
//! bond manifold, stalls, and the step counts.

use std::cell::RefCell;
use std::rc::Rc;

use packbench_core::run::TraceRow;
use rustc_hash::FxHashSet;
use serde::Serialize;

use crate::contacts::{Key, Link};
use crate::error::JammingError;
use crate::growth::{Growth, contact_time};
use crate::min_norm::{CgStats, MinNorm, Preconditioner, Solver};
use crate::projection::project;

use super::bonds::{Admission, opening_bond, tensile_bond};
use super::params::Params;

/// What a failed projection after a straight step says about the bond manifold.
pub(super) enum Fold {
    /// Nothing: the step was projected.
    None,
    /// Basis bond `k` is tensile and is released.
    Release(usize),
    /// The bonds cannot grow and every multiplier is compressive: jammed, with these forces.
    Jammed(Vec<f64>),
}

/// Relative overlap the contact that ends a step may reach after the step's projection: the
/// path bends, so the straight step overshoots that contact at second order; it becomes a bond
/// at once and is closed exactly, but a larger overshoot means the step was too long.
pub(super) const EVENT_OVERSHOOT: f64 = 1e-6;

/// Shortest step, relative to `t`: shortening a step stops here (at a fold, or when pairs are
/// still pushed into overlap).
pub(super) const SHORTEST_STEP: f64 = 1e-13;

/// A run whose growth factor grows by no more than `STALL_GROWTH` relative in `STALL_STEPS`
/// steps makes no progress (its bonds cycle, or the same step repeats) and stops as
/// `stalled`, keeping its packing.
pub(super) const STALL_GROWTH: f64 = 1e-14;
pub(super) const STALL_STEPS: u64 = 10_000;

/// Steps without growth after which the bonds are taken to cycle through a degenerate
/// configuration (several contacts at zero gap, each admission releasing a bond that the next
/// step meets again); the bond set is then chosen by one quadratic program over every contact
/// ([`Integrator::leave_cycle`]).
pub(super) const CYCLING_STEPS: u64 = 500;

/// The growth factor and the step at which it last grew by more than `STALL_GROWTH`.
pub(super) struct GrowthProgress {
    pub(super) t: f64,
    pub(super) step: u64,
}

impl GrowthProgress {
    /// Records the growth factor `t` after `steps` steps; true once it has not grown by more
    /// than `STALL_GROWTH` (relative) for `STALL_STEPS` steps.
    pub(super) fn stalled(&mut self, t: f64, steps: u64) -> bool {
        if t > self.t * (1.0 + STALL_GROWTH) {
            *self = GrowthProgress { t, step: steps };
            false
        } else {
            steps - self.step >= STALL_STEPS
        }
    }

    /// Whether the growth factor has not grown in the `CYCLING_STEPS` steps up to `steps`, nor
    /// since `since` (the step of the last attempt to leave a cycle).
    pub(super) fn cycling(&self, steps: u64, since: u64) -> bool {
        steps - self.step.max(since) >= CYCLING_STEPS
    }
}

/// A factorisation with the basis and positions it was made at.
type CachedFactor = (Vec<Key>, Vec<f64>, Rc<MinNorm>);

/// What the steps did: where the step count of a run comes from.
#[derive(Default, Serialize)]
pub(super) struct StepCounts {
    /// Steps that ended at a new contact.
    pub(super) events: u64,
    /// New contacts with independent rows that the step's projection carried apart again
    /// (not admitted; [`Admission::Apart`]).
    pub(super) events_apart: u64,
    /// Steps ended by a growth or displacement cap.
    pub(super) capped: u64,
    /// New bonds admitted into the basis.
    pub(super) added: u64,
    /// New bonds dependent on the basis and consistent with it.
    pub(super) redundant: u64,
    /// New contacts separating under the current motion.
    pub(super) separating: u64,
    /// Bonds released at a dependent new bond with tensile forces.
    pub(super) released_at_admission: u64,
    /// Tensile bonds weighed by the minimum-norm release rule; the forward solves (`(A Aᵀ)⁻¹`
    /// diagonal entries) it made to weigh them, or the releases weighed by one selected
    /// inversion instead; and the wall-clock seconds the rule took.
    pub(super) release_candidates: u64,
    pub(super) release_solves: u64,
    pub(super) release_selected_inversions: u64,
    pub(super) release_seconds: f64,
    /// Bonds released at a fold of the bond manifold (failed projection).
    pub(super) released_at_fold: u64,
    /// Bond sets chosen by one quadratic program after `CYCLING_STEPS` steps without growth
    /// ([`Integrator::leave_cycle`]).
    pub(super) cycles_left: u64,
    /// Failed projections whose step start was singular to rounding (a fold), judged by
    /// [`Solver::fold_multipliers`].
    pub(super) singular_folds: u64,
    /// Steps shortened after a failed projection with compressive multipliers.
    pub(super) shortened: u64,
    /// Steps shortened because their projection pushed a pair that is no bond into overlap.
    pub(super) shortened_by_overlap: u64,
    /// Pairs a projection pushed into overlap however short the step, taken as contacts.
    pub(super) overlapped_contacts: u64,
    /// Numeric factorisations of a bond matrix.
    pub(super) factorisations: u64,
    /// Symbolic factorisations (sparsity patterns of `A Aᵀ` built).
    pub(super) patterns: u64,
    /// Sparse factorisations that failed (dependent rows) and fell back to the dense SVD.
    pub(super) dense_fallbacks: u64,
    /// Bonds that joined or left an updated factor (`factor_updates`) in place.
    pub(super) factor_row_updates: u64,
    /// Wall-clock seconds in factorisations (symbolic and numeric).
    pub(super) factorisation_seconds: f64,
    /// Conjugate-gradient solves, their iterations, and solves that did not converge.
    pub(super) cg_solves: u64,
    pub(super) cg_iterations: u64,
    pub(super) cg_failures: u64,
}

/// The integrator's state: the growth state, the bond basis and its factorisation.
pub(super) struct Integrator<'p> {
    pub(super) g: Growth,
    pub(super) p: &'p Params,
    pub(super) basis: Vec<Key>,
    pub(super) redundant: Vec<Key>,
    pub(super) bonded: FxHashSet<Key>,
    pub(super) released: u64,
    /// Counters of what each step did, reported in `extra.step_counts`.
    pub(super) counts: StepCounts,
    pub(super) solver: Solver,
    /// The last factorisation, for the basis and positions it was made at.
    pub(super) cached: RefCell<Option<CachedFactor>>,
    /// The last exact sparse factor, which preconditions conjugate-gradient solves of later
    /// steps, and the largest iteration count of those solves.
    pub(super) preconditioner: RefCell<Option<Rc<Preconditioner>>>,
    pub(super) cg: Rc<CgStats>,
    /// Largest |Σ_i y_i| / max|y_i| seen (eqn 12 of Baranau & Tallarek 2014: zero total velocity).
    pub(super) total_velocity: f64,
    /// The velocities of the basis just grown by an independent bond, with the basis and
    /// positions they hold for.
    pub(super) next_velocities: Option<(Vec<Key>, Vec<f64>, Vec<f64>)>,
    /// Contacts waiting for their admission, the next one last.
    pub(super) pending: Vec<Key>,
    /// The contact being admitted, taken from `pending` (with factor updates a rebuilt pattern
    /// keeps it a slot).
    pub(super) admitting: Option<Key>,
    /// The contact that ended the last step when that step had length zero.
    pub(super) zero_step_event: Option<Key>,
}

impl Integrator<'_> {
    /// The factorisation of the basis rows `links` at the current positions (reused when
    /// neither changed since the last call): conjugate gradients preconditioned with an earlier
    /// factor while they converge fast, else an exact factor.
    pub(super) fn factor(&self, links: &[Link]) -> Result<Rc<MinNorm>, String> {
        self.factor_with(links, false)
    }

    /// The same, always exact: for the decisions after a failed step and at the end, where the
    /// preconditioner may be far off and the forward error of an iterative solve (condition
    /// number × tolerance) too large.
    pub(super) fn factor_exact(&self, links: &[Link]) -> Result<Rc<MinNorm>, String> {
        self.factor_with(links, true)
    }

    /// Projects the basis onto contact with an exact factor (the final projection; `jam` as in
    /// [`project`]).
    pub(super) fn project_exact(
        &mut self,
        jam: Option<(&Key, &[f64])>,
    ) -> Result<f64, JammingError> {
        let links = self.g.links(&self.basis);
        let mn = self.factor_exact(&links).map_err(JammingError::Solver)?;
        project(
            &mut self.g,
            &self.basis,
            Some((&links, &mn)),
            jam,
            self.p.projection_tol,
            &self.solver,
        )
    }

    /// Closes the jammed packing: bond `key` left the basis with `forces` (basis bonds, then
    /// `key`), and a last projection in positions and `t` makes every bond touch. At a fold
    /// that projection is singular (the bonds' Jacobian loses rank there) and may jump far, so
    /// it is kept only when it converges without pushing a pair that is no bond into overlap;
    /// otherwise the configuration stays where the last step's projection closed the bonds.
    /// A projection that moved particles farther than the candidate skin is not kept either:
    /// pairs off the candidate list could overlap unseen (a 6D fold once jumped into an
    /// overlap of 0.76 of a diameter). `key` rejoins the basis. Returns the largest relative
    /// bond gap.
    pub(super) fn close_jammed(&mut self, key: &Key, forces: &[f64]) -> f64 {
        self.bonded.insert(*key);
        let before = self.g.snapshot();
        let overlaps = self.unbonded_overlaps();
        let closed = self.project_exact(Some((key, forces)));
        self.basis.push(*key);
        match closed {
            Ok(gap)
                if self.g.candidates_cover_contacts()
                    && self.grown_overlaps(&overlaps, None).is_empty() =>
            {
                gap
            }
            _ => {
                self.g.restore(&before);
                self.g.worst_gap(&self.basis)
            }
        }
    }

    pub(super) fn factor_with(&self, links: &[Link], exact: bool) -> Result<Rc<MinNorm>, String> {
        if let Some((keys, x, mn)) = self.cached.borrow().as_ref()
            && *keys == self.basis
            && *x == self.g.x
            && !(exact && matches!(mn.as_ref(), MinNorm::Iterative(_)))
        {
            return Ok(Rc::clone(mn));
        }
        let (n, d) = (self.g.n, self.g.d);
        let reuse = !exact && self.cg.worst.get() <= self.p.refactor_iterations;
        let iterative = if reuse && links.len() > self.p.dense_max_bonds {
            self.preconditioner
                .borrow()
                .as_ref()
                .and_then(|pre| MinNorm::iterative(pre, &self.basis, links, n, d, &self.cg))
        } else {
            None
        };
        let mn = match iterative {
            Some(mn) => Rc::new(mn),
            None => {
                // An updated factor takes no bond without a slot (a bordered one borders it), so
                // with updates the contacts waiting to be admitted get slots first.
                let waiting = self.admitting.iter().chain(self.pending.iter().rev());
                let waiting = waiting.take(if self.p.factor_updates { usize::MAX } else { 0 });
                let mn = Rc::new(self.solver.factor(&self.basis, links, &self.g, waiting)?);
                if let Some(mut pre) = Preconditioner::new(&mn) {
                    if self.p.factor_updates {
                        pre = pre.with_updates();
                    }
                    *self.preconditioner.borrow_mut() = Some(Rc::new(pre));
                    self.cg.worst.set(0);
                }
                mn
            }
        };
        *self.cached.borrow_mut() = Some((self.basis.clone(), self.g.x.clone(), Rc::clone(&mn)));
        Ok(mn)
    }

    /// Drops the factorisation of the current basis when it is iterative, so that the next one
    /// is exact (and preconditions what follows). Returns whether it did: `false` when the
    /// velocities and decisions already come from an exact factor.
    pub(super) fn distrust_iterative(&mut self) -> bool {
        let iterative = matches!(
            self.cached.borrow().as_ref(),
            Some((_, _, mn)) if matches!(mn.as_ref(), MinNorm::Iterative(_))
        );
        if iterative {
            *self.cached.borrow_mut() = None;
            self.next_velocities = None;
            self.basis_changed();
        }
        iterative
    }

    /// After the basis changed, the next factorisation is exact: it preconditions the
    /// decisions of the following step, which need a preconditioner of their own basis.
    pub(super) fn basis_changed(&self) {
        self.cg.worst.set(usize::MAX);
    }

    /// After a bond joined the basis (its last row): the preconditioner is bordered with its
    /// row, which keeps it one of the new basis without a numeric factorisation; when that is
    /// not possible the next factorisation is exact.
    pub(super) fn bond_added(&self) {
        let links = self.g.links(&self.basis);
        let (n, d) = (self.g.n, self.g.d);
        self.change_preconditioner(|pre| pre.extend(&self.basis, &links, n, d));
    }

    /// After bond `gone` left the basis: the same, the preconditioner drops its row.
    pub(super) fn bond_released(&self, gone: &Key) {
        self.change_preconditioner(|pre| pre.release(gone));
    }

    pub(super) fn change_preconditioner(
        &self,
        change: impl FnOnce(&Preconditioner) -> Option<Preconditioner>,
    ) {
        let changed = self.preconditioner.borrow().as_deref().and_then(change);
        match changed {
            Some(pre) => {
                if pre.is_updated() {
                    let updates = &self.solver.row_updates;
                    updates.set(updates.get() + 1);
                }
                *self.preconditioner.borrow_mut() = Some(Rc::new(pre));
            }
            None => self.basis_changed(),
        }
    }

    /// Minimum-norm velocities of the basis (eqn 2, `y = A⁺b`).
    ///
    /// # Errors
    /// [`JammingError::Solver`] when the solve failed (non-finite velocities): the basis is
    /// singular at this configuration, although it was independent when its last bond joined.
    pub(super) fn velocities(
        &self,
        links: &[Link],
        mn: &MinNorm,
    ) -> Result<Vec<f64>, JammingError> {
        let b: Vec<f64> = links.iter().map(|l| l.size).collect();
        let y = mn.solve(links, &b, self.g.n, self.g.d);
        if y.iter().all(|v| v.is_finite()) {
            Ok(y)
        } else {
            Err(JammingError::Solver(format!(
                "the minimum-norm velocities of {} bonds are not finite: the bond basis is singular",
                links.len()
            )))
        }
    }

    /// The largest rank of a bond matrix: `d·N` less one for each periodic axis, along which a
    /// translation moves no bond. A basis this large spans every row, whatever the computed
    /// independence of a new one says.
    pub(super) fn max_rank(&self) -> usize {
        let periodic = self.g.container.periodic.iter().filter(|&&p| p).count();
        self.g.n * self.g.d - periodic
    }

    /// Relative overlaps of the candidates that are no bonds, 0 for bonds and pairs apart
    /// (aligned with the candidate keys, which a projection leaves unchanged).
    pub(super) fn unbonded_overlaps(&self) -> Vec<f64> {
        let mut out = vec![0.0; self.g.candidates.keys.len()];
        for (i, k) in self.g.candidates.within(0.0) {
            if !self.bonded.contains(k) {
                out[i] = (-self.g.link(k).rel_gap(self.g.t)).max(0.0);
            }
        }
        out
    }

    /// The pairs that are no bonds and overlap more than they did `before` (see
    /// [`Self::unbonded_overlaps`]) and more than `overlap_tol`, or [`EVENT_OVERSHOOT`] for the
    /// contact `event` that ends a step.
    pub(super) fn grown_overlaps(&self, before: &[f64], event: Option<&Key>) -> Vec<Key> {
        let grown = |&(i, k): &(usize, &Key)| {
            let tol = match Some(k) == event {
                true => EVENT_OVERSHOOT,
                false => self.p.overlap_tol,
            };
            !self.bonded.contains(k) && -self.g.link(k).rel_gap(self.g.t) > before[i].max(tol)
        };
        self.g
            .candidates
            .within(0.0)
            .filter(grown)
            .map(|(_, k)| *k)
            .collect()
    }
}

/// What one call of [`Integrator::step`] did.
pub(super) enum StepOutcome {
    /// A pending contact was weighed ([`Admission`]): joined the basis, was kept redundant,
    /// replaced a released bond, or was left apart.
    Admitted,
    /// A bond was released before the straight step (the active-set form, or at a fold of the
    /// bond manifold); the step is taken again with the new basis.
    BondReleased,
    /// A straight step was taken and projected.
    Advanced,
    /// No growth is possible: bond `key` left the basis with these forces (basis bonds, then
    /// `key`), to be closed by [`Integrator::close_jammed`].
    Jammed(Key, Vec<f64>),
}

impl Integrator<'_> {
    /// The trace row at `step`: the bond count and the bonds released so far.
    pub(super) fn trace_row(&self, step: u64, time_s: f64, phi: f64) -> TraceRow {
        TraceRow {
            step,
            time_s,
            phi,
            values: vec![
                ("bonds".into(), self.basis.len() as f64),
                ("bonds_released".into(), self.released as f64),
            ],
        }
    }

    /// One step of the integration: the next pending contact's admission, or else one straight
    /// step to the next new contact (or a growth cap) projected back onto the bonds.
    pub(super) fn step(&mut self) -> Result<StepOutcome, JammingError> {
        if let Some(key) = self.pending.pop() {
            if self.bonded.contains(&key) {
                return Ok(StepOutcome::Admitted);
            }
            let met_now = self.zero_step_event == Some(key);
            if met_now {
                self.zero_step_event = None;
            }
            self.admitting = Some(key);
            let admission = self.admit(key, met_now);
            self.admitting = None;
            match admission? {
                Admission::Jammed(f) => return Ok(StepOutcome::Jammed(key, f)),
                Admission::Added => self.counts.added += 1,
                Admission::Redundant => self.counts.redundant += 1,
                Admission::Released => self.counts.released_at_admission += 1,
                Admission::Separating => self.counts.separating += 1,
                Admission::Apart => self.counts.events_apart += 1,
            }
            return Ok(StepOutcome::Admitted);
        }
        self.straight_step()
    }

    /// A straight step along the minimum-norm velocities to the next new contact, projected
    /// back onto the bonds (every pending contact admitted).
    // Long because one step (velocities, the largest safe growth, the first new contact, the
    // release test) reads and updates the same bond set in an order the bytes of the path depend
    // on.
    pub(super) fn straight_step(&mut self) -> Result<StepOutcome, JammingError> {
        let (n, d) = (self.g.n, self.g.d);
        let periodic = self.g.container.is_fully_periodic();
        let links = self.g.links(&self.basis);
        let mn = self.factor(&links).map_err(JammingError::Solver)?;
        let y = match self.next_velocities.take() {
            Some((basis, x, y)) if basis == self.basis && x == self.g.x => y,
            _ => self.velocities(&links, &mn)?,
        };
        if let Some(k) = opening_bond(self.p, &mn, &links, n, d) {
            self.release(k);
            return Ok(StepOutcome::BondReleased);
        }
        let vmax = y
            .chunks_exact(d)
            .map(|v| v.iter().map(|a| a * a).sum::<f64>().sqrt())
            .fold(0.0, f64::max);
        if periodic && vmax > 0.0 {
            // Eqn 12: rows of A sum to zero over particles, so Σ y_i = 0 exactly.
            let tv = (0..d)
                .map(|k| (0..n).map(|i| y[i * d + k]).sum::<f64>().powi(2))
                .sum::<f64>()
                .sqrt();
            self.total_velocity = self.total_velocity.max(tv / vmax);
        }
        // Next new contact along the straight motion, capped for accuracy and list validity.
        let cap = (self.p.max_growth_step * self.g.t)
            .min(self.g.safe_step(vmax))
            .min(
                self.p.max_displacement_step * self.g.mean_diameter() / vmax.max(f64::MIN_POSITIVE),
            );
        let mut tau = cap;
        let mut event: Option<Key> = None;
        for (_, key) in self.g.candidates.within(cap * self.g.shrink_rate(vmax)) {
            if self.bonded.contains(key) {
                continue;
            }
            let l = self.g.link(key);
            if let Some(tc) = contact_time(&l, &y, self.g.t, d)
                && tc <= tau
            {
                tau = tc;
                event = Some(*key);
            }
        }
        // Step, then project the bonds back onto contact with the factorisation of the step's
        // start (Newton–chord). If that fails, the step crossed a fold of the bond manifold (the
        // largest t at which every bond can stay in contact): a bond whose multiplier is tensile
        // is released and the step retried; with every multiplier compressive the step is
        // shortened, and a fold reached with compressive forces is a jammed packing.
        // The projection also bends the path: a step whose correction pushes a pair that is
        // no bond into overlap (or the contact that ends it far past contact) missed that
        // pair's contact on the curved path, and is shortened.
        let saved = self.g.snapshot();
        let overlaps = self.unbonded_overlaps();
        let mut overlapped = Vec::new();
        let mut fold: Fold = Fold::None;
        loop {
            self.g.advance(&y, tau);
            let projected = project(
                &mut self.g,
                &self.basis,
                Some((&links, &mn)),
                None,
                self.p.projection_tol,
                &self.solver,
            );
            let failed = match projected {
                // The projection moved particles past the candidate skin, where pairs off the
                // list could overlap unseen: the step was too long for the path's curvature.
                Ok(_) if !self.g.candidates_cover_contacts() => {
                    if tau <= SHORTEST_STEP * self.g.t {
                        self.g.restore(&saved);
                        return Err(JammingError::Solver(
                            "the projection onto the bonds jumped farther than the candidate skin however short the step".into(),
                        ));
                    }
                    None
                }
                Ok(_) => {
                    overlapped = self.grown_overlaps(&overlaps, event.as_ref());
                    // Pairs still pushed in at the shortest step come from a gap the basis had
                    // at the step's start (`admit` no longer leaves one for a bond still apart,
                    // so this is a safety net): they are taken as contacts.
                    if overlapped.is_empty() || tau <= SHORTEST_STEP * self.g.t {
                        break;
                    }
                    None
                }
                Err(e) => Some(e),
            };
            self.g.restore(&saved);
            match failed {
                None => {
                    tau *= 0.25;
                    event = None;
                    self.counts.shortened_by_overlap += 1;
                }
                Some(e) => {
                    // The fold is judged by the signs of exact multipliers; a step start so
                    // close to the fold that the basis is singular to rounding takes them
                    // from a shifted factor.
                    let lambda = match self.factor_exact(&links) {
                        Ok(mn) => mn.multipliers(&links, n, d),
                        Err(_) => {
                            self.counts.singular_folds += 1;
                            self.solver
                                .fold_multipliers(&self.basis, &links, n, d)
                                .map_err(JammingError::Solver)?
                        }
                    };
                    if let Some(k) = tensile_bond(&lambda, self.p.force_tol) {
                        fold = Fold::Release(k);
                        break;
                    }
                    tau *= 0.25;
                    event = None;
                    self.counts.shortened += 1;
                    if tau < SHORTEST_STEP * self.g.t {
                        fold = if lambda.iter().all(|&l| l >= 0.0) && !lambda.is_empty() {
                            Fold::Jammed(lambda)
                        } else {
                            return Err(e);
                        };
                        break;
                    }
                }
            }
        }
        match fold {
            Fold::None => {}
            Fold::Release(k) => {
                self.counts.released_at_fold += 1;
                self.release(k);
                return Ok(StepOutcome::BondReleased);
            }
            Fold::Jammed(lambda) => {
                // The fold's forces are λ/|λ|: the most loaded bond leaves the basis and closes
                // through the growth factor in the final projection.
                let k = (0..lambda.len())
                    .max_by(|&a, &b| lambda[a].total_cmp(&lambda[b]))
                    .expect("non-empty");
                let key = self.basis.remove(k);
                let mut forces = lambda;
                let fk = forces.remove(k);
                forces.push(fk);
                return Ok(StepOutcome::Jammed(key, forces));
            }
        }
        self.counts.overlapped_contacts += overlapped.len() as u64;
        self.pending.append(&mut overlapped);
        if let Some(key) = event {
            if tau == 0.0 {
                self.zero_step_event = Some(key);
            }
            self.pending.push(key);
            self.counts.events += 1;
        } else {
            self.counts.capped += 1;
        }
        self.g.refresh();
        Ok(StepOutcome::Advanced)
    }
}
