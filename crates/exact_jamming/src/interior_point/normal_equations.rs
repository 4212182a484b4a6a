//! The normal equations `Gᵀ W G Δx = r` of one interior-point iteration: assembly over the
//! fixed sparsity of `GᵀG`, Jacobi scaling, faer's sparse Cholesky with huge pivots for the
//! columns no row holds, and iterative refinement of each direction.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::SparseColMatRef;
use faer::sparse::linalg::cholesky::LltRef;
use faer::{Conj, MatMut, Par, Side};

use super::{InequalityLp, LpSolution};
use packbench_core::sparse_pattern::LowerPattern;

/// A diagonal of the normal matrix at or below this is a column no row holds (see
/// [`NormalEquations::factor`]); above it, the Jacobi scales stay below 1e100 and their
/// products finite.
const UNWEIGHTED: f64 = 1e-200;

/// Rounds of iterative refinement of each Newton direction at most.
pub(super) const REFINEMENTS: usize = 4;

pub(super) fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |a, e| a.max(e.abs()))
}

/// Largest `α` with `v + α dv ≥ 0` (infinite when no component decreases).
pub(super) fn max_step(v: &[f64], dv: &[f64]) -> f64 {
    v.iter()
        .zip(dv)
        .filter(|(_, d)| **d < 0.0)
        .fold(f64::INFINITY, |a, (v, d)| a.min(-v / d))
}

/// The rows of `G` over the free variables, the pattern of `GᵀWG`, its symbolic Cholesky
/// factorisation, and where each row's products land among its values.
pub(super) struct NormalEquations {
    /// Free variables: `var[j]` is the LP variable of column j.
    pub(super) var: Vec<usize>,
    pub(super) n_vars: usize,
    pub(super) n: usize,
    /// `G` row-compressed over free columns.
    pub(super) row_ptr: Vec<usize>,
    pub(super) col: Vec<usize>,
    pub(super) val: Vec<f64>,
    /// `GᵀWG`'s lower triangle with its ordering and symbolic factor.
    pub(super) pattern: LowerPattern,
    /// Per row, the value slots of its term pairs (a ≤ b in term order), in row order.
    pub(super) slots: Vec<usize>,
    pub(super) diagonal: Vec<usize>,
    /// Threads of the numeric factorisations and solves ([`parallelism`]).
    pub(super) par: Par,
}

/// Columns (free LP variables) from which the numeric factorisation and its solves run on
/// rayon's threads: below, the supernodes are too small for the threads to pay (two threads
/// at N = 300 took 60.8 s CPU against 31.8 s, most of the extra spinning;
/// docs/notes/calippso-lp-solver.md). 3D at N = 4000 has about 12 000.
const PARALLEL_MIN_COLUMNS: usize = 10_000;

/// The parallelism of a factorisation of `n` columns: rayon's pool (its thread count, e.g.
/// `RAYON_NUM_THREADS`) when asked for and the system is large, else one thread.
fn parallelism(asked: bool, n: usize) -> Par {
    if asked && n >= PARALLEL_MIN_COLUMNS && rayon::current_num_threads() > 1 {
        Par::rayon(0)
    } else {
        Par::Seq
    }
}

/// Storage of a numeric factor and the scratch of its factorisation and solves.
pub(super) struct Workspace {
    pub(super) values: Vec<f64>,
    pub(super) factor_scratch: MemBuffer,
    pub(super) solve_scratch: std::cell::RefCell<MemBuffer>,
}

impl Workspace {
    pub(super) fn new(normal: &NormalEquations) -> Self {
        let (symbolic, par) = (normal.pattern.symbolic(), normal.par);
        Workspace {
            values: vec![0.0; symbolic.len_val()],
            factor_scratch: MemBuffer::new(
                symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()),
            ),
            solve_scratch: std::cell::RefCell::new(MemBuffer::new(
                symbolic.solve_in_place_scratch::<f64>(1, par),
            )),
        }
    }
}

/// A numeric factor of `GᵀWG`.
pub(super) struct Factor<'a> {
    pub(super) normal: &'a NormalEquations,
    pub(super) values: &'a [f64],
    pub(super) solve_scratch: &'a std::cell::RefCell<MemBuffer>,
    /// The Jacobi scaling `D^{-1/2}` the factor is of: `LLᵀ = D^{-1/2} GᵀWG D^{-1/2}`.
    pub(super) scale: Vec<f64>,
}

impl NormalEquations {
    pub(super) fn new(lp: &InequalityLp) -> Result<Self, String> {
        let mut column = vec![usize::MAX; lp.c.len()];
        let var: Vec<usize> = (0..lp.c.len()).filter(|&v| !lp.fixed[v]).collect();
        for (j, &v) in var.iter().enumerate() {
            column[v] = j;
        }
        let n = var.len();
        let (mut row_ptr, mut col, mut val) = (vec![0], Vec::new(), Vec::new());
        for k in 0..lp.rows() {
            for e in lp.row_ptr[k]..lp.row_ptr[k + 1] {
                if !lp.fixed[lp.col[e]] {
                    col.push(column[lp.col[e]]);
                    val.push(lp.val[e]);
                }
            }
            row_ptr.push(col.len());
        }
        let pairs = |k: usize| {
            let cols = &col[row_ptr[k]..row_ptr[k + 1]];
            (0..cols.len()).flat_map(move |a| {
                cols[a..]
                    .iter()
                    .map(move |&cb| (cols[a].min(cb), cols[a].max(cb)))
            })
        };
        let entries = (0..lp.rows()).flat_map(pairs).collect();
        let pattern = LowerPattern::new(n, entries).map_err(|e| format!("GᵀWG: {e}"))?;
        let slots = (0..lp.rows())
            .flat_map(pairs)
            .map(|e| pattern.slot(e))
            .collect();
        let diagonal = (0..n).map(|j| pattern.slot((j, j))).collect();
        Ok(NormalEquations {
            var,
            n_vars: lp.c.len(),
            n,
            row_ptr,
            col,
            val,
            pattern,
            slots,
            diagonal,
            par: parallelism(lp.parallel, n),
        })
    }

    pub(super) fn row(&self, k: usize) -> std::ops::Range<usize> {
        self.row_ptr[k]..self.row_ptr[k + 1]
    }

    /// `G x` over all rows.
    pub(super) fn g_times(&self, x: &[f64]) -> Vec<f64> {
        (0..self.row_ptr.len() - 1)
            .map(|k| self.row(k).map(|e| self.val[e] * x[self.col[e]]).sum())
            .collect()
    }

    /// `Gᵀ y`.
    pub(super) fn gt_times(&self, y: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.n];
        for (k, &yk) in y.iter().enumerate() {
            for e in self.row(k) {
                out[self.col[e]] += self.val[e] * yk;
            }
        }
        out
    }

    /// The Cholesky factor of `Gᵀ diag(w) G`, Jacobi-scaled; a pivot below 1e-13 of its
    /// column's diagonal becomes 1e64, which zeroes the step along that direction (see the
    /// module).
    pub(super) fn factor<'a>(
        &'a self,
        w: &[f64],
        work: &'a mut Workspace,
    ) -> Result<Factor<'a>, String> {
        let mut a = vec![0.0; self.pattern.len()];
        let mut next = 0;
        for (k, &wk) in w.iter().enumerate() {
            let vals = &self.val[self.row(k)];
            for (i, &va) in vals.iter().enumerate() {
                for &vb in &vals[i..] {
                    a[self.slots[next]] += wk * va * vb;
                    next += 1;
                }
            }
        }
        // Jacobi scaling, so that the pivot threshold is relative to each column's own size. A
        // column whose rows all have vanishing weights (z/s down to 1e-310 near an optimum,
        // a 3D start at N = 200) is left unscaled: 1/√diag would overflow the
        // products of two scales to ∞ and the matrix to NaN; unscaled, its pivot falls below
        // the threshold and the step along it is zeroed, as for any direction no row holds.
        let scale: Vec<f64> = self
            .diagonal
            .iter()
            .map(|&p| {
                if a[p] > UNWEIGHTED {
                    1.0 / a[p].sqrt()
                } else {
                    1.0
                }
            })
            .collect();
        let (col_ptr, row_idx) = self.pattern.columns();
        for c in 0..self.n {
            for p in col_ptr[c]..col_ptr[c + 1] {
                a[p] *= scale[c] * scale[row_idx[p]];
            }
        }
        self.pattern
            .symbolic()
            .factorize_numeric_llt(
                &mut work.values,
                SparseColMatRef::new(self.pattern.as_faer(), &a),
                Side::Lower,
                LltRegularization {
                    dynamic_regularization_delta: 1e64,
                    dynamic_regularization_epsilon: 1e-13,
                },
                self.par,
                MemStack::new(&mut work.factor_scratch),
                Default::default(),
            )
            .map_err(|e| format!("the normal equations GᵀWG have no Cholesky factor ({e:?})"))?;
        Ok(Factor {
            normal: self,
            values: &work.values,
            solve_scratch: &work.solve_scratch,
            scale,
        })
    }

    /// Maps the free-column iterate back to every LP variable.
    pub(super) fn solution(
        &self,
        x: Vec<f64>,
        z: Vec<f64>,
        iterations: u32,
        converged: bool,
    ) -> LpSolution {
        let mut full = vec![0.0; self.n_vars];
        for (j, &v) in self.var.iter().enumerate() {
            full[v] = x[j];
        }
        LpSolution {
            x: full,
            z,
            iterations,
            converged,
            interrupted: false,
            by_clarabel: false,
        }
    }
}

impl Factor<'_> {
    pub(super) fn solve(&self, rhs: &[f64]) -> Vec<f64> {
        let sym = self.normal.pattern.symbolic();
        let mut x: Vec<f64> = rhs.iter().zip(&self.scale).map(|(r, c)| r * c).collect();
        let mut buf = self.solve_scratch.borrow_mut();
        LltRef::new(sym, self.values).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(&mut x, self.normal.n, 1),
            self.normal.par,
            MemStack::new(&mut buf),
        );
        x.iter_mut().zip(&self.scale).for_each(|(v, c)| *v *= c);
        x
    }
}
