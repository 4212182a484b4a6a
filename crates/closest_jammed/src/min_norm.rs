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

use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};

use crate::contacts::Link;

/// Largest number of coordinates N·d for which a failed sparse factorisation falls back to the
/// dense SVD (its cost grows as K·(N·d)²).
pub(crate) const DENSE_FALLBACK_COORDINATES: usize = 3000;

/// A factorisation of a bond matrix for minimum-norm solves.
pub(crate) enum MinNorm {
    /// No bonds: every minimum-norm solution is zero.
    Empty,
    /// `pinv` is the dN × K pseudoinverse of A.
    Dense { pinv: Mat<f64> },
    /// Cholesky factor of the K × K matrix `A Aᵀ`.
    Sparse {
        llt: faer::sparse::linalg::solvers::Llt<usize, f64>,
    },
}

impl MinNorm {
    /// Factorises the bond matrix of `links` (`n` particles in `d` dimensions): dense SVD when
    /// there are at most `dense_max_bonds` bonds, sparse Cholesky of `A Aᵀ` otherwise.
    pub fn new(links: &[Link], n: usize, d: usize, dense_max_bonds: usize) -> Result<Self, String> {
        let k = links.len();
        if k == 0 {
            return Ok(MinNorm::Empty);
        }
        if k <= dense_max_bonds {
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
            let svd = a
                .thin_svd()
                .map_err(|e| format!("the SVD of the bond matrix did not converge ({e:?})"))?;
            return Ok(MinNorm::Dense {
                pinv: svd.pseudoinverse(),
            });
        }
        // (A Aᵀ)_kl = Σ_p a_kp · a_lp over the particles p both bonds act on.
        let mut by_particle: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
        let mut coef = |p: usize, r: usize, sign: f64| by_particle[p].push((r, sign));
        for (r, l) in links.iter().enumerate() {
            match l.j {
                Some(j) if j == l.i => {}
                Some(j) => {
                    coef(l.i, r, -1.0);
                    coef(j, r, 1.0);
                }
                None => coef(l.i, r, -1.0),
            }
        }
        let mut triplets = Vec::new();
        for list in &by_particle {
            for &(r, sr) in list {
                for &(c, sc) in list {
                    if c <= r {
                        let nr = &links[r].normal[..d];
                        let nc = &links[c].normal[..d];
                        let dot: f64 = (0..d).map(|m| nr[m] * nc[m]).sum();
                        triplets.push(Triplet::new(r, c, sr * sc * dot));
                    }
                }
            }
        }
        let m = SparseColMat::<usize, f64>::try_new_from_triplets(k, k, &triplets)
            .map_err(|e| format!("could not assemble A Aᵀ ({e:?})"))?;
        let llt = m.sp_cholesky(Side::Lower).map_err(|e| {
            format!("the bond Gram matrix A Aᵀ is not positive definite ({e:?}); the bonds are linearly dependent")
        })?;
        Ok(MinNorm::Sparse { llt })
    }

    /// Like [`MinNorm::new`], but when the sparse Cholesky factor fails (dependent rows) and the
    /// system has at most [`DENSE_FALLBACK_COORDINATES`] coordinates, uses the dense SVD, whose
    /// pseudoinverse handles dependent rows.
    pub fn with_fallback(
        links: &[Link],
        n: usize,
        d: usize,
        dense_max_bonds: usize,
    ) -> Result<Self, String> {
        MinNorm::new(links, n, d, dense_max_bonds).or_else(|e| {
            if n * d <= DENSE_FALLBACK_COORDINATES {
                MinNorm::new(links, n, d, usize::MAX)
            } else {
                Err(e)
            }
        })
    }

    /// The minimum-norm `y` (N·d) with `A y = rhs` in the least-squares sense.
    pub fn solve(&self, links: &[Link], rhs: &[f64], n: usize, d: usize) -> Vec<f64> {
        let mut y = vec![0.0; n * d];
        match self {
            MinNorm::Empty => {}
            MinNorm::Dense { pinv } => {
                for (c, yc) in y.iter_mut().enumerate() {
                    *yc = (0..rhs.len()).map(|r| pinv[(c, r)] * rhs[r]).sum();
                }
            }
            MinNorm::Sparse { llt } => {
                let z = self.gram_solve(llt, rhs);
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
            MinNorm::Sparse { llt } => self.gram_solve(llt, &b),
        }
    }

    /// Coefficients `f` minimising ‖a − Aᵀ f‖ for a coordinate vector `a`: `(A⁺)ᵀ a`.
    pub fn row_combination(&self, links: &[Link], a: &[f64], d: usize) -> Vec<f64> {
        match self {
            MinNorm::Empty => Vec::new(),
            MinNorm::Dense { pinv } => (0..pinv.ncols())
                .map(|r| (0..a.len()).map(|c| pinv[(c, r)] * a[c]).sum())
                .collect(),
            MinNorm::Sparse { llt } => {
                let aa: Vec<f64> = links.iter().map(|l| l.rate(a, d)).collect();
                self.gram_solve(llt, &aa)
            }
        }
    }

    fn gram_solve(
        &self,
        llt: &faer::sparse::linalg::solvers::Llt<usize, f64>,
        rhs: &[f64],
    ) -> Vec<f64> {
        let b = Mat::<f64>::from_fn(rhs.len(), 1, |r, _| rhs[r]);
        let z = llt.solve(&b);
        (0..rhs.len()).map(|r| z[(r, 0)]).collect()
    }
}
