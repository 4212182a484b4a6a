//! The preconditioner of the conjugate-gradient form of [`MinNorm`]: the sparse Cholesky factor
//! `G₀ = L Lᵀ` of an earlier bond set, bordered with the rows of bonds added since and with a
//! constraint for each bond released since, solved by block elimination with the small dense
//! Schur complement of `G₀` (LU with partial pivoting, faer's `PartialPivLu`). It is
//! `(A Aᵀ)⁻¹` exactly until the particles move, and a close approximation for the few steps
//! after. A border is refused (`None`, and the caller makes an exact factor) when it would
//! exceed `MAX_BORDER` bonds or when the base holds no sparse factor.
//!
//! With factor updates ([`Preconditioner::with_updates`]) there is no border: the base factor
//! is handed to CHOLMOD as an LDLᵀ ([`UpdatableFactor`]), and a bond that joins or leaves the
//! basis adds or deletes its slot's row of that factor in place. The
//! preconditioner is then the factor of exactly the current bonds, each row taken at the
//! configuration where it joined, and it answers `(A Aᵀ)⁻¹` diagonal entries for the release
//! rule without a new numeric factorisation.

use std::cell::RefCell;
use std::rc::Rc;

use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::{Mat, MatMut};

use super::MinNorm;
use super::gram_pattern::GramPattern;
use super::updatable_factor::UpdatableFactor;
use crate::contacts::{Key, Link};

/// The preconditioner of conjugate-gradient solves for a basis changed since its last exact
/// factor: the factor `G₀ = L Lᵀ` of the bonds it held then (`base`), bordered with the rows of
/// the bonds added since (each taken at the configuration where it was added) and with a
/// constraint `z_s = 0` with a free multiplier for each base bond released since, which drops
/// its row. The system `[G₀ B E; Bᵀ C 0; Eᵀ 0 0]` is solved by block elimination with the small
/// dense Schur complement `H` of `G₀` (one row per added or released bond). A new or released
/// bond then costs one solve with `G₀` instead of a numeric factorisation, and the
/// preconditioner is `(A Aᵀ)⁻¹` itself until the particles move.
pub(crate) struct Preconditioner {
    /// A [`MinNorm::Slotted`] factor.
    base: Rc<MinNorm>,
    /// Per slot of the base's pattern: whether it holds a base bond still in the basis.
    in_base: Vec<bool>,
    added: Vec<Rc<Border>>,
    /// `a_j·a_k` among the added bonds, taken when the later of the two was added.
    among_added: Vec<Vec<f64>>,
    /// Released base bonds: the coupling is their own slot.
    released: Vec<Rc<Border>>,
    /// The LU factor of `H` (none without a border).
    schur: Option<PartialPivLu<f64>>,
    /// With factor updates: the factor of the current bonds, shared with the preconditioners
    /// this one was changed from (each change replaces the owner's preconditioner, so only the
    /// newest is used).
    updated: Option<Rc<RefCell<UpdatableFactor>>>,
}

/// A column of a [`Preconditioner`]'s border: its couplings `(slot, value)` with the base
/// slots (a column of B, or the unit vector of a released slot) and `G₀⁻¹` of them.
struct Border {
    key: Key,
    coupling: Vec<(usize, f64)>,
    solved: Vec<f64>,
}

/// Where a bond sits in a [`Preconditioner`]: a slot of the base factor, or an added bond.
#[derive(Clone, Copy, PartialEq)]
pub(super) enum Role {
    Base(usize),
    Added(usize),
}

/// Most bonds a [`Preconditioner`] borders its factor with (added and released) before an exact
/// factor is made: each costs a dense vector over the slots in every application.
const MAX_BORDER: usize = 32;

impl Preconditioner {
    /// The exact factor `base` alone; `None` unless it is a sparse (slotted) factor.
    pub fn new(base: &Rc<MinNorm>) -> Option<Self> {
        let MinNorm::Slotted { pattern, slots, .. } = base.as_ref() else {
            return None;
        };
        let mut in_base = vec![false; pattern.len()];
        slots.iter().for_each(|&s| in_base[s] = true);
        Some(Preconditioner {
            base: Rc::clone(base),
            in_base,
            added: Vec::new(),
            among_added: Vec::new(),
            released: Vec::new(),
            schur: None,
            updated: None,
        })
    }

    /// This preconditioner kept by factor updates instead of a border: its base factor (faer's)
    /// handed to CHOLMOD as a simplicial LDLᵀ, which costs a copy, not a factorisation (a
    /// CHOLMOD factorisation of the same matrix took 35 ms at N = 1000 against faer's 4 ms).
    /// Unchanged (bordered) when CHOLMOD does not take it.
    pub fn with_updates(mut self) -> Self {
        let (pattern, values) = self.factor();
        let (perm, col_ptr, row_idx, val) = pattern.ldl_columns(values);
        self.updated = UpdatableFactor::from_ldl(&perm, &col_ptr, &row_idx, &val)
            .ok()
            .map(|f| Rc::new(RefCell::new(f)));
        self
    }

    /// The factor of the current bonds, with factor updates.
    pub(super) fn updated(&self) -> Option<&RefCell<UpdatableFactor>> {
        self.updated.as_deref()
    }

    /// Whether bonds that join or leave update the factor in place (no border).
    pub fn is_updated(&self) -> bool {
        self.updated.is_some()
    }

    pub(super) fn factor(&self) -> (&Rc<GramPattern>, &[f64]) {
        match self.base.as_ref() {
            MinNorm::Slotted {
                pattern, values, ..
            } => (pattern, values),
            _ => unreachable!("a preconditioner's base is a slotted factor"),
        }
    }

    pub(super) fn role(&self, key: &Key) -> Option<Role> {
        let (pattern, _) = self.factor();
        match pattern.slot_of.get(key) {
            Some(&s) if self.in_base[s] => Some(Role::Base(s)),
            _ => self
                .added
                .iter()
                .position(|a| a.key == *key)
                .map(Role::Added),
        }
    }

    /// Whether bonds were added or released since the base factor.
    pub(super) fn is_bordered(&self) -> bool {
        !self.added.is_empty() || !self.released.is_empty()
    }

    pub(super) fn len(&self) -> usize {
        self.in_base.iter().filter(|&&b| b).count() + self.added.len()
    }

    /// A border column for `coupling`, with `G₀⁻¹` of it.
    fn border(&self, key: Key, coupling: Vec<(usize, f64)>) -> Rc<Border> {
        let (pattern, values) = self.factor();
        let mut solved = vec![0.0; pattern.len()];
        coupling.iter().for_each(|&(s, v)| solved[s] = v);
        pattern.solve_in_place(values, &mut solved);
        Rc::new(Border {
            key,
            coupling,
            solved,
        })
    }

    /// This preconditioner bordered with the last bond of the basis `keys` (rows `links`, `n`
    /// particles in `d` dimensions), whose other bonds it holds. `None` when its border is full,
    /// or a bond it does not hold couples to the new one.
    pub fn extend(&self, keys: &[Key], links: &[Link], n: usize, d: usize) -> Option<Self> {
        let (new, others) = links.split_last()?;
        let mut a = vec![0.0; n * d];
        new.add_transposed(1.0, &mut a, d);
        let mut coupling = Vec::new();
        let mut with_added = vec![0.0; self.added.len() + 1];
        for (key, l) in keys.iter().zip(others) {
            let v = l.rate(&a, d);
            if v != 0.0 {
                match self.role(key)? {
                    Role::Base(s) => coupling.push((s, v)),
                    Role::Added(j) => with_added[j] = v,
                }
            }
        }
        with_added[self.added.len()] = new.rate(&a, d);
        if let Some(factor) = &self.updated {
            // Row and column of the new bond's slot: its couplings and its diagonal.
            let (pattern, _) = self.factor();
            let s = *pattern.slot_of.get(keys.last()?)?;
            coupling.push((s, with_added[0]));
            factor.borrow_mut().add_row(s, &coupling).ok()?;
            let mut out = self.with_border_room()?;
            out.in_base[s] = true;
            return Some(out);
        }
        let mut out = self.with_border_room()?;
        out.added.push(self.border(*keys.last()?, coupling));
        for (row, &v) in out.among_added.iter_mut().zip(&with_added) {
            row.push(v);
        }
        out.among_added.push(with_added);
        out.factor_schur();
        Some(out)
    }

    /// This preconditioner without bond `key`. `None` when its border is full or it does not
    /// hold `key`.
    pub fn release(&self, key: &Key) -> Option<Self> {
        let mut out = self.with_border_room()?;
        match self.role(key)? {
            Role::Base(s) if self.updated.is_some() => {
                self.updated.as_ref()?.borrow_mut().delete_row(s).ok()?;
                out.in_base[s] = false;
            }
            Role::Base(s) => {
                out.in_base[s] = false;
                out.released.push(self.border(*key, vec![(s, 1.0)]));
            }
            Role::Added(j) => {
                out.added.remove(j);
                out.among_added.remove(j);
                out.among_added.iter_mut().for_each(|row| {
                    row.remove(j);
                });
            }
        }
        out.factor_schur();
        Some(out)
    }

    /// A copy to change, when the border has room for one more column.
    fn with_border_room(&self) -> Option<Self> {
        (self.added.len() + self.released.len() < MAX_BORDER).then(|| Preconditioner {
            base: Rc::clone(&self.base),
            in_base: self.in_base.clone(),
            added: self.added.clone(),
            among_added: self.among_added.clone(),
            released: self.released.clone(),
            schur: None,
            updated: self.updated.clone(),
        })
    }

    /// Factors `H = [C − Bᵀ G₀⁻¹ B, −Bᵀ G₀⁻¹ E; −Eᵀ G₀⁻¹ B, −Eᵀ G₀⁻¹ E]` (symmetric, indefinite).
    fn factor_schur(&mut self) {
        let (na, m) = (self.added.len(), self.added.len() + self.released.len());
        let column = |p: usize| match p < na {
            true => &self.added[p],
            false => &self.released[p - na],
        };
        let h = Mat::<f64>::from_fn(m, m, |p, q| {
            let (bp, bq) = (column(p), column(q));
            let coupled: f64 = bp.coupling.iter().map(|&(s, v)| v * bq.solved[s]).sum();
            match p < na && q < na {
                true => self.among_added[p][q] - coupled,
                false => -coupled,
            }
        });
        self.schur = (m > 0).then(|| h.partial_piv_lu());
    }

    /// `out = M⁻¹ r` for the bonds with `roles` (every bond the preconditioner holds).
    pub(super) fn apply(&self, roles: &[Role], r: &[f64], out: &mut [f64]) {
        let (pattern, values) = self.factor();
        if let Some(factor) = &self.updated {
            let mut z = vec![0.0; pattern.len()];
            for (role, &v) in roles.iter().zip(r) {
                if let Role::Base(s) = *role {
                    z[s] = v;
                }
            }
            factor.borrow_mut().solve_in_place(&mut z);
            for (o, role) in out.iter_mut().zip(roles) {
                if let Role::Base(s) = *role {
                    *o = z[s];
                }
            }
            return;
        }
        let mut z = vec![0.0; pattern.len()];
        let na = self.added.len();
        let mut w = vec![0.0; na + self.released.len()];
        for (role, &v) in roles.iter().zip(r) {
            match *role {
                Role::Base(s) => z[s] = v,
                Role::Added(j) => w[j] = v,
            }
        }
        pattern.solve_in_place(values, &mut z);
        let border: Vec<&Rc<Border>> = self.added.iter().chain(&self.released).collect();
        if let Some(lu) = &self.schur {
            // The border's right-hand side: r_added − Bᵀ G₀⁻¹ r_base, and −Eᵀ G₀⁻¹ r_base.
            for (p, (wp, b)) in w.iter_mut().zip(&border).enumerate() {
                let coupled: f64 = b.coupling.iter().map(|&(s, v)| v * z[s]).sum();
                *wp = if p < na { *wp - coupled } else { -coupled };
            }
            let m = w.len();
            lu.solve_in_place(MatMut::from_column_major_slice_mut(&mut w, m, 1));
        }
        for (o, role) in out.iter_mut().zip(roles) {
            *o = match *role {
                Role::Base(s) => {
                    z[s] - w
                        .iter()
                        .zip(&border)
                        .map(|(wp, b)| wp * b.solved[s])
                        .sum::<f64>()
                }
                Role::Added(j) => w[j],
            };
        }
    }
}
