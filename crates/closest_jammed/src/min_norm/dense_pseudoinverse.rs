//! The dense form of [`MinNorm`]: the pseudoinverse `A⁺` of the bond matrix (dN × K, stored
//! densely) from faer's thin SVD of A, with singular values below faer's cutoff dropped, so it
//! is the minimum-norm least-squares solution even for dependent rows. Its cost grows as
//! K·(N·d)², so it serves few bonds and the fallback of small systems whose sparse factor
//! failed. When the SVD does not converge (faer's iteration on rank-deficient matrices), the
//! self-adjoint eigendecomposition of the K × K Gram matrix `A Aᵀ` takes over; it fails, with
//! an error, only when that does not converge either.

use faer::{Mat, MatRef, Side};

use super::MinNorm;
use crate::contacts::Link;

/// `A⁺ = Aᵀ (A Aᵀ)⁺` from the self-adjoint eigendecomposition of the small Gram matrix: the
/// fallback when the SVD of A does not converge. Squaring the singular values drops those below
/// about √ε·σ_max as zero, which is enough for the small dense systems that use it.
pub(super) fn gram_pseudoinverse(a: MatRef<'_, f64>) -> Result<Mat<f64>, String> {
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
}
