//! Small geometric helpers shared by containers, initialisation and analysis.

/// Volume of the unit ball in `d` dimensions: V_d = π^{d/2} / Γ(d/2 + 1), by the recursion
/// V_d = 2π/d · V_{d−2} with V_0 = 1, V_1 = 2 (exact for every d, no Gamma function needed).
pub fn unit_ball_volume(d: usize) -> f64 {
    match d {
        0 => 1.0,
        1 => 2.0,
        _ => 2.0 * std::f64::consts::PI / d as f64 * unit_ball_volume(d - 2),
    }
}

/// Volume of a `d`-ball of diameter `diameter`.
pub fn ball_volume(d: usize, diameter: f64) -> f64 {
    unit_ball_volume(d) * (0.5 * diameter).powi(d as i32)
}

/// Squared Euclidean norm.
#[inline]
pub fn norm2(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn unit_balls() {
        use std::f64::consts::PI;
        assert!((unit_ball_volume(2) - PI).abs() < 1e-15);
        assert!((unit_ball_volume(3) - 4.0 / 3.0 * PI).abs() < 1e-15);
        assert!((unit_ball_volume(4) - PI * PI / 2.0).abs() < 1e-14);
        assert!((unit_ball_volume(8) - PI.powi(4) / 24.0).abs() < 1e-13);
    }
}
