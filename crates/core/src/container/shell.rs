//! A cylindrical shell over axes 0 and 1 (Particle Assembler): inner and outer coaxial walls.

use super::{Container, Wall};
use crate::error::CoreError;

pub(super) fn validate(c: &Container, inner: f64, outer: f64) -> Result<(), CoreError> {
    if c.dim() < 3 {
        return Err(CoreError::Container(
            "a cylindrical shell needs d ≥ 3".into(),
        ));
    }
    if !(inner >= 0.0 && outer > inner && outer.is_finite()) {
        return Err(CoreError::Container(format!(
            "cylindrical shell radii inner {inner}, outer {outer} must satisfy 0 ≤ inner < outer"
        )));
    }
    if c.periodic[0]
        || c.periodic[1]
        || (c.lengths[0] - 2.0 * outer).abs() > 1e-12 * outer
        || (c.lengths[1] - 2.0 * outer).abs() > 1e-12 * outer
    {
        return Err(CoreError::Container(
            "the first two axes of a cylindrical shell must be non-periodic with length 2·outer"
                .into(),
        ));
    }
    Ok(())
}

/// π(R_o² − R_i²) × Π_{k≥2} L_k.
pub(super) fn volume(c: &Container, inner: f64, outer: f64) -> f64 {
    std::f64::consts::PI * (outer * outer - inner * inner) * c.lengths[2..].iter().product::<f64>()
}

pub(super) fn walls(
    c: &Container,
    inner: f64,
    outer: f64,
    x: &[f64],
    reach: f64,
    normal: &mut [f64],
    f: &mut impl FnMut(Wall<'_>),
) {
    let d = c.dim();
    let (ux, uy) = (x[0] - outer, x[1] - outer);
    let rho = ux.hypot(uy);
    let (ex, ey) = if rho > 0.0 {
        (ux / rho, uy / rho)
    } else {
        (1.0, 0.0)
    };
    normal[2..d].fill(0.0);
    if outer - rho < reach {
        normal[0] = ex;
        normal[1] = ey;
        f(Wall {
            id: 2 * d,
            distance: outer - rho,
            normal: &normal[..d],
        });
    }
    if inner > 0.0 && rho - inner < reach {
        normal[0] = -ex;
        normal[1] = -ey;
        f(Wall {
            id: 2 * d + 1,
            distance: rho - inner,
            normal: &normal[..d],
        });
    }
}
