//! The files one `packbench pack` run leaves: the final packing `NAME.txt`, its sidecar
//! `NAME.json`, and the `--save-interval` snapshots `NAME_step<K>.txt`, read back in step
//! order as the frames of the run.

use std::path::{Path, PathBuf};

use packbench_core::Packing;
use packbench_core::format::{Sidecar, read_packing};

use crate::args::ContainerArgs;
use crate::error::{BenchError, usage};
use crate::outputs::{read_input, sidecar_path};

/// A run read from disk.
pub struct RunFiles {
    /// The final packing.
    pub packing: Packing,
    /// Its sidecar (method, parameters, trace), when there is one.
    pub sidecar: Option<Sidecar>,
    /// The snapshots, `(step, packing)` in increasing step order.
    pub snapshots: Vec<(u64, Packing)>,
    /// The run's name (file stem), for titles.
    pub name: String,
}

/// Reads the run behind `path`: a packing `NAME.txt`, its sidecar `NAME.json`, or `NAME`
/// itself (any names the run). A plain packing of another tool is a run with no sidecar and no
/// snapshots. Errors: a file that cannot be read or parsed (usage error naming it).
pub fn read_run(path: &Path) -> Result<RunFiles, BenchError> {
    let txt = match path.extension() {
        Some(e) if e == "json" => path.with_extension("txt"),
        // `--output NAME` of `pack` names the run without its extension.
        None if !path.is_file() => path.with_extension("txt"),
        _ => path.to_path_buf(),
    };
    if !txt.is_file() {
        return Err(usage(format!(
            "{} is not a packing (expected the run's packing {} beside its sidecar)",
            path.display(),
            txt.display()
        )));
    }
    let sidecar = match std::fs::read_to_string(sidecar_path(&txt)) {
        Ok(text) => Some(serde_json::from_str::<Sidecar>(&text).map_err(|e| {
            usage(format!(
                "{} is not a packbench sidecar: {e}",
                sidecar_path(&txt).display()
            ))
        })?),
        Err(_) => None,
    };
    let packing = read_input(&txt.display().to_string(), &ContainerArgs::default())?;
    let mut snapshots = Vec::new();
    for (step, file) in snapshot_files(&txt)? {
        let text = std::fs::read_to_string(&file)
            .map_err(|e| usage(format!("cannot read {}: {e}", file.display())))?;
        snapshots.push((
            step,
            read_packing(&file.display().to_string(), &text, &packing.container)?,
        ));
    }
    let name = txt
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    Ok(RunFiles {
        packing,
        sidecar,
        snapshots,
        name,
    })
}

/// `NAME_step<K>.txt` beside `NAME.txt`, sorted by K.
fn snapshot_files(txt: &Path) -> Result<Vec<(u64, PathBuf)>, BenchError> {
    let dir = match txt.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let stem = txt
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let prefix = format!("{stem}_step");
    let entries = std::fs::read_dir(&dir)
        .map_err(|e| usage(format!("cannot list {}: {e}", dir.display())))?;
    let mut found: Vec<(u64, PathBuf)> = entries
        .flatten()
        .filter_map(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            let step = name
                .strip_prefix(&prefix)?
                .strip_suffix(".txt")?
                .parse()
                .ok()?;
            Some((step, e.path()))
        })
        .collect();
    found.sort_by_key(|(k, _)| *k);
    Ok(found)
}

/// At most `max` items of `items`, evenly spread and always keeping the last.
pub fn thin<T>(items: Vec<T>, max: usize) -> Vec<T> {
    let n = items.len();
    if n <= max || max == 0 {
        return items;
    }
    let keep: Vec<usize> = (0..max).map(|k| ((k + 1) * n).div_ceil(max) - 1).collect();
    items
        .into_iter()
        .enumerate()
        .filter(|(i, _)| keep.binary_search(i).is_ok())
        .map(|(_, t)| t)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thinning_keeps_the_count_and_the_last_item() {
        let v: Vec<usize> = (0..10).collect();
        assert_eq!(thin(v.clone(), 20), v);
        let t = thin(v, 4);
        assert_eq!(t.len(), 4);
        assert_eq!(*t.last().unwrap(), 9);
    }
}
