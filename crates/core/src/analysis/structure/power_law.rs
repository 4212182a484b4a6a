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
}
