//! Files written whole or not at all.
//!
//! Every result file is written under a temporary name in its own folder,
//! `.<stem>.partial.<extension>` (hidden, and keeping the extension, from which plotters
//! picks the image format), and renamed over its final name only once complete. A rename
//! within one folder is atomic, so a reader sees the previous file or the new one, never a
//! truncated one; a failed write (a full disk, a drawing error, a panic) removes the
//! temporary. A process killed mid-write leaves at most a `.partial.` file, which
//! [`super::remove_previous_results`] clears on the next run. (Durability across a power
//! loss would also need an fsync, which the result files do not warrant.)

use std::ffi::OsString;
use std::path::{Path, PathBuf};

use super::OutputError;

/// The infix that marks a temporary name.
pub(crate) const PARTIAL: &str = ".partial.";

/// The temporary name of `target`: `dir/.<stem>.partial.<extension>` (`.phi.partial.png`).
pub fn temporary_path(target: &Path) -> PathBuf {
    let stem = target.file_stem().unwrap_or_default();
    let mut name = OsString::from(".");
    name.push(stem);
    name.push(PARTIAL.trim_end_matches('.'));
    if let Some(ext) = target.extension() {
        name.push(".");
        name.push(ext);
    }
    target.with_file_name(name)
}

/// Removes the temporary file when dropped before [`Partial::commit`].
struct Partial {
    path: PathBuf,
    committed: bool,
}

impl Drop for Partial {
    fn drop(&mut self) {
        if !self.committed {
            // Nothing more to do if it cannot be removed: it carries the `.partial.` mark.
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

/// Runs `write` on the temporary path of `target` (see the module docs), then renames the
/// result over `target`. On an error, or a panic inside `write`, the temporary is removed
/// and `target` is left as it was. A `target` that exists and is not a regular file is
/// [`OutputError::NotAFile`] before anything is written ([`check_target`]).
pub fn write_atomically<T>(
    target: &Path,
    write: impl FnOnce(&Path) -> Result<T, OutputError>,
) -> Result<T, OutputError> {
    check_target(target)?;
    let mut partial = Partial {
        path: temporary_path(target),
        committed: false,
    };
    let value = write(&partial.path)?;
    std::fs::rename(&partial.path, target).map_err(|e| OutputError::io(target, e))?;
    partial.committed = true;
    Ok(value)
}

/// `Ok` when a file may be renamed over `target`: nothing is there, or a regular file;
/// else [`OutputError::NotAFile`] naming what is there (a rename would replace the
/// directory entry itself: a directory, a device such as `/dev/full`, a named pipe, a
/// symbolic link, whose target would be left as it was). Nothing is followed.
pub fn check_target(target: &Path) -> Result<(), OutputError> {
    let Ok(meta) = std::fs::symlink_metadata(target) else {
        return Ok(());
    };
    let kind = meta.file_type();
    let kind = if kind.is_file() {
        return Ok(());
    } else if kind.is_dir() {
        "a directory"
    } else if kind.is_symlink() {
        "a symbolic link"
    } else {
        "a device or a named pipe"
    };
    Err(OutputError::NotAFile {
        path: target.to_path_buf(),
        kind,
    })
}
