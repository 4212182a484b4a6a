//! Collisions of a growing sphere with a flat hard wall.
//!
//! The distance from the sphere's surface to the wall is `h(t) = h + u t` with `h` the centre's
//! distance minus the radius and `u` the centre's speed away from the wall minus the radius'
//! growth speed; contact is `h(t) = 0`.

/// Time until the surface reaches the wall, or `None` if it moves away. A surface already
/// touching or through the wall by rounding collides now if it still approaches.
#[inline]
pub(crate) fn collision_time(h: f64, u: f64) -> Option<f64> {
    if u >= 0.0 {
        None
    } else if h <= 0.0 {
        Some(0.0)
    } else {
        Some(h / -u)
    }
}

/// Change of the velocity component along the wall's outward normal for a unit-mass sphere
/// hitting it with normal speed `vn` (towards the wall, > 0 when approaching) while its radius
/// grows at `g_radius`: elastic in the frame of the moving surface, `vn' = −vn − 2 g_radius`,
/// with the same minimum as pair collisions (`crate::event::collision::impulse`). Returns the
/// magnitude of the momentum change, to be applied against the outward normal.
#[inline]
pub(crate) fn impulse(vn: f64, g_radius: f64, min_impulse: f64) -> f64 {
    2.0 * (vn + g_radius).max(min_impulse)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wall_contact_times_and_reflection() {
        assert_eq!(collision_time(0.5, -0.25), Some(2.0));
        assert_eq!(collision_time(0.5, 0.25), None);
        assert_eq!(collision_time(-1e-17, -0.25), Some(0.0));
        // Resting sphere, growing radius: leaves at twice the growth speed relative to the wall.
        let dp = impulse(0.0, 0.1, 0.0);
        assert!((dp - 0.2).abs() < 1e-15);
    }
}
