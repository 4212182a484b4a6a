//! Minimum-norm solves with the bond matrix A (one row per bond, one column per coordinate):
//! `y = A⁺ b`, the velocities of Baranau & Tallarek 2014 eqns (1)–(2).
//!
//! This module is the policy and the interface: [`MinNorm`] is a factorisation that answers
//! solves, multipliers and inverse diagonals whatever its form, and [`Solver`] picks the form
//! for a bond set and falls back when one fails. The forms live in their own files:
//! - [`dense_pseudoinverse`]: the thin SVD of A and its pseudoinverse, for few bonds (cheap,
//!   and exact even when rows are nearly dependent, since tiny singular values are cut off);
//! - [`gram_pattern`]: the sparse Cholesky factor of `A Aᵀ` (bonds sharing a particle
//!   couple), for many bonds; `y = Aᵀ (A Aᵀ)⁻¹ b` is the minimum-norm solution when the rows
//!   are independent, which the integrator guarantees by keeping dependent bonds out of the
//!   factorised basis. It fails with an error when `A Aᵀ` is not positive definite;
//! - [`conjugate_gradient`] with a [`bordered_preconditioner`]: between numeric
//!   factorisations, conjugate gradients solve the current bonds with an earlier factor
//!   bordered by the rows of the bonds added since;
//! - [`selected_inversion`]: diagonal entries of `(A Aᵀ)⁻¹` from the sparse factor, by pruned
//!   forward solves or by selected inversion, for the release test of the integrator.
//!
//! The sparse factor is computed over a fixed set of candidate rows, the *slots* of a
//! [`GramPattern`]: the bonds' rows hold `A Aᵀ`, every other slot an identity row, so the
//! sparsity pattern, its fill-reducing ordering and the symbolic factorisation depend only on
//! the slots and are reused for every bond set drawn from them (a step changes the bonds by
//! one). Only the numeric factorisation is redone, sequentially (`Par::Seq`).
mod bordered_preconditioner;
mod conjugate_gradient;
mod dense_pseudoinverse;
mod gram_pattern;
mod selected_inversion;
#[cfg(feature = "cholmod")]
mod updatable_factor;
#[cfg(not(feature = "cholmod"))]
#[path = "updatable_factor_absent.rs"]
mod updatable_factor;

use std::cell::{Cell, RefCell};
use std::collections::HashSet;
use std::rc::Rc;

use faer::Mat;

use crate::contacts::{Key, Link};
use crate::growth::Growth;

pub(crate) use bordered_preconditioner::Preconditioner;
pub(crate) use conjugate_gradient::CgStats;
use conjugate_gradient::{CG_TOL, Iterative};
use gram_pattern::GramPattern;
pub(crate) use selected_inversion::DIAGONAL_BATCH;

/// Largest number of coordinates N·d for which a failed sparse factorisation falls back to the
/// dense SVD (its cost grows as K·(N·d)²).
pub(crate) const DENSE_FALLBACK_COORDINATES: usize = 3000;

/// Candidates within this relative gap `r/σ − 1` get a slot when a [`GramPattern`] is built.
/// Every spare slot adds fill to each numeric factorisation and triangular solve; in the
/// exchange phase at N = 1000, 0.005 instead of 0.02 took a sixth off the run time, at three
/// times the (cheap) pattern rebuilds.
const PATTERN_GAP: f64 = 0.005;

/// Candidates that are no bonds get at most max(K/PATTERN_SPARE_DIVISOR, PATTERN_MIN_SPARE)
/// slots for K bonds, the closest by gap. A start made by compression (LS) has nearly every
/// pair of its network within `PATTERN_GAP` while few are bonds yet, and slots for all of them
/// made every numeric factorisation cost that of the full network (≈ 0.9 s at N = 10⁴ with 500
/// bonds). Contacts form roughly in gap order, so the pattern is rebuilt about once per
/// K/16 new bonds. Spare slots are fill in every triangular solve of the growth phase: K/16
/// instead of K took the first 10⁴ steps at N = 10⁴ from 318 s to 203 s CPU and `adam1` from
/// 19.7 s to 16.0 s, on the same paths; an exchange phase (`ls1`, 5000 steps) took as long
/// (137 s), its extra rebuilds paid by cheaper solves (docs/notes/closest-jammed-large-n.md).
const PATTERN_SPARE_DIVISOR: usize = 16;
const PATTERN_MIN_SPARE: usize = 64;

/// Diagonal shift of `A Aᵀ` (whose diagonal is 1–2 for unit bond normals) for the multipliers
/// at a fold where `A Aᵀ` is singular ([`Solver::fold_multipliers`]): far above the rounding
/// that broke its Cholesky factor, far below the other eigenvalues of a bond network.
const FOLD_SHIFT: f64 = 1e-10;

/// A factorisation of a bond matrix for minimum-norm solves.
pub(crate) enum MinNorm {
    /// No bonds: every minimum-norm solution is zero.
    Empty,
    /// `pinv` is the dN × K pseudoinverse of A.
    Dense { pinv: Mat<f64> },
    /// Cholesky factor `values` of `A Aᵀ` embedded in the slots of `pattern`; bond k is slot
    /// `slots[k]`.
    Slotted {
        pattern: Rc<GramPattern>,
        values: Vec<f64>,
        slots: Vec<usize>,
    },
    /// `A Aᵀ` of `links` solved by conjugate gradients, preconditioned with the factor of an
    /// earlier step bordered with the bonds added since ([`Preconditioner`]).
    Iterative(Box<Iterative>),
}

impl MinNorm {
    /// The minimum-norm `y` (N·d) with `A y = rhs` in the least-squares sense.
    pub fn solve(&self, links: &[Link], rhs: &[f64], n: usize, d: usize) -> Vec<f64> {
        self.solve_to(links, rhs, n, d, CG_TOL)
    }

    /// [`Self::solve`] where an iterative form stops at the relative residual `tol` of
    /// `A Aᵀ λ = rhs` (the factorised forms are exact whatever `tol`): for corrections that an
    /// outer iteration refines anyway.
    pub fn solve_to(&self, links: &[Link], rhs: &[f64], n: usize, d: usize, tol: f64) -> Vec<f64> {
        let mut y = vec![0.0; n * d];
        match self {
            MinNorm::Empty => {}
            MinNorm::Dense { pinv } => {
                for (c, yc) in y.iter_mut().enumerate() {
                    *yc = (0..rhs.len()).map(|r| pinv[(c, r)] * rhs[r]).sum();
                }
            }
            MinNorm::Slotted { .. } | MinNorm::Iterative(_) => {
                let z = self.gram_solve_to(rhs, tol);
                for (l, &zk) in links.iter().zip(&z) {
                    l.add_transposed(zk, &mut y, d);
                }
            }
        }
        y
    }

    /// Lagrange multipliers `λ = (A Aᵀ)⁻¹ b` of the minimum-norm solve with `b = D` (so
    /// `y = Aᵀ λ`).
    pub fn multipliers(&self, links: &[Link], n: usize, d: usize) -> Vec<f64> {
        let b: Vec<f64> = links.iter().map(|l| l.size).collect();
        match self {
            MinNorm::Empty => Vec::new(),
            MinNorm::Dense { .. } => {
                let y = self.solve(links, &b, n, d);
                self.row_combination(links, &y, d)
            }
            MinNorm::Slotted { .. } | MinNorm::Iterative(_) => self.gram_solve(&b),
        }
    }

    /// Coefficients `f` minimising ‖a − Aᵀ f‖ for a coordinate vector `a`: `(A⁺)ᵀ a`.
    pub fn row_combination(&self, links: &[Link], a: &[f64], d: usize) -> Vec<f64> {
        match self {
            MinNorm::Empty => Vec::new(),
            MinNorm::Dense { pinv } => (0..pinv.ncols())
                .map(|r| (0..a.len()).map(|c| pinv[(c, r)] * a[c]).sum())
                .collect(),
            MinNorm::Slotted { .. } | MinNorm::Iterative(_) => {
                let aa: Vec<f64> = links.iter().map(|l| l.rate(a, d)).collect();
                self.gram_solve(&aa)
            }
        }
    }

    /// `((A Aᵀ)⁻¹)_kk` for the basis bonds `ks`, or for each a value above its cap in `caps`
    /// when it exceeds that (the sparse forms stop its solve there). `None` for an iterative
    /// form whose preconditioner is bordered (bonds changed since its factor). Otherwise an
    /// iterative form answers with that factor: of the same bonds, some steps' motion away.
    pub fn inverse_diagonals(&self, ks: &[usize], caps: &[f64]) -> Option<Vec<f64>> {
        if let Some(diagonals) = self.updated_inverse_diagonals(ks, caps) {
            return Some(diagonals);
        }
        match self {
            // (A Aᵀ)⁺ = (A⁺)ᵀ A⁺: the squared norm of column k of A⁺.
            MinNorm::Dense { pinv } => {
                Some(ks.iter().map(|&k| pinv.col(k).squared_norm_l2()).collect())
            }
            _ => self.with_sparse_factor(ks, |pattern, values, slots| {
                pattern.inverse_diagonals(values, slots, caps)
            }),
        }
    }

    /// Whether [`Self::inverse_diagonals`] has a factor of these bonds to answer with.
    pub fn holds_factor(&self) -> bool {
        matches!(self, MinNorm::Dense { .. })
            || self.updated_form().is_some()
            || self.with_sparse_factor(&[], |_, _, _| ()).is_some()
    }

    /// `((A Aᵀ)⁻¹)_kk` for the basis bonds `ks` by selected inversion of the sparse factor
    /// ([`GramPattern::selected_inverse_diagonal`]), when that costs less than the forward
    /// solves of [`Self::inverse_diagonals`] would; `None` otherwise, and where
    /// [`Self::inverse_diagonals`] has no sparse factor to use.
    pub fn inverse_diagonals_by_selected_inversion(&self, ks: &[usize]) -> Option<Vec<f64>> {
        self.with_sparse_factor(ks, |pattern, values, slots| {
            if !pattern.selected_inversion_pays(slots) {
                return None;
            }
            pattern.selected_inverse_diagonal(values, slots)
        })
        .flatten()
    }

    /// Whether the basis bonds `ks` cost less to weigh by a selected inversion of a fresh
    /// factor than by the forward solves of this form's updated factor, which go one at a time
    /// through a simplicial factor: when [`GramPattern::selected_inversion_pays`] says so for
    /// its pattern, since a numeric factorisation is small beside either (at N = 10⁴, 0.15 s
    /// against 7.4 s a release for the solves). `false` for other forms.
    pub fn fresh_factor_pays(&self, ks: &[usize]) -> bool {
        let Some(it) = self.updated_form() else {
            return false;
        };
        it.base_slots(ks)
            .is_some_and(|s| it.pre.factor().0.selected_inversion_pays(&s))
    }

    /// [`Self::inverse_diagonals`] from the updated factor of an iterative form
    /// ([`Preconditioner::with_updates`]): the factor of these bonds, each row taken where it
    /// joined, by one sparse forward solve each. `None` for other forms, and once the
    /// iterative form has made an exact factor.
    fn updated_inverse_diagonals(&self, ks: &[usize], caps: &[f64]) -> Option<Vec<f64>> {
        let it = self.updated_form()?;
        let slots = it.base_slots(ks)?;
        let factor = it.pre.updated()?.borrow();
        let mut work = vec![0.0; factor.len()];
        let solve = |(&s, &cap): (&usize, &f64)| factor.inverse_diagonal(s, cap, &mut work);
        Some(slots.iter().zip(caps).map(solve).collect())
    }

    /// The iterative form whose preconditioner is an updated factor of its bonds, unless it
    /// has made an exact factor.
    fn updated_form(&self) -> Option<&Iterative> {
        match self {
            MinNorm::Iterative(it) if it.pre.is_updated() && it.exact.borrow().is_none() => {
                Some(it)
            }
            _ => None,
        }
    }

    /// `f(pattern, values, slots of ks)` with the sparse factor that holds the basis bonds
    /// `ks` (see [`Self::inverse_diagonals`]); `None` without one.
    fn with_sparse_factor<R>(
        &self,
        ks: &[usize],
        f: impl FnOnce(&GramPattern, &[f64], &[usize]) -> R,
    ) -> Option<R> {
        match self {
            MinNorm::Empty | MinNorm::Dense { .. } => None,
            MinNorm::Slotted {
                pattern,
                values,
                slots,
            } => {
                let s: Vec<usize> = ks.iter().map(|&k| slots[k]).collect();
                Some(f(pattern, values, &s))
            }
            MinNorm::Iterative(it) => {
                if let Some(exact) = it.exact.borrow().as_ref() {
                    return exact.with_sparse_factor(ks, f);
                }
                // Without a border the base factor holds exactly these bonds; an updated one
                // holds them in the updated factor instead.
                if it.pre.is_bordered() || it.pre.is_updated() {
                    return None;
                }
                let (pattern, values) = it.pre.factor();
                Some(f(pattern, values, &it.base_slots(ks)?))
            }
        }
    }

    /// `(A Aᵀ)⁻¹ rhs` (the pseudoinverse for the dense form).
    pub(crate) fn gram_solve(&self, rhs: &[f64]) -> Vec<f64> {
        self.gram_solve_to(rhs, CG_TOL)
    }

    /// [`Self::gram_solve`] to the relative residual `tol` for the iterative form.
    fn gram_solve_to(&self, rhs: &[f64], tol: f64) -> Vec<f64> {
        match self {
            MinNorm::Slotted {
                pattern,
                values,
                slots,
            } => {
                // Inactive slots are identity rows with a zero right-hand side: their
                // solution is zero and the bonds' block is solved exactly.
                let mut z = vec![0.0; pattern.len()];
                for (&s, &r) in slots.iter().zip(rhs) {
                    z[s] = r;
                }
                pattern.solve_in_place(values, &mut z);
                slots.iter().map(|&s| z[s]).collect()
            }
            MinNorm::Iterative(it) => it.gram_solve(rhs, tol),
            // (A Aᵀ)⁺ = (A⁺)ᵀ A⁺.
            MinNorm::Dense { pinv } => {
                let y: Vec<f64> = (0..pinv.nrows())
                    .map(|c| (0..rhs.len()).map(|r| pinv[(c, r)] * rhs[r]).sum())
                    .collect();
                (0..pinv.ncols())
                    .map(|r| (0..y.len()).map(|c| pinv[(c, r)] * y[c]).sum())
                    .collect()
            }
            MinNorm::Empty => Vec::new(),
        }
    }
}

/// Adds the seconds from its making to its drop to a total (every return of a timed function).
struct Clock<'a>(&'a Cell<f64>, std::time::Instant);

impl Drop for Clock<'_> {
    fn drop(&mut self) {
        self.0.set(self.0.get() + self.1.elapsed().as_secs_f64());
    }
}

/// Factorises bond matrices for one run: dense SVD for few bonds, sparse Cholesky of `A Aᵀ`
/// over a reused [`GramPattern`] for many (rebuilt over the bonds and the closest candidates
/// within a relative gap [`PATTERN_GAP`] when a bond has no slot), and the dense SVD again when
/// the sparse factor fails on a small system.
pub(crate) struct Solver {
    pub dense_max_bonds: usize,
    pattern: RefCell<Option<Rc<GramPattern>>>,
    /// Numeric factorisations and pattern (symbolic) builds so far.
    pub numeric: Cell<u64>,
    pub symbolic: Cell<u64>,
    /// Sparse factorisations that failed and fell back to the dense SVD.
    pub dense_fallbacks: Cell<u64>,
    /// Rows added to or deleted from an updated factor instead of a new factorisation.
    pub row_updates: Cell<u64>,
    /// Wall-clock seconds spent factorising.
    pub seconds: Cell<f64>,
}

impl Solver {
    pub fn new(dense_max_bonds: usize) -> Self {
        Solver {
            dense_max_bonds,
            pattern: RefCell::new(None),
            numeric: Cell::new(0),
            symbolic: Cell::new(0),
            dense_fallbacks: Cell::new(0),
            row_updates: Cell::new(0),
            seconds: Cell::new(0.0),
        }
    }

    /// Factorises the bonds `keys` with rows `links` at the configuration `g`; `next` are the
    /// contacts waiting to be admitted, in the order they will be, which get spare slots first
    /// when the pattern is rebuilt.
    pub fn factor<'k>(
        &self,
        keys: &[Key],
        links: &[Link],
        g: &Growth,
        next: impl Iterator<Item = &'k Key>,
    ) -> Result<MinNorm, String> {
        let _clock = Clock(&self.seconds, std::time::Instant::now());
        let (n, d) = (g.n, g.d);
        self.numeric.set(self.numeric.get() + 1);
        if links.len() <= self.dense_max_bonds {
            return MinNorm::dense(links, n, d);
        }
        let sparse = || -> Result<MinNorm, String> {
            if let Some(p) = self.pattern.borrow().as_ref()
                && let Some(mn) = p.factor(keys, links, d)?
            {
                return Ok(mn);
            }
            // Slots: the bonds, the contacts waiting to be admitted in the order they will be,
            // and the candidates close enough to become bonds soon (a wider set costs fill in
            // every numeric factorisation, a narrower one more rebuilds). Waiting contacts come
            // first: at a start at contact every gap is rounding, so the closest by gap are not
            // the next admitted, and an updated factor ([`Preconditioner::with_updates`]) takes
            // no bond without a slot (from an MLS start at N = 1000 with updates, 37 patterns
            // against 486 and 3.0 s against 10.7 s).
            let spare = (keys.len() / PATTERN_SPARE_DIVISOR).max(PATTERN_MIN_SPARE);
            let mut taken: HashSet<&Key> = keys.iter().collect();
            let waiting: Vec<Key> = next
                .filter(|k| taken.insert(k))
                .take(spare)
                .copied()
                .collect();
            let mut near: Vec<(f64, Key)> = g
                .candidates
                .keys
                .iter()
                .filter(|k| !taken.contains(k))
                .map(|k| (g.link(k).rel_gap(g.t), *k))
                .filter(|&(gap, _)| gap < PATTERN_GAP)
                .collect();
            let spare = spare - waiting.len();
            if near.len() > spare {
                near.select_nth_unstable_by(spare, |a, b| a.0.total_cmp(&b.0));
                near.truncate(spare);
            }
            let all: Vec<Key> = keys
                .iter()
                .chain(&waiting)
                .copied()
                .chain(near.iter().map(|p| p.1))
                .collect();
            let p = Rc::new(GramPattern::new(&all, n)?);
            self.symbolic.set(self.symbolic.get() + 1);
            let mn = p.factor(keys, links, d)?.expect("every key has a slot");
            *self.pattern.borrow_mut() = Some(p);
            Ok(mn)
        };
        sparse().or_else(|e| {
            if n * d <= DENSE_FALLBACK_COORDINATES {
                self.dense_fallbacks.set(self.dense_fallbacks.get() + 1);
                MinNorm::dense(links, n, d)
            } else {
                Err(e)
            }
        })
    }

    /// The multipliers `λ = G⁻¹ b` of the bonds `keys` (rows `links`) at a fold where
    /// `G = A Aᵀ` is singular to rounding and has no Cholesky factor (too many bonds for the
    /// dense pseudoinverse). With `G`'s eigenpairs (μ_k, u_k), the shifted solve gives
    /// `Σ u_k (u_kᵀb)/(μ_k + FOLD_SHIFT)`: the null vector u₀ dominates by
    /// `(μ₁ + FOLD_SHIFT)/FOLD_SHIFT`, so the signs of λ are those of the fold's forces
    /// (`Aᵀu₀ = 0`) taken in the limit of `G⁻¹ b` as the fold is approached.
    pub fn fold_multipliers(
        &self,
        keys: &[Key],
        links: &[Link],
        n: usize,
        d: usize,
    ) -> Result<Vec<f64>, String> {
        self.numeric.set(self.numeric.get() + 1);
        let pattern = Rc::new(GramPattern::new(keys, n)?);
        self.symbolic.set(self.symbolic.get() + 1);
        let mn = pattern
            .factor_shifted(keys, links, d, FOLD_SHIFT)?
            .expect("every key has a slot");
        Ok(mn.multipliers(links, n, d))
    }
}

#[cfg(test)]
mod tests;
