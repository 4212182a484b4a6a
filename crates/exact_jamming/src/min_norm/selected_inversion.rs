//! Diagonal entries `((A Aᵀ)⁻¹)_kk` from the sparse Cholesky factor of a [`GramPattern`], for
//! the release test of the integrator (a bond's multiplier sensitivity). Two algorithms:
//! pruned forward solves `‖L⁻¹ P e_s‖²` that visit only the supernodes on the
//! elimination-tree path from the slot to the root, batched and stopped at a cap; and
//! selected inversion (Takahashi's equations over supernodes, as in Lin Lin's SelInv), which
//! forms `(L Lᵀ)⁻¹` on the factor's pattern only and pays when many entries are wanted.
//! Neither fails on a valid factor; selected inversion needs a supernodal factor and answers
//! `None` for a simplicial one.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;
use faer::{Accum, Mat, MatMut, MatRef, Par};

use super::gram_pattern::GramPattern;

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

impl GramPattern {
    /// The diagonal entries `(M⁻¹)_ss` of the inverse of the matrix factorised in `values`, for
    /// the slots `slots`: `‖L⁻¹ P e_s‖²` with `M = Pᵀ L Lᵀ P`. A forward solve from a unit
    /// vector only reaches the supernodes on the elimination-tree path from slot s to the root,
    /// so only those are visited, and the solves of a batch go through each supernode together
    /// (one dense triangular solve and one product with many right-hand sides, not one each).
    /// The partial sums grow along the path: a solve stops after the first supernode that takes
    /// its sum above its cap, and returns that sum.
    pub(super) fn inverse_diagonals(
        &self,
        values: &[f64],
        slots: &[usize],
        caps: &[f64],
    ) -> Vec<f64> {
        let m = self.len();
        let SymbolicCholeskyRaw::Supernodal(sn) = self.symbolic().raw() else {
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
        self.symbolic().perm().map_or(slot, |p| p.arrays().1[slot])
    }

    /// Whether [`Self::selected_inverse_diagonal`] costs less than the pruned search of a
    /// release over `slots` by [`Self::inverse_diagonals`], taken as [`PRUNED_SOLVE_SHARE`] of
    /// the flops of their forward solves to the root.
    pub(super) fn selected_inversion_pays(&self, slots: &[usize]) -> bool {
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
    pub(super) fn selected_inverse_diagonal(
        &self,
        values: &[f64],
        slots: &[usize],
    ) -> Option<Vec<f64>> {
        let SymbolicCholeskyRaw::Supernodal(sn) = self.symbolic().raw() else {
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
}
