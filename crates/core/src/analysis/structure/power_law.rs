//! Power-law exponents of small values from their cumulative distribution.
//!
//! Fitting the cumulative count C(x) = #{x_i ≤ x} ∝ x^{1+a} instead of a histogram P(x) ∝ x^a
//! needs no bins and weighs every sample once (as Charbonneau et al., Nat. Commun. 5, 3725
//! (2014), do for gaps and forces).

use serde::{Deserialize, Serialize};

/// A fitted exponent with the window it was fitted over.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PowerLawFit {
    /// The exponent `a` of P(x) ∝ x^a.
    pub exponent: f64,
    /// The window `[lo, hi]` of x the fit used.
    pub window: [f64; 2],
    /// Number of samples inside the window.
    pub samples: usize,
}

/// Least-squares slope of log C(x_i) against log x_i over the sorted samples inside
/// `window`, minus one: the exponent `a` of P(x) ∝ x^a. `None` with fewer than 5 samples in
/// the window or no spread in x.
pub fn fit_small_values(sorted: &[f64], window: [f64; 2]) -> Option<PowerLawFit> {
    let (mut sx, mut sy, mut sxx, mut sxy, mut k) = (0.0, 0.0, 0.0, 0.0, 0usize);
    for (i, &x) in sorted.iter().enumerate() {
        if x < window[0] || x > window[1] || x <= 0.0 {
            continue;
        }
        let (lx, ly) = (x.ln(), ((i + 1) as f64).ln());
        sx += lx;
        sy += ly;
        sxx += lx * lx;
        sxy += lx * ly;
        k += 1;
    }
    if k < 5 {
        return None;
    }
    let n = k as f64;
    let var = sxx - sx * sx / n;
    if var <= 1e-12 * sxx.abs().max(1.0) {
        return None;
    }
    let slope = (sxy - sx * sy / n) / var;
    Some(PowerLawFit {
        exponent: slope - 1.0,
        window,
        samples: k,
    })
}

/// The exponent `a` of P(x) ∝ x^a on `window = [lo, hi]` fitted by maximum likelihood to the
/// samples inside the window, with its standard error from the Fisher information: the
/// estimate of a power law truncated at both ends, so values below `lo` (exact zeros of a
/// non-unique force solution, solver noise) neither enter nor bend it, as they bend the
/// cumulative count of [`fit_small_values`]. `None` with fewer than `min_samples` samples
/// inside the window.
pub fn fit_truncated_power_law(
    samples: &[f64],
    window: [f64; 2],
    min_samples: usize,
) -> Option<ExponentFit> {
    let [lo, hi] = window;
    let logs: Vec<f64> = samples
        .iter()
        .filter(|&&x| lo <= x && x <= hi)
        .map(|&x| (x / lo).ln())
        .collect();
    let k = logs.len();
    if k < min_samples.max(2) {
        return None;
    }
    let span = (hi / lo).ln();
    let mean = logs.iter().sum::<f64>() / k as f64;
    // u = ln(x/lo) on [0, L] has density ∝ e^{b u} (b = 1 + a), whose mean rises from 0 to L
    // with b: bisect for the b whose mean is the samples'.
    let (mut b_lo, mut b_hi) = (-200.0 / span, 200.0 / span);
    for _ in 0..200 {
        let b = 0.5 * (b_lo + b_hi);
        if log_moments(b, span).0 < mean {
            b_lo = b;
        } else {
            b_hi = b;
        }
    }
    let b = 0.5 * (b_lo + b_hi);
    let variance = log_moments(b, span).1;
    Some(ExponentFit {
        exponent: b - 1.0,
        error: 1.0 / (k as f64 * variance).sqrt(),
        window,
        samples: k,
    })
}

/// Mean and variance of u on [0, `span`] with density ∝ e^{b u} (a truncated exponential).
fn log_moments(b: f64, span: f64) -> (f64, f64) {
    let bl = b * span;
    if bl.abs() < 1e-4 {
        // The series about b = 0: the uniform density's L/2 and L²/12.
        return (
            span / 2.0 + b * span * span / 12.0,
            span * span / 12.0 - b * b * span.powi(4) / 720.0,
        );
    }
    let mean = span / -(-bl).exp_m1() - 1.0 / b;
    let half = (0.5 * bl).sinh();
    // L² e^{bL} / (e^{bL} − 1)² = L² / (4 sinh²(bL/2)).
    let variance = 1.0 / (b * b) - span * span / (4.0 * half * half);
    (mean, variance.max(f64::MIN_POSITIVE))
}

/// An exponent fitted by maximum likelihood, with its standard error and window.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ExponentFit {
    /// The exponent `a` of P(x) ∝ x^a.
    pub exponent: f64,
    /// Its standard error (one σ, from the Fisher information).
    pub error: f64,
    /// The window `[lo, hi]` of x the fit used.
    pub window: [f64; 2],
    /// Number of samples inside the window.
    pub samples: usize,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_the_exponent_of_a_power_law_sample() {
        // Quantiles of P(x) = (1+a) x^a on [0, 1]: x = u^{1/(1+a)}.
        for a in [-0.4, 0.0, 0.42] {
            let n = 20_000;
            let xs: Vec<f64> = (1..=n)
                .map(|i| (i as f64 / n as f64).powf(1.0 / (1.0 + a)))
                .collect();
            let fit = fit_small_values(&xs, [1e-3, 0.3]).unwrap();
            assert!((fit.exponent - a).abs() < 1e-3, "{a}: {}", fit.exponent);
        }
        assert!(fit_small_values(&[0.1, 0.2], [0.0, 1.0]).is_none());
    }

    /// The truncated maximum-likelihood fit recovers θ = 0.42311 (Charbonneau et al. 2014)
    /// and θ_ℓ = 0.17462 from samples of P(x) ∝ x^a, within three standard errors whatever
    /// lies below the window: 200 exact zeros bend the cumulative fit, not this one.
    #[test]
    fn the_truncated_fit_ignores_values_below_its_window() {
        for a in [0.42311, 0.17462] {
            let n = 4000;
            let mut xs: Vec<f64> = (1..=n)
                .map(|i| ((i as f64 - 0.5) / n as f64).powf(1.0 / (1.0 + a)))
                .collect();
            xs.extend(std::iter::repeat_n(0.0, 200));
            xs.sort_by(f64::total_cmp);
            let fit = fit_truncated_power_law(&xs, [0.01, 0.3], 20).unwrap();
            assert!(
                (fit.exponent - a).abs() < 3.0 * fit.error && fit.error < 0.1,
                "{a}: {fit:?}"
            );
            // The cumulative fit counts the zeros and its exponent falls below −0.5.
            assert!(fit_small_values(&xs, [0.01, 0.3]).unwrap().exponent < a - 0.3);
        }
        // Too few samples in the window: no fit.
        assert!(fit_truncated_power_law(&[0.05, 0.1, 0.2], [0.01, 0.3], 20).is_none());
    }
}
