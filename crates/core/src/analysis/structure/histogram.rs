//! Normalised histograms on linear or logarithmic bins.

use serde::{Deserialize, Serialize};

/// A probability density sampled on bins: `density[b]` is the fraction of samples in bin `b`
/// divided by the bin's width, at the bin centre `x[b]` (the geometric centre on log bins).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Histogram {
    /// Bin centres.
    pub x: Vec<f64>,
    /// Probability density per bin.
    pub density: Vec<f64>,
}

impl Histogram {
    /// `bins` equal bins over `[lo, hi]`; samples outside are counted in the normalisation
    /// but in no bin. Empty when there are no samples or the range is empty.
    pub fn linear(samples: &[f64], lo: f64, hi: f64, bins: usize) -> Histogram {
        Self::binned(samples, bins, lo, hi, |v| v)
    }

    /// `bins` logarithmically equal bins over `[lo, hi]` (`0 < lo < hi`); non-positive samples
    /// count in the normalisation only.
    pub fn logarithmic(samples: &[f64], lo: f64, hi: f64, bins: usize) -> Histogram {
        if lo.is_nan() || lo <= 0.0 {
            return Histogram::default();
        }
        let mut h = Self::binned(samples, bins, lo.ln(), hi.ln(), |v| {
            if v > 0.0 { v.ln() } else { f64::NEG_INFINITY }
        });
        // Density per unit of the sample, not of its logarithm.
        let w = (hi.ln() - lo.ln()) / bins as f64;
        for (x, p) in h.x.iter_mut().zip(h.density.iter_mut()) {
            let centre = x.exp();
            let width = centre * (0.5 * w).exp() - centre * (-0.5 * w).exp();
            *p *= w / width;
            *x = centre;
        }
        h
    }

    fn binned(samples: &[f64], bins: usize, lo: f64, hi: f64, map: impl Fn(f64) -> f64) -> Self {
        if samples.is_empty()
            || bins == 0
            || hi.is_nan()
            || hi <= lo
            || !lo.is_finite()
            || !hi.is_finite()
        {
            return Histogram::default();
        }
        let w = (hi - lo) / bins as f64;
        let mut count = vec![0usize; bins];
        for &s in samples {
            let v = map(s);
            if v >= lo && v <= hi {
                count[(((v - lo) / w) as usize).min(bins - 1)] += 1;
            }
        }
        let n = samples.len() as f64;
        Histogram {
            x: (0..bins).map(|b| lo + (b as f64 + 0.5) * w).collect(),
            density: count.iter().map(|&c| c as f64 / (n * w)).collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn densities_integrate_to_the_fraction_inside() {
        let s: Vec<f64> = (1..=1000).map(|i| i as f64 / 1000.0).collect();
        let h = Histogram::linear(&s, 0.0, 0.5, 10);
        let total: f64 = h.density.iter().sum::<f64>() * 0.05;
        assert!((total - 0.5).abs() < 1e-12);
        let g = Histogram::logarithmic(&s, 0.01, 1.0, 20);
        // ∫ p dx over log bins: Σ p_b · width_b.
        let w = (1.0f64.ln() - 0.01f64.ln()) / 20.0;
        let total: f64 =
            g.x.iter()
                .zip(&g.density)
                .map(|(x, p)| p * x * ((0.5 * w).exp() - (-0.5 * w).exp()))
                .sum();
        assert!((total - 0.991).abs() < 1e-9, "{total}");
    }
}
