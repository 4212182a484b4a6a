//! The hot loop of event-driven MD, collision prediction, for 3D spheres with AVX2: the list
//! partners of one sphere are predicted four at a time.
//!
//! Every arithmetic operation is the one of the scalar path (`System::pair_time_at` and
//! [`super::collision::collision_time`]), in the same order and without fused multiply–adds, and
//! the square root and division are correctly rounded in both, so the result is bit for bit the
//! scalar one and trajectories do not depend on which path ran (tested below and in
//! `crate::tests`). Only the loads differ: the four partners' records are transposed into lanes.
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

/// Whether this processor can run [`earliest_collision`].
pub(crate) fn available() -> bool {
    std::arch::is_x86_feature_detected!("avx2")
}

/// The earliest collision time of the sphere `f` with the partners `list` (indices of records
/// in `records`, [`RECORD`] doubles each) and the partner, the first in list order among equal
/// times; `(∞, 0)` when none collides.
///
/// # Safety
/// The processor must support AVX2 ([`available`]), and every index in `list` must be below
/// `records.len() / RECORD`.
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn earliest_collision(records: &[f64], list: &[u32], f: &Frame) -> (f64, u32) {
    debug_assert!(
        list.iter()
            .all(|&j| (j as usize + 1) * RECORD <= records.len())
    );
    let (mut best, mut who) = (f64::INFINITY, 0u32);
    for chunk in list.chunks(4) {
        // Lanes past the end repeat the first partner; their results are not read.
        let lane = |k: usize| chunk.get(k).copied().unwrap_or(chunk[0]) as usize * RECORD;
        // SAFETY: every lane starts a record inside `records` (the caller's contract).
        let t = unsafe {
            let base = records.as_ptr();
            four_times([lane(0), lane(1), lane(2), lane(3)].map(|o| base.add(o)), f)
        };
        let mut times = [0.0f64; 4];
        // SAFETY: `times` holds four doubles.
        unsafe { _mm256_storeu_pd(times.as_mut_ptr(), t) };
        for (&time, &j) in times.iter().zip(chunk) {
            if time < best {
                best = time;
                who = j;
            }
        }
    }
    (best, who)
}

/// The eight fields of four records as four-lane vectors, field k of record l in lane l: each
/// record is loaded as two halves and the halves transposed (cheaper than eight gathers).
///
/// # Safety
/// AVX2, and every pointer must start a record of [`RECORD`] doubles.
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn transposed(records: [*const f64; 4]) -> [__m256d; RECORD] {
    // SAFETY: each record holds RECORD = 8 doubles, two halves of four.
    let half = |l: usize, h: usize| unsafe { _mm256_loadu_pd(records[l].add(4 * h)) };
    let mut fields = [_mm256_setzero_pd(); RECORD];
    for h in 0..2 {
        let (a, b, c, d) = (half(0, h), half(1, h), half(2, h), half(3, h));
        // [a0 b0 a2 b2], [a1 b1 a3 b3], and the same of c and d; then the 128-bit halves.
        let (ab_even, ab_odd) = (_mm256_unpacklo_pd(a, b), _mm256_unpackhi_pd(a, b));
        let (cd_even, cd_odd) = (_mm256_unpacklo_pd(c, d), _mm256_unpackhi_pd(c, d));
        fields[4 * h] = _mm256_permute2f128_pd::<0x20>(ab_even, cd_even);
        fields[4 * h + 1] = _mm256_permute2f128_pd::<0x20>(ab_odd, cd_odd);
        fields[4 * h + 2] = _mm256_permute2f128_pd::<0x31>(ab_even, cd_even);
        fields[4 * h + 3] = _mm256_permute2f128_pd::<0x31>(ab_odd, cd_odd);
    }
    fields
}

/// Collision times of `f` with the four records starting at `records`.
///
/// # Safety
/// AVX2, and every pointer must start a record of [`RECORD`] doubles.
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn four_times(records: [*const f64; 4], f: &Frame) -> __m256d {
    let zero = _mm256_setzero_pd();
    // SAFETY: the caller's contract.
    let fields = unsafe { transposed(records) };
    let field = |k: usize| fields[k];
    // position_at(j, now) = x + v·(now − t), then the separation from `f`.
    let dt = _mm256_sub_pd(_mm256_set1_pd(f.now), field(T));
    let mut r = [zero; 3];
    let mut v = [zero; 3];
    for k in 0..3 {
        let vk = field(V + k);
        let xk = _mm256_add_pd(field(X + k), _mm256_mul_pd(vk, dt));
        let mut d = _mm256_sub_pd(xk, _mm256_set1_pd(f.x[k]));
        if f.periodic[k] {
            // Minimum image: `if d > L/2 { d −= L } else if d < −L/2 { d += L }`.
            let h = _mm256_set1_pd(f.half[k]);
            let l = _mm256_set1_pd(f.len[k]);
            let above = _mm256_cmp_pd::<_CMP_GT_OQ>(d, h);
            let below = _mm256_cmp_pd::<_CMP_LT_OQ>(d, _mm256_sub_pd(zero, h));
            let shifted = _mm256_blendv_pd(d, _mm256_sub_pd(d, l), above);
            d = _mm256_blendv_pd(shifted, _mm256_add_pd(d, l), _mm256_andnot_pd(above, below));
        }
        r[k] = d;
        v[k] = _mm256_sub_pd(vk, _mm256_set1_pd(f.v[k]));
    }
    let half_sum = _mm256_mul_pd(
        _mm256_set1_pd(0.5),
        _mm256_add_pd(_mm256_set1_pd(f.ratio), field(RATIO)),
    );
    let sigma = _mm256_mul_pd(half_sum, _mm256_set1_pd(f.scale));
    let g = _mm256_mul_pd(half_sum, _mm256_set1_pd(f.growth));
    let b = _mm256_sub_pd(dot(&r, &v), _mm256_mul_pd(sigma, g));
    let a = _mm256_sub_pd(dot(&v, &v), _mm256_mul_pd(g, g));
    let c = _mm256_sub_pd(dot(&r, &r), _mm256_mul_pd(sigma, sigma));
    // collision_time(a, b, c), lane by lane.
    let disc = _mm256_sub_pd(_mm256_mul_pd(b, b), _mm256_mul_pd(a, c));
    let root = _mm256_div_pd(
        c,
        _mm256_sub_pd(_mm256_sqrt_pd(_mm256_max_pd(disc, zero)), b),
    );
    let approaching = _mm256_cmp_pd::<_CMP_LT_OQ>(b, zero);
    let ahead = _mm256_and_pd(
        _mm256_and_pd(
            _mm256_cmp_pd::<_CMP_GT_OQ>(c, zero),
            _mm256_or_pd(approaching, _mm256_cmp_pd::<_CMP_LT_OQ>(a, zero)),
        ),
        _mm256_and_pd(
            _mm256_cmp_pd::<_CMP_GE_OQ>(disc, zero),
            _mm256_cmp_pd::<_CMP_GT_OQ>(root, zero),
        ),
    );
    let touching = _mm256_and_pd(_mm256_cmp_pd::<_CMP_LE_OQ>(c, zero), approaching);
    _mm256_blendv_pd(
        _mm256_blendv_pd(_mm256_set1_pd(f64::INFINITY), root, ahead),
        zero,
        touching,
    )
}

/// `a·b` summed over the three axes in the scalar order (`0 + a₀b₀ + a₁b₁ + a₂b₂`).
#[target_feature(enable = "avx2")]
#[inline]
fn dot(a: &[__m256d; 3], b: &[__m256d; 3]) -> __m256d {
    let mut s = _mm256_setzero_pd();
    for k in 0..3 {
        s = _mm256_add_pd(s, _mm256_mul_pd(a[k], b[k]));
    }
    s
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
    /// the scalar path's time and partner bit for bit.
    #[test]
    fn matches_the_scalar_prediction_bit_for_bit() {
        if !available() {
            eprintln!("no AVX2 on this processor: nothing to compare");
            return;
        }
        let mut rng = StdRng::seed_from_u64(3);
        let mut hits = 0;
        for case in 0..20_000 {
            let n = 1 + rng.random_range(0..12usize);
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
            // SAFETY: AVX2 is available and every index is a record.
            let got = unsafe { earliest_collision(&records, &list, &frame) };
            assert_eq!(
                got.0.to_bits(),
                want.0.to_bits(),
                "case {case}: {got:?} vs {want:?}"
            );
            assert_eq!(got.1, want.1, "case {case}");
            hits += usize::from(want.0.is_finite());
        }
        assert!(hits > 2000, "too few collisions sampled: {hits}");
    }
}
