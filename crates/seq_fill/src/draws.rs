//! The random radii: drawn from the size distribution (which describes diameters) in seeded
//! batches, each recorded as placed or discarded ("a radius that fits nowhere is discarded and
//! a new one drawn", Black & Cheviakov 2022 §2.1), so the bench can compare them with the target density.

use packbench_core::SizeDistribution;
use rand::SeedableRng;
use rand::rngs::StdRng;

use crate::error::SeqFillError;

/// Draws per batch: the distribution is validated and sampled once per batch, not per radius.
const BATCH: usize = 4096;

/// Draws used to estimate the mean radius r̄ that ε, δ and the corner spheres refer to.
const MEAN_SAMPLE: usize = 1 << 16;

/// The stream of radii of one fill.
pub(crate) struct Draws {
    rng: StdRng,
    distribution: SizeDistribution,
    batch: Vec<f64>,
    next: usize,
    /// Radii drawn and placed, in order.
    pub placed: Vec<f64>,
    /// Radii drawn and discarded because they fitted nowhere, in order.
    pub discarded: Vec<f64>,
}

impl Draws {
    /// A stream seeded with `seed`.
    pub(crate) fn new(distribution: &SizeDistribution, seed: u64) -> Self {
        Draws {
            rng: StdRng::seed_from_u64(seed),
            distribution: distribution.clone(),
            batch: Vec::new(),
            next: 0,
            placed: Vec::new(),
            discarded: Vec::new(),
        }
    }

    /// The mean radius r̄ of the distribution, from a fixed large sample of its own seeded
    /// stream (the core's distributions have no closed-form mean in general).
    pub(crate) fn mean_radius(
        distribution: &SizeDistribution,
        seed: u64,
    ) -> Result<f64, SeqFillError> {
        let mut rng = StdRng::seed_from_u64(seed ^ 0x6d65_616e_7261_6469);
        let sample = distribution.sample(MEAN_SAMPLE, &mut rng)?;
        Ok(0.5 * sample.iter().sum::<f64>() / MEAN_SAMPLE as f64)
    }

    /// The radius below which a tenth of the distribution lies, from the same sample as
    /// [`Draws::mean_radius`]: small spheres fill the gaps between large ones, so the number of
    /// spheres a brick takes follows the small radii, not the mean (sizes 1 and 20).
    pub(crate) fn small_radius(
        distribution: &SizeDistribution,
        seed: u64,
    ) -> Result<f64, SeqFillError> {
        let mut rng = StdRng::seed_from_u64(seed ^ 0x6d65_616e_7261_6469);
        let mut sample = distribution.sample(MEAN_SAMPLE, &mut rng)?;
        sample.sort_by(f64::total_cmp);
        Ok(0.5 * sample[MEAN_SAMPLE / 10])
    }

    /// The next radius.
    pub(crate) fn radius(&mut self) -> Result<f64, SeqFillError> {
        if self.next == self.batch.len() {
            self.batch = self.distribution.sample(BATCH, &mut self.rng)?;
            self.next = 0;
        }
        self.next += 1;
        Ok(0.5 * self.batch[self.next - 1])
    }

    /// Radii drawn so far.
    pub(crate) fn count(&self) -> u64 {
        (self.placed.len() + self.discarded.len()) as u64
    }
}
