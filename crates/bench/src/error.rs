//! The binary's two kinds of failure: bad input (exit 2) and a run that failed (exit 1).

use packbench_core::CoreError;

/// An error of a packbench command.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// The user's input is wrong: flags, files, scenes. Exit code 2.
    #[error("{0}")]
    Usage(String),
    /// The input was fine but the run failed. Exit code 1.
    #[error("{0}")]
    Run(String),
}

impl BenchError {
    /// Process exit code.
    pub fn exit_code(&self) -> i32 {
        match self {
            BenchError::Usage(_) => 2,
            BenchError::Run(_) => 1,
        }
    }
}

impl From<CoreError> for BenchError {
    fn from(e: CoreError) -> Self {
        match e {
            CoreError::Io { .. } | CoreError::Solver(_) => BenchError::Run(e.to_string()),
            _ => BenchError::Usage(e.to_string()),
        }
    }
}

/// Shorthand for a usage error.
pub fn usage(msg: impl Into<String>) -> BenchError {
    BenchError::Usage(msg.into())
}
