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
//! reused, see `min_norm.rs`) once a solve needs more than `REFACTOR_ITERATIONS`, after a bond
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
use crate::min_norm::{CgStats, DIAGONAL_BATCH, MinNorm, Preconditioner, Solver};
use crate::projection::project;

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

/// Smallest force over the largest force magnitude.
fn min_force_ratio(forces: &[f64]) -> f64 {
    let fmax = forces.iter().fold(0.0f64, |m, &f| m.max(f.abs()));
    forces.iter().fold(f64::INFINITY, |m, &f| m.min(f)) / fmax
}

/// A basis bond is clearly tensile when its force is below `−CLEAR_TENSION·max |f|` (the new
/// bond's own force is +1, so [`min_force_ratio`] of all forces tells).
const CLEAR_TENSION: f64 = 1e-3;

/// The range of a new bond's computed relative distance from the basis rows' span in which it
/// is computed again with one correction ([`Integrator::dependence`]). Below it the Gram solve
/// lost nothing that matters (a well-conditioned basis gives 1e-16 to 1e-13 for a row in its
/// span); above it the row is independent by a wide margin.
const DEPENDENCE_REFINED: (f64, f64) = (1e-12, 1e-3);

/// What became of a new bond.
enum Admission {
    /// Joined the basis.
    Added,
    /// Dependent and consistent with the other bonds: kept in contact by them.
    Redundant,
    /// Separating under the current motion: not a bond.
    Separating,
    /// Independent but apart: the projection after the step that met it bent the path and
    /// carried the pair apart again (near a fold, by up to 1e-5 relative). Joining the basis
    /// would pull it shut against the growth; it is met again later.
    Apart,
    /// Made the system unsolvable with a tensile force on basis bond `k`, which was released.
    Released,
    /// Made the system unsolvable with all forces compressive: jammed. Forces on the basis
    /// bonds, then on the new bond.
    Jammed(Vec<f64>),
}

/// What a failed projection after a straight step says about the bond manifold.
enum Fold {
    /// Nothing: the step was projected.
    None,
    /// Basis bond `k` is tensile and is released.
    Release(usize),
    /// The bonds cannot grow and every multiplier is compressive: jammed, with these forces.
    Jammed(Vec<f64>),
}

/// The basis bond with the most tensile multiplier, if it is below `−force_tol·max |λ|`.
fn tensile_bond(lambda: &[f64], force_tol: f64) -> Option<usize> {
    let lmax = lambda.iter().fold(0.0f64, |m, &l| m.max(l.abs()));
    let (k, lmin) =
        lambda.iter().enumerate().fold(
            (usize::MAX, 0.0),
            |(w, m), (k, &l)| if l < m { (k, l) } else { (w, m) },
        );
    (k != usize::MAX && lmin < -force_tol * lmax).then_some(k)
}

/// Relative overlap the contact that ends a step may reach after the step's projection: the
/// path bends, so the straight step overshoots that contact at second order; it becomes a bond
/// at once and is closed exactly, but a larger overshoot means the step was too long.
const EVENT_OVERSHOOT: f64 = 1e-6;

/// Shortest step, relative to `t`: shortening a step stops here (at a fold, or when pairs are
/// still pushed into overlap).
const SHORTEST_STEP: f64 = 1e-13;

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
}

/// How [`Integrator::min_norm_release`] weighed the tensile bonds.
enum Weighing {
    /// With this many pruned forward solves.
    Solves(u64),
    /// With one selected inversion of the factor.
    SelectedInversion,
}

/// How a new bond's row relates to the basis ([`Integrator::dependence`]).
struct Dependence {
    independence: f64,
    res: f64,
    forces: Vec<f64>,
    off_span: Vec<f64>,
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
    /// `key` rejoins the basis. Returns the largest relative bond gap.
    fn close_jammed(&mut self, key: &Key, forces: &[f64]) -> f64 {
        self.bonded.insert(*key);
        let before = self.g.snapshot();
        let overlaps = self.unbonded_overlaps();
        let closed = self.project_exact(Some((key, forces)));
        self.basis.push(*key);
        match closed {
            Ok(gap) if self.grown_overlaps(&overlaps, None).is_empty() => gap,
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

    /// Releases basis bond `k`. Redundant bonds were held in contact by the basis rows they
    /// depend on, which no longer span them, so they go back to `pending` to be admitted again
    /// (left redundant, such a pair drifts into overlap: two spheres of a thin slab once ended
    /// at the same place, when a release at admission skipped this).
    fn release(&mut self, k: usize, pending: &mut Vec<Key>) {
        let gone = self.basis.remove(k);
        self.bonded.remove(&gone);
        self.bond_released(&gone);
        for key in self.redundant.drain(..) {
            self.bonded.remove(&key);
            pending.push(key);
        }
        self.released += 1;
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

    /// Adds bond `key` at the current configuration, keeping the basis independent. A bond
    /// released for it frees its redundant bonds into `pending` ([`Self::release`]).
    fn admit(&mut self, key: Key, pending: &mut Vec<Key>) -> Result<Admission, JammingError> {
        // Its row a joins the basis when its distance to the basis rows' span is not tiny.
        let Dependence {
            independence,
            mut res,
            mut forces,
            off_span,
        } = self.dependence(&key)?;
        if independence > self.p.dependency_tol && self.basis.len() < self.max_rank() {
            if self.g.link(&key).rel_gap(self.g.t) > self.p.contact_tol {
                return Ok(Admission::Apart);
            }
            // A contact the motion opens (`a_k·y > b_k`) needs no bond. Contact events always
            // close, but the redundant bonds a release sends back may not: re-bonding such a
            // partner of the released bond restored its span, and a 6D crystal cycled at a
            // fold, releasing and re-adding for ever.
            if res < 0.0 {
                return Ok(Admission::Separating);
            }
            let links = self.g.links(&self.basis);
            let mn = self.factor(&links).map_err(JammingError::Solver)?;
            let velocities = self.velocities(&links, &mn)?;
            // The minimum-norm velocities with the new row from those without it (block
            // elimination, no solve with the grown basis): `y' = y + (res/|e|²) e` meets the
            // new row (`a_k·e = |e|²`), leaves the others (`A e = 0`), and stays in the span.
            let scale = res / off_span.iter().map(|v| v * v).sum::<f64>();
            let grown = velocities
                .iter()
                .zip(&off_span)
                .map(|(y, e)| y + scale * e)
                .collect();
            self.basis.push(key);
            self.bonded.insert(key);
            self.bond_added();
            self.next_velocities = Some((self.basis.clone(), self.g.x.clone(), grown));
            return Ok(Admission::Added);
        }
        if res.abs() <= self.p.dependency_tol * self.g.link(&key).size {
            self.redundant.push(key);
            self.bonded.insert(key);
            return Ok(Admission::Redundant);
        }
        if res < 0.0 {
            return Ok(Admission::Separating);
        }
        // Move to the exact point where the new bond touches while the basis stays in contact,
        // in positions and t (fᵀD = fᵀb > 0, so δt is defined whatever the force signs); the
        // forces, judged there, are exact even for degenerate networks whose forces vanish.
        // With mixed-sign forces fᵀD may be near zero and the projection ill-posed; then the
        // configuration where the step stopped is kept.
        let before = self.g.snapshot();
        let overlaps = self.unbonded_overlaps();
        for pass in 0..2 {
            let links = self.g.links(&self.basis);
            let mn = self.factor(&links).map_err(JammingError::Solver)?;
            let projected = project(
                &mut self.g,
                &self.basis,
                Some((&links, &mn)),
                Some((&key, &forces)),
                self.p.projection_tol,
                &self.solver,
            );
            // An ill-posed projection can also converge far away, with pairs that are no bonds
            // overlapping: it is undone like a failed one.
            if projected.is_err() || !self.grown_overlaps(&overlaps, None).is_empty() {
                self.g.restore(&before);
                // A new bond still apart would, once in the basis, be closed by pushing the
                // pair of the bond it replaces into overlap (by its gap over that bond's
                // |force|, from fᵀA = 0): it is left to be met again as a contact.
                if self.g.link(&key).rel_gap(self.g.t) > self.p.contact_tol {
                    return Ok(Admission::Separating);
                }
                Dependence { res, forces, .. } = self.dependence(&key)?;
                break;
            }
            // The projection moves the particles by the drift of one straight step, which
            // changes the forces at that order: a clearly tensile bond, judged just before it,
            // is released without the refactorisation that judging after it costs.
            if pass == 0 && min_force_ratio(&forces) < -CLEAR_TENSION {
                break;
            }
            Dependence { res, forces, .. } = self.dependence(&key)?;
        }
        let fmax = forces.iter().fold(0.0f64, |m, &f| m.max(f.abs()));
        let tensile: Vec<usize> = (0..forces.len() - 1)
            .filter(|&k| forces[k] < -self.p.force_tol * fmax)
            .collect();
        if tensile.is_empty() {
            return Ok(Admission::Jammed(forces));
        }
        // A tensile bond: release it, keep the new one (the configuration satisfies both sets).
        let k = match self.p.release_rule {
            ReleaseRule::MostTensile => tensile
                .iter()
                .copied()
                .min_by(|&a, &b| forces[a].total_cmp(&forces[b]))
                .expect("a tensile bond"),
            ReleaseRule::MinimumNorm => {
                let clock = std::time::Instant::now();
                let (k, weighing) = self.min_norm_release(&tensile, &forces, res)?;
                let counts = &mut self.counts;
                counts.release_seconds += clock.elapsed().as_secs_f64();
                counts.release_candidates += tensile.len() as u64;
                match weighing {
                    Weighing::Solves(solves) => counts.release_solves += solves,
                    Weighing::SelectedInversion => counts.release_selected_inversions += 1,
                }
                k
            }
        };
        self.release(k, pending);
        self.basis.push(key);
        self.bonded.insert(key);
        self.bond_added();
        Ok(Admission::Released)
    }

    /// Which of the `tensile` basis bonds to release at a dependent new bond with forces
    /// `forces` and residual `res`: the one whose release leaves the smallest velocities, seed
    /// 001 eqn 2 carried over to the choice of the bond that opens.
    ///
    /// Releasing bond k (force f_k < 0) while the other bonds and the new one stay in contact
    /// leaves one velocity field in the rows' span, `y' = Aᵀ G⁻¹ (b + r_k e_k)` with
    /// `G = A Aᵀ`: bond k opens at the rate `r_k = res/(−f_k) > 0` that the new bond's
    /// consistency fixes (`fᵀ A y' = 0`). So `‖y'‖² − ‖y‖² = 2 r_k λ_k + r_k² (G⁻¹)_kk`, with
    /// `λ = G⁻¹ b` the multipliers. Searched exactly with pruning: with `G = Pᵀ L Lᵀ P`,
    /// `(G⁻¹)_kk = ‖L⁻¹ P e_k‖²` is at least its part in the first supernode of the solve, so
    /// the bonds are visited by that lower bound, the search ends once it exceeds the best, and
    /// each forward solve stops once its partial sum does. When the solves would cost more
    /// than a selected inversion of the factor, which gives every `(G⁻¹)_kk` at once, that is
    /// used instead. Returns the bond and how the bonds were weighed.
    fn min_norm_release(
        &self,
        tensile: &[usize],
        forces: &[f64],
        res: f64,
    ) -> Result<(usize, Weighing), JammingError> {
        let links = self.g.links(&self.basis);
        let mut mn = self.factor(&links).map_err(JammingError::Solver)?;
        // A preconditioner bordered since its factor holds no factor of these bonds.
        if !mn.holds_factor() {
            mn = self.factor_exact(&links).map_err(JammingError::Solver)?;
        }
        let lambda = mn.multipliers(&links, self.g.n, self.g.d);
        let rate = |k: usize| res / -forces[k];
        let growth = |k: usize, gkk: f64| 2.0 * rate(k) * lambda[k] + rate(k).powi(2) * gkk;
        if let Some(diagonals) = mn.inverse_diagonals_by_selected_inversion(tensile) {
            let best = tensile
                .iter()
                .zip(diagonals)
                .map(|(&k, gkk)| (growth(k, gkk), k))
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .expect("a tensile bond");
            return Ok((best.1, Weighing::SelectedInversion));
        }
        // The first supernode of each forward solve: a lower bound of (G⁻¹)_kk.
        let floor = vec![f64::NEG_INFINITY; tensile.len()];
        let bounds = mn
            .inverse_diagonals(tensile, &floor)
            .unwrap_or_else(|| vec![0.0; tensile.len()]);
        let mut order: Vec<(f64, f64, usize)> = tensile
            .iter()
            .zip(&bounds)
            .map(|(&k, &bound)| (growth(k, bound), rate(k), k))
            .collect();
        order.sort_by(|a, b| a.0.total_cmp(&b.0));
        // Weighed in the order of their bounds, in batches that double up to the size of one
        // batch of forward solves (the first ones set a good best early); each solve stops at
        // the best growth so far, and the search ends at a bound above it.
        let (mut best, mut release, mut solves) = (f64::INFINITY, order[0].2, 0);
        let (mut next, mut size) = (0, 1);
        while next < order.len() && order[next].0 < best {
            let batch: Vec<&(f64, f64, usize)> = order[next..]
                .iter()
                .take_while(|c| c.0 < best)
                .take(size)
                .collect();
            size = (2 * size).min(DIAGONAL_BATCH);
            next += batch.len();
            solves += batch.len() as u64;
            let ks: Vec<usize> = batch.iter().map(|c| c.2).collect();
            let caps: Vec<f64> = batch
                .iter()
                .map(|&&(_, r, k)| (best - 2.0 * r * lambda[k]) / (r * r))
                .collect();
            let diagonals = mn
                .inverse_diagonals(&ks, &caps)
                .unwrap_or_else(|| vec![f64::INFINITY; ks.len()]);
            for (&&(_, _, k), gkk) in batch.iter().zip(diagonals) {
                let growth = growth(k, gkk);
                if growth < best {
                    (best, release) = (growth, k);
                }
            }
        }
        Ok((release, Weighing::Solves(solves)))
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

    /// For a bond `key` and the basis: `‖a_k − Aᵀf'‖/‖a_k‖` with `f' = (A⁺)ᵀ a_k` (how far its row
    /// is from the basis rows' span; 0 for a self-image), the residual `b_k − a_k·y` (= fᵀb when
    /// dependent), the would-be left null vector `f = (−f', 1)` of the basis plus `key`, and
    /// the part `e = a_k − Aᵀf'` of its row off the span.
    fn dependence(&self, key: &Key) -> Result<Dependence, JammingError> {
        let d = self.g.d;
        let links = self.g.links(&self.basis);
        let mn = self.factor(&links).map_err(JammingError::Solver)?;
        let lk = self.g.link(key);
        let mut a = vec![0.0; self.g.n * d];
        lk.add_transposed(1.0, &mut a, d);
        let norm_a = a.iter().map(|v| v * v).sum::<f64>().sqrt();
        let mut comb = mn.row_combination(&links, &a, d);
        let mut e = a;
        for (l, &c) in links.iter().zip(&comb) {
            l.add_transposed(-c, &mut e, d);
        }
        let relative = |e: &[f64]| match norm_a > 0.0 {
            true => e.iter().map(|v| v * v).sum::<f64>().sqrt() / norm_a,
            false => 0.0,
        };
        let mut independence = relative(&e);
        // The Gram (normal-equation) solve errs by about cond(A)²·ε; its error lies in the
        // span, so it shows as a distance from the span of a row that has none. Near a
        // crystal, where the basis is ill-conditioned, a row in the span can so seem off it
        // by more than `dependency_tol`, and the forces of a dependent one are inexact enough
        // to release the wrong bond for ever (a 6D crystal stalled so). One correction with
        // the same factor (Björck's corrected semi-normal equations) brings the error to about
        // cond(A)·ε.
        if (DEPENDENCE_REFINED.0..DEPENDENCE_REFINED.1).contains(&independence) {
            let correction = mn.row_combination(&links, &e, d);
            for ((l, &dc), c) in links.iter().zip(&correction).zip(&mut comb) {
                l.add_transposed(-dc, &mut e, d);
                *c += dc;
            }
            independence = relative(&e);
        }
        // b_k − a_k·y = b_k − f'·b without the velocities: y is in the rows' span, to which
        // e = a_k − Aᵀf' is orthogonal, and A y = b.
        let res = lk.size
            - comb
                .iter()
                .zip(&links)
                .map(|(c, l)| c * l.size)
                .sum::<f64>();
        let mut forces: Vec<f64> = comb.iter().map(|&c| -c).collect();
        forces.push(1.0);
        Ok(Dependence {
            independence,
            res,
            forces,
            off_span: e,
        })
    }
}

/// Drives `start` to its closest jammed configuration (seed 001 App. C).
///
/// Returns the jammed packing (termination `jammed`), or the packing reached when `max_steps`
/// or an interrupt stopped the run (`max_steps`, `interrupted`). `extra` holds `bonds`,
/// `bonds_redundant`, `bonds_released`, `non_rattler_bonds`, `n_dof`, `rattlers`,
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
    let (n, d) = (g.n, g.d);
    let periodic = g.container.is_fully_periodic();
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
    let mut pending: Vec<Key> = pending.into_iter().map(|(_, k)| k).collect();

    let mut trace = Vec::new();
    let mut steps = 0u64;
    let mut last_report = Instant::now();
    let mut jam_forces: Option<(Key, Vec<f64>)> = None;
    let termination;
    loop {
        if let Some(key) = pending.pop() {
            if it.bonded.contains(&key) {
                continue;
            }
            match it.admit(key, &mut pending)? {
                Admission::Jammed(f) => {
                    jam_forces = Some((key, f));
                    termination = "jammed";
                    break;
                }
                Admission::Added => it.counts.added += 1,
                Admission::Redundant => it.counts.redundant += 1,
                Admission::Released => it.counts.released_at_admission += 1,
                Admission::Separating => it.counts.separating += 1,
                Admission::Apart => it.counts.events_apart += 1,
            }
            if !pending.is_empty() {
                continue;
            }
        }
        // A run stops only between steps, with every contact admitted: the contact that ended
        // the last step may overlap by up to `EVENT_OVERSHOOT` until its admission closes it.
        if observer.should_stop() {
            termination = "interrupted";
            break;
        }
        if steps >= params.max_steps {
            termination = "max_steps";
            break;
        }
        let links = it.g.links(&it.basis);
        let mn = it.factor(&links).map_err(JammingError::Solver)?;
        let y = match it.next_velocities.take() {
            Some((basis, x, y)) if basis == it.basis && x == it.g.x => y,
            _ => it.velocities(&links, &mn)?,
        };
        if params.open_tensile_bonds
            && let Some(k) = tensile_bond(&mn.multipliers(&links, n, d), params.force_tol)
        {
            it.release(k, &mut pending);
            continue;
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
            it.total_velocity = it.total_velocity.max(tv / vmax);
        }
        // Next new contact along the straight motion, capped for accuracy and list validity.
        let cap = (params.max_growth_step * it.g.t)
            .min(it.g.safe_step(vmax))
            .min(params.max_displacement_step * it.g.mean_diameter() / vmax.max(f64::MIN_POSITIVE));
        let mut tau = cap;
        let mut event: Option<Key> = None;
        for (_, key) in it.g.candidates.within(cap * it.g.shrink_rate(vmax)) {
            if it.bonded.contains(key) {
                continue;
            }
            let l = it.g.link(key);
            if let Some(tc) = contact_time(&l, &y, it.g.t, d)
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
        let saved = it.g.snapshot();
        let overlaps = it.unbonded_overlaps();
        let mut overlapped = Vec::new();
        let mut fold: Fold = Fold::None;
        loop {
            it.g.advance(&y, tau);
            let projected = project(
                &mut it.g,
                &it.basis,
                Some((&links, &mn)),
                None,
                params.projection_tol,
                &it.solver,
            );
            let failed = match projected {
                Ok(_) => {
                    overlapped = it.grown_overlaps(&overlaps, event.as_ref());
                    // Pairs still pushed in at the shortest step come from a gap the basis had
                    // at the step's start (`admit` no longer leaves one for a bond still apart,
                    // so this is a safety net): they are taken as contacts.
                    if overlapped.is_empty() || tau <= SHORTEST_STEP * it.g.t {
                        break;
                    }
                    None
                }
                Err(e) => Some(e),
            };
            it.g.restore(&saved);
            match failed {
                None => {
                    tau *= 0.25;
                    event = None;
                    it.counts.shortened_by_overlap += 1;
                }
                Some(e) => {
                    // The fold is judged by the signs of exact multipliers; a step start so
                    // close to the fold that the basis is singular to rounding takes them
                    // from a shifted factor.
                    let lambda = match it.factor_exact(&links) {
                        Ok(mn) => mn.multipliers(&links, n, d),
                        Err(_) => {
                            it.counts.singular_folds += 1;
                            it.solver
                                .fold_multipliers(&it.basis, &links, n, d)
                                .map_err(JammingError::Solver)?
                        }
                    };
                    if let Some(k) = tensile_bond(&lambda, params.force_tol) {
                        fold = Fold::Release(k);
                        break;
                    }
                    tau *= 0.25;
                    event = None;
                    it.counts.shortened += 1;
                    if tau < SHORTEST_STEP * it.g.t {
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
                it.counts.released_at_fold += 1;
                it.release(k, &mut pending);
                continue;
            }
            Fold::Jammed(lambda) => {
                // The fold's forces are λ/|λ|: the most loaded bond leaves the basis and closes
                // through the growth factor in the final projection.
                let k = (0..lambda.len())
                    .max_by(|&a, &b| lambda[a].total_cmp(&lambda[b]))
                    .expect("non-empty");
                let key = it.basis.remove(k);
                let mut forces = lambda;
                let fk = forces.remove(k);
                forces.push(fk);
                jam_forces = Some((key, forces));
                termination = "jammed";
                break;
            }
        }
        it.counts.overlapped_contacts += overlapped.len() as u64;
        pending.append(&mut overlapped);
        if let Some(key) = event {
            pending.push(key);
            it.counts.events += 1;
        } else {
            it.counts.capped += 1;
        }
        it.g.refresh();
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
            trace.push(TraceRow {
                step: steps,
                time_s: clock.elapsed().as_secs_f64(),
                phi,
                values: vec![
                    ("bonds".into(), it.basis.len() as f64),
                    ("bonds_released".into(), it.released as f64),
                ],
            });
        }
    }
    let mut final_gap = f64::NAN;
    let mut min_force_ratio = f64::NAN;
    if let Some((key, forces)) = &jam_forces {
        final_gap = it.close_jammed(key, forces);
        min_force_ratio = self::min_force_ratio(forces);
    } else if !it.basis.is_empty() {
        // A stopped run: bonds admitted since the last step's projection (they may overlap by
        // up to `EVENT_OVERSHOOT`) are closed too, so the packing returned is overlap-free.
        // A failed projection leaves the configuration as it was.
        let _ = it.project_exact(None);
    }
    let phi = it.g.phi(phi0);
    trace.push(TraceRow {
        step: steps,
        time_s: clock.elapsed().as_secs_f64(),
        phi,
        values: vec![
            ("bonds".into(), it.basis.len() as f64),
            ("bonds_released".into(), it.released as f64),
        ],
    });
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
    ] {
        extra.insert(k.into(), v);
    }
    Ok(Outcome {
        packing: it.g.packing(),
        steps,
        termination: termination.into(),
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
