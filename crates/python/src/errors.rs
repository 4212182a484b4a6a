//! Rust errors as Python exceptions, with the sentences the command line prints, its flags
//! read as the keywords that stand for them (`box=` for `--box`): bad input (the binary's exit
//! code 2) is `ValueError`, a failed run (exit code 1) is `RuntimeError`.

use packbench::error::BenchError;
use packbench_core::CoreError;
use pyo3::PyErr;
use pyo3::exceptions::{PyRuntimeError, PyValueError};

use crate::keywords::keyword_sentence;

/// The Python exception of a bench error.
pub fn bench_err(e: BenchError) -> PyErr {
    match e {
        BenchError::Usage(m) => PyValueError::new_err(keyword_sentence(&m)),
        BenchError::Run(m) => PyRuntimeError::new_err(keyword_sentence(&m)),
    }
}

/// The Python exception of a core error, classified as the binary classifies it.
pub fn core_err(e: CoreError) -> PyErr {
    bench_err(BenchError::from(e))
}

/// A `ValueError` with `msg`.
pub fn value_err(msg: impl Into<String>) -> PyErr {
    PyValueError::new_err(msg.into())
}
