//! Admission and release of bonds in the equality form: a new contact joins the basis, is
//! kept in contact by it (dependent and consistent), separates, or makes the system
//! unsolvable, when a tensile bond is released ([`ReleaseRule`]) or the packing is jammed
//! (Baranau & Tallarek 2014 App. C, Farkas). The dependence of a new bond's row on the basis is the residual
//! of a minimum-norm Gram solve, refined once in the range where rounding could decide it.

use packbench_core::analysis::{Contact, ContactNetwork, rattlers};

use super::{Integrator, Params, ReleaseRule};
use crate::contacts::{Key, Link};
use crate::error::JammingError;
use crate::growth::Growth;
use crate::min_norm::{DIAGONAL_BATCH, MinNorm};
use crate::projection::project;

/// A basis bond is clearly tensile when its force is below `−CLEAR_TENSION·max |f|` (the new
/// bond's own force is +1, so [`min_force_ratio`] of all forces tells).
const CLEAR_TENSION: f64 = 1e-3;

/// The range of a new bond's computed relative distance from the basis rows' span in which it
/// is computed again with one correction ([`Integrator::dependence`]). Below it the Gram solve
/// lost nothing that matters (a well-conditioned basis gives 1e-16 to 1e-13 for a row in its
/// span); above it the row is independent by a wide margin.
const DEPENDENCE_REFINED: (f64, f64) = (1e-12, 1e-3);

/// What became of a new bond.
pub(super) enum Admission {
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

/// The basis bond with the most tensile multiplier, if it is below `−force_tol·max |λ|`.
pub(crate) fn tensile_bond(lambda: &[f64], force_tol: f64) -> Option<usize> {
    let lmax = lambda.iter().fold(0.0f64, |m, &l| m.max(l.abs()));
    let (k, lmin) =
        lambda.iter().enumerate().fold(
            (usize::MAX, 0.0),
            |(w, m), (k, &l)| if l < m { (k, l) } else { (w, m) },
        );
    (k != usize::MAX && lmin < -force_tol * lmax).then_some(k)
}

/// Smallest force over the largest force magnitude.
pub(super) fn min_force_ratio(forces: &[f64]) -> f64 {
    let fmax = forces.iter().fold(0.0f64, |m, &f| m.max(f.abs()));
    forces.iter().fold(f64::INFINITY, |m, &f| m.min(f)) / fmax
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
    /// Releases basis bond `k`. Redundant bonds were held in contact by the basis rows they
    /// depend on, which no longer span them, so they go back to `pending` to be admitted again
    /// (left redundant, such a pair drifts into overlap: two spheres of a thin slab once ended
    /// at the same place, when a release at admission skipped this).
    pub(super) fn release(&mut self, k: usize) {
        let gone = self.basis.remove(k);
        self.bonded.remove(&gone);
        self.bond_released(&gone);
        for key in self.redundant.drain(..) {
            self.bonded.remove(&key);
            self.pending.push(key);
        }
        self.released += 1;
    }

    /// Adds bond `key` at the current configuration, keeping the basis independent. A bond
    /// released for it frees its redundant bonds into the pending contacts ([`Self::release`]).
    ///
    /// `met_now`: `key` ended a step of length zero, so the velocities of this configuration
    /// close it (`a_k·y < b_k`). A residual `b_k − a_k·y` of the other sign then says the two
    /// computations of it disagree, and nothing else changes before the same step is taken
    /// again: a 2D start of 100 disks repeated one for 240 000 steps. With iterative solves
    /// the next ones are made exact ([`Self::distrust_iterative`]); with exact ones the
    /// residual is rounding, and the bond is kept in contact ([`Self::at_rest`]).
    // Long because admitting a contact (its slot, the solvability test, the release it may force,
    // the factor update) is one transaction that must leave the bond set consistent at every exit.
    pub(super) fn admit(&mut self, key: Key, met_now: bool) -> Result<Admission, JammingError> {
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
            if res < 0.0 && !self.at_rest(met_now) {
                return Ok(Admission::Separating);
            }
            // The velocities of the grown basis, for the step that follows, when none of the
            // contacts still waiting is admitted before it (from a start at contact they all
            // are, one solve each for velocities that the next admission discards).
            let grown = match self.pending.is_empty() {
                true => Some(self.grown_velocities(res, &off_span)?),
                false => None,
            };
            self.basis.push(key);
            self.bonded.insert(key);
            self.bond_added();
            self.next_velocities = grown.map(|y| (self.basis.clone(), self.g.x.clone(), y));
            return Ok(Admission::Added);
        }
        let consistent = res.abs() <= self.p.dependency_tol * self.g.link(&key).size;
        if consistent || (res < 0.0 && self.at_rest(met_now)) {
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
        self.release(k);
        self.basis.push(key);
        self.bonded.insert(key);
        self.bond_added();
        Ok(Admission::Released)
    }

    /// The minimum-norm velocities of the basis grown by a new row off its span by `off_span`
    /// with residual `res`, from those without it (block elimination, no solve with the grown
    /// basis): `y' = y + (res/|e|²) e` meets the new row (`a_k·e = |e|²`), leaves the others
    /// (`A e = 0`), and stays in the span.
    fn grown_velocities(&self, res: f64, off_span: &[f64]) -> Result<Vec<f64>, JammingError> {
        let links = self.g.links(&self.basis);
        let mn = self.factor(&links).map_err(JammingError::Solver)?;
        let velocities = self.velocities(&links, &mn)?;
        let scale = res / off_span.iter().map(|v| v * v).sum::<f64>();
        Ok(velocities
            .iter()
            .zip(off_span)
            .map(|(y, e)| y + scale * e)
            .collect())
    }

    /// Whether a new bond with a residual that says it separates is at rest instead: `met_now`
    /// (the velocities say it closes, see [`Self::admit`]) and the solves exact. With
    /// iterative solves the next factorisation is made exact and the bond is met again.
    fn at_rest(&mut self, met_now: bool) -> bool {
        met_now && !self.distrust_iterative()
    }

    /// Which of the `tensile` basis bonds to release at a dependent new bond with forces
    /// `forces` and residual `res`: the one whose release leaves the smallest velocities,
    /// Baranau & Tallarek 2014 eqn 2 carried over to the choice of the bond that opens.
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
        // A preconditioner bordered since its factor holds no factor of these bonds; an updated
        // one does, but many bonds are weighed faster on a fresh supernodal factor.
        if !mn.holds_factor() || mn.fresh_factor_pays(tensile) {
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

/// The bond the active-set form of the QP (`open_tensile_bonds` of the equality form's
/// [`crate::closest_jammed::Params`]) opens before a step: the most tensile basis bond, when a
/// Lagrange multiplier `λ = (A Aᵀ)⁻¹ D` of the minimum-norm solve with factor `mn` of the basis
/// rows `links` is below `−force_tol·max |λ|` (steepest descent, Baranau & Tallarek 2014 App. B). `None` in
/// the equality form, which opens bonds only where the bonded system has no solution.
pub(crate) fn opening_bond(
    params: &Params,
    mn: &MinNorm,
    links: &[Link],
    n: usize,
    d: usize,
) -> Option<usize> {
    if !params.open_tensile_bonds {
        return None;
    }
    tensile_bond(&mn.multipliers(links, n, d), params.force_tol)
}
