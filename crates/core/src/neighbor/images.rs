//! Pairs across every periodic image, for boxes too small for the minimum image.
//!
//! When a periodic side is shorter than twice the reach `D_max + skin`, a pair can touch
//! through more than one image and a particle can touch its own image (Baranau & Tallarek 2014 App. C:
//! "x_ii may be non-zero"). The minimum-image [`CellList`](super::CellList) misses those
//! contacts; this enumeration finds them all, in O(N² · images), which only small systems need.

use crate::MAX_DIM;
use crate::container::Container;

/// Whether the minimum image can miss a pair within `reach` (centre distance): true when some
/// periodic side is shorter than `2·reach`. A second image of a pair lies at least `L/2` away
/// along that axis, so longer sides leave at most one image within reach.
pub fn needs_images(container: &Container, reach: f64) -> bool {
    container
        .lengths
        .iter()
        .zip(&container.periodic)
        .any(|(&l, &p)| p && l < 2.0 * reach)
}

/// Calls `f(i, j, shift)` for every pair `i ≤ j` and image shift (box lengths per axis, `d`
/// entries, 0 on non-periodic axes) with `|x_j + Σ_k shift_k L_k e_k − x_i| < (D_i + D_j)/2 +
/// skin`. A particle's own images are listed once, for their lexicographically positive shift
/// (the negative one is the same contact seen from the image). Positions need not be wrapped.
/// Shifts come in the order of an odometer whose first axis turns fastest.
pub fn for_each_image_pair(
    container: &Container,
    positions: &[f64],
    diameters: &[f64],
    skin: f64,
    mut f: impl FnMut(usize, usize, &[i32]),
) {
    let d = container.dim();
    let n = diameters.len();
    let x = positions;
    let mut dx = [0.0; MAX_DIM];
    let mut shift = [0i32; MAX_DIM];
    for i in 0..n {
        for j in i..n {
            let reach = 0.5 * (diameters[i] + diameters[j]) + skin;
            for k in 0..d {
                dx[k] = x[j * d + k] - x[i * d + k];
            }
            let mut visit = |shift: &[i32]| {
                let listed = i != j || shift.iter().find(|&&s| s != 0).is_some_and(|&s| s > 0);
                if listed {
                    f(i, j, shift);
                }
            };
            shifts_within(
                container,
                &dx[..d],
                d,
                reach * reach,
                &mut shift,
                &mut visit,
            );
        }
    }
}

/// Visits every shift of axes `0..axes` (the others already set in `shift`) whose part
/// `Σ_{k < axes} (dx_k + shift_k L_k)²` is below `budget`, the last axis outermost. Each axis
/// takes only the shifts that what the outer axes left of the budget allows, so the work
/// follows the number of images within reach rather than a cube of shifts (7⁸ per pair in 8D
/// with D near L).
fn shifts_within(
    container: &Container,
    dx: &[f64],
    axes: usize,
    budget: f64,
    shift: &mut [i32; MAX_DIM],
    visit: &mut dyn FnMut(&[i32]),
) {
    let Some(k) = axes.checked_sub(1) else {
        visit(&shift[..dx.len()]);
        return;
    };
    let (lo, hi) = match container.periodic[k] {
        true => {
            let (l, r) = (container.lengths[k], budget.sqrt());
            (
                ((-r - dx[k]) / l).ceil() as i32,
                ((r - dx[k]) / l).floor() as i32,
            )
        }
        false => (0, 0),
    };
    for s in lo..=hi {
        let v = dx[k] + f64::from(s) * container.lengths[k];
        let left = budget - v * v;
        if left > 0.0 {
            shift[k] = s;
            shifts_within(container, dx, k, left, shift, visit);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Every shift in a cube around the minimum image wide enough for the largest reach, in
    /// odometer order (first axis fastest), kept when within the pair's reach.
    fn cube(c: &Container, x: &[f64], dia: &[f64], skin: f64) -> Vec<(usize, usize, Vec<i32>)> {
        let d = c.dim();
        let reach = dia.iter().fold(0.0f64, |m, &v| m.max(v)) + skin;
        let m: Vec<i32> = (0..d)
            .map(|k| match c.periodic[k] {
                true => (reach / c.lengths[k]).ceil() as i32 + 1,
                false => 0,
            })
            .collect();
        let mut out = Vec::new();
        for i in 0..dia.len() {
            for j in i..dia.len() {
                let base: Vec<i32> = (0..d)
                    .map(|k| match c.periodic[k] {
                        true => -((x[j * d + k] - x[i * d + k]) / c.lengths[k]).round() as i32,
                        false => 0,
                    })
                    .collect();
                let mut off: Vec<i32> = m.iter().map(|&r| -r).collect();
                'odometer: loop {
                    let shift: Vec<i32> = (0..d).map(|k| base[k] + off[k]).collect();
                    let r2: f64 = (0..d)
                        .map(|k| x[j * d + k] - x[i * d + k] + f64::from(shift[k]) * c.lengths[k])
                        .map(|v| v * v)
                        .sum();
                    let positive = shift.iter().find(|&&s| s != 0).is_some_and(|&s| s > 0);
                    let cut = 0.5 * (dia[i] + dia[j]) + skin;
                    if (i != j || positive) && r2 < cut * cut {
                        out.push((i, j, shift));
                    }
                    for k in 0..=d {
                        if k == d {
                            break 'odometer;
                        }
                        off[k] += 1;
                        if off[k] <= m[k] {
                            break;
                        }
                        off[k] = -m[k];
                    }
                }
            }
        }
        out
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(60))]
        /// The pruned enumeration lists exactly the cube's images, in the same order, with
        /// spheres up to 1.6 box lengths across (several images per pair, self-contacts).
        #[test]
        fn matches_a_cube_of_shifts(
            d in 2usize..=5,
            n in 1usize..7,
            seed in any::<u64>(),
            walls in any::<u8>(),
            skin in 0.0f64..0.3,
        ) {
            use rand::{RngExt, SeedableRng};
            let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
            let lengths: Vec<f64> = (0..d).map(|_| rng.random_range(1.0..2.0)).collect();
            let flags: Vec<bool> = (0..d).map(|k| walls >> k & 1 == 1).collect();
            let c = Container::with_flags(&lengths, &flags).unwrap();
            // Unwrapped positions, as a run leaves them.
            let x: Vec<f64> = (0..n * d).map(|k| lengths[k % d] * rng.random_range(-1.0..2.0)).collect();
            let dia: Vec<f64> = (0..n).map(|_| rng.random_range(0.1..1.6)).collect();
            let mut got = Vec::new();
            for_each_image_pair(&c, &x, &dia, skin, |i, j, s| got.push((i, j, s.to_vec())));
            prop_assert_eq!(got, cube(&c, &x, &dia, skin));
        }
    }
}
