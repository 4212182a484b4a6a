//! Projection of bonded pairs back onto exact contact.
//!
//! Straight steps keep bonds in contact only to first order; a Newton–chord iteration with the
//! minimum-norm correction `δx = A⁺(−g)` (g: bond gaps) restores them. At jamming the bonds are
//! dependent and `A δx = −g` has no solution in general; the growth factor then moves too:
//! with the forces f (`Aᵀf = 0`), `δt = fᵀg / fᵀD` makes `A δx = −g + D δt` solvable, so every
//! bond of the jammed network touches exactly.

use crate::contacts::{Key, Link};
use crate::error::JammingError;
use crate::growth::Growth;
use crate::min_norm::MinNorm;

/// Projects the bonds `basis` onto contact using the factorisation `mn` of the rows `links`
/// (the basis evaluated before projecting). `jam = Some((key, forces))` adds the dependent
/// bond `key` and lets `t` move, with `forces` over `basis` then `key`. Returns the largest
/// remaining relative gap.
///
/// # Errors
/// [`JammingError::Solver`] when the iteration diverges (a degenerate bond network).
pub(crate) fn project(
    g: &mut Growth,
    basis: &[Key],
    links: &[Link],
    mn: &MinNorm,
    jam: Option<(&Key, &[f64])>,
    tol: f64,
) -> Result<f64, JammingError> {
    let (n, d) = (g.n, g.d);
    let mut worst = f64::INFINITY;
    let mut first = f64::NAN;
    for _ in 0..12 {
        let now = g.links(basis);
        let mut gaps: Vec<f64> = now.iter().map(|l| l.gap(g.t)).collect();
        let mut sizes: Vec<f64> = now.iter().map(|l| l.size).collect();
        if let Some((key, _)) = jam {
            let lk = g.link(key);
            gaps.push(lk.gap(g.t));
            sizes.push(lk.size);
        }
        worst = gaps
            .iter()
            .zip(&sizes)
            .map(|(gap, s)| gap.abs() / (s * g.t))
            .fold(0.0, f64::max);
        if worst <= tol {
            break;
        }
        if first.is_nan() {
            first = worst;
        } else if !(worst <= 10.0 * first.max(1e-8)) {
            return Err(JammingError::Solver(format!(
                "projecting the bonds onto contact diverged (relative gap {worst:.3e}); the bond network is degenerate"
            )));
        }
        let dt = match jam {
            Some((_, f)) => {
                let fg: f64 = f.iter().zip(&gaps).map(|(a, b)| a * b).sum();
                let fs: f64 = f.iter().zip(&sizes).map(|(a, b)| a * b).sum();
                fg / fs
            }
            None => 0.0,
        };
        let rhs: Vec<f64> = (0..now.len()).map(|k| -gaps[k] + sizes[k] * dt).collect();
        let dx = mn.solve(links, &rhs, n, d);
        g.displace(&dx);
        g.t += dt;
    }
    Ok(worst)
}
