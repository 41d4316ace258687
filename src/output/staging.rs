//! A run's results written apart and swapped in when it ends, so that the previous results
//! stay whole until the new ones are complete.
//!
//! A run writes every file into `<folder>/.mechanism-staging/`, inside its output folder
//! (not beside it: the folder's parent may not be writable, and a rename within one folder
//! is never a copy across file systems), under the [`FolderLock`]. Its `summary.json`,
//! written last, marks the staged results complete. [`Staging::commit`] then swaps them in:
//!
//! 1. each staged file is renamed over its name in the folder (atomic per file);
//! 2. the files the previous summary lists that the new one does not are removed (only if
//!    the previous summary is ours: [`super::remove_previous_results`]);
//! 3. the new `summary.json` is renamed in: from here on the folder is the new run's;
//! 4. the staging folder is removed.
//!
//! A run killed before its summary is staged leaves the folder as it was; the next run
//! removes the staging folder. A run killed during the swap leaves a staged summary, and the
//! next run completes the swap first (steps 1 to 4 repeat without harm).

use std::path::{Path, PathBuf};

use super::OutputError;
use super::lock::FolderLock;
use super::previous::{SUMMARY_FILE, is_ours, listed_files, previous_results};

/// The name of the staging folder inside an output folder.
pub const STAGING_FOLDER: &str = ".mechanism-staging";

/// The staging folder of one run (see the module docs).
#[derive(Debug)]
pub struct Staging {
    dir: PathBuf,
    staging: PathBuf,
}

impl Staging {
    /// Prepares a fresh, empty staging folder in the folder `lock` holds, after completing
    /// or discarding what a run before left there (see the module docs).
    pub fn begin(lock: &FolderLock) -> Result<Self, OutputError> {
        let dir = lock.dir().to_path_buf();
        let staging = dir.join(STAGING_FOLDER);
        let left = Self {
            dir: dir.clone(),
            staging: staging.clone(),
        };
        if is_ours(&staging.join(SUMMARY_FILE)) {
            left.swap()?;
        }
        remove_staging(&staging)?;
        std::fs::create_dir(&staging).map_err(|e| OutputError::io(&staging, e))?;
        Ok(Self { dir, staging })
    }

    /// Where the run writes its files.
    pub fn path(&self) -> &Path {
        &self.staging
    }

    /// The output folder the results are swapped into.
    pub fn target(&self) -> &Path {
        &self.dir
    }

    /// True once the run's `summary.json` is staged.
    pub fn is_complete(&self) -> bool {
        is_ours(&self.staging.join(SUMMARY_FILE))
    }

    /// Swaps the staged results in (see the module docs) when the summary is staged;
    /// otherwise discards them, leaving the folder as it was. Returns whether they were
    /// swapped in.
    pub fn commit(self) -> Result<bool, OutputError> {
        let complete = self.is_complete();
        if complete {
            self.swap()?;
        }
        remove_staging(&self.staging)?;
        Ok(complete)
    }

    /// Steps 1 to 3 of the module docs.
    fn swap(&self) -> Result<(), OutputError> {
        let entries = std::fs::read_dir(&self.staging).map_err(|e| self.io(e))?;
        let mut staged = Vec::new();
        for entry in entries {
            let entry = entry.map_err(|e| self.io(e))?;
            if entry.file_type().is_ok_and(|t| t.is_file()) {
                staged.push(entry.file_name());
            }
        }
        let rename = |name: &std::ffi::OsStr| {
            let target = self.dir.join(name);
            std::fs::rename(self.staging.join(name), &target)
                .map_err(|e| OutputError::io(target, e))
        };
        for name in staged.iter().filter(|n| *n != SUMMARY_FILE) {
            rename(name)?;
        }
        // The new run's files: those its summary lists (some may be in place already, moved
        // by a swap that was cut short) and those staged.
        let new = listed_files(&self.staging.join(SUMMARY_FILE));
        for name in previous_results(&self.dir) {
            let path = self.dir.join(&name);
            let rewritten = new.contains(&name) || staged.iter().any(|n| *n == *name);
            let file = path.symlink_metadata().is_ok_and(|m| m.is_file());
            if !rewritten && name != SUMMARY_FILE && file {
                std::fs::remove_file(&path).map_err(|e| OutputError::io(&path, e))?;
            }
        }
        rename(SUMMARY_FILE.as_ref())
    }

    fn io(&self, e: std::io::Error) -> OutputError {
        OutputError::io(&self.staging, e)
    }
}

/// Removes the staging folder and what it holds (a symbolic link or a file in its place is
/// removed, never followed).
fn remove_staging(staging: &Path) -> Result<(), OutputError> {
    let removed = match staging.symlink_metadata() {
        Err(_) => return Ok(()),
        Ok(m) if m.is_dir() => std::fs::remove_dir_all(staging),
        Ok(_) => std::fs::remove_file(staging),
    };
    removed.map_err(|e| OutputError::io(staging, e))
}
