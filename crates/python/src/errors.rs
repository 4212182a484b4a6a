//! Rust errors as Python exceptions, with the sentences the command line prints, its flags
//! read as the keywords that stand for them (`box=` for `--box`): bad input (the binary's exit
//! code 2) is `ValueError`, a failed run (exit code 1) is `RuntimeError`.

use packbench::error::BenchError;
use packbench_core::CoreError;
use pyo3::PyErr;
use pyo3::exceptions::{PyRuntimeError, PyValueError};

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

/// The command line's flags and the keywords that stand for them in Python.
const FLAGS: [(&str, &str); 48] = [
    ("--box", "box="),
    ("--walls", "walls="),
    ("--fix-height", "fix_height="),
    ("--shell", "shell="),
    ("--hemispheres", "hemispheres="),
    ("--Ndim", "dim="),
    ("--N", "n="),
    ("--phi", "phi="),
    ("--dist", "dist="),
    ("--d", "d="),
    ("--D", "d="),
    ("--d1", "d1="),
    ("--d2", "d2="),
    ("--p", "p="),
    ("--mu", "mu="),
    ("--sigma", "sigma="),
    ("--mu1", "mu1="),
    ("--sigma1", "sigma1="),
    ("--mu2", "mu2="),
    ("--sigma2", "sigma2="),
    ("--d_min", "d_min="),
    ("--d_max", "d_max="),
    ("--exponent", "exponent="),
    ("--scale", "scale="),
    ("--shape", "shape="),
    ("--custom_list", "custom_list="),
    ("--placement", "placement="),
    ("--seed", "seed="),
    ("--seeds", "seeds="),
    ("--max-steps", "max_steps="),
    ("--refine", "refine="),
    ("--methods", "methods="),
    ("--jobs", "jobs="),
    ("--fix_height", "fix_height="),
    ("--objective", "objective="),
    ("--target", "target="),
    ("--budget", "budget="),
    ("--population", "population="),
    ("--seeds-per-candidate", "seeds_per_candidate="),
    ("--screen-margin", "screen_margin="),
    ("--components", "components="),
    ("--max-ratio", "max_ratio="),
    ("--confirm", "confirm="),
    ("--fractions", "fractions="),
    ("--draw", "draw="),
    ("--optimizer", "optimizer="),
    ("--param", "bounds="),
    ("--set", "params="),
];

/// `message` with every command-line flag replaced by its keyword (`--dist bidisperse needs
/// --d1` → `dist="bidisperse" needs d1=`); words that are not flags are kept.
pub fn keyword_sentence(message: &str) -> String {
    let mut out = String::with_capacity(message.len());
    let mut rest = message;
    while let Some(at) = rest.find("--") {
        out.push_str(&rest[..at]);
        let tail = &rest[at..];
        let end = tail[2..]
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '-'))
            .map_or(tail.len(), |e| e + 2);
        let flag = &tail[..end];
        match FLAGS.iter().find(|(f, _)| *f == flag) {
            Some((_, keyword)) => {
                out.push_str(keyword);
                rest = &tail[end..];
                // A flag's value right after it (`--dist bidisperse`, `--Ndim 1:`) joins it.
                if keyword.ends_with('=')
                    && let Some(value) = rest.strip_prefix(' ')
                {
                    let vend = value
                        .find(|c: char| c.is_whitespace() || c == ':' || c == ',')
                        .unwrap_or(value.len());
                    let word = &value[..vend];
                    if is_value(word) {
                        if word.parse::<f64>().is_ok() {
                            out.push_str(word);
                        } else {
                            out.push_str(&format!("{word:?}"));
                        }
                        rest = &value[vend..];
                    }
                }
            }
            None => {
                out.push_str(flag);
                rest = &tail[end..];
            }
        }
    }
    out.push_str(rest);
    out
}

/// True for a word that reads as a flag's value rather than the sentence going on: a
/// number, or a name the sentence does not use as a verb.
fn is_value(word: &str) -> bool {
    const VERBS: [&str; 16] = [
        "has", "needs", "must", "is", "takes", "and", "or", "the", "a", "of", "to", "with",
        "applies", "for", "given", "gives",
    ];
    !word.is_empty() && !word.starts_with('-') && !VERBS.contains(&word) && !word.starts_with('`')
}
