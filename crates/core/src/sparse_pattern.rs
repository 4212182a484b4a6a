//! The sparsity pattern of a symmetric positive (semi)definite matrix built from products of
//! sparse rows (`G Gᵀ` of the force balance's projection, `GᵀWG` of calippso's normal equations,
//! `A Aᵀ` of closest-jammed's minimum-norm solves): the lower triangle, column-compressed with
//! sorted rows and every diagonal present, where each entry's value lives ([`LowerPattern::slot`]),
//! METIS's fill-reducing ordering ([`crate::fill_ordering::nested_dissection`]) and faer's symbolic
//! Cholesky factorisation over it. Built once per pattern; each numeric factorisation reuses it.

use faer::Side;
use faer::sparse::SymbolicSparseColMatRef;
use faer::sparse::linalg::cholesky::{self, SymbolicCholesky};

use crate::fill_ordering::nested_dissection;

/// The lower triangle of a symmetric matrix's pattern with its ordering and symbolic factor.
pub struct LowerPattern {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    symbolic: SymbolicCholesky<usize>,
}

impl LowerPattern {
    /// The pattern of order `n` holding the entries `(column, row)` (column ≤ row, in any order,
    /// repeats allowed) and every diagonal.
    ///
    /// Errors: faer's symbolic factorisation failed (it names the error).
    pub fn new(n: usize, entries: Vec<(usize, usize)>) -> Result<Self, String> {
        let (pattern, _) = Self::with_sums(n, entries.into_iter().map(|(c, r)| (c, r, 0.0)))?;
        Ok(pattern)
    }

    /// [`Self::new`] for entries that carry a value: also returns, per stored entry in storage
    /// order, the sum of the values of its repeats (0 for a diagonal no entry names).
    pub fn with_sums(
        n: usize,
        entries: impl IntoIterator<Item = (usize, usize, f64)>,
    ) -> Result<(Self, Vec<f64>), String> {
        let mut entries: Vec<(usize, usize, f64)> =
            (0..n).map(|j| (j, j, 0.0)).chain(entries).collect();
        entries.sort_unstable_by_key(|&(c, r, _)| (c, r));
        let mut col_ptr = vec![0usize; n + 1];
        let mut row_idx = Vec::with_capacity(entries.len());
        let mut sums: Vec<f64> = Vec::with_capacity(entries.len());
        let mut last = (usize::MAX, usize::MAX);
        for (c, r, v) in entries {
            debug_assert!(
                c <= r && r < n,
                "({c}, {r}) is not in the lower triangle of order {n}"
            );
            if (c, r) == last {
                *sums.last_mut().expect("an entry") += v;
            } else {
                row_idx.push(r);
                sums.push(v);
                col_ptr[c + 1] += 1;
                last = (c, r);
            }
        }
        for c in 0..n {
            col_ptr[c + 1] += col_ptr[c];
        }
        let ordering = nested_dissection(n, &col_ptr, &row_idx);
        let symbolic = cholesky::factorize_symbolic_cholesky(
            SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx),
            Side::Lower,
            ordering.as_faer(n),
            Default::default(),
        )
        .map_err(|e| format!("symbolic Cholesky factorisation failed ({e:?})"))?;
        let pattern = LowerPattern {
            n,
            col_ptr,
            row_idx,
            symbolic,
        };
        Ok((pattern, sums))
    }

    /// Order of the matrix.
    pub fn order(&self) -> usize {
        self.n
    }

    /// Stored entries (the length of a value vector over this pattern).
    pub fn len(&self) -> usize {
        self.row_idx.len()
    }

    /// Whether the pattern stores no entry (order 0).
    pub fn is_empty(&self) -> bool {
        self.row_idx.is_empty()
    }

    /// Where entry `(column c, row r)` (c ≤ r) is among the values.
    ///
    /// Panics when the pattern does not hold it.
    pub fn slot(&self, (c, r): (usize, usize)) -> usize {
        let range = self.col_ptr[c]..self.col_ptr[c + 1];
        range.start
            + self.row_idx[range]
                .binary_search(&r)
                .expect("an entry of the pattern")
    }

    /// The pattern as faer takes it.
    pub fn as_faer(&self) -> SymbolicSparseColMatRef<'_, usize> {
        SymbolicSparseColMatRef::new_checked(self.n, self.n, &self.col_ptr, None, &self.row_idx)
    }

    /// Column pointers and row indices (rows ascending in each column, the diagonal first).
    pub fn columns(&self) -> (&[usize], &[usize]) {
        (&self.col_ptr, &self.row_idx)
    }

    /// The symbolic Cholesky factorisation over the fill-reducing ordering.
    pub fn symbolic(&self) -> &SymbolicCholesky<usize> {
        &self.symbolic
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn repeats_merge_and_every_diagonal_is_stored() {
        let (p, sums) =
            LowerPattern::with_sums(3, [(0, 2, 1.0), (1, 1, 2.0), (0, 2, -3.0)]).unwrap();
        assert_eq!(
            p.columns(),
            (&[0usize, 2, 3, 4][..], &[0usize, 2, 1, 2][..])
        );
        assert_eq!(sums, vec![0.0, -2.0, 2.0, 0.0]);
        assert_eq!(p.slot((0, 2)), 1);
        assert_eq!(p.slot((2, 2)), 3);
        assert_eq!((p.order(), p.len()), (3, 4));
        assert!(p.symbolic().len_val() >= p.len());
    }
}
