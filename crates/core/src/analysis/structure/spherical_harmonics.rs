//! Spherical harmonics Y_lm(θ, φ) for m ≥ 0 from the normalised associated Legendre functions,
//! by the stable three-term recurrence in l (Press et al., Numerical Recipes 3rd ed., §6.7,
//! eqns 6.7.9–6.7.10).
//!
//! Convention: Y_lm(θ, φ) = P̄_l^m(cos θ) e^{imφ} with P̄_l^m = √((2l+1)/(4π) (l−m)!/(l+m)!) P_l^m
//! and the Condon–Shortley phase (−1)^m inside P_l^m. Negative m follow from
//! Y_l,−m = (−1)^m conj(Y_lm); bond-order parameters only need |q_lm|², so callers use m ≥ 0.

use std::f64::consts::PI;

/// Normalised associated Legendre function P̄_l^m(x) for `0 ≤ m ≤ l`, `x` in [−1, 1].
pub fn normalised_legendre(l: usize, m: usize, x: f64) -> f64 {
    debug_assert!(m <= l);
    // P̄_m^m = (−1)^m √((2m+1)/(4π) · (2m−1)!!/(2m)!!) (1−x²)^{m/2}, built as a running product
    // so no factorial overflows.
    let one_minus_x2 = ((1.0 - x) * (1.0 + x)).max(0.0);
    let mut pmm = 1.0;
    let mut odd = 1.0;
    for _ in 0..m {
        pmm *= one_minus_x2 * odd / (odd + 1.0);
        odd += 2.0;
    }
    let mut pmm = ((2 * m + 1) as f64 * pmm / (4.0 * PI)).sqrt();
    if m % 2 == 1 {
        pmm = -pmm;
    }
    if l == m {
        return pmm;
    }
    // P̄_{m+1}^m = x √(2m+3) P̄_m^m.
    let mut pmmp1 = x * ((2 * m + 3) as f64).sqrt() * pmm;
    if l == m + 1 {
        return pmmp1;
    }
    // P̄_l^m = √((4l²−1)/(l²−m²)) (x P̄_{l−1}^m − √(((l−1)²−m²)/(4(l−1)²−1)) P̄_{l−2}^m).
    let mm = (m * m) as f64;
    let mut old_factor = ((2 * m + 3) as f64).sqrt();
    let mut pll = 0.0;
    for ll in m + 2..=l {
        let l2 = (ll * ll) as f64;
        let factor = ((4.0 * l2 - 1.0) / (l2 - mm)).sqrt();
        pll = factor * (x * pmmp1 - pmm / old_factor);
        old_factor = factor;
        pmm = pmmp1;
        pmmp1 = pll;
    }
    pll
}

/// Y_lm of the unit vector `u` (3 components) for m = 0..=l, as (re, im) pairs.
pub fn spherical_harmonics(l: usize, u: [f64; 3], out: &mut [(f64, f64)]) {
    let cos_theta = u[2].clamp(-1.0, 1.0);
    let phi = u[1].atan2(u[0]);
    for (m, y) in out.iter_mut().enumerate().take(l + 1) {
        let p = normalised_legendre(l, m, cos_theta);
        let (s, c) = (m as f64 * phi).sin_cos();
        *y = (p * c, p * s);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12 * (1.0 + b.abs())
    }

    #[test]
    fn closed_forms_of_low_orders() {
        for &x in &[-1.0, -0.7, -0.2, 0.0, 0.3, 0.9, 1.0] {
            let s2: f64 = 1.0 - x * x;
            assert!(close(
                normalised_legendre(0, 0, x),
                (1.0 / (4.0 * PI)).sqrt()
            ));
            assert!(close(
                normalised_legendre(1, 0, x),
                (3.0 / (4.0 * PI)).sqrt() * x
            ));
            // Y_11 = −½√(3/(2π)) sin θ e^{iφ}.
            assert!(close(
                normalised_legendre(1, 1, x),
                -0.5 * (3.0 / (2.0 * PI)).sqrt() * s2.sqrt()
            ));
            // Y_22 = ¼√(15/(2π)) sin²θ e^{2iφ}.
            assert!(close(
                normalised_legendre(2, 2, x),
                0.25 * (15.0 / (2.0 * PI)).sqrt() * s2
            ));
            // Y_60 = √(13/(4π)) (231x⁶ − 315x⁴ + 105x² − 5)/16.
            let p6 = (231.0 * x.powi(6) - 315.0 * x.powi(4) + 105.0 * x * x - 5.0) / 16.0;
            assert!(close(
                normalised_legendre(6, 0, x),
                (13.0 / (4.0 * PI)).sqrt() * p6
            ));
            // Y_44 = (3/16)√(35/(2π)) sin⁴θ e^{4iφ}.
            assert!(close(
                normalised_legendre(4, 4, x),
                3.0 / 16.0 * (35.0 / (2.0 * PI)).sqrt() * s2 * s2
            ));
        }
    }

    #[test]
    fn addition_theorem_sums_to_2l_plus_1_over_4pi() {
        // Σ_m |Y_lm|² = (2l+1)/(4π) for every direction (m < 0 mirrors m > 0).
        let mut y = vec![(0.0, 0.0); 13];
        for l in [2usize, 4, 6, 8, 12] {
            for &(a, b) in &[(0.3f64, 1.1f64), (2.9, -0.4), (1.2, 3.0)] {
                let u = [a.sin() * b.cos(), a.sin() * b.sin(), f64::cos(a)];
                spherical_harmonics(l, u, &mut y);
                let sum: f64 = y[0].0 * y[0].0
                    + 2.0 * y[1..=l].iter().map(|(r, i)| r * r + i * i).sum::<f64>();
                assert!(
                    close(sum, (2 * l + 1) as f64 / (4.0 * PI)),
                    "l = {l}: {sum}"
                );
            }
        }
    }
}
