//! A (hyper)sphere wall over the first `t` axes, centred in the box (RCPGenerator `--walls -t`).

use super::{Container, Wall};
use crate::error::CoreError;
use crate::geometry::unit_ball_volume;

pub(super) fn validate(c: &Container, t: usize) -> Result<(), CoreError> {
    let d = c.dim();
    if t < 2 || t > d {
        return Err(CoreError::Container(format!(
            "a ball over {t} axes needs 2 ≤ t ≤ d = {d}"
        )));
    }
    if (0..t).any(|k| c.periodic[k] || (c.lengths[k] - c.lengths[0]).abs() > 1e-12 * c.lengths[0]) {
        return Err(CoreError::Container(
            "the axes of a ball must be non-periodic and share the ball's diameter".into(),
        ));
    }
    Ok(())
}

/// V_t(R) × Π_{k≥t} L_k.
pub(super) fn volume(c: &Container, t: usize) -> f64 {
    let r = 0.5 * c.lengths[0];
    unit_ball_volume(t) * r.powi(t as i32) * c.lengths[t..].iter().product::<f64>()
}

pub(super) fn walls(
    c: &Container,
    t: usize,
    x: &[f64],
    reach: f64,
    normal: &mut [f64],
    f: &mut impl FnMut(Wall<'_>),
) {
    let d = c.dim();
    let r = 0.5 * c.lengths[0];
    let mut rho2 = 0.0;
    for k in 0..t {
        let u = x[k] - r;
        normal[k] = u;
        rho2 += u * u;
    }
    let rho = rho2.sqrt();
    let dist = r - rho;
    if dist < reach {
        normal[t..d].fill(0.0);
        if rho > 0.0 {
            for n in &mut normal[..t] {
                *n /= rho;
            }
        } else {
            // At the exact centre every direction is equally far; pick the first axis.
            normal[..t].fill(0.0);
            normal[0] = 1.0;
        }
        f(Wall {
            id: 2 * d,
            distance: dist,
            normal: &normal[..d],
        });
    }
}
