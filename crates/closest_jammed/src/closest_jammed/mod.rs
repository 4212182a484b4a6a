//! The closest-jammed integrator (seed 001, Appendix C, eqns 1–4).
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
//! bonds otherwise; the QP form ([`crate::closest_jammed_qp`]) does.
//!
//! Linear algebra per step (`A Aᵀ λ = b`, `y = Aᵀλ`): consecutive steps differ by a small motion
//! and one bond, so the velocities and the projection are solved by conjugate gradients
//! preconditioned with the sparse Cholesky factor of an earlier step, bordered with the rows of
//! the bonds added since (`min_norm::Preconditioner`), and refactorised (symbolic pattern
//! reused, see the `min_norm` module) once a solve needs more than `REFACTOR_ITERATIONS`, after a bond
//! is released, and when the bordering is full. So the decisions that depend on signs or
//! near-zero values at a new bond (its dependence and residual, the forces) are solved with a
//! preconditioner of their own basis a few steps' motion away, where the preconditioned matrix
//! is nearly the identity and the forward error is that of a direct solve; the forces at a fold
//! and the final projection use an exact factor.

use std::cell::RefCell;
use std::collections::HashSet;
use std::rc::Rc;
use std::time::Instant;

use packbench_core::Packing;
use packbench_core::analysis::{Contact, ContactNetwork, rattlers};
use packbench_core::run::{Observer, Outcome, Progress, TraceRow};
use serde::{Deserialize, Serialize};
use serde_json::json;

use crate::contacts::{Key, Link};
use crate::error::JammingError;
use crate::growth::{Growth, contact_time};
use crate::min_norm::{CgStats, MinNorm, Preconditioner, Solver};
use crate::projection::project;
use crate::verdict::checked_termination;

mod bonds;
use bonds::Admission;
pub(crate) use bonds::tensile_bond;

use crate::closest_jammed_qp::opening_bond;

/// Options of the closest-jammed integrator. Seed 001 fixes no constants; the defaults make
/// contacts exact to about 1e-14 relative.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default)]
pub struct Params {
    /// Largest number of integration steps (one per new contact or growth cap).
    pub max_steps: u64,
    /// Largest relative growth `Δt/t` of one straight step between contacts (accuracy knob).
    pub max_growth_step: f64,
    /// Largest displacement of any particle in one straight step, in mean diameters (keeps the
    /// drift of bonds off contact, which the projection removes, small).
    pub max_displacement_step: f64,
    /// Candidate skin, in mean diameters: pairs closer than this are checked for new contacts.
    pub skin: f64,
    /// Pairs of the starting packing with relative gap `r/σ − 1` at most this start as bonds.
    pub contact_tol: f64,
    /// A new bond is dependent on the basis when its row `a` is within `dependency_tol·‖a‖` of
    /// the basis rows' span.
    pub dependency_tol: f64,
    /// Forces below `−force_tol·max f` count as tensile (the bond is released).
    pub force_tol: f64,
    /// Projection stops when every bond's relative gap is below this.
    pub projection_tol: f64,
    /// Release a bond as soon as its Lagrange multiplier `λ_k` of the minimum-norm solve
    /// (`y = Aᵀλ`, `λ = (A Aᵀ)⁻¹ D`) turns tensile, below `−force_tol·max |λ|`: the growth is
    /// then the steepest descent of seed 001 App. B (the QP form's path, solved as an active
    /// set). When false (the default, App. C literally), bonds are released only when the
    /// bonded system has no solution: at a dependent new bond with tensile forces, or at a
    /// fold of the bond manifold (the bonds cannot all stay in contact as `t` grows, the
    /// velocities diverge, and `λ/|λ|` tends to the fold's forces).
    pub open_tensile_bonds: bool,
    /// Which tensile bond is released at a dependent new bond (App. C's equations leave it
    /// open).
    pub release_rule: ReleaseRule,
    /// Bond counts up to this use the dense SVD pseudoinverse; more use sparse Cholesky of A Aᵀ.
    pub dense_max_bonds: usize,
    /// Largest relative overlap tolerated in the starting packing.
    pub overlap_tol: f64,
    /// Pass a snapshot to the observer every this many steps (0: never).
    pub save_interval: u64,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            max_steps: 10_000_000,
            max_growth_step: 1e-2,
            max_displacement_step: 5e-3,
            skin: 0.3,
            contact_tol: 1e-9,
            dependency_tol: 1e-6,
            force_tol: 1e-9,
            projection_tol: 1e-14,
            open_tensile_bonds: false,
            release_rule: ReleaseRule::default(),
            dense_max_bonds: 48,
            overlap_tol: 1e-9,
            save_interval: 0,
        }
    }
}

/// The bond released when a new bond makes the bonded system unsolvable with tensile forces.
/// Any bond with a tensile force may open while the others stay in contact (`fᵀ A y' = 0` fixes
/// its opening rate `res/(−f_k) > 0`); the rules differ in the path they take.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum ReleaseRule {
    /// The bond with the most tensile force: it opens the slowest, and in the long exchange
    /// phase of N = 300–1000 packings it came back about 15 steps later in 9 releases out of
    /// 10. At N = 1000 it had not jammed after 2·10⁵ steps
    /// (docs/notes/closest-jammed-release-rule.md).
    MostTensile,
    /// The bond whose release leaves the smallest velocities (the default): seed 001 eqn 2
    /// carried over to the choice (`min_norm_release`). It jams in fewer steps than the most
    /// tensile rule (1.1–1.9 times at N = 100, more than 4 times at N = 1000), and is the only
    /// rule that has jammed N = 1000 starts (same note).
    #[default]
    MinimumNorm,
}

impl Params {
    /// Checks every parameter; the error names the one out of range.
    pub fn validate(&self) -> Result<(), JammingError> {
        let positive = [
            ("max_growth_step", self.max_growth_step),
            ("max_displacement_step", self.max_displacement_step),
            ("skin", self.skin),
            ("dependency_tol", self.dependency_tol),
            ("projection_tol", self.projection_tol),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(JammingError::Parameter(format!(
                    "{name} = {v} must be a positive number"
                )));
            }
        }
        for (name, v) in [
            ("contact_tol", self.contact_tol),
            ("force_tol", self.force_tol),
            ("overlap_tol", self.overlap_tol),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(JammingError::Parameter(format!(
                    "{name} = {v} must be a non-negative number"
                )));
            }
        }
        Ok(())
    }
}

/// Conjugate-gradient iterations of one solve above which the next factorisation is exact (and
/// becomes the new preconditioner).
const REFACTOR_ITERATIONS: usize = 3;

/// What a failed projection after a straight step says about the bond manifold.
enum Fold {
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
const EVENT_OVERSHOOT: f64 = 1e-6;

/// Shortest step, relative to `t`: shortening a step stops here (at a fold, or when pairs are
/// still pushed into overlap).
const SHORTEST_STEP: f64 = 1e-13;

/// A run whose growth factor grows by no more than `STALL_GROWTH` relative in `STALL_STEPS`
/// steps makes no progress (its bonds cycle, or the same step repeats) and stops as
/// `stalled`, keeping its packing.
const STALL_GROWTH: f64 = 1e-14;
const STALL_STEPS: u64 = 10_000;

/// The growth factor and the step at which it last grew by more than `STALL_GROWTH`.
struct GrowthProgress {
    t: f64,
    step: u64,
}

impl GrowthProgress {
    /// Records the growth factor `t` after `steps` steps; true once it has not grown by more
    /// than `STALL_GROWTH` (relative) for `STALL_STEPS` steps.
    fn stalled(&mut self, t: f64, steps: u64) -> bool {
        if t > self.t * (1.0 + STALL_GROWTH) {
            *self = GrowthProgress { t, step: steps };
            false
        } else {
            steps - self.step >= STALL_STEPS
        }
    }
}

/// A factorisation with the basis and positions it was made at.
type CachedFactor = (Vec<Key>, Vec<f64>, Rc<MinNorm>);

/// What the steps did: where the step count of a run comes from.
#[derive(Default, Serialize)]
struct StepCounts {
    /// Steps that ended at a new contact.
    events: u64,
    /// New contacts with independent rows that the step's projection carried apart again
    /// (not admitted; [`Admission::Apart`]).
    events_apart: u64,
    /// Steps ended by a growth or displacement cap.
    capped: u64,
    /// New bonds admitted into the basis.
    added: u64,
    /// New bonds dependent on the basis and consistent with it.
    redundant: u64,
    /// New contacts separating under the current motion.
    separating: u64,
    /// Bonds released at a dependent new bond with tensile forces.
    released_at_admission: u64,
    /// Tensile bonds weighed by the minimum-norm release rule; the forward solves (`(A Aᵀ)⁻¹`
    /// diagonal entries) it made to weigh them, or the releases weighed by one selected
    /// inversion instead; and the wall-clock seconds the rule took.
    release_candidates: u64,
    release_solves: u64,
    release_selected_inversions: u64,
    release_seconds: f64,
    /// Bonds released at a fold of the bond manifold (failed projection).
    released_at_fold: u64,
    /// Failed projections whose step start was singular to rounding (a fold), judged by
    /// [`Solver::fold_multipliers`].
    singular_folds: u64,
    /// Steps shortened after a failed projection with compressive multipliers.
    shortened: u64,
    /// Steps shortened because their projection pushed a pair that is no bond into overlap.
    shortened_by_overlap: u64,
    /// Pairs a projection pushed into overlap however short the step, taken as contacts.
    overlapped_contacts: u64,
    /// Numeric factorisations of a bond matrix.
    factorisations: u64,
    /// Symbolic factorisations (sparsity patterns of `A Aᵀ` built).
    patterns: u64,
    /// Sparse factorisations that failed (dependent rows) and fell back to the dense SVD.
    dense_fallbacks: u64,
    /// Wall-clock seconds in factorisations (symbolic and numeric).
    factorisation_seconds: f64,
    /// Conjugate-gradient solves, their iterations, and solves that did not converge.
    cg_solves: u64,
    cg_iterations: u64,
    cg_failures: u64,
}

/// The integrator's state: the growth state, the bond basis and its factorisation.
struct Integrator<'p> {
    g: Growth,
    p: &'p Params,
    basis: Vec<Key>,
    redundant: Vec<Key>,
    bonded: HashSet<Key>,
    released: u64,
    /// Counters of what each step did, reported in `extra.step_counts`.
    counts: StepCounts,
    solver: Solver,
    /// The last factorisation, for the basis and positions it was made at.
    cached: RefCell<Option<CachedFactor>>,
    /// The last exact sparse factor, which preconditions conjugate-gradient solves of later
    /// steps, and the largest iteration count of those solves.
    preconditioner: RefCell<Option<Rc<Preconditioner>>>,
    cg: Rc<CgStats>,
    /// Largest |Σ_i y_i| / max|y_i| seen (eqn 12 of seed 001: zero total velocity).
    total_velocity: f64,
    /// The velocities of the basis just grown by an independent bond, with the basis and
    /// positions they hold for.
    next_velocities: Option<(Vec<Key>, Vec<f64>, Vec<f64>)>,
    /// Contacts waiting for their admission, the next one last.
    pending: Vec<Key>,
    /// The contact that ended the last step when that step had length zero.
    zero_step_event: Option<Key>,
}

impl Integrator<'_> {
    /// The factorisation of the basis rows `links` at the current positions (reused when
    /// neither changed since the last call): conjugate gradients preconditioned with an earlier
    /// factor while they converge fast, else an exact factor.
    fn factor(&self, links: &[Link]) -> Result<Rc<MinNorm>, String> {
        self.factor_with(links, false)
    }

    /// The same, always exact: for the decisions after a failed step and at the end, where the
    /// preconditioner may be far off and the forward error of an iterative solve (condition
    /// number × tolerance) too large.
    fn factor_exact(&self, links: &[Link]) -> Result<Rc<MinNorm>, String> {
        self.factor_with(links, true)
    }

    /// Projects the basis onto contact with an exact factor (the final projection; `jam` as in
    /// [`project`]).
    fn project_exact(&mut self, jam: Option<(&Key, &[f64])>) -> Result<f64, JammingError> {
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
    fn close_jammed(&mut self, key: &Key, forces: &[f64]) -> f64 {
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

    fn factor_with(&self, links: &[Link], exact: bool) -> Result<Rc<MinNorm>, String> {
        if let Some((keys, x, mn)) = self.cached.borrow().as_ref()
            && *keys == self.basis
            && *x == self.g.x
            && !(exact && matches!(mn.as_ref(), MinNorm::Iterative(_)))
        {
            return Ok(Rc::clone(mn));
        }
        let (n, d) = (self.g.n, self.g.d);
        let reuse = !exact && self.cg.worst.get() <= REFACTOR_ITERATIONS;
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
                let mn = Rc::new(self.solver.factor(&self.basis, links, &self.g)?);
                if let Some(pre) = Preconditioner::new(&mn) {
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
    fn distrust_iterative(&mut self) -> bool {
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
    fn basis_changed(&self) {
        self.cg.worst.set(usize::MAX);
    }

    /// After a bond joined the basis (its last row): the preconditioner is bordered with its
    /// row, which keeps it one of the new basis without a numeric factorisation; when that is
    /// not possible the next factorisation is exact.
    fn bond_added(&self) {
        let links = self.g.links(&self.basis);
        let (n, d) = (self.g.n, self.g.d);
        self.change_preconditioner(|pre| pre.extend(&self.basis, &links, n, d));
    }

    /// After bond `gone` left the basis: the same, the preconditioner drops its row.
    fn bond_released(&self, gone: &Key) {
        self.change_preconditioner(|pre| pre.release(gone));
    }

    fn change_preconditioner(
        &self,
        change: impl FnOnce(&Preconditioner) -> Option<Preconditioner>,
    ) {
        let changed = self.preconditioner.borrow().as_deref().and_then(change);
        match changed {
            Some(pre) => *self.preconditioner.borrow_mut() = Some(Rc::new(pre)),
            None => self.basis_changed(),
        }
    }

    /// Minimum-norm velocities of the basis (eqn 2, `y = A⁺b`).
    ///
    /// # Errors
    /// [`JammingError::Solver`] when the solve failed (non-finite velocities): the basis is
    /// singular at this configuration, although it was independent when its last bond joined.
    fn velocities(&self, links: &[Link], mn: &MinNorm) -> Result<Vec<f64>, JammingError> {
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
    fn max_rank(&self) -> usize {
        let periodic = self.g.container.periodic.iter().filter(|&&p| p).count();
        self.g.n * self.g.d - periodic
    }

    /// Relative overlaps of the candidates that are no bonds, 0 for bonds and pairs apart
    /// (aligned with the candidate keys, which a projection leaves unchanged).
    fn unbonded_overlaps(&self) -> Vec<f64> {
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
    fn grown_overlaps(&self, before: &[f64], event: Option<&Key>) -> Vec<Key> {
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
enum StepOutcome {
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
    fn trace_row(&self, step: u64, time_s: f64, phi: f64) -> TraceRow {
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
    fn step(&mut self) -> Result<StepOutcome, JammingError> {
        if let Some(key) = self.pending.pop() {
            if self.bonded.contains(&key) {
                return Ok(StepOutcome::Admitted);
            }
            let met_now = self.zero_step_event == Some(key);
            if met_now {
                self.zero_step_event = None;
            }
            match self.admit(key, met_now)? {
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
    fn straight_step(&mut self) -> Result<StepOutcome, JammingError> {
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

/// Drives `start` to its closest jammed configuration (seed 001 App. C).
///
/// Returns the jammed packing (termination `jammed`), or the packing reached when `max_steps`,
/// an interrupt or a run without progress stopped it (`max_steps`, `interrupted`, `stalled`:
/// `t` grew by no more than 1e-14 relative in 10 000 steps, `extra.stall` says so). `extra`
/// holds `bonds`, `bonds_redundant`, `bonds_released`, `non_rattler_bonds`, `n_dof`, `rattlers`,
/// `total_velocity_max` (eqn 12), `min_force_ratio`, `final_bond_gap`, `growth_factor` and
/// `step_counts` (what the steps did: contact events, capped steps, admissions, releases at
/// admission and at folds, numeric and symbolic factorisations, conjugate-gradient solves).
///
/// # Errors
/// [`JammingError::InvalidPacking`] and [`JammingError::Overlap`] for a bad start,
/// [`JammingError::Parameter`] for bad options, [`JammingError::Solver`] when the bond matrix
/// cannot be factorised.
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
        bonded: HashSet::new(),
        released: 0,
        counts: StepCounts::default(),
        solver: Solver::new(params.dense_max_bonds),
        cached: RefCell::new(None),
        preconditioner: RefCell::new(None),
        cg: Rc::new(CgStats::default()),
        total_velocity: 0.0,
        next_velocities: None,
        pending: Vec::new(),
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
    let termination = loop {
        // A run stops only between steps, with every contact admitted: the contact that ended
        // the last step may overlap by up to `EVENT_OVERSHOOT` until its admission closes it.
        if it.pending.is_empty() {
            if observer.should_stop() {
                break "interrupted";
            }
            if steps >= params.max_steps {
                break "max_steps";
            }
            if progress.stalled(it.g.t, steps) {
                break "stalled";
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

/// Bonds among non-rattlers, `n_dof = d·N' − m + 1`, and the rattler count of a bond network
/// (rattlers removed recursively by the core's rule: fewer than d+1 bonds).
pub(crate) fn bond_count(g: &Growth, basis: &[Key], redundant: &[Key]) -> (usize, usize, usize) {
    let mut net = ContactNetwork::default();
    for key in basis.iter().chain(redundant) {
        let l = g.link(key);
        net.contacts.push(Contact {
            i: l.i,
            j: l.j,
            wall: None,
            gap: 0.0,
        });
    }
    let rattler = rattlers(&net, g.n, g.d);
    let active = rattler.iter().filter(|&&r| !r).count();
    let bonds = net
        .contacts
        .iter()
        .filter(|c| !rattler[c.i] && c.j.is_none_or(|j| !rattler[j]))
        .count();
    let n_dof = if active == 0 {
        0
    } else {
        (g.d * active + 1).saturating_sub(g.container.rigid_motions())
    };
    (bonds, n_dof, g.n - active)
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
