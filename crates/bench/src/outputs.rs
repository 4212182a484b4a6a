//! Reading packings the way every subcommand does (a run's start too), and writing a packing
//! with its sidecar.

use std::io::Read;
use std::path::{Path, PathBuf};

use packbench_core::format::{Sidecar, read_packing, write_all_atomic, write_atomic, write_text};
use packbench_core::init::initial_packing;
use packbench_core::{Container, Packing, Scene};

use crate::records::RunRecord;

use crate::args::{ContainerArgs, SceneArgs};
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

/// The starting packing of a run and the scene it came from: the packing in `file` (`-` for
/// standard input) placed in the container flags of `scene_args`, or without a file the
/// initial packing of the scene flags drawn with `seed`, as `packbench init` draws it.
///
/// Errors: an unreadable or bad file, a bad scene, a φ the placement cannot reach.
pub fn start_packing(
    file: Option<&str>,
    scene_args: &SceneArgs,
    seed: u64,
) -> Result<(Packing, Option<Scene>), BenchError> {
    match file {
        Some(f) => Ok((read_input(f, &scene_args.container)?, None)),
        None => {
            let scene = scene_args.scene(Some(seed))?;
            Ok((initial_packing(&scene, seed)?, Some(scene)))
        }
    }
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

/// `--output NAME` → `NAME.txt` (RCPGenerator appends .txt unless it is there). A name that
/// ends in a path separator or is an existing folder is refused: it names no file.
pub fn output_path(name: &str) -> Result<PathBuf, BenchError> {
    let folder = name.is_empty()
        || name.ends_with(std::path::MAIN_SEPARATOR)
        || name.ends_with('/')
        || Path::new(name).is_dir();
    if folder {
        return Err(usage(format!(
            "--output `{name}` names a folder, not a file; give a file name such as {}",
            Path::new(name).join("packing").display()
        )));
    }
    let path = if name.ends_with(".txt") {
        PathBuf::from(name)
    } else {
        PathBuf::from(format!("{name}.txt"))
    };
    if path.is_dir() {
        return Err(usage(format!(
            "--output `{name}` would write {}, which is a folder; give another name",
            path.display()
        )));
    }
    Ok(path)
}

/// Writes `packing` as plain text to `path` and `sidecar` beside it, all-or-nothing: both
/// appear, or neither does and no temporary file is left.
pub fn write_packing(path: &Path, packing: &Packing, sidecar: &Sidecar) -> Result<(), BenchError> {
    let json = serde_json::to_string_pretty(sidecar).map_err(|e| BenchError::Run(e.to_string()))?;
    write_all_atomic(&[
        (path, write_text(packing).as_bytes()),
        (&sidecar_path(path), json.as_bytes()),
    ])?;
    Ok(())
}

/// Where a comparison in folder `out` keeps the packing of one run.
fn run_packing_path(out: &Path, method: &str, seed: u64) -> PathBuf {
    out.join("packings")
        .join(format!("{method}_seed{seed}.txt"))
}

/// Saves the packing of a comparison's run in folder `out` as
/// `packings/<method>_seed<seed>.txt`, with its container beside it (`.container.json`).
pub fn save_packing(out: &Path, rec: &RunRecord, p: &Packing) -> Result<(), BenchError> {
    let path = run_packing_path(out, &rec.method, rec.seed);
    write_atomic(&path, write_text(p).as_bytes())?;
    let json = serde_json::to_string(&p.container).map_err(|e| BenchError::Run(e.to_string()))?;
    write_atomic(&path.with_extension("container.json"), json.as_bytes())?;
    Ok(())
}

/// Reads the packing of a run saved by a comparison in folder `out`, if it is there.
pub fn load_packing(out: &Path, method: &str, seed: u64) -> Option<Packing> {
    let path = run_packing_path(out, method, seed);
    let text = std::fs::read_to_string(&path).ok()?;
    let container =
        serde_json::from_str(&std::fs::read_to_string(path.with_extension("container.json")).ok()?)
            .ok()?;
    read_packing(&path.display().to_string(), &text, &container).ok()
}

/// Removes the packing (and its container) a comparison in folder `out` saved for a run, if
/// any: `compare --resume-missing` reruns it.
pub fn remove_packing(out: &Path, method: &str, seed: u64) -> Result<(), BenchError> {
    let txt = run_packing_path(out, method, seed);
    for path in [txt.with_extension("container.json"), txt] {
        match std::fs::remove_file(&path) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                return Err(BenchError::Run(format!(
                    "cannot remove {}: {e}",
                    path.display()
                )));
            }
            _ => {}
        }
    }
    Ok(())
}
