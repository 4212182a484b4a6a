//! The crate's error type: every message is one sentence naming what was wrong.

use packbench_core::CoreError;
use thiserror::Error;

/// Errors of a sequential fill: bad parameters, a brick the corner spheres do not fit, a
/// domain too large to hold in memory, and I/O failures of the writers.
#[derive(Debug, Error)]
pub enum SeqFillError {
    /// A parameter is out of range; the message names it and its allowed range.
    #[error("invalid seq-fill parameter: {0}")]
    Parameter(String),
    /// The size distribution or the container was refused by the core.
    #[error(transparent)]
    Core(#[from] CoreError),
    /// Writing a contact list or face lists failed.
    #[error("{context}: {source}")]
    Io {
        /// What was being written.
        context: String,
        /// The underlying failure.
        #[source]
        source: std::io::Error,
    },
}

impl packbench_core::run::MethodError for SeqFillError {
    fn is_input_error(&self) -> bool {
        match self {
            SeqFillError::Parameter(_) => true,
            SeqFillError::Core(e) => packbench_core::run::MethodError::is_input_error(e),
            SeqFillError::Io { .. } => false,
        }
    }
}
