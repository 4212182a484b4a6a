//! `packbench.set_num_threads`: the thread pool every run started from Python works in (the
//! methods' parallel loops are rayon's), instead of one thread per core.

use std::sync::{Arc, Mutex};

use pyo3::prelude::*;
use rayon::{ThreadPool, ThreadPoolBuilder};

use crate::errors::value_err;

/// The pool `set_num_threads` made, if any.
static POOL: Mutex<Option<Arc<ThreadPool>>> = Mutex::new(None);

/// Runs `job` in the pool of `set_num_threads` (rayon's global pool when none was set).
pub fn install<T: Send>(job: impl FnOnce() -> T + Send) -> T {
    let pool = POOL.lock().ok().and_then(|p| p.clone());
    match pool {
        Some(pool) => pool.install(job),
        None => job(),
    }
}

/// Sets the number of threads the methods' parallel loops use in every later call (`pack`,
/// `analyze`, `relax`; `compare` runs `jobs` runs at once, each on one thread). `None`
/// restores one thread per core. The result of a run does not depend on it (the same seed
/// gives the same bits with any thread count). Raises ValueError for n < 1.
#[pyfunction]
#[pyo3(signature = (n))]
pub fn set_num_threads(n: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
    let n = match n {
        None => None,
        Some(v) => Some(crate::keywords::count(v, "n", 1)? as usize),
    };
    let pool = match n {
        None => None,
        Some(n) => Some(Arc::new(
            ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| value_err(format!("set_num_threads: {e}")))?,
        )),
    };
    *POOL
        .lock()
        .map_err(|_| value_err("set_num_threads: the pool lock is poisoned"))? = pool;
    Ok(())
}

/// The number of threads later runs use.
#[pyfunction]
pub fn get_num_threads() -> usize {
    POOL.lock()
        .ok()
        .and_then(|p| p.as_ref().map(|p| p.current_num_threads()))
        .unwrap_or_else(rayon::current_num_threads)
}
