//! A particle reaching the surface of its bounding sphere (Donev, Torquato & Stillinger 2005,
//! "Neighbor list collision-driven molecular dynamics simulation for nonspherical hard
//! particles", §IV): the event that renews its neighbour list.
//!
//! Each particle `i` has a bounding sphere of fixed radius `R_i` centred where the particle was
//! when its neighbour list was built; two particles can only touch while their bounding spheres
//! overlap, so as long as every particle (its growing surface included) stays inside its
//! bounding sphere, only neighbour-list partners need to be predicted.

/// Time until a particle whose centre is `offset` from its bounding sphere's centre, moving at
/// `speed`, with radius `radius` growing at `radius_growth`, may touch the bounding sphere of
/// radius `bound` from inside. Conservative (the centre is assumed to move straight away from
/// the bounding centre, `|s + v t| ≤ |s| + |v| t`), so the true exit is never earlier; 0 when
/// rounding already put the particle on or past the surface; ∞ when nothing moves or grows.
#[inline]
pub(crate) fn exit_time(
    offset: f64,
    speed: f64,
    radius: f64,
    radius_growth: f64,
    bound: f64,
) -> f64 {
    let room = bound - radius - offset;
    let closing = speed + radius_growth;
    if room <= 0.0 {
        0.0
    } else if closing > 0.0 {
        room / closing
    } else {
        f64::INFINITY
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exit_is_conservative_and_never_negative() {
        // Straight out from the centre: exact.
        assert_eq!(exit_time(0.0, 1.0, 0.5, 0.0, 0.75), 0.25);
        // Growth alone fills the room.
        assert_eq!(exit_time(0.0, 0.0, 0.5, 0.5, 0.75), 0.5);
        assert_eq!(exit_time(0.3, 1.0, 0.5, 0.0, 0.75), 0.0);
        assert_eq!(exit_time(0.1, 0.0, 0.5, 0.0, 0.75), f64::INFINITY);
    }
}
