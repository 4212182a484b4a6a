//! File formats: RCPGenerator's plain text (read and write), the JSON sidecar, exports to
//! extended XYZ, LAMMPS data and dump, and VTK (OVITO, ParaView, LAMMPS), and atomic writes.

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
///
/// A target that exists and is neither a regular file nor a directory (a device such as
/// `/dev/null`, a FIFO, a terminal behind `/dev/stdout`) is written in place after the others:
/// a rename would replace it with a regular file (as root, `--output /dev/null` once
/// replaced the machine's `/dev/null`).
pub fn write_all_atomic(files: &[(&Path, &[u8])]) -> Result<(), CoreError> {
    let (special, files): (Vec<_>, Vec<_>) = files.iter().partition(|(path, _)| is_special(path));
    write_renamed(&files)?;
    for (path, bytes) in special {
        std::fs::OpenOptions::new()
            .write(true)
            .open(path)
            .and_then(|mut f| f.write_all(bytes))
            .map_err(|e| CoreError::io(format!("writing {}", path.display()), e))?;
    }
    Ok(())
}

/// True for an existing path that is neither a regular file nor a directory.
fn is_special(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir())
}

/// The all-or-nothing part of [`write_all_atomic`]: temporaries, then renames.
fn write_renamed(files: &[&(&Path, &[u8])]) -> Result<(), CoreError> {
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
    files: &[&(&Path, &[u8])],
    temps: &mut Vec<std::path::PathBuf>,
) -> Result<(), CoreError> {
    for &&(path, bytes) in files {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Writing to a device writes through it and leaves it a device.
    #[cfg(unix)]
    #[test]
    fn a_device_target_is_written_in_place() {
        use std::os::unix::fs::FileTypeExt;
        let null = Path::new("/dev/null");
        write_atomic(null, b"a packing").unwrap();
        assert!(
            std::fs::metadata(null)
                .unwrap()
                .file_type()
                .is_char_device()
        );
    }

    /// A regular target is replaced whole, and no temporary is left beside it.
    #[test]
    fn a_regular_target_is_replaced_through_a_temporary() {
        let dir = std::env::temp_dir().join(format!("packbench-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("out.txt");
        write_atomic(&file, b"first").unwrap();
        write_atomic(&file, b"second").unwrap();
        assert_eq!(std::fs::read(&file).unwrap(), b"second");
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
