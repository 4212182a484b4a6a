//! Farr & Groot's one-dimensional estimate of φ_RCP for spheres of any size distribution
//! (R. S. Farr and R. D. Groot, "Close packing density of polydisperse hard spheres",
//! J. Chem. Phys. 131, 244104 (2009), arXiv:0912.0852).
//!
//! The mapping, in three steps:
//!
//! 1. **Spheres to rods.** A random straight line through a 3D packing crosses a sphere of
//!    diameter D with probability ∝ D² (its cross-section) and cuts from it a chord of length
//!    L = D√U, U uniform on (0, 1) (chord density 2L/D² on [0, D]). The fraction of the line
//!    inside spheres is the volume fraction φ, so a 1D packing of these rods estimates φ.
//!    Here the rods are the `n` quantiles of the chord-length distribution of the given
//!    diameters, T(L) = Σ_{D_i > L} (D_i² − L²) / Σ_i D_i² (the fraction of chords longer than
//!    L), inverted exactly: T is piecewise quadratic between sorted diameters. No random
//!    numbers, so the estimate is a pure function of the diameters.
//! 2. **Rods to a 1D random close packing.** Rods are placed longest first on a periodic
//!    line that starts as the first rod and a free gap f·L₁. Each rod L is offered the longest
//!    gap g: if g ≥ (1 + f)·L it goes in, leaving a free length f·L beside it and the rest
//!    g − (1 + f)·L (at least f·L) on its other side; otherwise the line is lengthened to take
//!    it, its gap g replaced by two free lengths f·L. φ is the rods' total length over the
//!    line's.
//! 3. **Calibration.** The free-length ratio f is the one parameter; it is fixed so that equal
//!    spheres give φ_RCP = 0.6435 ([`FG_PHI_MONO`], the monodisperse value Farr & Groot
//!    calibrate to), solved by bisection on the chords of equal spheres ([`free_length`]).
//!
//! Stated range (the paper's abstract): hard spheres in 3D of any size distribution; it agrees
//! with the authors' simulations for bidisperse, tridisperse and log-normal distributions and
//! reproduces the exact limits of large size ratios (small spheres filling the voids of a
//! packing of large ones, or large ones as inclusions in a packing of small ones), which the
//! tests check. Provenance of step 2: the paper's text could not be opened here; the placement
//! rule (longest first, into the longest gap, a free length proportional to the rod) is the
//! one public implementations of the method use (docs/notes/structure.md), and should be
//! checked against the paper.

use std::collections::BinaryHeap;
use std::sync::OnceLock;

/// φ_RCP of equal spheres the free length is calibrated to (Farr & Groot 2009).
pub const FG_PHI_MONO: f64 = 0.6435;

/// Number of rods (chord-length quantiles) in the 1D packing; the estimate moves by less than
/// 1e-5 between 2·10⁴ and 5·10⁴ rods for log-normal distributions with σ ≤ 0.3.
pub const FG_RODS: usize = 50_000;

/// A gap length ordered for the max-heap (gaps are finite and non-negative).
#[derive(Clone, Copy)]
struct Gap(f64);

impl PartialEq for Gap {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other).is_eq()
    }
}

impl Eq for Gap {}

impl PartialOrd for Gap {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Gap {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

/// The `n` chord lengths of a random line through spheres of these diameters, longest first
/// (step 1 of the module doc). Diameters must be positive and finite; `n ≥ 1`.
pub fn chord_lengths(diameters: &[f64], n: usize) -> Vec<f64> {
    let mut d = diameters.to_vec();
    d.sort_by(f64::total_cmp);
    let m = d.len();
    let w: f64 = d.iter().map(|x| x * x).sum();
    // tail[j] = Σ_{i ≥ j} d_i²: for L in [d_{j−1}, d_j) the spheres j.. are longer than L and
    // T(L) = (tail[j] − (m − j) L²) / w.
    let mut tail = vec![0.0; m + 1];
    for j in (0..m).rev() {
        tail[j] = tail[j + 1] + d[j] * d[j];
    }
    let lower = |j: usize| if j == 0 { 0.0 } else { d[j - 1] };
    let mut j = m - 1;
    (1..=n)
        .map(|k| {
            // Quantile T(L) = q, small q first: the longest chords first.
            let q = (k as f64 - 0.5) / n as f64;
            while j > 0 && (tail[j] - (m - j) as f64 * lower(j) * lower(j)) / w < q {
                j -= 1;
            }
            ((tail[j] - q * w) / (m - j) as f64).max(0.0).sqrt()
        })
        .collect()
}

/// φ of the 1D packing of `rods` (longest first) with free-length ratio `f` (step 2).
pub fn pack_rods(rods: &[f64], f: f64) -> f64 {
    let Some((&first, rest)) = rods.split_first() else {
        return 0.0;
    };
    let mut gaps = BinaryHeap::with_capacity(rods.len() + 1);
    gaps.push(Gap(f * first));
    let (mut solid, mut free) = (first, f * first);
    for &l in rest {
        let Gap(g) = gaps.pop().expect("the line always has a gap");
        let free_here = f * l;
        let other = if g >= (1.0 + f) * l {
            (g - (1.0 + f) * l).max(free_here)
        } else {
            free_here
        };
        free += free_here + other - g;
        solid += l;
        gaps.push(Gap(free_here));
        gaps.push(Gap(other));
    }
    solid / (solid + free)
}

/// The free-length ratio f for which equal spheres give [`FG_PHI_MONO`] with [`FG_RODS`] rods
/// (step 3), found once by bisection and cached.
pub fn free_length() -> f64 {
    static F: OnceLock<f64> = OnceLock::new();
    *F.get_or_init(|| {
        let rods = chord_lengths(&[1.0], FG_RODS);
        // φ(0) = 1 and φ(2) < 0.4; φ falls with f.
        let (mut lo, mut hi) = (0.0, 2.0);
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if pack_rods(&rods, mid) > FG_PHI_MONO {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    })
}

/// Farr–Groot φ_RCP of 3D spheres with these diameters, or `None` for an empty list or a
/// diameter that is not positive and finite.
pub fn farr_groot(diameters: &[f64]) -> Option<f64> {
    if diameters.is_empty() || !diameters.iter().all(|d| d.is_finite() && *d > 0.0) {
        return None;
    }
    Some(pack_rods(&chord_lengths(diameters, FG_RODS), free_length()))
}

#[cfg(test)]
mod tests {
    use rand::SeedableRng;
    use rand::rngs::StdRng;

    use super::*;
    use crate::distribution::SizeDistribution;

    /// `n_small` spheres of diameter 1 per large one of diameter `ratio`, so that the small
    /// spheres hold the volume fraction `x_small` of the solid.
    fn bidisperse(ratio: f64, x_small: f64) -> Vec<f64> {
        let n_large = 20;
        let n_small = (n_large as f64 * x_small / (1.0 - x_small) * ratio.powi(3)).round();
        let mut d = vec![ratio; n_large];
        d.extend(std::iter::repeat_n(1.0, n_small as usize));
        d
    }

    #[test]
    fn chords_follow_the_area_weighted_chord_distribution() {
        // Equal spheres: T(L) = 1 − L², so the mean chord is 2/3 D and the longest is ≤ D.
        let rods = chord_lengths(&[2.0; 5], 10_000);
        let mean = rods.iter().sum::<f64>() / rods.len() as f64;
        assert!((mean - 4.0 / 3.0).abs() < 1e-4, "mean chord {mean}");
        assert!(rods.windows(2).all(|w| w[0] >= w[1]) && rods[0] <= 2.0);
        // Two sizes 1 and 3 at equal numbers: a chord is from the large sphere with
        // probability 9/10 and the chords longer than 1 are 9/10 · (1 − 1/9) = 0.8 of all.
        let rods = chord_lengths(&[1.0, 3.0], 10_000);
        let longer = rods.iter().filter(|&&l| l > 1.0).count() as f64 / 1e4;
        assert!((longer - 0.8).abs() < 2e-4, "{longer}");
    }

    #[test]
    fn equal_spheres_give_the_calibration_value_at_any_size() {
        for d in [1.0, 0.37, 12.0] {
            let phi = farr_groot(&[d; 7]).unwrap();
            assert!((phi - FG_PHI_MONO).abs() < 1e-12, "D = {d}: φ = {phi}");
        }
        // Equal rods without polydisperse chords would give 1/(1 + f).
        let f = free_length();
        assert!((pack_rods(&[1.0; 100], f) - 1.0 / (1.0 + f)).abs() < 1e-12);
    }

    #[test]
    fn large_size_ratios_reach_the_exact_bidisperse_limits() {
        let phi = FG_PHI_MONO;
        // Few small spheres fill the voids of an RCP of large ones: φ = φ_m / (1 − x_small).
        for x in [0.1, 0.15, 0.2] {
            let got = farr_groot(&bidisperse(100.0, x)).unwrap();
            let exact = phi / (1.0 - x);
            assert!((got - exact).abs() < 1e-3, "x_small {x}: {got} vs {exact}");
        }
        // Many small spheres: the large ones are inclusions in an RCP of small ones,
        // φ = 1 / (x_large + x_small / φ_m); this branch converges more slowly with the ratio.
        for x in [0.4, 0.6, 0.8] {
            let got = farr_groot(&bidisperse(100.0, x)).unwrap();
            let exact = 1.0 / (1.0 - x + x / phi);
            assert!((got - exact).abs() < 5e-3, "x_small {x}: {got} vs {exact}");
        }
    }

    #[test]
    fn polydispersity_raises_phi() {
        // Log-normal diameters at mean 1 with std σ = 0, 0.1, 0.2, 0.3 (4000 drawn, seeded).
        let phis: Vec<f64> = [0.0, 0.1, 0.2, 0.3]
            .iter()
            .map(|&sigma| {
                let d = SizeDistribution::LognormalMean1 { sigma }
                    .sample(4000, &mut StdRng::seed_from_u64(1))
                    .unwrap();
                farr_groot(&d).unwrap()
            })
            .collect();
        assert!((phis[0] - FG_PHI_MONO).abs() < 1e-12);
        assert!(phis.windows(2).all(|w| w[1] > w[0] + 1e-3), "{phis:?}");
        assert!(phis[3] < 0.70, "{phis:?}");
    }

    #[test]
    fn bad_diameters_give_no_value() {
        assert_eq!(farr_groot(&[]), None);
        assert_eq!(farr_groot(&[1.0, f64::NAN]), None);
        assert_eq!(farr_groot(&[1.0, 0.0]), None);
    }
}
