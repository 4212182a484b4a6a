//! Pairs across every periodic image, for boxes too small for the minimum image.
//!
//! When a periodic side is shorter than twice the reach `D_max + skin`, a pair can touch
//! through more than one image and a particle can touch its own image (seed 001 App. C:
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
pub fn for_each_image_pair(
    container: &Container,
    positions: &[f64],
    diameters: &[f64],
    skin: f64,
    mut f: impl FnMut(usize, usize, &[i32]),
) {
    let d = container.dim();
    let n = diameters.len();
    let reach = diameters.iter().fold(0.0f64, |m, &v| m.max(v)) + skin;
    // Image range per axis around the minimum image: enough to cover the reach either side.
    let mut range = [0i32; MAX_DIM];
    for k in 0..d {
        if container.periodic[k] {
            range[k] = (reach / container.lengths[k]).ceil() as i32 + 1;
        }
    }
    let x = positions;
    let mut offset = [0i32; MAX_DIM];
    let mut shift = [0i32; MAX_DIM];
    for i in 0..n {
        for j in i..n {
            let sigma = 0.5 * (diameters[i] + diameters[j]);
            // The minimum image of the raw difference, then an odometer over offsets from it.
            let mut base = [0i32; MAX_DIM];
            for k in 0..d {
                if container.periodic[k] {
                    base[k] =
                        -((x[j * d + k] - x[i * d + k]) / container.lengths[k]).round() as i32;
                }
                offset[k] = -range[k];
            }
            loop {
                let mut r2 = 0.0;
                for k in 0..d {
                    shift[k] = base[k] + offset[k];
                    let v = x[j * d + k] - x[i * d + k] + shift[k] as f64 * container.lengths[k];
                    r2 += v * v;
                }
                let listed = i != j || shift[..d].iter().find(|&&s| s != 0).is_some_and(|&s| s > 0);
                if listed && r2.sqrt() < sigma + skin {
                    f(i, j, &shift[..d]);
                }
                let mut k = 0;
                while k < d {
                    offset[k] += 1;
                    if offset[k] <= range[k] {
                        break;
                    }
                    offset[k] = -range[k];
                    k += 1;
                }
                if k == d {
                    break;
                }
            }
        }
    }
}
