//! Leaving a cycle of bond exchanges at a degenerate configuration.
//!
//! Where more contacts sit at zero gap than the basis can hold (a 2D crystal patch, or the
//! last bonds of a packing near jamming), each dependent new contact releases a tensile bond
//! whose pair the next step of length zero meets again, and the growth factor stops. Like
//! the simplex method at a degenerate vertex, exchanging one bond at a time can then cycle
//! for ever: 2D starts of 100 disks ran 10 000 exchanges without growth. The equations of
//! Baranau & Tallarek 2014 App. C only ask for the minimum-norm velocities that keep every bond in contact;
//! App. B's steepest descent, `min ‖y‖²` subject to `a_c·y ≥ D_c` for *every* contact, picks
//! the bonds that must stay closed all at once. So after `CYCLING_STEPS` steps without
//! growth one such quadratic program (the QP form's step, [`super::qp_form`]) chooses the
//! bonds: the contacts it holds (positive duals), or the support of its certificate when it
//! is infeasible (then the packing is jammed), are admitted again one by one, largest dual
//! first, and the integrator's own admission finds the basis, the redundant bonds and, at a
//! jam, the forces. The other contacts open along the program's velocities.

use super::Integrator;
use super::qp_form::{self, steepest_descent};
use crate::contacts::Key;
use crate::error::JammingError;

impl Integrator<'_> {
    /// Replaces the bond set by the contacts that one quadratic program over every contact at
    /// contact holds (module doc), to be admitted from `pending`. The released bonds count in
    /// `bonds_released`.
    ///
    /// # Errors
    /// [`JammingError::Solver`] when clarabel fails.
    pub(super) fn leave_cycle(&mut self) -> Result<(), JammingError> {
        let contacts: Vec<Key> = self
            .g
            .candidates
            .keys
            .iter()
            .filter(|k| {
                self.bonded.contains(k) || self.g.link(k).rel_gap(self.g.t) <= self.p.contact_tol
            })
            .copied()
            .collect();
        // The QP form's own tolerances.
        let qp = qp_form::Params::default();
        let (_, mut held) = steepest_descent(&self.g, &contacts, qp.qp_tol, qp.active_tol)
            .map_err(|e| JammingError::Solver(format!("closest-jammed, leaving a cycle: {e}")))?;
        // `pending` is popped from its end: the largest dual is admitted first.
        held.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
        self.released += self
            .basis
            .iter()
            .filter(|k| !held.iter().any(|(h, _)| h == *k))
            .count() as u64;
        self.basis.clear();
        self.redundant.clear();
        self.bonded.clear();
        *self.cached.borrow_mut() = None;
        *self.preconditioner.borrow_mut() = None;
        self.next_velocities = None;
        self.zero_step_event = None;
        self.basis_changed();
        self.pending = held.into_iter().map(|(k, _)| k).collect();
        self.counts.cycles_left += 1;
        Ok(())
    }
}
