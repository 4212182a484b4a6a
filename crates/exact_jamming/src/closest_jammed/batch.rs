//! Batched exchanges: at a dependent new bond whose forces are tensile on several basis bonds,
//! every one of them is released at once and the new bond joins, instead of the one bond the
//! release rule picks.
//!
//! Releasing any set of bonds with a non-zero force leaves the new bond's row independent of
//! the rest (the forces are the only left null vector of the basis plus the new row), so the
//! smaller basis always has minimum-norm velocities. Unlike a single release, whose bond opens
//! at the rate `res/(−f_k) > 0` that the new bond's consistency fixes, released bonds of a
//! batch are not bound to open under those velocities: one that closes would be met again by a
//! step of length zero. So the released bonds that those velocities do not open at a relative
//! rate above `dependency_tol` (`a_k·y − D_k ≤ dependency_tol·D_k`) are kept, and the smaller
//! batch is tried again; the batch **fails** when fewer than two bonds are left to release, and
//! the single release of the release rule is made instead. Contacts are already admitted in a
//! batch: every pending contact (the one that ended the step and pairs the projection pushed
//! into overlap) is admitted before the next step.
//!
//! Off by default: at N = 1000 it released 1.6 times the bonds and took 1.9 times the CPU
//! (docs/notes/closest-jammed-release-rule.md).

use super::Integrator;
use crate::contacts::Key;
use crate::error::JammingError;

impl Integrator<'_> {
    /// Releases the basis bonds at the indices `tensile`, less those the smaller basis's
    /// velocities close, and admits `key` in one batch (module doc), when `batch_releases` is
    /// on and more than one bond is tensile. Returns whether a batch was kept; when not, the
    /// basis is as before (`batch_failures` counts such batches) and the next factorisation is
    /// exact. Each round is one exact factorisation (`batch_rounds` counts the repeated ones).
    ///
    /// # Errors
    /// [`JammingError::Solver`] when the smaller basis cannot be factorised.
    pub(super) fn batch_release(
        &mut self,
        key: Key,
        tensile: &[usize],
    ) -> Result<bool, JammingError> {
        if !self.p.batch_releases || tensile.len() < 2 {
            return Ok(false);
        }
        let before = self.basis.clone();
        let mut gone: Vec<Key> = tensile.iter().map(|&k| before[k]).collect();
        let y = loop {
            if gone.len() < 2 {
                self.basis = before;
                self.basis_changed();
                self.counts.batch_failures += 1;
                return Ok(false);
            }
            self.basis = (before.iter().filter(|k| !gone.contains(k)))
                .copied()
                .chain([key])
                .collect();
            self.basis_changed();
            let links = self.g.links(&self.basis);
            let mn = self.factor(&links).map_err(JammingError::Solver)?;
            let (d, tol) = (self.g.d, self.p.dependency_tol);
            let Ok(y) = self.velocities(&links, &mn) else {
                gone.clear();
                continue;
            };
            let closing = |k: &Key| {
                let l = self.g.link(k);
                l.rate(&y, d) - l.size <= tol * l.size
            };
            let count = gone.len();
            gone.retain(|k| !closing(k));
            if gone.len() == count {
                break y;
            }
            self.counts.batch_rounds += 1;
        };
        for g in &gone {
            self.bonded.remove(g);
        }
        for r in std::mem::take(&mut self.redundant) {
            self.bonded.remove(&r);
            self.pending.push(r);
        }
        self.bonded.insert(key);
        self.released += gone.len() as u64;
        self.counts.batch_bonds_released += gone.len() as u64;
        self.next_velocities =
            (self.pending.is_empty()).then(|| (self.basis.clone(), self.g.x.clone(), y));
        Ok(true)
    }
}
