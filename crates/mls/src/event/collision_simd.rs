//! The hot loop of event-driven MD, collision prediction, for 3D spheres in SIMD lanes: the list
//! partners of one sphere are predicted eight at a time with AVX-512F, or four with AVX2.
//!
//! Every arithmetic operation is the one of the scalar path (`System::pair_time_at` and
//! [`super::collision::collision_time`]), in the same order and without fused multiply–adds, and
//! the square root and division are correctly rounded in both, so the result is bit for bit the
//! scalar one and trajectories do not depend on which path ran (tested below and in
//! `crate::tests`). Only the loads differ: the partners' records are transposed into lanes.
//! The arithmetic is written once ([`lane_times`]) over the [`Lanes`] of each instruction set.
//! Measured in docs/notes/mls-event-engine.md and docs/BENCHMARKS.md#kernels.

use std::arch::x86_64::*;

/// One particle as `System` stores it for d = 3 (`#[repr(C, align(64))]`): position at its own
/// time, velocity, that time, and diameter over the mean diameter, 8 doubles.
pub(crate) const RECORD: usize = 8;
const X: usize = 0;
const V: usize = 3;
const T: usize = 6;
const RATIO: usize = 7;

/// The predicting sphere, moved to `now`, and what the prediction needs of the box.
pub(crate) struct Frame {
    pub x: [f64; 3],
    pub v: [f64; 3],
    pub ratio: f64,
    pub now: f64,
    /// Mean diameter at `now`, and its growth speed.
    pub scale: f64,
    pub growth: f64,
    pub len: [f64; 3],
    pub half: [f64; 3],
    pub periodic: [bool; 3],
}

/// The SIMD instruction set a prediction runs on. A value exists only where the processor
/// has that set ([`Kernel::widest`]), which is what makes the vector operations safe to call.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Kernel(Set);

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Set {
    Avx2,
    Avx512,
}

impl Kernel {
    /// The widest set this processor has: AVX-512F (eight lanes), else AVX2 (four), else none.
    pub(crate) fn widest() -> Option<Kernel> {
        if std::arch::is_x86_feature_detected!("avx512f") {
            Some(Kernel(Set::Avx512))
        } else {
            Self::avx2()
        }
    }

    /// AVX2, if this processor has it (tests compare it with the wider set).
    pub(crate) fn avx2() -> Option<Kernel> {
        std::arch::is_x86_feature_detected!("avx2").then_some(Kernel(Set::Avx2))
    }

    /// The earliest collision time of the sphere `f` with the partners `list` (indices of
    /// records in `records`, [`RECORD`] doubles each) and the partner, the first in list order
    /// among equal times; `(∞, 0)` when none collides.
    ///
    /// # Safety
    /// Every index in `list` must be below `records.len() / RECORD`.
    pub(crate) unsafe fn earliest_collision(
        self,
        records: &[f64],
        list: &[u32],
        f: &Frame,
    ) -> (f64, u32) {
        debug_assert!(
            list.iter()
                .all(|&j| (j as usize + 1) * RECORD <= records.len())
        );
        // SAFETY: `self` exists only where the processor has its set (`widest`, `avx2`); the
        // indices are the caller's contract.
        unsafe {
            match self.0 {
                Set::Avx2 => earliest_avx2(Avx2(()), records, list, f),
                Set::Avx512 => earliest_avx512(Avx512(()), records, list, f),
            }
        }
    }
}

/// [`earliest`] compiled for AVX2.
///
/// # Safety
/// As [`earliest`].
#[target_feature(enable = "avx2")]
unsafe fn earliest_avx2(s: Avx2, records: &[f64], list: &[u32], f: &Frame) -> (f64, u32) {
    // SAFETY: the caller's contract.
    unsafe { earliest(s, records, list, f) }
}

/// [`earliest`] compiled for AVX-512F.
///
/// # Safety
/// As [`earliest`].
#[target_feature(enable = "avx512f")]
unsafe fn earliest_avx512(s: Avx512, records: &[f64], list: &[u32], f: &Frame) -> (f64, u32) {
    // SAFETY: the caller's contract.
    unsafe { earliest(s, records, list, f) }
}

/// The prediction over `list` in chunks of `L::WIDTH` partners. Inlined into the entry point of
/// each set, whose target feature then lets the intrinsics inline.
///
/// # Safety
/// Every index in `list` must be below `records.len() / RECORD`.
#[inline(always)]
unsafe fn earliest<L: Lanes>(s: L, records: &[f64], list: &[u32], f: &Frame) -> (f64, u32) {
    let (mut best, mut who) = (f64::INFINITY, 0u32);
    for chunk in list.chunks(L::WIDTH) {
        // SAFETY: every index of `chunk` starts a record inside `records` (the contract).
        let fields = unsafe { s.fields(records.as_ptr(), chunk) };
        // Lanes past the chunk repeat its first partner, so the first lane at the minimum is
        // one of the chunk; a later chunk wins only with a smaller time.
        let (time, lane) = s.first_minimum(lane_times(s, &fields, f));
        if time < best {
            best = time;
            who = chunk[lane];
        }
    }
    (best, who)
}

/// The vector operations the prediction needs, for one instruction set. Implemented by
/// zero-sized tokens made only where the processor has the set ([`Kernel`]), so the methods
/// are safe; each is inlined into an entry point compiled for its set.
trait Lanes: Copy {
    const WIDTH: usize;
    type V: Copy;
    type M: Copy;
    /// Field k of the records of `chunk` (at most `WIDTH` indices) in vector k, record l in
    /// lane l; lanes past the chunk repeat its first record.
    ///
    /// # Safety
    /// Every index of `chunk` must start a record of [`RECORD`] doubles at `records`.
    unsafe fn fields(self, records: *const f64, chunk: &[u32]) -> [Self::V; RECORD];
    /// The smallest lane of `v` (no NaN) and the first lane that holds it.
    fn first_minimum(self, v: Self::V) -> (f64, usize);
    fn splat(self, x: f64) -> Self::V;
    fn add(self, a: Self::V, b: Self::V) -> Self::V;
    fn sub(self, a: Self::V, b: Self::V) -> Self::V;
    fn mul(self, a: Self::V, b: Self::V) -> Self::V;
    fn div(self, a: Self::V, b: Self::V) -> Self::V;
    fn sqrt(self, a: Self::V) -> Self::V;
    /// `max(a, b)`, `b` where either is NaN (as `f64::max(a, 0.0)` for `b = 0`).
    fn max(self, a: Self::V, b: Self::V) -> Self::V;
    fn lt(self, a: Self::V, b: Self::V) -> Self::M;
    fn le(self, a: Self::V, b: Self::V) -> Self::M;
    fn gt(self, a: Self::V, b: Self::V) -> Self::M;
    fn ge(self, a: Self::V, b: Self::V) -> Self::M;
    fn and(self, a: Self::M, b: Self::M) -> Self::M;
    fn or(self, a: Self::M, b: Self::M) -> Self::M;
    /// `!a & b`.
    fn and_not(self, a: Self::M, b: Self::M) -> Self::M;
    /// `yes` in the lanes of `m`, `no` elsewhere.
    fn select(self, m: Self::M, yes: Self::V, no: Self::V) -> Self::V;
}

/// Collision times of `f` with the records whose fields are `fields`, lane by lane: the scalar
/// path's operations in its order.
#[inline(always)]
fn lane_times<L: Lanes>(s: L, fields: &[L::V; RECORD], f: &Frame) -> L::V {
    let zero = s.splat(0.0);
    // position_at(j, now) = x + v·(now − t), then the separation from `f`.
    let dt = s.sub(s.splat(f.now), fields[T]);
    let mut r = [zero; 3];
    let mut v = [zero; 3];
    for k in 0..3 {
        let vk = fields[V + k];
        let xk = s.add(fields[X + k], s.mul(vk, dt));
        let mut d = s.sub(xk, s.splat(f.x[k]));
        if f.periodic[k] {
            // Minimum image: `if d > L/2 { d −= L } else if d < −L/2 { d += L }`.
            let h = s.splat(f.half[k]);
            let l = s.splat(f.len[k]);
            let above = s.gt(d, h);
            let below = s.lt(d, s.sub(zero, h));
            let shifted = s.select(above, s.sub(d, l), d);
            d = s.select(s.and_not(above, below), s.add(d, l), shifted);
        }
        r[k] = d;
        v[k] = s.sub(vk, s.splat(f.v[k]));
    }
    // `a·b` summed over the three axes in the scalar order (`0 + a₀b₀ + a₁b₁ + a₂b₂`).
    let dot =
        |a: &[L::V; 3], b: &[L::V; 3]| (0..3).fold(zero, |sum, k| s.add(sum, s.mul(a[k], b[k])));
    let half_sum = s.mul(s.splat(0.5), s.add(s.splat(f.ratio), fields[RATIO]));
    let sigma = s.mul(half_sum, s.splat(f.scale));
    let g = s.mul(half_sum, s.splat(f.growth));
    let b = s.sub(dot(&r, &v), s.mul(sigma, g));
    let a = s.sub(dot(&v, &v), s.mul(g, g));
    let c = s.sub(dot(&r, &r), s.mul(sigma, sigma));
    // collision_time(a, b, c), lane by lane.
    let disc = s.sub(s.mul(b, b), s.mul(a, c));
    let root = s.div(c, s.sub(s.sqrt(s.max(disc, zero)), b));
    let approaching = s.lt(b, zero);
    let ahead = s.and(
        s.and(s.gt(c, zero), s.or(approaching, s.lt(a, zero))),
        s.and(s.ge(disc, zero), s.gt(root, zero)),
    );
    let touching = s.and(s.le(c, zero), approaching);
    s.select(
        touching,
        zero,
        s.select(ahead, root, s.splat(f64::INFINITY)),
    )
}

/// AVX2: four lanes.
#[derive(Clone, Copy)]
struct Avx2(());

// SAFETY (every method): an `Avx2` exists only where the processor has AVX2 (`Kernel`).
impl Lanes for Avx2 {
    const WIDTH: usize = 4;
    type V = __m256d;
    type M = __m256d;

    /// Each record is loaded as two halves and the halves of four records transposed (cheaper
    /// than eight gathers).
    #[inline(always)]
    unsafe fn fields(self, records: *const f64, chunk: &[u32]) -> [__m256d; RECORD] {
        let lane = |k: usize| chunk.get(k).copied().unwrap_or(chunk[0]) as usize * RECORD;
        // SAFETY: each lane starts a record of RECORD = 8 doubles, two halves of four.
        let half = |l: usize, h: usize| unsafe { _mm256_loadu_pd(records.add(lane(l) + 4 * h)) };
        let mut fields = [unsafe { _mm256_setzero_pd() }; RECORD];
        for h in 0..2 {
            let (a, b, c, d) = (half(0, h), half(1, h), half(2, h), half(3, h));
            // [a0 b0 a2 b2], [a1 b1 a3 b3], and the same of c and d; then the 128-bit halves.
            unsafe {
                let (ab_even, ab_odd) = (_mm256_unpacklo_pd(a, b), _mm256_unpackhi_pd(a, b));
                let (cd_even, cd_odd) = (_mm256_unpacklo_pd(c, d), _mm256_unpackhi_pd(c, d));
                fields[4 * h] = _mm256_permute2f128_pd::<0x20>(ab_even, cd_even);
                fields[4 * h + 1] = _mm256_permute2f128_pd::<0x20>(ab_odd, cd_odd);
                fields[4 * h + 2] = _mm256_permute2f128_pd::<0x31>(ab_even, cd_even);
                fields[4 * h + 3] = _mm256_permute2f128_pd::<0x31>(ab_odd, cd_odd);
            }
        }
        fields
    }
    #[inline(always)]
    fn first_minimum(self, v: __m256d) -> (f64, usize) {
        unsafe {
            // The minimum in every lane: first across the 128-bit halves, then within them.
            let halves = _mm256_min_pd(v, _mm256_permute2f128_pd::<0x01>(v, v));
            let min = _mm256_min_pd(halves, _mm256_permute_pd::<0b0101>(halves));
            let at = _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_EQ_OQ>(v, min));
            (_mm256_cvtsd_f64(min), at.trailing_zeros() as usize)
        }
    }
    #[inline(always)]
    fn splat(self, x: f64) -> __m256d {
        unsafe { _mm256_set1_pd(x) }
    }
    #[inline(always)]
    fn add(self, a: __m256d, b: __m256d) -> __m256d {
        unsafe { _mm256_add_pd(a, b) }
    }
    #[inline(always)]
    fn sub(self, a: __m256d, b: __m256d) -> __m256d {
        unsafe { _mm256_sub_pd(a, b) }
    }
    #[inline(always)]
    fn mul(self, a: __m256d, b: __m256d) -> __m256d {
        unsafe { _mm256_mul_pd(a, b) }
    }
    #[inline(always)]
    fn div(self, a: __m256d, b: __m256d) -> __m256d {
        unsafe { _mm256_div_pd(a, b) }
    }
    #[inline(always)]
    fn sqrt(self, a: __m256d) -> __m256d {
        unsafe { _mm256_sqrt_pd(a) }
    }
    #[inline(always)]
    fn max(self, a: __m256d, b: __m256d) -> __m256d {
        unsafe { _mm256_max_pd(a, b) }
    }
    #[inline(always)]
    fn lt(self, a: __m256d, b: __m256d) -> __m256d {
        unsafe { _mm256_cmp_pd::<_CMP_LT_OQ>(a, b) }
    }
    #[inline(always)]
    fn le(self, a: __m256d, b: __m256d) -> __m256d {
        unsafe { _mm256_cmp_pd::<_CMP_LE_OQ>(a, b) }
    }
    #[inline(always)]
    fn gt(self, a: __m256d, b: __m256d) -> __m256d {
        unsafe { _mm256_cmp_pd::<_CMP_GT_OQ>(a, b) }
    }
    #[inline(always)]
    fn ge(self, a: __m256d, b: __m256d) -> __m256d {
        unsafe { _mm256_cmp_pd::<_CMP_GE_OQ>(a, b) }
    }
    #[inline(always)]
    fn and(self, a: __m256d, b: __m256d) -> __m256d {
        unsafe { _mm256_and_pd(a, b) }
    }
    #[inline(always)]
    fn or(self, a: __m256d, b: __m256d) -> __m256d {
        unsafe { _mm256_or_pd(a, b) }
    }
    #[inline(always)]
    fn and_not(self, a: __m256d, b: __m256d) -> __m256d {
        unsafe { _mm256_andnot_pd(a, b) }
    }
    #[inline(always)]
    fn select(self, m: __m256d, yes: __m256d, no: __m256d) -> __m256d {
        unsafe { _mm256_blendv_pd(no, yes, m) }
    }
}

/// AVX-512F: eight lanes, comparisons into bit masks.
#[derive(Clone, Copy)]
struct Avx512(());

// SAFETY (every method): an `Avx512` exists only where the processor has AVX-512F (`Kernel`).
impl Lanes for Avx512 {
    const WIDTH: usize = 8;
    type V = __m512d;
    type M = __mmask8;

    /// Each record is one vector; the eight are transposed in three rounds (pairs of doubles,
    /// then of 128-bit blocks, then of 256-bit halves).
    #[inline(always)]
    unsafe fn fields(self, records: *const f64, chunk: &[u32]) -> [__m512d; RECORD] {
        let lane = |k: usize| chunk.get(k).copied().unwrap_or(chunk[0]) as usize * RECORD;
        // SAFETY: each lane starts a record of RECORD = 8 doubles.
        let r: [__m512d; 8] =
            std::array::from_fn(|l| unsafe { _mm512_loadu_pd(records.add(lane(l))) });
        unsafe {
            // t[2p] = [r₂ₚ₀ r₂ₚ₊₁,₀ r₂ₚ₂ r₂ₚ₊₁,₂ …] (even fields of records 2p, 2p+1), t[2p+1] odd.
            let t: [__m512d; 8] = std::array::from_fn(|k| match k % 2 {
                0 => _mm512_unpacklo_pd(r[k], r[k + 1]),
                _ => _mm512_unpackhi_pd(r[k - 1], r[k]),
            });
            // Blocks 0 and 2 (or 1 and 3) of two such vectors: fields {0,4} (or {2,6}) of four
            // records, and the same with the odd fields.
            let lo = _mm512_setr_epi64(0, 1, 8, 9, 4, 5, 12, 13);
            let hi = _mm512_setr_epi64(2, 3, 10, 11, 6, 7, 14, 15);
            let u: [__m512d; 8] = std::array::from_fn(|k| {
                let (q, parity, blocks) = (k / 4, k % 2, (k / 2) % 2);
                let (a, b) = (t[4 * q + parity], t[4 * q + 2 + parity]);
                _mm512_permutex2var_pd(a, if blocks == 0 { lo } else { hi }, b)
            });
            // u[4q + 2·blocks + parity] holds fields (2·blocks + parity) and that plus 4 of
            // records 4q..4q+3, in its low and high 256 bits.
            std::array::from_fn(|field| {
                let k = field % 4;
                let (a, b) = (u[k], u[4 + k]);
                match field / 4 {
                    0 => _mm512_shuffle_f64x2::<0x44>(a, b),
                    _ => _mm512_shuffle_f64x2::<0xEE>(a, b),
                }
            })
        }
    }
    #[inline(always)]
    fn first_minimum(self, v: __m512d) -> (f64, usize) {
        unsafe {
            let min = _mm512_reduce_min_pd(v);
            let at = _mm512_cmp_pd_mask::<_CMP_EQ_OQ>(v, _mm512_set1_pd(min));
            (min, at.trailing_zeros() as usize)
        }
    }
    #[inline(always)]
    fn splat(self, x: f64) -> __m512d {
        unsafe { _mm512_set1_pd(x) }
    }
    #[inline(always)]
    fn add(self, a: __m512d, b: __m512d) -> __m512d {
        unsafe { _mm512_add_pd(a, b) }
    }
    #[inline(always)]
    fn sub(self, a: __m512d, b: __m512d) -> __m512d {
        unsafe { _mm512_sub_pd(a, b) }
    }
    #[inline(always)]
    fn mul(self, a: __m512d, b: __m512d) -> __m512d {
        unsafe { _mm512_mul_pd(a, b) }
    }
    #[inline(always)]
    fn div(self, a: __m512d, b: __m512d) -> __m512d {
        unsafe { _mm512_div_pd(a, b) }
    }
    #[inline(always)]
    fn sqrt(self, a: __m512d) -> __m512d {
        unsafe { _mm512_sqrt_pd(a) }
    }
    #[inline(always)]
    fn max(self, a: __m512d, b: __m512d) -> __m512d {
        unsafe { _mm512_max_pd(a, b) }
    }
    #[inline(always)]
    fn lt(self, a: __m512d, b: __m512d) -> __mmask8 {
        unsafe { _mm512_cmp_pd_mask::<_CMP_LT_OQ>(a, b) }
    }
    #[inline(always)]
    fn le(self, a: __m512d, b: __m512d) -> __mmask8 {
        unsafe { _mm512_cmp_pd_mask::<_CMP_LE_OQ>(a, b) }
    }
    #[inline(always)]
    fn gt(self, a: __m512d, b: __m512d) -> __mmask8 {
        unsafe { _mm512_cmp_pd_mask::<_CMP_GT_OQ>(a, b) }
    }
    #[inline(always)]
    fn ge(self, a: __m512d, b: __m512d) -> __mmask8 {
        unsafe { _mm512_cmp_pd_mask::<_CMP_GE_OQ>(a, b) }
    }
    #[inline(always)]
    fn and(self, a: __mmask8, b: __mmask8) -> __mmask8 {
        a & b
    }
    #[inline(always)]
    fn or(self, a: __mmask8, b: __mmask8) -> __mmask8 {
        a | b
    }
    #[inline(always)]
    fn and_not(self, a: __mmask8, b: __mmask8) -> __mmask8 {
        !a & b
    }
    #[inline(always)]
    fn select(self, m: __mmask8, yes: __m512d, no: __m512d) -> __m512d {
        unsafe { _mm512_mask_blend_pd(m, no, yes) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::event::collision::collision_time;
    use rand::rngs::StdRng;
    use rand::{RngExt, SeedableRng};

    /// The scalar prediction, written out as `System::pair_time_at` computes it.
    fn scalar(records: &[f64], list: &[u32], f: &Frame) -> (f64, u32) {
        let (mut best, mut who) = (f64::INFINITY, 0u32);
        for &j in list {
            let p = &records[j as usize * RECORD..][..RECORD];
            let dt = f.now - p[T];
            let r: [f64; 3] = std::array::from_fn(|k| {
                let mut d = (p[X + k] + p[V + k] * dt) - f.x[k];
                if f.periodic[k] {
                    if d > f.half[k] {
                        d -= f.len[k];
                    } else if d < -f.half[k] {
                        d += f.len[k];
                    }
                }
                d
            });
            let v: [f64; 3] = std::array::from_fn(|k| p[V + k] - f.v[k]);
            let dot = |a: &[f64; 3], b: &[f64; 3]| {
                let mut s = 0.0;
                for k in 0..3 {
                    s += a[k] * b[k];
                }
                s
            };
            let half_sum = 0.5 * (f.ratio + p[RATIO]);
            let (sigma, g) = (half_sum * f.scale, half_sum * f.growth);
            let t = collision_time(
                dot(&v, &v) - g * g,
                dot(&r, &v) - sigma * g,
                dot(&r, &r) - sigma * sigma,
            );
            if t < best {
                best = t;
                who = j;
            }
        }
        (best, who)
    }

    /// Random spheres in a periodic (or walled) unit box, some touching or overlapping by a
    /// hair, some coincident, some moving apart faster than they grow: the vector path gives
    /// the scalar path's time and partner bit for bit, in four lanes and (where the processor
    /// has AVX-512F) in eight.
    #[test]
    fn matches_the_scalar_prediction_bit_for_bit() {
        let kernels: Vec<Kernel> = [Kernel::avx2(), Kernel::widest()]
            .into_iter()
            .flatten()
            .collect();
        if kernels.is_empty() {
            eprintln!("no AVX2 on this processor: nothing to compare");
            return;
        }
        let mut rng = StdRng::seed_from_u64(3);
        let mut hits = 0;
        for case in 0..20_000 {
            let n = 1 + rng.random_range(0..20usize);
            let periodic = [case % 3 != 0, true, case % 5 != 0];
            let len = [1.0, 0.8, 1.3];
            let scale = rng.random_range(0.05..0.3);
            let mut records = vec![0.0; n * RECORD];
            for p in records.chunks_exact_mut(RECORD) {
                for k in 0..3 {
                    p[X + k] = rng.random_range(-0.05..len[k] + 0.05);
                    p[V + k] = rng.random_range(-1.0..1.0);
                }
                p[T] = rng.random_range(-0.1..0.0);
                p[RATIO] = rng.random_range(0.5..1.5);
            }
            // A partner placed at contact (rounding decides the sign of c), or on top.
            if n > 1 && case % 4 == 0 {
                let (a, b) = records.split_at_mut(RECORD);
                b[..RECORD].copy_from_slice(&a[..RECORD]);
                b[X] += if case % 8 == 0 {
                    0.0
                } else {
                    0.5 * (a[RATIO] + b[RATIO]) * scale
                };
            }
            let me = rng.random_range(0..n);
            let p = &records[me * RECORD..][..RECORD];
            let now = rng.random_range(0.0..0.1);
            let frame = Frame {
                x: std::array::from_fn(|k| p[X + k] + p[V + k] * (now - p[T])),
                v: std::array::from_fn(|k| p[V + k]),
                ratio: p[RATIO],
                now,
                scale,
                growth: if case % 2 == 0 {
                    0.0
                } else {
                    rng.random_range(0.0..2.0)
                },
                len,
                half: len.map(|l| 0.5 * l),
                periodic,
            };
            let list: Vec<u32> = (0..n as u32).filter(|&j| j as usize != me).collect();
            let want = scalar(&records, &list, &frame);
            for kernel in &kernels {
                // SAFETY: every index is a record.
                let got = unsafe { kernel.earliest_collision(&records, &list, &frame) };
                assert_eq!(
                    got.0.to_bits(),
                    want.0.to_bits(),
                    "case {case}, {kernel:?}: {got:?} vs {want:?}"
                );
                assert_eq!(got.1, want.1, "case {case}, {kernel:?}");
            }
            hits += usize::from(want.0.is_finite());
        }
        assert!(hits > 2000, "too few collisions sampled: {hits}");
    }
}
