//! File formats: RCPGenerator's plain text (read and write), the JSON sidecar, exports to
//! extended XYZ (OVITO), LAMMPS data and legacy VTK (ParaView), and atomic writes.

mod export;
mod sidecar;
mod text;

pub use export::{ExportFormat, export};
pub use sidecar::Sidecar;
pub use text::{TextData, parse_text, read_packing, value_problem, write_text};

use std::io::Write;
use std::path::Path;

use crate::error::CoreError;

/// Writes `bytes` to `path` through a temporary file in the same directory and a rename, so an
/// interrupted run never leaves half a file behind.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), CoreError> {
    let name = path.display().to_string();
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    if !dir.exists() {
        std::fs::create_dir_all(dir)
            .map_err(|e| CoreError::io(format!("creating {}", dir.display()), e))?;
    }
    let tmp = dir.join(format!(
        ".{}.tmp{}",
        path.file_name()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default(),
        std::process::id()
    ));
    let mut f =
        std::fs::File::create(&tmp).map_err(|e| CoreError::io(format!("creating {name}"), e))?;
    f.write_all(bytes)
        .map_err(|e| CoreError::io(format!("writing {name}"), e))?;
    f.sync_all().ok();
    drop(f);
    std::fs::rename(&tmp, path).map_err(|e| CoreError::io(format!("renaming into {name}"), e))
}
