//! Collisions of two spheres whose diameters grow linearly in time (Lubachevsky–Stillinger).
//!
//! With separation `r(t) = r + v t` (v the relative velocity) and contact distance
//! `σ(t) = σ + g t` (g the growth speed of the pair's mean diameter), contact happens when
//! `|r + v t|² = (σ + g t)²`, i.e. `a t² + 2 b t + c = 0` with
//! `a = v·v − g²`, `b = r·v − σ g`, `c = r·r − σ²`.

/// Time until two growing spheres touch, or ∞ if they never do on current trajectories.
///
/// Takes the earliest non-negative root in the numerically stable form `t = c / (−b + √(b² − a c))`,
/// which equals `(−b − √disc)/a` but never subtracts nearly equal numbers when `b < 0`
/// (approaching) and also covers `a < 0` (growth outruns the relative speed, so contact is
/// certain) with `b ≥ 0`.
///
/// Near jamming (gaps ~1e-12 σ) rounding can leave a pair that just collided with `c`
/// slightly negative. Such a pair is only made to collide again (at `t = 0`) if it is still
/// approaching (`b < 0`), so spheres never pass through each other; a pair that is separating
/// is left alone, and the collision rule guarantees separation (see [`impulse`]), so this
/// cannot start a cascade of zero-time collisions.
///
/// Branch-free: the root is computed whatever the case and the answer selected (the cases are
/// a coin toss to the branch predictor). Measured as fast as a branchy form with an early exit
/// against the best time so far (docs/notes/mls-event-engine.md), and simpler.
#[inline(always)]
pub(crate) fn collision_time(a: f64, b: f64, c: f64) -> f64 {
    let disc = b * b - a * c;
    let t = c / (disc.max(0.0).sqrt() - b);
    // Ahead: apart now, not separating faster than growing, the paths meet (disc ≥ 0), and the
    // root is positive (−b + √disc > 0; NaN and −∞ fail the test).
    let ahead = (c > 0.0) & ((b < 0.0) | (a < 0.0)) & (disc >= 0.0) & (t > 0.0);
    // Touching or overlapping by rounding: collide now only if still approaching.
    let now = (c <= 0.0) & (b < 0.0);
    let t = if ahead { t } else { f64::INFINITY };
    if now { 0.0 } else { t }
}

/// Momentum given to `j` (and taken from `i`) along the unit normal `n` from `i` to `j` when two
/// unit-mass spheres collide with normal relative speed `vn = (v_j − v_i)·n` while their
/// contact distance grows at speed `g`.
///
/// The collision is elastic in the frame of the moving contact surface: the normal speed
/// relative to the surface, `vn − g`, is reversed, so `vn' = 2g − vn` and the impulse is
/// `J = g − vn` (Lubachevsky–Stillinger: the growth speed is added to the separation). To keep
/// the pair from being re-predicted as approaching because of rounding at pressures ~1e12, the
/// impulse is at least `min_impulse` (a tiny fraction of the thermal speed, see
/// `System::min_impulse`), which makes the surfaces part at a speed the next prediction resolves.
#[inline]
pub(crate) fn impulse(vn: f64, g: f64, min_impulse: f64) -> f64 {
    (g - vn).max(min_impulse)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::rngs::StdRng;
    use rand::{RngExt, SeedableRng};

    /// First root of f(t) = |r+vt|² − (σ+gt)² on [0, t_max] by scanning and bisection.
    fn brute_force(r: [f64; 3], v: [f64; 3], sigma: f64, g: f64, t_max: f64) -> Option<f64> {
        let f = |t: f64| {
            let d2: f64 = (0..3).map(|k| (r[k] + v[k] * t).powi(2)).sum();
            d2 - (sigma + g * t).powi(2)
        };
        let steps = 200_000;
        let mut lo = 0.0;
        for s in 1..=steps {
            let hi = t_max * s as f64 / steps as f64;
            if f(hi) <= 0.0 {
                let (mut a, mut b) = (lo, hi);
                for _ in 0..200 {
                    let m = 0.5 * (a + b);
                    if f(m) <= 0.0 { b = m } else { a = m }
                }
                return Some(b);
            }
            lo = hi;
        }
        None
    }

    #[test]
    fn collision_times_match_a_brute_force_root_finder() {
        let mut rng = StdRng::seed_from_u64(7);
        let mut hits = 0;
        for _ in 0..1500 {
            let r: [f64; 3] = std::array::from_fn(|_| rng.random_range(-2.0..2.0));
            let v: [f64; 3] = std::array::from_fn(|_| rng.random_range(-1.0..1.0));
            let rn = (r.iter().map(|x| x * x).sum::<f64>()).sqrt();
            let sigma = rng.random_range(0.0..rn);
            let g = if rng.random::<bool>() {
                0.0
            } else {
                rng.random_range(0.0..0.5)
            };
            let a = v.iter().map(|x| x * x).sum::<f64>() - g * g;
            let b = (0..3).map(|k| r[k] * v[k]).sum::<f64>() - sigma * g;
            let c = rn * rn - sigma * sigma;
            let t_max = 20.0;
            let got = Some(collision_time(a, b, c)).filter(|&t| t <= t_max);
            let want = brute_force(r, v, sigma, g, t_max);
            match (got, want) {
                (Some(x), Some(y)) => {
                    hits += 1;
                    assert!((x - y).abs() <= 1e-9 * (1.0 + y), "{x} vs {y}");
                }
                (None, None) => {}
                // A grazing miss can touch within the scan resolution; accept only a tangent.
                (x, y) => {
                    panic!("predicted {x:?}, brute force {y:?} for r={r:?} v={v:?} σ={sigma} g={g}")
                }
            }
        }
        assert!(hits > 200, "too few collisions sampled: {hits}");
    }

    #[test]
    fn touching_pairs_collide_now_only_when_approaching() {
        assert_eq!(collision_time(1.0, -0.5, -1e-16), 0.0);
        assert_eq!(collision_time(1.0, 0.5, -1e-16), f64::INFINITY);
        // Growth faster than separation: contact is certain even when moving apart.
        let t = collision_time(-1.0, 0.1, 0.5);
        assert!(t > 0.0 && t.is_finite());
        // Separating faster than growing, and paths that miss: never.
        assert_eq!(collision_time(1.0, 0.5, 1.0), f64::INFINITY);
        assert_eq!(collision_time(1.0, -0.5, 1.0), f64::INFINITY);
    }

    #[test]
    fn the_impulse_reflects_the_speed_relative_to_the_growing_surface() {
        let (vn, g) = (-0.3, 0.1);
        let j = impulse(vn, g, 0.0);
        let vn_after = vn + 2.0 * j;
        assert!((vn_after - g - (g - vn)).abs() < 1e-15);
        assert_eq!(impulse(0.1 + 1e-20, 0.1, 1e-9), 1e-9);
    }
}
