//! The two-sample Kolmogorov–Smirnov test: do two samples (of diameters, radii, …) come from
//! one continuous distribution? seq-fill compares the radii it placed with fresh draws; the
//! size distributions' tests compare their quantile samples with their random draws.

/// A two-sample KS test: the largest distance `d` between the two empirical distribution
/// functions, and the asymptotic probability of a distance at least as large when both samples
/// come from one continuous distribution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KsTest {
    pub d: f64,
    pub p_value: f64,
    pub n1: usize,
    pub n2: usize,
}

/// The two-sample KS test of `a` against `b` (both non-empty, finite).
pub fn two_sample_ks(a: &[f64], b: &[f64]) -> KsTest {
    let sorted = |v: &[f64]| {
        let mut s = v.to_vec();
        s.sort_by(f64::total_cmp);
        s
    };
    let (a, b) = (sorted(a), sorted(b));
    let (n1, n2) = (a.len(), b.len());
    let (mut i, mut j, mut d) = (0, 0, 0.0f64);
    while i < n1 && j < n2 {
        // Step past every copy of the smaller value in both samples (ties move together).
        let x = a[i].min(b[j]);
        while i < n1 && a[i] <= x {
            i += 1;
        }
        while j < n2 && b[j] <= x {
            j += 1;
        }
        d = d.max((i as f64 / n1 as f64 - j as f64 / n2 as f64).abs());
    }
    // Effective size and Stephens' small-sample correction of the statistic (Press et al.,
    // Numerical Recipes, 3rd ed., §14.3.3, eq. 14.3.18).
    let ne = (n1 * n2) as f64 / (n1 + n2) as f64;
    let lambda = (ne.sqrt() + 0.12 + 0.11 / ne.sqrt()) * d;
    KsTest {
        d,
        p_value: kolmogorov_q(lambda),
        n1,
        n2,
    }
}

/// Q_KS(λ) = 2 Σ_{k≥1} (−1)^{k−1} exp(−2k²λ²), the Kolmogorov tail (1 at λ = 0).
fn kolmogorov_q(lambda: f64) -> f64 {
    if lambda < 0.2 {
        return 1.0;
    }
    let mut sum = 0.0;
    for k in 1..=100 {
        let term = (-2.0 * (k * k) as f64 * lambda * lambda).exp();
        sum += if k % 2 == 1 { term } else { -term };
        if term < 1e-16 {
            break;
        }
    }
    (2.0 * sum).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_of_known_samples() {
        // Identical samples: 0; disjoint ones: 1; {1, 2, 3, 4} against {3, 4, 5, 6}: the
        // empirical functions differ by 1/2 between 2 and 3.
        assert_eq!(two_sample_ks(&[1.0, 2.0, 3.0], &[1.0, 2.0, 3.0]).d, 0.0);
        assert_eq!(two_sample_ks(&[1.0, 2.0], &[3.0, 4.0, 5.0]).d, 1.0);
        assert_eq!(
            two_sample_ks(&[1.0, 2.0, 3.0, 4.0], &[3.0, 4.0, 5.0, 6.0]).d,
            0.5
        );
    }

    #[test]
    fn kolmogorov_tail_at_its_tabulated_critical_values() {
        // The 5 % and 1 % critical values of the Kolmogorov distribution, 1.358 and 1.628.
        assert!((kolmogorov_q(1.358) - 0.05).abs() < 5e-4);
        assert!((kolmogorov_q(1.628) - 0.01).abs() < 2e-4);
        assert_eq!(kolmogorov_q(0.0), 1.0);
    }
}
