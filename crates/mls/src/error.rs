//! The crate's one error type.

use packbench_core::CoreError;
use thiserror::Error;

/// Why an LS or MLS run could not start. Once a run has started it always returns an
/// [`packbench_core::run::Outcome`] whose `termination` tag says how it ended.
#[derive(Debug, Error)]
pub enum MlsError {
    /// The starting packing is inconsistent (see [`packbench_core::Packing::validate`]).
    #[error(transparent)]
    Core(#[from] CoreError),
    /// The starting packing has no particles.
    #[error("the starting packing has no particles; LS and MLS need at least one sphere")]
    Empty,
    /// The dimension has no compiled event-driven kernel.
    #[error("dimension {0} is not supported by ls/mls: it must be between 2 and {max}", max = crate::MAX_DIM)]
    Dimension(usize),
    /// The container has a feature event-driven LS does not model.
    #[error("container not supported by ls/mls: {0}")]
    Container(String),
    /// A parameter is out of range.
    #[error("invalid ls/mls parameter: {0}")]
    Parameter(String),
    /// A checkpoint to resume from is incomplete or inconsistent.
    #[error("cannot resume from this checkpoint: {0}")]
    Checkpoint(String),
}

impl packbench_core::run::MethodError for MlsError {
    /// Every error of LS and MLS is found before the run starts.
    fn is_input_error(&self) -> bool {
        match self {
            MlsError::Core(e) => packbench_core::run::MethodError::is_input_error(e),
            _ => true,
        }
    }
}
