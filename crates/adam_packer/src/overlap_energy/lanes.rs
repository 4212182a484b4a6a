//! The force loop's pair terms four at a time in AVX2 lanes.
//!
//! A chunk of rows is walked in list order and its pairs are put four at a time into lanes
//! (a group may span rows); their separations, overlaps and forces are computed together, and
//! the caller then adds them up pair by pair in list order, as the scalar loop does. Every
//! arithmetic operation is the scalar one ([`super::pair_force`]) in the same order, without
//! fused multiply–adds, and the square root and division are correctly rounded in both, so
//! the forces and sums are bit for bit the scalar loop's (test
//! `the_avx2_force_loop_gives_the_baseline_bytes`). Computing a whole chunk before adding any
//! of it up lets the processor overlap the square roots and divisions of many groups.

use std::arch::x86_64::*;
use std::ops::Range;

use super::{Frame, PairTerms, pair_terms};
use crate::neighbor_list::Rows;

/// AVX2 on this processor: the token exists only where it does, which is what makes the
/// vector operations safe to call.
#[derive(Clone, Copy, Debug)]
pub(super) struct Avx2(());

impl Avx2 {
    /// The token, if this processor has AVX2.
    pub(super) fn detect() -> Option<Avx2> {
        std::arch::is_x86_feature_detected!("avx2").then_some(Avx2(()))
    }

    /// The terms of every listed pair of the rows `rows`, in list order, four pairs an entry
    /// (lanes past the last pair repeat the group's first pair): the first entries of `out`,
    /// which grows as needed (entries past those are left as they were). Compiled for AVX2, so
    /// a caller not compiled for it calls it in `unsafe`, on the token's word.
    #[target_feature(enable = "avx2")]
    pub(super) fn rows_terms<'o, const D: usize, const ALL_PERIODIC: bool, const ABSOLUTE: bool>(
        self,
        x: &[[f64; D]],
        dia: &[f64],
        list: &Rows,
        rows: Range<usize>,
        frame: &Frame<D, ABSOLUTE>,
        out: &'o mut Vec<FourPairs<D>>,
    ) -> &'o [FourPairs<D>] {
        let pairs_listed: usize = rows.clone().map(|i| list.get(i).len()).sum();
        let groups = pairs_listed.div_ceil(4);
        // Grown only: every slot used below is written before it is read.
        if out.len() < groups {
            out.resize_with(groups, FourPairs::default);
        }
        let mut slots = out[..groups].iter_mut();
        let mut pairs = [(0usize, 0usize); 4];
        let mut n = 0;
        for i in rows {
            for &j in list.get(i) {
                pairs[n] = (i, j as usize);
                n += 1;
                if n == 4 {
                    let slot = slots.next().expect("a slot for every four pairs");
                    // SAFETY: this function is compiled for AVX2.
                    unsafe { four_pairs::<D, ALL_PERIODIC, ABSOLUTE>(x, dia, &pairs, frame, slot) };
                    n = 0;
                }
            }
        }
        if n > 0 {
            let first = pairs[0];
            pairs[n..].fill(first);
            let slot = slots.next().expect("a slot for the last pairs");
            // SAFETY: as above.
            unsafe { four_pairs::<D, ALL_PERIODIC, ABSOLUTE>(x, dia, &pairs, frame, slot) };
        }
        &out[..groups]
    }
}

/// The terms of four pairs, lane l for the l-th pair: overlap ε, σ/r − 1, weight and the
/// force on the row particle, as [`super::pair_terms`] gives them.
pub(super) struct FourPairs<const D: usize> {
    eps: [f64; 4],
    stretch: [f64; 4],
    weight: [f64; 4],
    force: [[f64; 4]; D],
}

impl<const D: usize> Default for FourPairs<D> {
    fn default() -> Self {
        FourPairs {
            eps: [0.0; 4],
            stretch: [0.0; 4],
            weight: [0.0; 4],
            force: [[0.0; 4]; D],
        }
    }
}

impl<const D: usize> FourPairs<D> {
    /// Lane `l`'s terms.
    #[inline(always)]
    pub(super) fn lane(&self, l: usize) -> PairTerms<D> {
        (
            self.eps[l],
            self.stretch[l],
            self.weight[l],
            std::array::from_fn(|k| self.force[k][l]),
        )
    }

    /// Sets lane `l`'s terms.
    fn set_lane(&mut self, l: usize, (eps, stretch, weight, force): PairTerms<D>) {
        self.eps[l] = eps;
        self.stretch[l] = stretch;
        self.weight[l] = weight;
        for (lanes, fk) in self.force.iter_mut().zip(force) {
            lanes[l] = fk;
        }
    }
}

/// The terms of the pairs (i, j) of `pairs`, lane by lane: [`super::pair_terms`]'s operations
/// in its order. Inlined into [`Avx2::rows_terms`], whose target feature then lets the
/// intrinsics inline.
///
/// # Safety
/// The processor must have AVX2.
#[inline(always)]
unsafe fn four_pairs<const D: usize, const ALL_PERIODIC: bool, const ABSOLUTE: bool>(
    x: &[[f64; D]],
    dia: &[f64],
    pairs: &[(usize, usize); 4],
    frame: &Frame<D, ABSOLUTE>,
    out: &mut FourPairs<D>,
) {
    let geo = &frame.geo;
    let xi = pairs.map(|(i, _)| &x[i]);
    let xj = pairs.map(|(_, j)| &x[j]);
    // SAFETY (the stores): each target holds four doubles.
    let store = |to: &mut [f64; 4], v: __m256d| unsafe { _mm256_storeu_pd(to.as_mut_ptr(), v) };
    // SAFETY: inlined into AVX2 code only (the contract).
    let coincident = unsafe {
        let zero = _mm256_setzero_pd();
        let mut dx = [zero; D];
        let mut r2 = zero;
        for k in 0..D {
            let mut t = _mm256_sub_pd(
                _mm256_set_pd(xj[3][k], xj[2][k], xj[1][k], xj[0][k]),
                _mm256_set_pd(xi[3][k], xi[2][k], xi[1][k], xi[0][k]),
            );
            if ALL_PERIODIC || geo.periodic[k] {
                // Geometry::nearest_image: t − L above L/2, t + L below −L/2, else t.
                let half = _mm256_set1_pd(geo.half[k]);
                let length = _mm256_set1_pd(geo.length[k]);
                let above = _mm256_cmp_pd::<_CMP_GT_OQ>(t, half);
                let below = _mm256_cmp_pd::<_CMP_LT_OQ>(t, _mm256_sub_pd(zero, half));
                let down = _mm256_sub_pd(t, length);
                let up = _mm256_add_pd(t, length);
                t = _mm256_blendv_pd(_mm256_blendv_pd(t, up, below), down, above);
            }
            dx[k] = t;
            r2 = _mm256_add_pd(r2, _mm256_mul_pd(t, t));
        }
        let [(i0, j0), (i1, j1), (i2, j2), (i3, j3)] = *pairs;
        let sigma = _mm256_mul_pd(
            _mm256_set1_pd(0.5),
            _mm256_add_pd(
                _mm256_set_pd(dia[i3], dia[i2], dia[i1], dia[i0]),
                _mm256_set_pd(dia[j3], dia[j2], dia[j1], dia[j0]),
            ),
        );
        let one = _mm256_set1_pd(1.0);
        let w = if ABSOLUTE {
            // system::absolute_weight: (σ/D̄)².
            let q = _mm256_div_pd(sigma, _mm256_set1_pd(frame.mean_diameter));
            _mm256_mul_pd(q, q)
        } else {
            one
        };
        let q = _mm256_div_pd(one, _mm256_mul_pd(sigma, _mm256_sqrt_pd(r2)));
        let eps = _mm256_max_pd(_mm256_sub_pd(one, _mm256_mul_pd(r2, q)), zero);
        let stretch = _mm256_max_pd(
            _mm256_sub_pd(_mm256_mul_pd(_mm256_mul_pd(sigma, sigma), q), one),
            zero,
        );
        // −c by its sign bit, as the scalar negation (0 − c would give +0 for c = 0).
        let minus_c = _mm256_xor_pd(
            _mm256_mul_pd(_mm256_mul_pd(w, eps), q),
            _mm256_set1_pd(-0.0),
        );
        store(&mut out.eps, eps);
        store(&mut out.stretch, stretch);
        store(&mut out.weight, w);
        for (lanes, t) in out.force.iter_mut().zip(dx) {
            store(lanes, _mm256_mul_pd(minus_c, t));
        }
        _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_EQ_OQ>(r2, zero))
    };
    // Coincident centres (no lane's value above is used): the scalar path separates them.
    if coincident != 0 {
        for (l, &(i, j)) in pairs.iter().enumerate() {
            if coincident & (1 << l) != 0 {
                out.set_lane(
                    l,
                    pair_terms::<D, ALL_PERIODIC, ABSOLUTE>(x, dia, i, j, frame),
                );
            }
        }
    }
}
