//! The dense form of [`MinNorm`]: the pseudoinverse `A⁺` of the bond matrix (dN × K, stored
//! densely) from faer's thin SVD of A, with singular values below faer's cutoff dropped, so it
//! is the minimum-norm least-squares solution even for dependent rows. Its cost grows as
//! K·(N·d)², so it serves few bonds and the fallback of small systems whose sparse factor
//! failed. When the SVD does not converge (faer's iteration on rank-deficient matrices), the
//! self-adjoint eigendecomposition of the K × K Gram matrix `A Aᵀ` takes over; it fails, with
//! an error, only when that does not converge either.
//!
//! Every faer call here is sequential (`Par::Seq`): faer's convenience methods (`thin_svd`,
//! `self_adjoint_eigen`, `*`) take its global parallelism, rayon's thread count, which changes
//! their blocking and so the last bits of the result; the same start must give the same bytes
//! whatever `RAYON_NUM_THREADS` is. These matrices are small, so nothing is lost.

use faer::diag::Diag;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::evd::{self, ComputeEigenvectors};
use faer::linalg::matmul::matmul;
use faer::linalg::svd::{self, ComputeSvdVectors};
use faer::{Accum, Mat, MatRef, Par};

use super::MinNorm;
use crate::contacts::Link;

/// `A⁺ = Aᵀ (A Aᵀ)⁺` from the self-adjoint eigendecomposition of the small Gram matrix: the
/// fallback when the SVD of A does not converge. Squaring the singular values drops those below
/// about √ε·σ_max as zero, which is enough for the small dense systems that use it.
pub(super) fn gram_pseudoinverse(a: MatRef<'_, f64>) -> Result<Mat<f64>, String> {
    let k = a.nrows();
    let mut gram = Mat::<f64>::zeros(k, k);
    matmul(
        gram.as_mut(),
        Accum::Replace,
        a,
        a.transpose(),
        1.0,
        Par::Seq,
    );
    let mut u = Mat::<f64>::zeros(k, k);
    let mut s = Diag::<f64>::zeros(k);
    let scratch = evd::self_adjoint_evd_scratch::<f64>(
        k,
        ComputeEigenvectors::Yes,
        Par::Seq,
        Default::default(),
    );
    evd::self_adjoint_evd(
        gram.as_ref(),
        s.as_mut(),
        Some(u.as_mut()),
        Par::Seq,
        MemStack::new(&mut MemBuffer::new(scratch)),
        Default::default(),
    )
    .map_err(|e| format!("{e:?}"))?;
    let mut gram_pinv = Mat::<f64>::zeros(k, k);
    let scratch = evd::pseudoinverse_from_self_adjoint_evd_scratch::<f64>(k, Par::Seq);
    evd::pseudoinverse_from_self_adjoint_evd(
        gram_pinv.as_mut(),
        s.as_ref(),
        u.as_ref(),
        Par::Seq,
        MemStack::new(&mut MemBuffer::new(scratch)),
    );
    let mut pinv = Mat::<f64>::zeros(a.ncols(), k);
    matmul(
        pinv.as_mut(),
        Accum::Replace,
        a.transpose(),
        gram_pinv.as_ref(),
        1.0,
        Par::Seq,
    );
    Ok(pinv)
}

/// `A⁺` from the thin SVD of A (faer's default cutoff of small singular values); an error when
/// the SVD does not converge.
fn svd_pseudoinverse(a: MatRef<'_, f64>) -> Result<Mat<f64>, svd::SvdError> {
    let (m, n) = a.shape();
    let size = m.min(n);
    let mut u = Mat::<f64>::zeros(m, size);
    let mut v = Mat::<f64>::zeros(n, size);
    let mut s = Diag::<f64>::zeros(size);
    let thin = ComputeSvdVectors::Thin;
    let scratch = svd::svd_scratch::<f64>(m, n, thin, thin, Par::Seq, Default::default());
    svd::svd(
        a,
        s.as_mut(),
        Some(u.as_mut()),
        Some(v.as_mut()),
        Par::Seq,
        MemStack::new(&mut MemBuffer::new(scratch)),
        Default::default(),
    )?;
    let mut pinv = Mat::<f64>::zeros(n, m);
    let scratch = svd::pseudoinverse_from_svd_scratch::<f64>(m, n, Par::Seq);
    svd::pseudoinverse_from_svd(
        pinv.as_mut(),
        s.as_ref(),
        u.as_ref(),
        v.as_ref(),
        Par::Seq,
        MemStack::new(&mut MemBuffer::new(scratch)),
    );
    Ok(pinv)
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
        let pinv = match svd_pseudoinverse(a.as_ref()) {
            Ok(pinv) => pinv,
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
