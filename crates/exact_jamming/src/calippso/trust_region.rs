//! The trust-region bound on the displacements (`bound_schedule = trust-region`): the LP's
//! model agreement with the exact distances, and the bound's update.

use crate::growth::Growth;

use super::curved_walls::curved_wall_gamma;
use super::lp::LpStep;

/// Agreement of the LP's linear model with the exact non-overlap at the new positions: with
/// `p = √Γ_LP − 1` (what the LP promised) and `a = √Γ_exact − 1` (the largest inflation the
/// exact distances of the LP's pairs and walls allow after the step), `min(p, a)/max(p, a)`,
/// 1 when they agree. The linearisation drops `|s_j − s_i|²`, so `a ≥ p` for pairs and flat
/// walls: a step long against the gaps it closes makes `a ≫ p`. A curved wall can make
/// `a < p`. Called after `g.x` has moved and before `g.t` has grown.
pub(super) fn model_agreement(g: &Growth, step: &LpStep) -> f64 {
    let exact = step
        .keys
        .iter()
        .map(|k| {
            // Pairs: |r|² ≥ Γσ²; walls: h ≥ √Γ ρ (the row's ρ(1 + Γ)/2, exactly).
            let l = g.link(k);
            let ratio = (l.dist / (l.size * g.t)).max(0.0);
            ratio * ratio
        })
        .fold(curved_wall_gamma(g), f64::min);
    let p = (1.0 + step.g).max(0.0).sqrt() - 1.0;
    let a = exact.sqrt() - 1.0;
    let (lo, hi) = (p.min(a), p.max(a));
    if hi <= 0.0 { 1.0 } else { (lo / hi).max(0.0) }
}

/// The trust region's next bound (mean radii) after an LP with bound `bound`, model agreement
/// `agreement` and largest non-rattler displacement `s_over_bound` times the bound.
pub(super) fn trust_update(bound: f64, agreement: f64, s_over_bound: f64) -> f64 {
    if agreement < 0.25 {
        (0.5 * bound).max(TRUST_MIN)
    } else if agreement > 0.75 && s_over_bound >= 0.99 {
        2.0 * bound
    } else {
        bound
    }
}

/// The smallest trust-region bound, in mean radii.
pub(super) const TRUST_MIN: f64 = 1e-6;
