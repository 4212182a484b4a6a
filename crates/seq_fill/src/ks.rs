//! The radii a fill placed against radii drawn afresh from the distribution it draws from, by
//! the core's two-sample Kolmogorov–Smirnov test (Black & Cheviakov 2022 compare them by
//! histogram, their Fig. 2 e, f).

use packbench_core::SizeDistribution;
use packbench_core::ks::{KsTest, two_sample_ks};
use rand::SeedableRng;
use rand::rngs::StdRng;

use crate::error::SeqFillError;

/// The KS test of the placed `radii` against `fresh` radii drawn anew from `distribution`
/// (which describes diameters) with its own seed, independent of the fill's stream.
///
/// Errors: a distribution that cannot be sampled.
pub fn radii_against_distribution(
    radii: &[f64],
    distribution: &SizeDistribution,
    fresh: usize,
    seed: u64,
) -> Result<KsTest, SeqFillError> {
    let mut rng = StdRng::seed_from_u64(seed ^ 0x6b73_5f66_7265_7368);
    let drawn: Vec<f64> = distribution
        .sample(fresh, &mut rng)?
        .into_iter()
        .map(|dia| 0.5 * dia)
        .collect();
    Ok(two_sample_ks(radii, &drawn))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sample_of_the_distribution_passes_and_a_shifted_one_fails() {
        let weibull = SizeDistribution::Weibull {
            scale: 31.4,
            shape: 3.55,
        };
        let mut rng = StdRng::seed_from_u64(7);
        let own: Vec<f64> = weibull
            .sample(2000, &mut rng)
            .unwrap()
            .iter()
            .map(|d| 0.5 * d)
            .collect();
        let same = radii_against_distribution(&own, &weibull, 20_000, 1).unwrap();
        assert!(same.p_value > 0.001, "{same:?}");
        let smaller: Vec<f64> = own.iter().map(|r| 0.9 * r).collect();
        let shifted = radii_against_distribution(&smaller, &weibull, 20_000, 1).unwrap();
        assert!(shifted.p_value < 1e-6, "{shifted:?}");
    }
}
