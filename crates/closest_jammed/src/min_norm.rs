//! Minimum-norm solves with the bond matrix A (one row per bond, one column per coordinate):
//! `y = A⁺ b`, the velocities of seed 001 eqns (1)–(2).
//!
//! Two factorisations, both from faer:
//! - dense: the thin SVD of A and its pseudoinverse, for few bonds (cheap, and exact even when
//!   rows are nearly dependent, since tiny singular values are cut off);
//! - sparse: the Cholesky factor of `A Aᵀ` (bonds sharing a particle couple), for many bonds;
//!   `y = Aᵀ (A Aᵀ)⁻¹ b` is the minimum-norm solution when the rows are independent, which the
//!   integrator guarantees by keeping dependent bonds out of the factorised basis. It fails with
//!   an error when `A Aᵀ` is not positive definite.
//!
//! The sparse factor is computed over a fixed set of candidate rows, the *slots* of a
//! [`GramPattern`]: the bonds' rows hold `A Aᵀ`, every other slot an identity row, so the
//! sparsity pattern, its fill-reducing ordering and the symbolic factorisation depend only on
//! the slots and are reused for every bond set drawn from them (a step changes the bonds by
//! one). Only the numeric factorisation is redone, sequentially (`Par::Seq`). Between numeric
//! factorisations, conjugate gradients solve the current bonds with an earlier factor bordered
//! by the rows of the bonds added since ([`Preconditioner`]).

use std::cell::{Cell, RefCell};
use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::collections::{HashMap, HashSet};
use std::rc::Rc;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::matmul::matmul;
use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::sparse::linalg::cholesky::{self, LltRef, SymbolicCholesky, SymbolicCholeskyRaw};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Accum, Conj, Mat, MatMut, MatRef, Par, Side};

use crate::conjugate_gradient::pcg;
use crate::contacts::{Key, Link};
use crate::growth::Growth;

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
enum Role {
    Base(usize),
    Added(usize),
}

/// Most bonds a [`Preconditioner`] borders its factor with (added and released) before an exact
/// factor is made: each costs a dense vector over the slots in every application.
const MAX_BORDER: usize = 32;

/// Most forward solves made together by [`GramPattern::inverse_diagonals`]: enough
/// right-hand sides for the dense kernels of the large supernodes near the root to run at
/// matrix speed. Fewer when the work matrix (slots × solves) would exceed `DIAGONAL_WORK`
/// entries.
pub(crate) const DIAGONAL_BATCH: usize = 64;
const DIAGONAL_WORK: usize = 1 << 21;

/// The pruned search of a release (`GramPattern::inverse_diagonals` with caps) is taken to cost
/// this share of the forward solves to the root for all its candidates; a selected inversion is
/// used when its flops are below that. Measured on one core
/// (docs/notes/closest-jammed-release-rule.md):
/// at N = 2000 (lognormal σ = 0.3) the selected inversion has 1.06 times the flops of the full
/// solves and takes 145 ms a release against 98 ms pruned; at N = 10⁴ (3D, near jamming) it has
/// 0.52 times their flops and takes 3.5 s against 7.6 s. The share lies between the two.
const PRUNED_SOLVE_SHARE: f64 = 0.75;

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
        })
    }

    fn factor(&self) -> (&Rc<GramPattern>, &[f64]) {
        match self.base.as_ref() {
            MinNorm::Slotted {
                pattern, values, ..
            } => (pattern, values),
            _ => unreachable!("a preconditioner's base is a slotted factor"),
        }
    }

    fn role(&self, key: &Key) -> Option<Role> {
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

    /// Every bond this preconditioner holds.
    fn len(&self) -> usize {
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
    fn apply(&self, roles: &[Role], r: &[f64], out: &mut [f64]) {
        let (pattern, values) = self.factor();
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

/// The state of [`MinNorm::Iterative`].
pub(crate) struct Iterative {
    pre: Rc<Preconditioner>,
    keys: Vec<Key>,
    links: Vec<Link>,
    /// Where each bond sits in `pre`.
    roles: Vec<Role>,
    n: usize,
    d: usize,
    /// Iteration counts (shared with the owner, who refactorises when they grow).
    stats: Rc<CgStats>,
    /// The exact factor, made when the iteration failed.
    exact: RefCell<Option<MinNorm>>,
}

/// Conjugate-gradient iteration counts of the solves with one preconditioner.
#[derive(Default)]
pub(crate) struct CgStats {
    /// Largest iteration count of a solve, `usize::MAX` after a failure.
    pub worst: Cell<usize>,
    /// Solves and iterations in total.
    pub solves: Cell<u64>,
    pub iterations: Cell<u64>,
    pub failures: Cell<u64>,
}

/// Relative residual `‖A Aᵀ λ − r‖/‖r‖` at which conjugate gradients stop.
const CG_TOL: f64 = 1e-13;
/// Iterations after which conjugate gradients give up and the exact factor is made (about the
/// cost of a numeric factorisation in triangular solves at N·d ~ 3000 in 3D).
const CG_MAX_ITERATIONS: usize = 20;

/// `A⁺ = Aᵀ (A Aᵀ)⁺` from the self-adjoint eigendecomposition of the small Gram matrix: the
/// fallback when the SVD of A does not converge. Squaring the singular values drops those below
/// about √ε·σ_max as zero, which is enough for the small dense systems that use it.
fn gram_pseudoinverse(a: MatRef<'_, f64>) -> Result<Mat<f64>, String> {
    let gram = a * a.transpose();
    let evd = gram
        .self_adjoint_eigen(Side::Lower)
        .map_err(|e| format!("{e:?}"))?;
    Ok(a.transpose() * evd.pseudoinverse())
}

impl MinNorm {
    /// The dense pseudoinverse of the bond matrix of `links` (`n` particles in `d` dimensions)
    /// by its thin SVD: for few bonds, and as the fallback when a sparse factor fails, since it
    /// handles dependent rows (tiny singular values are cut off).
    pub fn dense(links: &[Link], n: usize, d: usize) -> Result<Self, String> {
        let k = links.len();
        if k == 0 {
            return Ok(MinNorm::Empty);
        }
        let mut a = Mat::<f64>::zeros(k, n * d);
        let mut row = vec![0.0; n * d];
        for (r, l) in links.iter().enumerate() {
            row.iter_mut().for_each(|v| *v = 0.0);
            l.add_transposed(1.0, &mut row, d);
            for (c, &v) in row.iter().enumerate() {
                if v != 0.0 {
                    a[(r, c)] = v;
                }
            }
        }
        let pinv = match a.thin_svd() {
            Ok(svd) => svd.pseudoinverse(),
            // faer's SVD can fail to converge on rank-deficient bond matrices.
            Err(svd_error) => gram_pseudoinverse(a.as_ref()).map_err(|e| {
                format!(
                    "the SVD of the bond matrix did not converge ({svd_error:?}), nor the eigendecomposition of A Aᵀ ({e})"
                )
            })?,
        };
        Ok(MinNorm::Dense { pinv })
    }

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
                // Without a border the base factor holds exactly these bonds.
                if !it.pre.added.is_empty() || !it.pre.released.is_empty() {
                    return None;
                }
                let (pattern, values) = it.pre.factor();
                let base_slot = |&k: &usize| match it.roles[k] {
                    Role::Base(s) => Some(s),
                    Role::Added(_) => None,
                };
                let s: Vec<usize> = ks.iter().map(base_slot).collect::<Option<_>>()?;
                Some(f(pattern, values, &s))
            }
        }
    }

    /// `(A Aᵀ)⁻¹ rhs` (the pseudoinverse for the dense form).
    fn gram_solve(&self, rhs: &[f64]) -> Vec<f64> {
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

    /// Conjugate-gradient solves for the bonds `keys` (rows `links`), preconditioned with
    /// `pre`; `None` unless `keys` are exactly the bonds `pre` holds. `stats` records the
    /// iteration counts.
    pub fn iterative(
        pre: &Rc<Preconditioner>,
        keys: &[Key],
        links: &[Link],
        n: usize,
        d: usize,
        stats: &Rc<CgStats>,
    ) -> Option<MinNorm> {
        let roles: Vec<Role> = keys.iter().map(|k| pre.role(k)).collect::<Option<_>>()?;
        if roles.len() != pre.len() {
            return None;
        }
        Some(MinNorm::Iterative(Box::new(Iterative {
            pre: Rc::clone(pre),
            keys: keys.to_vec(),
            links: links.to_vec(),
            roles,
            n,
            d,
            stats: Rc::clone(stats),
            exact: RefCell::new(None),
        })))
    }
}

impl Iterative {
    /// `(A Aᵀ)⁻¹ rhs` by conjugate gradients to the relative residual `tol`. Only solves to
    /// full accuracy ([`CG_TOL`]) enter `stats.worst`, which decides when to refactorise: a
    /// loose solve's few iterations say nothing about the preconditioner.
    fn gram_solve(&self, rhs: &[f64], tol: f64) -> Vec<f64> {
        if let Some(exact) = self.exact.borrow().as_ref() {
            return exact.gram_solve(rhs);
        }
        let (n, d) = (self.n, self.d);
        let (pattern, _) = self.pre.factor();
        // out = A Aᵀ v.
        let apply = |v: &[f64], out: &mut [f64]| {
            let mut y = vec![0.0; n * d];
            for (l, &c) in self.links.iter().zip(v) {
                l.add_transposed(c, &mut y, d);
            }
            for (o, l) in out.iter_mut().zip(&self.links) {
                *o = l.rate(&y, d);
            }
        };
        let precond = |r: &[f64], out: &mut [f64]| self.pre.apply(&self.roles, r, out);
        let st = &self.stats;
        st.solves.set(st.solves.get() + 1);
        if let Some((x, iterations)) = pcg(apply, precond, rhs, tol, CG_MAX_ITERATIONS) {
            if tol <= CG_TOL {
                st.worst.set(st.worst.get().max(iterations));
            }
            st.iterations.set(st.iterations.get() + iterations as u64);
            return x;
        }
        // Not converged: the exact factor of these bonds.
        st.worst.set(usize::MAX);
        st.failures.set(st.failures.get() + 1);
        // (Over the preconditioner's pattern when every bond has a slot there, which saves the
        // symbolic factorisation.)
        let exact = pattern
            .factor(&self.keys, &self.links, d)
            .ok()
            .flatten()
            .or_else(|| {
                GramPattern::new(&self.keys, n)
                    .map(Rc::new)
                    .and_then(|p| p.factor(&self.keys, &self.links, d))
                    .ok()
                    .flatten()
            })
            .or_else(|| {
                (n * d <= DENSE_FALLBACK_COORDINATES)
                    .then(|| MinNorm::dense(&self.links, n, d).ok())
                    .flatten()
            });
        let z = match &exact {
            Some(e) => e.gram_solve(rhs),
            None => vec![f64::NAN; rhs.len()],
        };
        *self.exact.borrow_mut() = exact;
        z
    }
}

/// The sparsity pattern of `A Aᵀ` over a fixed set of candidate rows (slots), with its
/// fill-reducing ordering and symbolic Cholesky factorisation, computed once and reused for
/// every bond set drawn from the slots.
pub(crate) struct GramPattern {
    slot_of: HashMap<Key, usize>,
    /// Lower triangle, column-compressed, rows sorted; diagonal first in each column.
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// Per stored entry: `Σ_p s_r(p)·s_c(p)` over the particles both slots act on, with
    /// `s = ±1` the sign of the row's normal on that particle (`(A Aᵀ)_rc = sign·n_r·n_c`).
    sign: Vec<f64>,
    symbolic: SymbolicCholesky<usize>,
    /// The supernode of every (permuted) column, when the factor is supernodal.
    supernode_of: Vec<usize>,
    /// Per supernode, the flops of a forward solve of one right-hand side from it to the root
    /// (the path [`GramPattern::inverse_diagonals`] takes), and the flops of
    /// [`GramPattern::selected_inverse_diagonal`].
    path_flops: Vec<f64>,
    selected_inversion_flops: f64,
    /// Work matrix of [`GramPattern::inverse_diagonals`], one column per solve, kept zero.
    work: RefCell<Vec<f64>>,
}

/// The particles a candidate's row acts on, with the sign of its normal there (eqn 1:
/// `n·(y_j − y_i)`; a wall: `−n·y_i`; a self-image: nothing).
fn row_particles(key: &Key) -> [(usize, f64); 2] {
    const NONE: (usize, f64) = (usize::MAX, 0.0);
    match *key {
        Key::Pair { i, j, .. } if i == j => [NONE, NONE],
        Key::Pair { i, j, .. } => [(i as usize, -1.0), (j as usize, 1.0)],
        Key::Wall { i, .. } => [(i as usize, -1.0), NONE],
    }
}

impl GramPattern {
    /// The pattern over `keys` (deduplicated) for `n` particles.
    pub fn new(keys: &[Key], n: usize) -> Result<Self, String> {
        let mut slot_of = HashMap::with_capacity(keys.len());
        let mut slots = Vec::with_capacity(keys.len());
        for k in keys {
            if !slot_of.contains_key(k) {
                slot_of.insert(*k, slots.len());
                slots.push(*k);
            }
        }
        let m = slots.len();
        let mut by_particle: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
        for (r, k) in slots.iter().enumerate() {
            for (p, s) in row_particles(k) {
                if p != usize::MAX {
                    by_particle[p].push((r, s));
                }
            }
        }
        // Entries (col c ≤ row r) with their sign sums, every diagonal present.
        let mut entries: Vec<(usize, usize, f64)> = (0..m).map(|r| (r, r, 0.0)).collect();
        for list in &by_particle {
            for &(r, sr) in list {
                for &(c, sc) in list {
                    if c <= r {
                        entries.push((c, r, sr * sc));
                    }
                }
            }
        }
        entries.sort_unstable_by_key(|&(c, r, _)| (c, r));
        let mut col_ptr = vec![0usize; m + 1];
        let mut row_idx = Vec::with_capacity(entries.len());
        let mut sign: Vec<f64> = Vec::with_capacity(entries.len());
        let mut last = (usize::MAX, usize::MAX);
        for (c, r, s) in entries {
            if (c, r) == last {
                *sign.last_mut().expect("an entry") += s;
            } else {
                row_idx.push(r);
                sign.push(s);
                col_ptr[c + 1] += 1;
                last = (c, r);
            }
        }
        for c in 0..m {
            col_ptr[c + 1] += col_ptr[c];
        }
        let sym = SymbolicSparseColMatRef::new_checked(m, m, &col_ptr, None, &row_idx);
        let symbolic = cholesky::factorize_symbolic_cholesky(
            sym,
            Side::Lower,
            Default::default(),
            Default::default(),
        )
        .map_err(|e| format!("symbolic factorisation of A Aᵀ failed ({e:?})"))?;
        let (mut supernode_of, mut path_flops, mut selected_inversion_flops) =
            (Vec::new(), Vec::new(), 0.0);
        if let SymbolicCholeskyRaw::Supernodal(sn) = symbolic.raw() {
            supernode_of = vec![0; m];
            for s in 0..sn.n_supernodes() {
                supernode_of[sn.supernode_begin()[s]..sn.supernode_end()[s]].fill(s);
            }
            // A supernode's parent comes after it: fill from the root down.
            path_flops = vec![0.0; sn.n_supernodes()];
            for s in (0..sn.n_supernodes()).rev() {
                let size = (sn.supernode_end()[s] - sn.supernode_begin()[s]) as f64;
                let pattern = sn.supernode(s).pattern();
                let p = pattern.len() as f64;
                let above = pattern
                    .first()
                    .map_or(0.0, |&r| path_flops[supernode_of[r]]);
                // A triangular solve and a product with the rows below.
                path_flops[s] = above + size * size + 2.0 * p * size;
                // U, Z_BB U, L_JJ⁻¹, L_JJ⁻ᵀ L_JJ⁻¹ and Uᵀ Z_BJ.
                selected_inversion_flops +=
                    2.0 * p * p * size + 3.0 * p * size * size + 4.0 / 3.0 * size.powi(3);
            }
        }
        Ok(GramPattern {
            slot_of,
            col_ptr,
            row_idx,
            sign,
            symbolic,
            supernode_of,
            path_flops,
            selected_inversion_flops,
            work: RefCell::new(Vec::new()),
        })
    }

    /// The diagonal entries `(M⁻¹)_ss` of the inverse of the matrix factorised in `values`, for
    /// the slots `slots`: `‖L⁻¹ P e_s‖²` with `M = Pᵀ L Lᵀ P`. A forward solve from a unit
    /// vector only reaches the supernodes on the elimination-tree path from slot s to the root,
    /// so only those are visited, and the solves of a batch go through each supernode together
    /// (one dense triangular solve and one product with many right-hand sides, not one each).
    /// The partial sums grow along the path: a solve stops after the first supernode that takes
    /// its sum above its cap, and returns that sum.
    fn inverse_diagonals(&self, values: &[f64], slots: &[usize], caps: &[f64]) -> Vec<f64> {
        let m = self.len();
        let SymbolicCholeskyRaw::Supernodal(sn) = self.symbolic.raw() else {
            let solve = |&s: &usize| {
                let mut z = vec![0.0; m];
                z[s] = 1.0;
                self.solve_in_place(values, &mut z);
                z[s]
            };
            return slots.iter().map(solve).collect();
        };
        let (begin, end) = (sn.supernode_begin(), sn.supernode_end());
        let val_ptr = sn.col_ptr_for_val();
        let mut sums = vec![0.0; slots.len()];
        let (mut gathered, mut below, mut active) = (Vec::new(), Vec::new(), Vec::new());
        let batch = (DIAGONAL_WORK / m).clamp(1, DIAGONAL_BATCH);
        let mut w = self.work.borrow_mut();
        w.resize(m * batch, 0.0);
        // The entries of `w` written, set back to zero after each batch.
        let mut touched = Vec::new();
        for first in (0..slots.len()).step_by(batch) {
            let last = (first + batch).min(slots.len());
            // One column of `w` per solve of the batch; (supernode, solve) pairs due, lowest
            // supernode first: every supernode comes after its descendants.
            let mut due = BinaryHeap::new();
            for (c, &s) in slots[first..last].iter().enumerate() {
                let column = self.column_of(s);
                w[c * m + column] = 1.0;
                touched.push(c * m + column);
                due.push(Reverse((self.supernode_of[column], c)));
            }
            while let Some(Reverse((node, c))) = due.pop() {
                active.clear();
                active.push(c);
                while let Some(&Reverse((next, c))) = due.peek() {
                    if next != node {
                        break;
                    }
                    due.pop();
                    active.push(c);
                }
                // Supernode `node`: columns begin..end, its block column-major with the
                // diagonal block's rows first, then the rows of `pattern`.
                let (start, size) = (begin[node], end[node] - begin[node]);
                let pattern = sn.supernode(node).pattern();
                let rows = size + pattern.len();
                let block = &values[val_ptr[node]..val_ptr[node + 1]];
                gathered.clear();
                for &c in &active {
                    gathered.extend_from_slice(&w[c * m + start..c * m + start + size]);
                }
                let mut x = MatMut::from_column_major_slice_mut(&mut gathered, size, active.len());
                let diagonal = MatRef::from_column_major_slice_with_stride(block, size, size, rows);
                solve_lower_triangular_in_place(diagonal, x.as_mut(), Par::Seq);
                for (j, &c) in active.iter().enumerate() {
                    sums[first + c] += x.as_ref().col(j).squared_norm_l2();
                }
                if pattern.is_empty() {
                    continue;
                }
                below.clear();
                below.resize(pattern.len() * active.len(), 0.0);
                matmul(
                    MatMut::from_column_major_slice_mut(&mut below, pattern.len(), active.len()),
                    Accum::Replace,
                    MatRef::from_column_major_slice_with_stride(
                        &block[size..],
                        pattern.len(),
                        size,
                        rows,
                    ),
                    x.as_ref(),
                    1.0,
                    Par::Seq,
                );
                let parent = self.supernode_of[pattern[0]];
                for (j, &c) in active.iter().enumerate() {
                    if sums[first + c] > caps[first + c] {
                        continue;
                    }
                    let update = &below[j * pattern.len()..(j + 1) * pattern.len()];
                    for (&row, b) in pattern.iter().zip(update) {
                        w[c * m + row] -= b;
                        touched.push(c * m + row);
                    }
                    due.push(Reverse((parent, c)));
                }
            }
            for i in touched.drain(..) {
                w[i] = 0.0;
            }
        }
        sums
    }

    /// The column of the (fill-reducing permuted) factor that holds `slot`.
    fn column_of(&self, slot: usize) -> usize {
        self.symbolic.perm().map_or(slot, |p| p.arrays().1[slot])
    }

    /// Whether [`Self::selected_inverse_diagonal`] costs less than the pruned search of a
    /// release over `slots` by [`Self::inverse_diagonals`], taken as [`PRUNED_SOLVE_SHARE`] of
    /// the flops of their forward solves to the root.
    fn selected_inversion_pays(&self, slots: &[usize]) -> bool {
        if self.path_flops.is_empty() {
            return false;
        }
        let solves: f64 = slots
            .iter()
            .map(|&s| self.path_flops[self.supernode_of[self.column_of(s)]])
            .sum();
        self.selected_inversion_flops < PRUNED_SOLVE_SHARE * solves
    }

    /// The diagonal of `M⁻¹` at `slots`, for the matrix factorised in `values`, by
    /// selected inversion (Takahashi's equations over supernodes, as in Lin Lin's SelInv): with
    /// `M = L Lᵀ` and `Z = M⁻¹`, `Z L = L⁻ᵀ` gives for a supernode J, the rows B below its
    /// diagonal block and `U = L_BJ L_JJ⁻¹`
    /// `Z_BJ = −Z_BB U` and `Z_JJ = L_JJ⁻ᵀ L_JJ⁻¹ − Uᵀ Z_BJ`.
    /// `Z_BB` lies on the blocks of J's ancestors, so the supernodes are visited from the root
    /// down and `Z` is formed only on the factor's pattern: a few factorisations' work, whatever
    /// the number of entries wanted. `None` for a simplicial factor.
    fn selected_inverse_diagonal(&self, values: &[f64], slots: &[usize]) -> Option<Vec<f64>> {
        let SymbolicCholeskyRaw::Supernodal(sn) = self.symbolic.raw() else {
            return None;
        };
        let (begin, end) = (sn.supernode_begin(), sn.supernode_end());
        let val_ptr = sn.col_ptr_for_val();
        let mut z = vec![0.0; values.len()];
        let (mut u, mut z_bb, mut at) = (Vec::new(), Vec::new(), Vec::new());
        for node in (0..sn.n_supernodes()).rev() {
            let size = end[node] - begin[node];
            let pattern = sn.supernode(node).pattern();
            let (p, rows) = (pattern.len(), size + pattern.len());
            let block = &values[val_ptr[node]..val_ptr[node + 1]];
            let l_jj = MatRef::from_column_major_slice_with_stride(block, size, size, rows);
            // U = L_BJ L_JJ⁻¹, from L_JJᵀ Uᵀ = L_BJᵀ.
            u.clear();
            u.resize(p * size, 0.0);
            let mut u_mat = MatMut::from_column_major_slice_mut(&mut u, p, size);
            u_mat.copy_from(MatRef::from_column_major_slice_with_stride(
                &block[size..],
                p,
                size,
                rows,
            ));
            solve_upper_triangular_in_place(l_jj.transpose(), u_mat.transpose_mut(), Par::Seq);
            // Z_BB, both triangles, from the lower parts of the ancestors' blocks: the rows of B
            // from B[c] on are all rows of the supernode that owns column B[c].
            z_bb.clear();
            z_bb.resize(p * p, 0.0);
            let mut c = 0;
            while c < p {
                let owner = self.supernode_of[pattern[c]];
                let (o_begin, o_end) = (begin[owner], end[owner]);
                let o_pattern = sn.supernode(owner).pattern();
                let o_rows = o_end - o_begin + o_pattern.len();
                let first = c;
                at.clear();
                at.extend(pattern[first..].iter().map(|&row| match row < o_end {
                    true => row - o_begin,
                    false => o_end - o_begin + o_pattern.partition_point(|&q| q < row),
                }));
                let o_block = &z[val_ptr[owner]..val_ptr[owner + 1]];
                while c < p && pattern[c] < o_end {
                    let column = &o_block[(pattern[c] - o_begin) * o_rows..];
                    for r in c..p {
                        let v = column[at[r - first]];
                        z_bb[c * p + r] = v;
                        z_bb[r * p + c] = v;
                    }
                    c += 1;
                }
            }
            let z_j = MatMut::from_column_major_slice_with_stride_mut(
                &mut z[val_ptr[node]..val_ptr[node + 1]],
                rows,
                size,
                rows,
            );
            let (mut z_jj, mut z_bj) = z_j.split_at_row_mut(size);
            let u_mat = MatRef::from_column_major_slice(&u, p, size);
            matmul(
                z_bj.as_mut(),
                Accum::Replace,
                MatRef::from_column_major_slice(&z_bb, p, p),
                u_mat,
                -1.0,
                Par::Seq,
            );
            let mut l_inv = Mat::<f64>::identity(size, size);
            solve_lower_triangular_in_place(l_jj, l_inv.as_mut(), Par::Seq);
            matmul(
                z_jj.as_mut(),
                Accum::Replace,
                l_inv.transpose(),
                l_inv.as_ref(),
                1.0,
                Par::Seq,
            );
            matmul(
                z_jj.as_mut(),
                Accum::Add,
                u_mat.transpose(),
                z_bj.as_ref(),
                -1.0,
                Par::Seq,
            );
        }
        let diagonal = |&s: &usize| {
            let column = self.column_of(s);
            let node = self.supernode_of[column];
            let rows = end[node] - begin[node] + sn.supernode(node).pattern().len();
            let offset = column - begin[node];
            z[val_ptr[node] + offset * rows + offset]
        };
        Some(slots.iter().map(diagonal).collect())
    }

    /// Solves `M z = rhs` in place (`z` holds rhs over all slots) with the factor `values` of
    /// this pattern.
    fn solve_in_place(&self, values: &[f64], z: &mut [f64]) {
        let sym = &self.symbolic;
        let mut buf = MemBuffer::new(sym.solve_in_place_scratch::<f64>(1, Par::Seq));
        LltRef::new(sym, values).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(z, self.len(), 1),
            Par::Seq,
            MemStack::new(&mut buf),
        );
    }

    /// Number of slots.
    pub fn len(&self) -> usize {
        self.col_ptr.len() - 1
    }

    /// The slot of every key, or `None` if one has none.
    fn slots(&self, keys: &[Key]) -> Option<Vec<usize>> {
        keys.iter().map(|k| self.slot_of.get(k).copied()).collect()
    }

    /// Numeric Cholesky factor of `A Aᵀ` for the bonds `keys` (rows `links`), embedded in the
    /// slots; `Ok(None)` when a key has no slot.
    fn factor(
        self: &Rc<Self>,
        keys: &[Key],
        links: &[Link],
        d: usize,
    ) -> Result<Option<MinNorm>, String> {
        self.factor_shifted(keys, links, d, 0.0)
    }

    /// [`Self::factor`] of `A Aᵀ + shift·I`.
    fn factor_shifted(
        self: &Rc<Self>,
        keys: &[Key],
        links: &[Link],
        d: usize,
        shift: f64,
    ) -> Result<Option<MinNorm>, String> {
        let Some(slots) = self.slots(keys) else {
            return Ok(None);
        };
        let m = self.len();
        let mut bond_of_slot = vec![usize::MAX; m];
        for (k, &s) in slots.iter().enumerate() {
            bond_of_slot[s] = k;
        }
        let mut val = vec![0.0; self.row_idx.len()];
        for c in 0..m {
            let bc = bond_of_slot[c];
            let range = self.col_ptr[c]..self.col_ptr[c + 1];
            for ((v, &r), &sign) in val[range.clone()]
                .iter_mut()
                .zip(&self.row_idx[range.clone()])
                .zip(&self.sign[range])
            {
                let br = bond_of_slot[r];
                *v = if bc == usize::MAX || br == usize::MAX {
                    if r == c { 1.0 } else { 0.0 }
                } else {
                    let (nr, nc) = (&links[br].normal[..d], &links[bc].normal[..d]);
                    sign * (0..d).map(|q| nr[q] * nc[q]).sum::<f64>()
                        + if r == c { shift } else { 0.0 }
                };
            }
        }
        let sym = SymbolicSparseColMatRef::new_checked(m, m, &self.col_ptr, None, &self.row_idx);
        let a = SparseColMatRef::new(sym, &val);
        let mut values = vec![0.0; self.symbolic.len_val()];
        let mut buf = MemBuffer::new(
            self.symbolic
                .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
        );
        self.symbolic
            .factorize_numeric_llt(
                &mut values,
                a,
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut buf),
                Default::default(),
            )
            .map_err(|e| {
                format!("the bond Gram matrix A Aᵀ is not positive definite ({e:?}); the bonds are linearly dependent")
            })?;
        Ok(Some(MinNorm::Slotted {
            pattern: Rc::clone(self),
            values,
            slots,
        }))
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
            seconds: Cell::new(0.0),
        }
    }

    /// Factorises the bonds `keys` with rows `links` at the configuration `g`.
    pub fn factor(&self, keys: &[Key], links: &[Link], g: &Growth) -> Result<MinNorm, String> {
        let clock = std::time::Instant::now();
        let out = self.factor_timed(keys, links, g);
        self.seconds
            .set(self.seconds.get() + clock.elapsed().as_secs_f64());
        out
    }

    fn factor_timed(&self, keys: &[Key], links: &[Link], g: &Growth) -> Result<MinNorm, String> {
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
            // Slots: the bonds and the candidates close enough to become bonds soon (a wider
            // set costs fill in every numeric factorisation, a narrower one more rebuilds).
            let bonded: HashSet<&Key> = keys.iter().collect();
            let mut near: Vec<(f64, Key)> = g
                .candidates
                .keys
                .iter()
                .filter(|k| !bonded.contains(k))
                .map(|k| (g.link(k).rel_gap(g.t), *k))
                .filter(|&(gap, _)| gap < PATTERN_GAP)
                .collect();
            let spare = (keys.len() / PATTERN_SPARE_DIVISOR).max(PATTERN_MIN_SPARE);
            if near.len() > spare {
                near.select_nth_unstable_by(spare, |a, b| a.0.total_cmp(&b.0));
                near.truncate(spare);
            }
            let all: Vec<Key> = keys
                .iter()
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
mod tests {
    use super::*;
    use packbench_core::MAX_DIM;

    /// The fallback agrees with the SVD's pseudoinverse on a rank-deficient bond-like matrix
    /// (the third row is the sum of the first two).
    #[test]
    fn gram_pseudoinverse_matches_the_svd() {
        let rows = [
            [1.0, -0.5, 0.0, 2.0, 0.3],
            [0.0, 1.5, -1.0, 0.5, 0.0],
            [1.0, 1.0, -1.0, 2.5, 0.3],
        ];
        let a = Mat::<f64>::from_fn(3, 5, |r, c| rows[r][c]);
        let by_svd = a.thin_svd().unwrap().pseudoinverse();
        let by_gram = gram_pseudoinverse(a.as_ref()).unwrap();
        let err = (&by_svd - &by_gram).norm_max();
        assert!(err < 1e-10, "{err}");
    }

    /// A bond network of `m³` particles on a periodic cubic grid with pseudo-random normals:
    /// bonds to the +x and +y neighbours, and to the +z one for every third particle (about 2.3
    /// per particle, fewer than the 3 coordinates, so the rows are independent), plus unbonded
    /// slots to the other +z neighbours. Its Gram matrix fills in like a 3D packing's.
    fn network(m: usize) -> (Vec<Key>, Vec<Link>, Vec<Key>) {
        let n = m * m * m;
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut uniform = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let key = |i: usize, j: usize| Key::Pair {
            i: i as u32,
            j: j as u32,
            shift: [0; MAX_DIM],
        };
        let neighbour = |i: usize, axis: usize| {
            let stride = m.pow(axis as u32);
            let c = (i / stride) % m;
            i - c * stride + ((c + 1) % m) * stride
        };
        let (mut keys, mut links, mut spare) = (Vec::new(), Vec::new(), Vec::new());
        for i in 0..n {
            for axis in 0..3 {
                let j = neighbour(i, axis);
                if axis == 2 && i % 3 != 0 {
                    spare.push(key(i, j));
                    continue;
                }
                let v = [uniform(), uniform(), uniform()];
                let norm = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                let mut normal = [0.0; MAX_DIM];
                (0..3).for_each(|q| normal[q] = v[q] / norm);
                keys.push(key(i, j));
                links.push(Link {
                    i,
                    j: Some(j),
                    normal,
                    dist: 1.0,
                    size: 1.0,
                });
            }
        }
        (keys, links, spare)
    }

    /// The batched path-restricted forward solves and the selected inversion give the diagonal
    /// of `(A Aᵀ)⁻¹` of full solves, and with caps the solves stop at partial sums between the
    /// cap and the exact value.
    #[test]
    fn inverse_diagonals_match_full_solves() {
        let m = 9;
        let n = m * m * m;
        let (keys, links, spare) = network(m);
        let all: Vec<Key> = keys.iter().chain(&spare).copied().collect();
        let pattern = Rc::new(GramPattern::new(&all, n).unwrap());
        assert!(
            matches!(pattern.symbolic.raw(), SymbolicCholeskyRaw::Supernodal(_)),
            "the test should exercise the supernodal path"
        );
        let mn = pattern.factor(&keys, &links, 3).unwrap().unwrap();
        // More bonds than one batch, so that batches and their work matrices are reused.
        let ks: Vec<usize> = (0..keys.len()).step_by(7).collect();
        assert!(ks.len() > DIAGONAL_BATCH);
        let exact: Vec<f64> = ks
            .iter()
            .map(|&k| {
                let mut e = vec![0.0; keys.len()];
                e[k] = 1.0;
                mn.gram_solve(&e)[k]
            })
            .collect();
        let uncapped = vec![f64::INFINITY; ks.len()];
        let fast = mn.inverse_diagonals(&ks, &uncapped).unwrap();
        let halves: Vec<f64> = exact.iter().map(|e| 0.5 * e).collect();
        let capped = mn.inverse_diagonals(&ks, &halves).unwrap();
        // The first supernode alone is a lower bound.
        let first = mn
            .inverse_diagonals(&ks, &vec![f64::NEG_INFINITY; ks.len()])
            .unwrap();
        assert!(pattern.work.borrow().iter().all(|&v| v == 0.0));
        let MinNorm::Slotted { values, slots, .. } = &mn else {
            panic!("a slotted factor")
        };
        let ks_slots: Vec<usize> = ks.iter().map(|&k| slots[k]).collect();
        let selected = pattern
            .selected_inverse_diagonal(values, &ks_slots)
            .unwrap();
        for (j, &e) in exact.iter().enumerate() {
            let by_selection = selected[j];
            assert!(
                (by_selection - e).abs() <= 1e-10 * e,
                "{}: {by_selection} vs {e}",
                ks[j]
            );
            assert!(
                (fast[j] - e).abs() <= 1e-10 * e,
                "{}: {} vs {e}",
                ks[j],
                fast[j]
            );
            assert!(
                capped[j] > 0.5 * e && capped[j] <= e * (1.0 + 1e-12),
                "{}",
                ks[j]
            );
            assert!(first[j] > 0.0 && first[j] <= e * (1.0 + 1e-12), "{}", ks[j]);
        }
        assert!(
            first.iter().zip(&exact).any(|(f, e)| f < &(0.99 * e)),
            "the bound should stop early somewhere"
        );
    }

    /// A factor of all but the last bonds, bordered with those bonds one at a time and with two
    /// base bonds and one added bond released, solves the changed Gram system at once:
    /// bordering is exact while the particles stay put, so conjugate gradients converge in one
    /// iteration to the exact factor's solution.
    #[test]
    fn a_bordered_factor_solves_the_changed_basis() {
        let m = 6;
        let n = m * m * m;
        let (keys, links, spare) = network(m);
        let all: Vec<Key> = keys.iter().chain(&spare).copied().collect();
        let pattern = Rc::new(GramPattern::new(&all, n).unwrap());
        let k0 = keys.len() - 5;
        let base = Rc::new(
            pattern
                .factor(&keys[..k0], &links[..k0], 3)
                .unwrap()
                .unwrap(),
        );
        let mut pre = Preconditioner::new(&base).unwrap();
        let (mut basis, mut rows) = (keys[..k0].to_vec(), links[..k0].to_vec());
        for k in k0..keys.len() {
            basis.push(keys[k]);
            rows.push(links[k]);
            pre = pre.extend(&basis, &rows, n, 3).unwrap();
        }
        for gone in [0, 7, k0 + 1] {
            pre = pre.release(&keys[gone]).unwrap();
            let at = basis.iter().position(|k| *k == keys[gone]).unwrap();
            basis.remove(at);
            rows.remove(at);
        }
        let stats = Rc::new(CgStats::default());
        let pre = Rc::new(pre);
        let bordered = MinNorm::iterative(&pre, &basis, &rows, n, 3, &stats).unwrap();
        let exact = GramPattern::new(&basis, n)
            .map(Rc::new)
            .unwrap()
            .factor(&basis, &rows, 3)
            .unwrap()
            .unwrap();
        let rhs: Vec<f64> = (0..basis.len()).map(|k| 1.0 + (k % 7) as f64).collect();
        let (x, y) = (bordered.gram_solve(&rhs), exact.gram_solve(&rhs));
        let err = x
            .iter()
            .zip(&y)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(err <= 1e-10 * scale, "{err} vs {scale}");
        assert!(
            stats.failures.get() == 0 && stats.worst.get() <= 1,
            "{}",
            stats.worst.get()
        );
        // A basis missing a bond the preconditioner holds gets no iterative form.
        assert!(MinNorm::iterative(&pre, &basis[1..], &rows[1..], n, 3, &stats).is_none());
    }

    /// A square with both diagonals braced (4 particles in a plane, 6 bonds, 5 independent)
    /// is a fold in miniature: `A Aᵀ` is singular and its null vector is the self-stress,
    /// sides `+1` and diagonals `−√2`. The fold multipliers are that self-stress, balanced
    /// (`Aᵀλ = 0`), with the sign of `G⁻¹b` approached from outside the fold (`λᵀb > 0`).
    #[test]
    fn fold_multipliers_are_the_self_stress_of_a_singular_basis() {
        let corners = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let pairs = [(0, 1), (1, 2), (3, 2), (0, 3), (0, 2), (1, 3)];
        let (mut keys, mut links) = (Vec::new(), Vec::new());
        for &(i, j) in &pairs {
            let (a, b): ([f64; 2], [f64; 2]) = (corners[i], corners[j]);
            let dist = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
            let mut normal = [0.0; MAX_DIM];
            normal[0] = (b[0] - a[0]) / dist;
            normal[1] = (b[1] - a[1]) / dist;
            keys.push(Key::Pair {
                i: i as u32,
                j: j as u32,
                shift: [0; MAX_DIM],
            });
            links.push(Link {
                i,
                j: Some(j),
                normal,
                dist,
                size: 1.0,
            });
        }
        let lambda = Solver::new(0)
            .fold_multipliers(&keys, &links, 4, 3)
            .unwrap();
        let mut net = vec![0.0; 12];
        for (l, &f) in links.iter().zip(&lambda) {
            l.add_transposed(f, &mut net, 3);
        }
        let scale = lambda.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let unbalanced = net.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(unbalanced <= 1e-6 * scale, "{unbalanced} vs {scale}");
        for k in 0..6 {
            let expected = if k < 4 { 1.0 } else { -2f64.sqrt() };
            assert!(
                (lambda[k] / lambda[0] - expected).abs() < 1e-6,
                "{lambda:?}"
            );
        }
        assert!(lambda[0] > 0.0, "{lambda:?}");
    }
}
