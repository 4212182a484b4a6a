//! A walled brick minus two (hyper)hemispheres centred on the faces x = 0 and x = L_0
//! (3DRSP Example 3). The hemispheres are convex obstacles: the distance to each is
//! `|x − c| − R`, and the outward normal points towards its centre.

use super::{Container, Wall};
use crate::error::CoreError;
use crate::geometry::unit_ball_volume;

pub(super) fn validate(c: &Container, radii: [f64; 2]) -> Result<(), CoreError> {
    let d = c.dim();
    let half_min = c.lengths[1..]
        .iter()
        .fold(f64::INFINITY, |m, &l| m.min(0.5 * l));
    if radii
        .iter()
        .any(|&r| !(r.is_finite() && r >= 0.0 && r <= half_min))
    {
        return Err(CoreError::Container(format!(
            "hemisphere radii {radii:?} must lie in [0, {half_min}] (half the smallest side across x)"
        )));
    }
    if radii[0] + radii[1] > c.lengths[0] {
        return Err(CoreError::Container(format!(
            "hemisphere radii {radii:?} add up to more than the brick length {} along x",
            c.lengths[0]
        )));
    }
    if c.periodic.iter().any(|&p| p) || d < 2 {
        return Err(CoreError::Container(
            "a hemisphere-cut brick has walls on every axis".into(),
        ));
    }
    Ok(())
}

/// Brick volume minus two half balls.
pub(super) fn volume(c: &Container, radii: [f64; 2]) -> f64 {
    let d = c.dim();
    let half_ball = |r: f64| 0.5 * unit_ball_volume(d) * r.powi(d as i32);
    c.lengths.iter().product::<f64>() - half_ball(radii[0]) - half_ball(radii[1])
}

pub(super) fn walls(
    c: &Container,
    radii: [f64; 2],
    x: &[f64],
    reach: f64,
    normal: &mut [f64],
    f: &mut impl FnMut(Wall<'_>),
) {
    let d = c.dim();
    for (side, &r) in radii.iter().enumerate() {
        if r <= 0.0 {
            continue;
        }
        let cx = if side == 0 { 0.0 } else { c.lengths[0] };
        let mut dist2 = 0.0;
        for k in 0..d {
            let centre = if k == 0 { cx } else { 0.5 * c.lengths[k] };
            normal[k] = centre - x[k];
            dist2 += normal[k] * normal[k];
        }
        let dist = dist2.sqrt();
        if dist - r < reach {
            if dist > 0.0 {
                for n in &mut normal[..d] {
                    *n /= dist;
                }
            } else {
                normal[..d].fill(0.0);
                normal[0] = if side == 0 { -1.0 } else { 1.0 };
            }
            f(Wall {
                id: 2 * d + side,
                distance: dist - r,
                normal: &normal[..d],
            });
        }
    }
}
