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
//!
//! The lock file is opened without following a symbolic link (`O_NOFOLLOW` on Unix), and
//! only a regular file is taken: a `.mechanism.lock` that links to another file (which the
//! process id would overwrite), a folder, a pipe or a device is refused
//! ([`OutputError::LockNotAFile`]) and left as it is.

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
    /// [`OutputError::Locked`] when another live process holds it;
    /// [`OutputError::LockNotAFile`] when `.mechanism.lock` is not a regular file (a
    /// symbolic link is never followed); [`OutputError::Io`] when the folder or the lock
    /// file cannot be created or locked.
    pub fn acquire(dir: &Path) -> Result<Self, OutputError> {
        ensure_dir(dir)?;
        let path = dir.join(LOCK_FILE);
        let io = |e| OutputError::io(&path, e);
        loop {
            let mut file = open_lock_file(&path)?;
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

/// Opens (or creates) the lock file `path`, refusing anything but a regular file: checked
/// before the open, where a symbolic link is said as such, and again on the file opened,
/// which `O_NOFOLLOW` (Unix) keeps from being a link's target should one appear between.
fn open_lock_file(path: &Path) -> Result<File, OutputError> {
    let refuse = |kind| OutputError::LockNotAFile {
        path: path.to_path_buf(),
        kind,
    };
    if let Ok(meta) = std::fs::symlink_metadata(path)
        && !meta.is_file()
    {
        return Err(refuse(kind_of(&meta)));
    }
    let mut options = OpenOptions::new();
    options.read(true).write(true).create(true).truncate(false);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt as _;
        // O_NONBLOCK: a named pipe put there meanwhile opens at once (and is refused below)
        // instead of waiting for a writer; it changes nothing for a regular file.
        options.custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK);
    }
    let file = options.open(path).map_err(|e| {
        // ELOOP: the last component became a symbolic link after the check.
        #[cfg(unix)]
        if e.raw_os_error() == Some(libc::ELOOP) {
            return refuse("a symbolic link");
        }
        OutputError::io(path, e)
    })?;
    let meta = file.metadata().map_err(|e| OutputError::io(path, e))?;
    if !meta.is_file() {
        return Err(refuse(kind_of(&meta)));
    }
    Ok(file)
}

/// What a file that is not a regular one is, as the refusal says it.
fn kind_of(meta: &std::fs::Metadata) -> &'static str {
    let kind = meta.file_type();
    if kind.is_symlink() {
        "a symbolic link"
    } else if kind.is_dir() {
        "a directory"
    } else {
        "a device or a named pipe"
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
