//! Overlap-free starting packings for the exact-jamming methods.

use packbench_core::Packing;

use crate::contacts::{Candidates, link};
use crate::error::JammingError;

/// Shrinks every diameter by one common factor so that no two particles (nor a particle and a
/// wall) overlap, leaving a relative clearance `margin` at the closest pair. A packing that is
/// already overlap-free is returned unchanged. This turns a random configuration (RCPGenerator's
/// initializer lets spheres overlap) or a Poisson configuration into a valid start.
///
/// # Errors
/// [`JammingError::InvalidPacking`] for an invalid packing, [`JammingError::Parameter`] for a
/// margin outside `[0, 1)` or coincident centres (no common shrink can separate them).
pub fn shrink_to_overlap_free(start: &Packing, margin: f64) -> Result<Packing, JammingError> {
    start.validate()?;
    if !(0.0..1.0).contains(&margin) {
        return Err(JammingError::Parameter(format!(
            "margin {margin} must lie in [0, 1)"
        )));
    }
    let cands = Candidates::build(
        &start.container,
        &start.positions,
        &start.diameters,
        1.0,
        0.0,
    );
    let ratio = cands
        .keys
        .iter()
        .map(|k| {
            let l = link(&start.container, &start.positions, &start.diameters, k);
            l.dist / l.size
        })
        .fold(f64::INFINITY, f64::min);
    let mut out = start.clone();
    if ratio >= 1.0 {
        return Ok(out);
    }
    if ratio.is_nan() || ratio <= 0.0 {
        return Err(JammingError::Parameter(
            "two particles share a centre (or one sits on a wall), so no shrink can separate them"
                .into(),
        ));
    }
    out.scale_diameters(ratio * (1.0 - margin));
    Ok(out)
}
