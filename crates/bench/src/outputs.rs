//! Reading packings the way every subcommand does, and writing a packing with its sidecar.

use std::io::Read;
use std::path::{Path, PathBuf};

use packbench_core::format::{Sidecar, read_packing, write_atomic, write_text};
use packbench_core::{Container, Packing};

use crate::args::ContainerArgs;
use crate::error::{BenchError, usage};

/// Reads `file` (`-` for standard input). The container comes from the flags when any is
/// given, else from the sidecar `<stem>.json` beside the file, else a periodic unit box.
pub fn read_input(file: &str, flags: &ContainerArgs) -> Result<Packing, BenchError> {
    let text = if file == "-" {
        let mut s = String::new();
        std::io::stdin()
            .read_to_string(&mut s)
            .map_err(|e| BenchError::Run(format!("reading standard input: {e}")))?;
        s
    } else {
        std::fs::read_to_string(file).map_err(|e| usage(format!("cannot read {file}: {e}")))?
    };
    let data =
        packbench_core::format::parse_text(if file == "-" { "<stdin>" } else { file }, &text)?;
    let container = if !flags.is_empty() || flags.fix_height {
        flags.container(data.dim)?
    } else if let Some(c) = sidecar_container(file) {
        c
    } else {
        Container::periodic_box(&vec![1.0; data.dim])?
    };
    Ok(read_packing(
        if file == "-" { "<stdin>" } else { file },
        &text,
        &container,
    )?)
}

/// The sidecar path of an output: `out.txt` → `out.json`.
pub fn sidecar_path(packing_path: &Path) -> PathBuf {
    packing_path.with_extension("json")
}

fn sidecar_container(file: &str) -> Option<Container> {
    if file == "-" {
        return None;
    }
    let text = std::fs::read_to_string(sidecar_path(Path::new(file))).ok()?;
    let s: Sidecar = serde_json::from_str(&text).ok()?;
    Some(s.container)
}

/// `--output NAME` → `NAME.txt` (RCPGenerator appends .txt unless it is there).
pub fn output_path(name: &str) -> PathBuf {
    if name.ends_with(".txt") {
        PathBuf::from(name)
    } else {
        PathBuf::from(format!("{name}.txt"))
    }
}

/// Writes `packing` as plain text to `path` and `sidecar` beside it, both atomically.
pub fn write_packing(path: &Path, packing: &Packing, sidecar: &Sidecar) -> Result<(), BenchError> {
    write_atomic(path, write_text(packing).as_bytes())?;
    let json = serde_json::to_string_pretty(sidecar).map_err(|e| BenchError::Run(e.to_string()))?;
    write_atomic(&sidecar_path(path), json.as_bytes())?;
    Ok(())
}
