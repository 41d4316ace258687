//! One run at a time in an output folder: a lock file held for the whole run.
//!
//! The lock is the operating system's advisory lock on `<folder>/.mechanism.lock`
//! ([`std::fs::File::try_lock`], `flock` on Unix, `LockFileEx` on Windows), held from the
//! moment a run claims its folder until it ends. The file holds the process id of its
//! holder, which the refusal names. A lock left by a process that died (`kill -9`, a power
//! loss) is stale: the operating system released it with the process, so the next run
//! takes the file over at once; no process id is trusted, so a reused one cannot keep a
//! folder locked. On Unix the holder removes the file when it ends, and a run that opened
//! a file removed meanwhile tries again, so two runs never hold two different files.

use std::fs::{File, OpenOptions, TryLockError};
use std::io::{Read as _, Write as _};
use std::path::{Path, PathBuf};

use super::{OutputError, ensure_dir};

/// The name of the lock file in an output folder.
pub const LOCK_FILE: &str = ".mechanism.lock";

/// The lock of one output folder, released (and its file removed) when dropped.
#[derive(Debug)]
pub struct FolderLock {
    dir: PathBuf,
    file: File,
}

impl FolderLock {
    /// Locks `dir` (created if missing) for this process.
    ///
    /// # Errors
    /// [`OutputError::Locked`] when another live process holds it; [`OutputError::Io`]
    /// when the folder or the lock file cannot be created or locked.
    pub fn acquire(dir: &Path) -> Result<Self, OutputError> {
        ensure_dir(dir)?;
        let path = dir.join(LOCK_FILE);
        let io = |e| OutputError::io(&path, e);
        loop {
            let mut file = OpenOptions::new()
                .read(true)
                .write(true)
                .create(true)
                .truncate(false)
                .open(&path)
                .map_err(io)?;
            match file.try_lock() {
                Ok(()) => {}
                Err(TryLockError::WouldBlock) => {
                    let mut id = String::new();
                    let _ = file.read_to_string(&mut id);
                    let holder = match id.trim() {
                        "" => "its process id not yet written".to_string(),
                        id => format!("process {id}"),
                    };
                    return Err(OutputError::Locked {
                        dir: dir.to_path_buf(),
                        holder,
                    });
                }
                Err(TryLockError::Error(e)) => return Err(io(e)),
            }
            // The holder before may have removed the file between our open and our lock.
            if !is_same_file(&file, &path) {
                continue;
            }
            file.set_len(0).map_err(io)?;
            write!(file, "{}", std::process::id()).map_err(io)?;
            return Ok(Self {
                dir: dir.to_path_buf(),
                file,
            });
        }
    }

    /// The locked folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }
}

impl Drop for FolderLock {
    fn drop(&mut self) {
        // Removed while still held (Unix), so no other run can lock the removed file; the
        // lock itself is released when `file` closes.
        #[cfg(unix)]
        let _ = std::fs::remove_file(self.dir.join(LOCK_FILE));
        let _ = self.file.unlock();
    }
}

/// True when `path` is the file `file` has open (Unix: the same device and inode).
#[cfg(unix)]
fn is_same_file(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt as _;
    match (file.metadata(), std::fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

/// True: elsewhere the lock file is never removed, so the file opened is the one there.
#[cfg(not(unix))]
fn is_same_file(_file: &File, _path: &Path) -> bool {
    true
}
