//! The exactly balancing contact forces nearest to equal ones: f = 1 − Gᵀλ with
//! (G Gᵀ) λ = G 1, so that G f = 0 and ‖f − 1‖ is least among balancing forces.
//!
//! G Gᵀ is the stiffness matrix of the contact network over the non-rattlers' coordinates
//! (the Hessian of unit springs on the contacts): sparse, and positive definite when the
//! network is rigid. When no contact touches a wall the net forces of any f sum to zero, so
//! G Gᵀ is singular along the d translations; the first non-rattler is then pinned (its rows
//! left out), and its balance follows from everyone else's.
//!
//! In an isostatic network the balancing forces are unique up to scale, so this is the
//! quadratic program's solution whenever the packing carries positive forces. In a
//! hyperstatic one the projection may come out with some negative forces (a soft packing's
//! network, or near-contacts inside the contact tolerance), and the caller goes on to the
//! descent. Dropping those contacts and projecting again was tried: it leaves particles with
//! too few contacts, and the factorisation fails. One factorisation costs what one
//! interior-point iteration of the program costs, and the program needs about twenty.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::SparseColMatRef;
use faer::sparse::linalg::cholesky::LltRef;
use faer::{Conj, MatMut, Par, Side};

use super::ContactColumns;
use crate::MAX_DIM;
use crate::sparse_pattern::LowerPattern;

/// A force below this (the mean is 1) is negative, not rounding.
const NEGATIVE: f64 = -1e-9;

/// Rows of G Gᵀ above which no projection is tried: ordering and analysing its pattern alone
/// take 3.5 s at 2.9·10⁵ rows (3D, N = 10⁵), where the factor would not be affordable anyway.
const ROWS: usize = 100_000;

/// Entries of the Cholesky factor above which no projection is tried: 4·10⁷ (320 MB) take
/// about 2 s to factorise; 3D packings reach them near N = 2·10⁴ (N = 10⁵: 4.9·10⁸ entries,
/// 60 s), and the descent takes over.
const FACTOR_ENTRIES: usize = 40_000_000;

/// Rounds of iterative refinement of λ: the stiffness matrix of a nearly isostatic network is
/// ill-conditioned (its softest modes go to zero with the excess contacts).
const REFINEMENTS: usize = 2;

/// The balancing forces nearest to equal ones, one per column of `g`, if none is negative;
/// None if some are, or the network is floppy (G Gᵀ has no Cholesky factor) or too large to
/// factorise.
pub(super) fn projected_forces(g: &ContactColumns) -> Option<Vec<f64>> {
    let f = Stiffness::new(g)?.factor()?.project();
    f.iter().all(|&v| v >= NEGATIVE).then_some(f)
}

/// The rows of each column of G over the unpinned coordinates, and the pattern, ordering and
/// symbolic factorisation of G Gᵀ.
struct Stiffness<'g> {
    g: &'g ContactColumns,
    /// Rows of G left out (those of the pinned particle, if any).
    pinned: usize,
    /// Order of G Gᵀ.
    m: usize,
    /// Lower triangle of G Gᵀ with its ordering and symbolic factor.
    pattern: LowerPattern,
}

impl<'g> Stiffness<'g> {
    fn new(g: &'g ContactColumns) -> Option<Self> {
        let walls = (0..g.columns()).any(|k| g.column(k).1.is_none());
        let pinned = if walls { 0 } else { g.d };
        let m = g.rows.checked_sub(pinned).filter(|&m| m > 0 && m <= ROWS)?;
        let mut pairs = Vec::new();
        for k in 0..g.columns() {
            let (e, len) = entries(g, pinned, k);
            for a in 0..len {
                pairs.extend(e[a..len].iter().map(|b| low_high(e[a].0, b.0)));
            }
        }
        let pattern = LowerPattern::new(m, pairs).ok()?;
        if pattern.symbolic().len_val() > FACTOR_ENTRIES {
            return None;
        }
        Some(Stiffness {
            g,
            pinned,
            m,
            pattern,
        })
    }

    fn entries(&self, k: usize) -> ([(usize, f64); 2 * MAX_DIM], usize) {
        entries(self.g, self.pinned, k)
    }

    /// The numeric Cholesky factor of G Gᵀ; None if there is none (a floppy network).
    fn factor(&self) -> Option<Projector<'_>> {
        let mut values = vec![0.0; self.pattern.len()];
        for k in 0..self.g.columns() {
            let (e, len) = self.entries(k);
            for a in 0..len {
                for b in &e[a..len] {
                    values[self.pattern.slot(low_high(e[a].0, b.0))] += e[a].1 * b.1;
                }
            }
        }
        let symbolic = self.pattern.symbolic();
        let mut factor = vec![0.0; symbolic.len_val()];
        symbolic
            .factorize_numeric_llt(
                &mut factor,
                SparseColMatRef::new(self.pattern.as_faer(), &values),
                Side::Lower,
                LltRegularization::default(),
                Par::Seq,
                MemStack::new(&mut MemBuffer::new(
                    symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
                )),
                Default::default(),
            )
            .ok()?;
        Some(Projector {
            stiffness: self,
            factor,
            scratch: MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq)).into(),
        })
    }

    /// G x over the unpinned rows.
    fn g_times(&self, x: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.m];
        for (k, &xk) in x.iter().enumerate() {
            let (e, len) = self.entries(k);
            e[..len].iter().for_each(|&(r, v)| out[r] += v * xk);
        }
        out
    }

    /// Gᵀ y.
    fn gt_times(&self, y: &[f64]) -> Vec<f64> {
        (0..self.g.columns())
            .map(|k| {
                let (e, len) = self.entries(k);
                e[..len].iter().map(|&(r, v)| v * y[r]).sum()
            })
            .collect()
    }
}

/// The projection onto the balancing forces, f ↦ f − Gᵀ(G Gᵀ)⁻¹G f, by a Cholesky factor.
struct Projector<'s> {
    stiffness: &'s Stiffness<'s>,
    factor: Vec<f64>,
    scratch: std::cell::RefCell<MemBuffer>,
}

impl Projector<'_> {
    fn solve(&self, mut x: Vec<f64>) -> Vec<f64> {
        let s = self.stiffness;
        LltRef::new(s.pattern.symbolic(), &self.factor).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(&mut x, s.m, 1),
            Par::Seq,
            MemStack::new(&mut self.scratch.borrow_mut()),
        );
        x
    }

    /// The balancing forces nearest to equal ones, 1 − Gᵀλ, with λ refined against the
    /// matrix itself.
    fn project(&self) -> Vec<f64> {
        let s = self.stiffness;
        let target = vec![1.0; s.g.columns()];
        let rhs = s.g_times(&target);
        let mut lambda = self.solve(rhs.clone());
        for _ in 0..REFINEMENTS {
            let gg = s.g_times(&s.gt_times(&lambda));
            let r: Vec<f64> = rhs.iter().zip(&gg).map(|(b, a)| b - a).collect();
            let dl = self.solve(r);
            lambda.iter_mut().zip(&dl).for_each(|(l, d)| *l += d);
        }
        target
            .iter()
            .zip(s.gt_times(&lambda))
            .map(|(t, g)| t - g)
            .collect()
    }
}

/// (column, row) of the lower triangle holding the pair of rows a, b.
fn low_high(a: usize, b: usize) -> (usize, usize) {
    (a.min(b), a.max(b))
}

/// Column k's entries of G over the rows from `pinned` on, (row − pinned, value), and how
/// many there are: −n on particle i's coordinates, +n on j's.
fn entries(g: &ContactColumns, pinned: usize, k: usize) -> ([(usize, f64); 2 * MAX_DIM], usize) {
    let (ri, rj, n) = g.column(k);
    let mut e = [(0, 0.0); 2 * MAX_DIM];
    let mut len = 0;
    for (first, sign) in [(Some(ri), -1.0), (rj, 1.0)] {
        let Some(first) = first.filter(|&r| r >= pinned) else {
            continue;
        };
        for a in 0..g.d {
            e[len] = (first - pinned + a, sign * n[a]);
            len += 1;
        }
    }
    (e, len)
}
