//! The one error type of the core. Every message is one sentence that names what was wrong
//! and, for files, where.

use thiserror::Error;

/// Errors from building scenes and containers, sampling, reading files and analysing packings.
#[derive(Debug, Error)]
pub enum CoreError {
    /// The dimension is outside `2..=MAX_DIM`.
    #[error("dimension {0} is not supported: it must be between 2 and {max}", max = crate::MAX_DIM)]
    Dimension(usize),
    /// A container description is inconsistent (wrong number of lengths, non-positive length…).
    #[error("invalid container: {0}")]
    Container(String),
    /// A size distribution is unknown or lacks a parameter.
    #[error("invalid size distribution: {0}")]
    Distribution(String),
    /// A scene or packing parameter is out of range.
    #[error("invalid parameter: {0}")]
    Parameter(String),
    /// A packing is inconsistent (NaN, negative diameter, particle outside the container…).
    #[error("invalid packing: {0}")]
    Packing(String),
    /// A value in a file could not be used; `line` and `column` are 1-based.
    #[error("{file}:{line}:{column}: {message}")]
    Parse {
        file: String,
        line: usize,
        column: usize,
        message: String,
    },
    /// A file as a whole could not be used (empty, unreadable, wrong format).
    #[error("{file}: {message}")]
    File { file: String, message: String },
    /// An I/O failure.
    #[error("{context}: {source}")]
    Io {
        context: String,
        #[source]
        source: std::io::Error,
    },
    /// The force-balance solver failed.
    #[error("force balance: {0}")]
    Solver(String),
}

impl CoreError {
    /// Wraps an I/O error with what was being done.
    pub fn io(context: impl Into<String>, source: std::io::Error) -> Self {
        CoreError::Io {
            context: context.into(),
            source,
        }
    }
}
