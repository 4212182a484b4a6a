//! The coordinates held at zero in each LP, one per rigid motion of the container.

use packbench_core::Shape;

use crate::growth::Growth;

/// Coordinates (indices into s) held at zero in an LP, one for each rigid motion of the
/// container, so that no direction of the LP is free. Along a free direction the interior
/// point stops at the centre of the optimal face, not at zero: the packing would drift LP after
/// LP, never meeting `tol_s`, and a rotation along a curved wall would let [`curved_wall_gamma`]
/// shrink it. Translations: the periodic coordinates of `anchor`. Rotations of a ball over t
/// axes (or of a cylindrical shell, t = 2) in the planes (k, l), k < l < t: a rotation by ω
/// moves coordinate l of a particle at p by ω p_k, so coordinates l > k of the non-rattler
/// farthest from the centre along k are held.
pub(super) fn held_coordinates(g: &Growth, anchor: usize, rattler: Option<&[bool]>) -> Vec<usize> {
    let d = g.d;
    let mut held: Vec<usize> = (0..d)
        .filter(|&k| g.container.periodic[k])
        .map(|k| anchor * d + k)
        .collect();
    let axes = match g.container.shape {
        Shape::Ball { axes } => axes,
        Shape::CylindricalShell { .. } => 2,
        _ => 0,
    };
    let centre = 0.5 * g.container.lengths[0];
    for k in 0..axes.saturating_sub(1) {
        let far = (0..g.n)
            .filter(|&i| rattler.is_none_or(|r| !r[i]))
            .max_by(|&i, &j| {
                let off = |p: usize| (g.x[p * d + k] - centre).abs();
                off(i).total_cmp(&off(j))
            });
        if let Some(a) = far {
            held.extend((k + 1..axes).map(|l| a * d + l));
        }
    }
    held.sort_unstable();
    held.dedup();
    held
}
