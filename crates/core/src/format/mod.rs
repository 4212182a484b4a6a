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
/// interrupted run never leaves half a file behind; on any error the temporary file is
/// removed. A `path` that is a directory is refused ([`CoreError::File`]).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), CoreError> {
    write_all_atomic(&[(path, bytes)])
}

/// Writes several files all-or-nothing (a packing and its sidecar): every file goes to a
/// temporary beside it first, and only when all are written are they renamed into place. On
/// any error every temporary is removed, and so is any file this call already renamed, so
/// either all files appear or none of the new ones do.
pub fn write_all_atomic(files: &[(&Path, &[u8])]) -> Result<(), CoreError> {
    let mut temps: Vec<std::path::PathBuf> = Vec::new();
    let result = write_temps(files, &mut temps).and_then(|()| {
        for (k, ((path, _), tmp)) in files.iter().zip(&temps).enumerate() {
            if let Err(e) = std::fs::rename(tmp, path) {
                for (done, _) in &files[..k] {
                    let _ = std::fs::remove_file(done);
                }
                return Err(CoreError::io(
                    format!("renaming into {}", path.display()),
                    e,
                ));
            }
        }
        temps.clear();
        Ok(())
    });
    for tmp in &temps {
        let _ = std::fs::remove_file(tmp);
    }
    result
}

/// Writes each file's bytes to its temporary, recording every temporary created in `temps`.
fn write_temps(
    files: &[(&Path, &[u8])],
    temps: &mut Vec<std::path::PathBuf>,
) -> Result<(), CoreError> {
    for (path, bytes) in files {
        let name = path.display().to_string();
        if path.is_dir() {
            return Err(CoreError::File {
                file: name,
                message: "is a directory; give a file name".into(),
            });
        }
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
        let mut f = std::fs::File::create(&tmp)
            .map_err(|e| CoreError::io(format!("creating {name}"), e))?;
        temps.push(tmp);
        f.write_all(bytes)
            .and_then(|()| f.sync_all())
            .map_err(|e| CoreError::io(format!("writing {name}"), e))?;
    }
    Ok(())
}
