//! The one error type of the crate.

use thiserror::Error;

/// Why an exact-jamming run could not start or could not finish.
#[derive(Debug, Error)]
pub enum JammingError {
    /// The starting packing is inconsistent (see `Packing::validate`).
    #[error("the starting packing is invalid: {0}")]
    InvalidPacking(#[from] packbench_core::CoreError),
    /// A parameter is out of range; the message names it.
    #[error("invalid parameter: {0}")]
    Parameter(String),
    /// The starting packing already has overlapping particles, which these methods cannot undo.
    #[error(
        "particles {i} and {j} overlap by a relative {overlap:.3e} in the starting packing; exact jamming needs an overlap-free start"
    )]
    Overlap {
        /// First particle (0-based).
        i: usize,
        /// Second particle (0-based), or the first again for a wall.
        j: usize,
        /// Relative overlap `1 − r/σ`.
        overlap: f64,
    },
    /// The final packing overlaps beyond the tolerance (the checks during a run clear overlaps
    /// by shrinking the diameters instead).
    #[error(
        "particles {i} and {j} overlap by a relative {overlap:.3e} after iteration {iteration}, beyond the tolerance; tighten the solver tolerance"
    )]
    OverlapDuringRun {
        /// First particle (0-based).
        i: usize,
        /// Second particle (0-based), or the first again for a wall.
        j: usize,
        /// Relative overlap `1 − r/σ`.
        overlap: f64,
        /// Iteration (LP) after which it was found.
        iteration: u64,
    },
    /// A linear or conic solve failed in a way the method cannot recover from.
    #[error("{0}")]
    Solver(String),
}

impl packbench_core::run::MethodError for JammingError {
    fn is_input_error(&self) -> bool {
        matches!(
            self,
            JammingError::InvalidPacking(_)
                | JammingError::Parameter(_)
                | JammingError::Overlap { .. }
        )
    }
}
