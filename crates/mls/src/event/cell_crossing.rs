//! A particle leaving its cell of the event-driven cell grid.

/// Time until a particle at coordinate `x`, moving at `v` along one axis, leaves the cell
/// `[lo, hi)` through the face it moves towards, with the face it leaves through (`+1` for
/// `hi`, `−1` for `lo`). Faces are taken from the cell index, not from `x`, so a position
/// that rounding put a hair outside the cell gives time 0, never a step backwards.
#[inline]
pub(crate) fn crossing_time(x: f64, v: f64, lo: f64, hi: f64) -> Option<(f64, i8)> {
    if v > 0.0 {
        Some((((hi - x) / v).max(0.0), 1))
    } else if v < 0.0 {
        Some((((lo - x) / v).max(0.0), -1))
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossing_goes_through_the_face_ahead() {
        assert_eq!(crossing_time(0.25, 0.5, 0.0, 1.0), Some((1.5, 1)));
        assert_eq!(crossing_time(0.25, -0.5, 0.0, 1.0), Some((0.5, -1)));
        assert_eq!(crossing_time(1.0 + 1e-16, 0.5, 0.0, 1.0), Some((0.0, 1)));
        assert_eq!(crossing_time(0.5, 0.0, 0.0, 1.0), None);
    }
}
