//! Curved walls (ball, cylinder, cylindrical shell) in CALiPPSO's LPs: the cap on Γ from
//! the exact wall distances after a step.

use packbench_core::Shape;

use crate::growth::Growth;

/// The largest Γ the curved wall of the container allows at the current positions,
/// `min_i (h_i/ρ_i)²` with `h_i` the exact distance of particle i to its nearest wall and `ρ_i`
/// its radius before inflation; `+∞` for a box, whose flat walls the LP's rows describe exactly.
///
/// The LP's wall row is the tangent plane at the particle's projection on the wall. The inside
/// of a ball or cylinder curves towards the particle, so a step `s` along the wall brings it
/// closer by up to `|s_⊥|²/(2|p|)` than the row says (|p| the distance from the axis), and the
/// LP's Γ may overlap the wall; capping Γ here keeps every update overlap-free. At convergence
/// `s → 0` and the cap meets the LP's Γ.
pub(super) fn curved_wall_gamma(g: &Growth) -> f64 {
    if matches!(g.container.shape, Shape::Box) {
        return f64::INFINITY;
    }
    let d = g.d;
    (0..g.n)
        .map(|i| {
            let h = g.container.wall_clearance(&g.x[i * d..(i + 1) * d]);
            let rho = 0.5 * g.diameters[i] * g.t;
            let ratio = (h / rho).max(0.0);
            ratio * ratio
        })
        .fold(f64::INFINITY, f64::min)
}
