//! Keyword values checked at the boundary, so every bad value is a `ValueError` that names the
//! keyword the user typed (`n=-3: …`), and the library's sentences, written for the command
//! line's flags, read with the keywords' names (`--box has 2 lengths` → `box= has 2 lengths`).

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyString};

use crate::errors::value_err;

/// An integer keyword of at least `min` (`n`, `seed`, `seeds`, `max_steps`, `jobs`, …).
/// ValueError for a bool, a non-integer or a value below `min`.
pub fn count(value: &Bound<'_, PyAny>, name: &str, min: u64) -> PyResult<u64> {
    let type_name = value.get_type().name()?.to_string();
    // Whole numbers are what `operator.index` takes (int, NumPy integers); a bool is not one.
    let whole = if value.is_instance_of::<PyBool>() {
        None
    } else {
        value
            .call_method0("__index__")
            .ok()
            .and_then(|i| i.extract::<i128>().ok())
    };
    let Some(v) = whole else {
        return Err(value_err(format!(
            "{name}={}: {name} must be a whole number, not {type_name}",
            value.repr()?
        )));
    };
    if v < i128::from(min) || v > i128::from(u64::MAX) {
        return Err(value_err(format!(
            "{name}={v}: {name} must be a whole number of at least {min}"
        )));
    }
    Ok(v as u64)
}

/// A real-number keyword (`phi`, …): ValueError naming it for anything `float()` refuses.
pub fn number(value: &Bound<'_, PyAny>, name: &str) -> PyResult<f64> {
    if value.is_instance_of::<PyString>() || value.is_instance_of::<PyBool>() {
        return Err(value_err(format!(
            "{name}={}: {name} must be a number",
            value.repr()?
        )));
    }
    value.extract::<f64>().map_err(|_| {
        value_err(format!(
            "{name}={}: {name} must be a number",
            value.repr().map(|r| r.to_string()).unwrap_or_default()
        ))
    })
}

/// [`number`] of an optional keyword.
pub fn opt_number(value: Option<&Bound<'_, PyAny>>, name: &str) -> PyResult<Option<f64>> {
    value.map(|v| number(v, name)).transpose()
}

/// [`count`] of an optional keyword.
pub fn opt_count(value: Option<&Bound<'_, PyAny>>, name: &str, min: u64) -> PyResult<Option<u64>> {
    value.map(|v| count(v, name, min)).transpose()
}

/// A string keyword (`dist`, `placement`, …): ValueError naming it for anything else, with
/// `hint` after the sentence.
pub fn text(value: &Bound<'_, PyAny>, name: &str, hint: &str) -> PyResult<String> {
    if value.is_instance_of::<PyString>() {
        return value.extract();
    }
    Err(value_err(format!(
        "{name} must be a name (a string), not {}{hint}",
        value.get_type().name()?
    )))
}

/// [`text`] of an optional keyword.
pub fn opt_text(
    value: Option<&Bound<'_, PyAny>>,
    name: &str,
    hint: &str,
) -> PyResult<Option<String>> {
    value.map(|v| text(v, name, hint)).transpose()
}

/// The command line's flags and the keywords that stand for them in Python.
const FLAGS: [(&str, &str); 45] = [
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
