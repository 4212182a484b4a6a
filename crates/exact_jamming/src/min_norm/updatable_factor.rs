//! A sparse LDLᵀ factor of a symmetric positive definite matrix that is modified row by row
//! instead of recomputed: SuiteSparse's CHOLMOD (`cholmod_rowadd`, `cholmod_rowdel`, each a
//! rank-two update of the simplicial factor), through the small C shim `cholmod_shim.c` that
//! keeps CHOLMOD's structures opaque. All unsafe code of the crate's CHOLMOD use is in this
//! module.
//!
//! The matrix is the slotted bond Gram matrix of [`super::gram_pattern`]: a slot that holds no
//! bond is an identity row, so a bond joining the basis is `cholmod_rowadd` of its slot's row
//! and a bond leaving it is `cholmod_rowdel`, both exact for the matrix they describe. With
//! G = Pᵀ L D Lᵀ P, `(G⁻¹)_ss = Σ_j (L⁻¹ P e_s)_j² / D_j`, a sparse forward solve along the
//! elimination-tree path from the slot's column to the root.
//!
//! Invariants the safe type keeps: the handle is non-null and owned (freed once, in `Drop`);
//! the column arrays read by [`UpdatableFactor::inverse_diagonal`] are borrowed from the handle
//! only while `&self` is (every change takes `&mut self`); every index passed to C is below the
//! factor's order; the type is neither `Send` nor `Sync` (CHOLMOD's workspace lives in the
//! handle).

use std::ffi::c_int;
use std::ptr::NonNull;

#[repr(C)]
struct Handle {
    _private: [u8; 0],
}

#[link(name = "cholmod")]
unsafe extern "C" {}

unsafe extern "C" {
    #[cfg(test)]
    fn pb_factor_new(
        n: c_int,
        colptr: *const c_int,
        rowind: *const c_int,
        val: *const f64,
    ) -> *mut Handle;
    fn pb_factor_from_ldl(
        n: c_int,
        perm: *const c_int,
        colptr: *const c_int,
        rowind: *const c_int,
        val: *const f64,
    ) -> *mut Handle;
    fn pb_factor_free(f: *mut Handle);
    fn pb_factor_perm(f: *const Handle, perm: *mut c_int);
    fn pb_factor_columns(
        f: *const Handle,
        colptr: *mut *const c_int,
        rowind: *mut *const c_int,
        val: *mut *const f64,
        colcount: *mut *const c_int,
        nzmax: *mut usize,
    );
    fn pb_factor_rowadd(
        f: *mut Handle,
        k: c_int,
        nnz: c_int,
        rowind: *const c_int,
        val: *const f64,
    ) -> c_int;
    fn pb_factor_rowdel(f: *mut Handle, k: c_int) -> c_int;
    fn pb_factor_solve(f: *mut Handle, b: *mut f64) -> c_int;
}

/// A simplicial LDLᵀ factor of an `n × n` symmetric positive definite matrix, kept by row
/// additions and deletions.
pub(crate) struct UpdatableFactor {
    handle: NonNull<Handle>,
    n: usize,
    /// Row of L for each row of the matrix (the inverse of CHOLMOD's fill-reducing permutation).
    position: Vec<usize>,
}

/// The simplicial factor's arrays, borrowed from the handle.
struct Columns<'a> {
    start: &'a [c_int],
    rows: &'a [c_int],
    values: &'a [f64],
    count: &'a [c_int],
}

fn to_c(v: usize) -> Result<c_int, String> {
    c_int::try_from(v).map_err(|_| format!("{v} exceeds CHOLMOD's 32-bit indices"))
}

impl UpdatableFactor {
    /// Factors the matrix whose lower triangle is `col_ptr`/`row_idx`/`val`
    /// (column-compressed, rows ascending) with CHOLMOD's own ordering and factorisation (the
    /// fresh factor the tests compare updates with). Fails when it is not positive definite.
    #[cfg(test)]
    pub fn new(col_ptr: &[usize], row_idx: &[usize], val: &[f64]) -> Result<Self, String> {
        let n = col_ptr.len() - 1;
        let cp: Vec<c_int> = col_ptr.iter().map(|&v| to_c(v)).collect::<Result<_, _>>()?;
        let ri: Vec<c_int> = row_idx.iter().map(|&v| to_c(v)).collect::<Result<_, _>>()?;
        assert_eq!(val.len(), row_idx.len(), "one value per stored entry");
        assert_eq!(
            col_ptr[n],
            row_idx.len(),
            "column pointers end at the entry count"
        );
        // SAFETY: the three arrays are valid for n + 1 and col_ptr[n] elements (checked above)
        // and outlive the call, which copies them.
        let raw = unsafe { pb_factor_new(to_c(n)?, cp.as_ptr(), ri.as_ptr(), val.as_ptr()) };
        Self::from_handle(raw, n)
    }

    /// The factor given as a simplicial LDLᵀ: `perm[k]` the matrix row at row k of L, and
    /// the columns of L in its indexing (`col_ptr`/`row_idx`/`val`, rows ascending, the
    /// diagonal first holding `D_jj`), as [`super::gram_pattern::GramPattern::ldl_columns`]
    /// gives them. Fails when a `D_jj` is not positive.
    pub fn from_ldl(
        perm: &[usize],
        col_ptr: &[usize],
        row_idx: &[usize],
        val: &[f64],
    ) -> Result<Self, String> {
        let n = perm.len();
        assert_eq!(
            col_ptr.len(),
            n + 1,
            "one column per row of the permutation"
        );
        assert_eq!(
            col_ptr[n],
            row_idx.len(),
            "column pointers end at the entry count"
        );
        assert_eq!(val.len(), row_idx.len(), "one value per stored entry");
        assert!(row_idx.iter().all(|&r| r < n), "rows below the order");
        let c = |v: &[usize]| v.iter().map(|&x| to_c(x)).collect::<Result<Vec<_>, _>>();
        let (pm, cp, ri) = (c(perm)?, c(col_ptr)?, c(row_idx)?);
        // SAFETY: the arrays hold n, n + 1, col_ptr[n] and col_ptr[n] elements (checked above),
        // every index below n, and outlive the call, which copies them.
        let raw = unsafe {
            pb_factor_from_ldl(
                to_c(n)?,
                pm.as_ptr(),
                cp.as_ptr(),
                ri.as_ptr(),
                val.as_ptr(),
            )
        };
        Self::from_handle(raw, n)
    }

    fn from_handle(raw: *mut Handle, n: usize) -> Result<Self, String> {
        let handle = NonNull::new(raw).ok_or_else(|| {
            "CHOLMOD could not factor the matrix (not positive definite, or out of memory)"
                .to_string()
        })?;
        let mut perm = vec![0 as c_int; n];
        // SAFETY: `handle` is a live factor of order n, `perm` holds n elements.
        unsafe { pb_factor_perm(handle.as_ptr(), perm.as_mut_ptr()) };
        let mut position = vec![0; n];
        for (k, &row) in perm.iter().enumerate() {
            position[row as usize] = k;
        }
        Ok(UpdatableFactor {
            handle,
            n,
            position,
        })
    }

    /// The order of the matrix.
    pub fn len(&self) -> usize {
        self.n
    }

    /// Row and column `row` of the matrix become `entries` (`(row, value)` pairs, the
    /// diagonal included); before, they must be those of the identity. Fails when the matrix is
    /// no longer positive definite, and the factor must then be rebuilt.
    pub fn add_row(&mut self, row: usize, entries: &[(usize, f64)]) -> Result<(), String> {
        assert!(row < self.n, "row {row} of a factor of order {}", self.n);
        let rows: Vec<c_int> = entries
            .iter()
            .map(|&(r, _)| to_c(self.position[r]))
            .collect::<Result<_, _>>()?;
        let vals: Vec<f64> = entries.iter().map(|e| e.1).collect();
        // SAFETY: live handle; `rows` and `vals` hold entries.len() elements each, every index
        // below n (`position` is a permutation of 0..n).
        let ok = unsafe {
            pb_factor_rowadd(
                self.handle.as_ptr(),
                to_c(self.position[row])?,
                to_c(rows.len())?,
                rows.as_ptr(),
                vals.as_ptr(),
            )
        };
        match ok {
            1 => Ok(()),
            _ => Err(format!(
                "adding row {row} left the matrix not positive definite"
            )),
        }
    }

    /// Row and column `row` of the matrix become those of the identity.
    pub fn delete_row(&mut self, row: usize) -> Result<(), String> {
        assert!(row < self.n, "row {row} of a factor of order {}", self.n);
        // SAFETY: live handle, index below n.
        let ok = unsafe { pb_factor_rowdel(self.handle.as_ptr(), to_c(self.position[row])?) };
        match ok {
            1 => Ok(()),
            _ => Err(format!("CHOLMOD failed to delete row {row}")),
        }
    }

    /// `b := G⁻¹ b` (length n).
    pub fn solve_in_place(&mut self, b: &mut [f64]) {
        assert_eq!(b.len(), self.n, "a right-hand side of the factor's order");
        // SAFETY: live handle, `b` holds n elements.
        let ok = unsafe { pb_factor_solve(self.handle.as_ptr(), b.as_mut_ptr()) };
        if ok != 1 {
            b.fill(f64::NAN);
        }
    }

    fn columns(&self) -> Columns<'_> {
        let (mut s, mut r, mut v, mut c, mut len) = (
            std::ptr::null(),
            std::ptr::null(),
            std::ptr::null(),
            std::ptr::null(),
            0,
        );
        // SAFETY: live handle; the arrays are the simplicial factor's (n + 1 column starts,
        // n counts, and `len` = nzmax allocated entries), unchanged while `&self` is borrowed
        // since every change takes `&mut self`.
        unsafe {
            pb_factor_columns(
                self.handle.as_ptr(),
                &mut s,
                &mut r,
                &mut v,
                &mut c,
                &mut len,
            );
            Columns {
                start: std::slice::from_raw_parts(s, self.n + 1),
                rows: std::slice::from_raw_parts(r, len),
                values: std::slice::from_raw_parts(v, len),
                count: std::slice::from_raw_parts(c, self.n),
            }
        }
    }

    /// `(G⁻¹)_rr` by a sparse forward solve from row `row`'s column of L to the root, with `work`
    /// a zero vector of length n (left zero). The solve stops once its partial sum (a lower
    /// bound, growing column by column) exceeds `cap`, and returns that bound: with `cap` −∞,
    /// the first column's `1/D`.
    pub fn inverse_diagonal(&self, row: usize, cap: f64, work: &mut [f64]) -> f64 {
        let cols = self.columns();
        let mut next = Some(self.position[row]);
        work[self.position[row]] = 1.0;
        let (mut sum, mut stopped) = (0.0, false);
        while let Some(j) = next {
            let (start, count) = (cols.start[j] as usize, cols.count[j] as usize);
            // The parent in the elimination tree: the first row below the diagonal. A column's
            // rows are all on the path to the root, so walking it on clears the work vector.
            next = (count > 1).then(|| cols.rows[start + 1] as usize);
            let xj = std::mem::take(&mut work[j]);
            if stopped {
                continue;
            }
            sum += xj * xj / cols.values[start];
            for p in start + 1..start + count {
                work[cols.rows[p] as usize] -= cols.values[p] * xj;
            }
            stopped = sum > cap;
        }
        sum
    }
}

impl Drop for UpdatableFactor {
    fn drop(&mut self) {
        // SAFETY: the handle is owned and freed only here.
        unsafe { pb_factor_free(self.handle.as_ptr()) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::rngs::StdRng;
    use rand::{RngExt, SeedableRng};

    /// A random sparse symmetric positive definite `n × n` matrix `A Aᵀ + I/2` (A with three
    /// nonzeros per row), dense for checks.
    fn random_gram(n: usize, rng: &mut StdRng) -> Vec<Vec<f64>> {
        let m = 2 * n;
        let rows: Vec<Vec<(usize, f64)>> = (0..n)
            .map(|_| {
                (0..3)
                    .map(|_| (rng.random_range(0..m), rng.random_range(-1.0..1.0)))
                    .collect()
            })
            .collect();
        let dot = |a: &[(usize, f64)], b: &[(usize, f64)]| {
            a.iter()
                .flat_map(|&(i, x)| b.iter().filter(move |e| e.0 == i).map(move |e| x * e.1))
                .sum::<f64>()
        };
        (0..n)
            .map(|r| {
                (0..n)
                    .map(|c| dot(&rows[r], &rows[c]) + if r == c { 0.5 } else { 0.0 })
                    .collect()
            })
            .collect()
    }

    fn lower_csc(g: &[Vec<f64>]) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
        let n = g.len();
        let (mut cp, mut ri, mut v) = (vec![0], Vec::new(), Vec::new());
        for c in 0..n {
            for (r, row) in g.iter().enumerate().skip(c) {
                if row[c] != 0.0 || r == c {
                    ri.push(r);
                    v.push(row[c]);
                }
            }
            cp.push(ri.len());
        }
        (cp, ri, v)
    }

    /// The LDLᵀ factor of `g` computed densely, in natural order, as an [`UpdatableFactor`].
    fn dense_ldl(g: &[Vec<f64>]) -> UpdatableFactor {
        let n = g.len();
        let mut l = vec![vec![0.0; n]; n];
        let mut dg = vec![0.0; n];
        for j in 0..n {
            dg[j] = g[j][j] - (0..j).map(|k| l[j][k] * l[j][k] * dg[k]).sum::<f64>();
            l[j][j] = 1.0;
            for i in j + 1..n {
                l[i][j] =
                    (g[i][j] - (0..j).map(|k| l[i][k] * l[j][k] * dg[k]).sum::<f64>()) / dg[j];
            }
        }
        let (mut cp, mut ri, mut v) = (vec![0], Vec::new(), Vec::new());
        for j in 0..n {
            ri.push(j);
            v.push(dg[j]);
            for (i, row) in l.iter().enumerate().skip(j + 1) {
                if row[j] != 0.0 {
                    ri.push(i);
                    v.push(row[j]);
                }
            }
            cp.push(ri.len());
        }
        let perm: Vec<usize> = (0..n).collect();
        UpdatableFactor::from_ldl(&perm, &cp, &ri, &v).unwrap()
    }

    fn dense_solve(g: &[Vec<f64>], b: &[f64]) -> Vec<f64> {
        let n = g.len();
        let m = faer::Mat::<f64>::from_fn(n, n, |r, c| g[r][c]);
        let rhs = faer::Mat::<f64>::from_fn(n, 1, |r, _| b[r]);
        let x = faer::linalg::solvers::Solve::solve(
            &m.llt(faer::Side::Lower).expect("positive definite"),
            &rhs,
        );
        (0..n).map(|r| x[(r, 0)]).collect()
    }

    /// Random swaps of active rows (one deleted, one added), as the bond basis of the
    /// closest-jammed integrator changes: after each, the updated factor solves as a fresh one
    /// to 1e-12, and its inverse diagonals match.
    #[test]
    fn row_swaps_solve_as_a_fresh_factorisation() {
        let mut rng = StdRng::seed_from_u64(7);
        let n = 60;
        let mut active: Vec<bool> = (0..n).map(|_| rng.random_bool(0.6)).collect();
        // The matrix with every row active; a subset's matrix is its rows, identity elsewhere.
        let full = random_gram(n, &mut rng);
        let restrict = |active: &[bool]| -> Vec<Vec<f64>> {
            (0..n)
                .map(|r| {
                    (0..n)
                        .map(|c| match (active[r] && active[c], r == c) {
                            (true, _) => full[r][c],
                            (false, diag) => f64::from(u8::from(diag)),
                        })
                        .collect()
                })
                .collect()
        };
        // The first factor handed over as an LDLᵀ in natural order.
        let mut f = dense_ldl(&restrict(&active));
        let mut work = vec![0.0; n];
        for swap in 0..40 {
            let on: Vec<usize> = (0..n).filter(|&r| active[r]).collect();
            let off: Vec<usize> = (0..n).filter(|&r| !active[r]).collect();
            let gone = on[rng.random_range(0..on.len())];
            let new = off[rng.random_range(0..off.len())];
            f.delete_row(gone).unwrap();
            active[gone] = false;
            active[new] = true;
            let entries: Vec<(usize, f64)> = (0..n)
                .filter(|&c| active[c] && full[new][c] != 0.0)
                .map(|c| (c, full[new][c]))
                .collect();
            f.add_row(new, &entries).unwrap();
            let g = restrict(&active);
            let b: Vec<f64> = (0..n).map(|_| rng.random_range(-1.0..1.0)).collect();
            let mut x = b.clone();
            f.solve_in_place(&mut x);
            let (cp, ri, v) = lower_csc(&g);
            let mut fresh = b.clone();
            UpdatableFactor::new(&cp, &ri, &v)
                .unwrap()
                .solve_in_place(&mut fresh);
            let exact = dense_solve(&g, &b);
            let scale = exact.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for r in 0..n {
                assert!(
                    (x[r] - fresh[r]).abs() <= 1e-12 * scale,
                    "swap {swap}, row {r}"
                );
                assert!(
                    (x[r] - exact[r]).abs() <= 1e-12 * scale,
                    "swap {swap}, row {r}"
                );
            }
            for r in [new, on[0]] {
                let mut e = vec![0.0; n];
                e[r] = 1.0;
                let inv = dense_solve(&g, &e)[r];
                let got = f.inverse_diagonal(r, f64::INFINITY, &mut work);
                assert!(f.inverse_diagonal(r, f64::NEG_INFINITY, &mut work) <= got);
                assert!(
                    (got - inv).abs() <= 1e-12 * inv.abs(),
                    "swap {swap}, row {r}"
                );
                assert!(work.iter().all(|&w| w == 0.0));
            }
        }
    }

    #[test]
    fn a_matrix_that_is_not_positive_definite_is_refused() {
        // [[1, 2], [2, 1]] has eigenvalue −1.
        let err = UpdatableFactor::new(&[0, 2, 3], &[0, 1, 1], &[1.0, 2.0, 1.0]);
        assert!(err.is_err());
        // Adding a row that makes it indefinite fails too.
        let mut f = UpdatableFactor::new(&[0, 1, 2], &[0, 1], &[1.0, 1.0]).unwrap();
        f.delete_row(1).unwrap();
        assert!(f.add_row(1, &[(0, 2.0), (1, 1.0)]).is_err());
    }
}
