//! A run's results written apart and swapped in when it ends, so that the previous results
//! stay whole until the new ones are complete.
//!
//! A run writes every file into `<folder>/.mechanism-staging/`, inside its output folder
//! (not beside it: the folder's parent may not be writable, and a rename within one folder
//! is never a copy across file systems), under the [`FolderLock`]. Its `summary.json`,
//! written last, marks the staged results complete. [`Staging::commit`] then swaps them in,
//! all or nothing:
//!
//! 1. every name to be renamed over is checked first: nothing there, or a regular file
//!    ([`check_target`]; a folder named `trajectory.csv` stops the swap before anything
//!    moves);
//! 2. each staged file is renamed over its name in the folder, the file it replaces moved
//!    aside into `.mechanism-staging/.replaced/` first;
//! 3. the files the previous summary lists that the new one does not are moved aside too
//!    (only if the previous summary is ours: [`super::remove_previous_results`]);
//! 4. the new `summary.json` is renamed in: from here on the folder is the new run's;
//! 5. the staging folder is removed, and with it what was moved aside.
//!
//! A rename that fails in steps 2 to 4 (a full or failing disk, a file the user put there
//! meanwhile) undoes the renames before it, in reverse order: the folder is as it was, and
//! the run's results are discarded with the staging folder. A run that cannot write its
//! files whole calls [`Staging::discard`], which leaves the folder as it was too.
//!
//! A run killed before its summary is staged leaves the folder as it was; the next run
//! removes the staging folder. A run killed during the swap leaves a staged summary, and the
//! next run completes the swap first (the steps repeat without harm).

use std::ffi::{OsStr, OsString};
use std::path::{Path, PathBuf};

use super::OutputError;
use super::atomic::check_target;
use super::lock::FolderLock;
use super::previous::{SUMMARY_FILE, is_ours, listed_files, previous_results};

/// The name of the staging folder inside an output folder.
pub const STAGING_FOLDER: &str = ".mechanism-staging";

/// Where the swap moves the files it replaces, inside the staging folder, until the new
/// summary is in (so that a failed swap can put them back).
const REPLACED: &str = ".replaced";

/// The staging folder of one run (see the module docs).
#[derive(Debug)]
pub struct Staging {
    dir: PathBuf,
    staging: PathBuf,
}

/// A rename: `std::fs::rename`, or a failing one in the tests.
type Rename<'a> = &'a mut dyn FnMut(&Path, &Path) -> std::io::Result<()>;

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
    /// swapped in. A swap that fails is undone first: the folder is as it was, and the
    /// error says why.
    pub fn commit(self) -> Result<bool, OutputError> {
        let complete = self.is_complete();
        let swapped = if complete { self.swap() } else { Ok(()) };
        // Whatever a failed swap could not put back stays in the staging folder, where the
        // next run finds the staged summary and completes the swap.
        let restored = swapped.is_ok() || is_empty_or_missing(&self.staging.join(REPLACED));
        let removed = if restored {
            remove_staging(&self.staging)
        } else {
            Ok(())
        };
        swapped?;
        removed?;
        Ok(complete)
    }

    /// Discards the staged results: the folder stays as it was (a run whose files could
    /// not all be written replaces nothing).
    pub fn discard(self) -> Result<(), OutputError> {
        remove_staging(&self.staging)
    }

    /// Steps 1 to 4 of the module docs, undone on a failure.
    fn swap(&self) -> Result<(), OutputError> {
        self.swap_with(&mut |from, to| std::fs::rename(from, to))
    }

    /// [`Staging::swap`] with the renames done by `rename`.
    fn swap_with(&self, rename: Rename) -> Result<(), OutputError> {
        let staged = self.staged()?;
        for name in &staged {
            check_target(&self.dir.join(name))?;
        }
        // The previous results the new run does not rewrite: those its summary lists (some
        // may be in place already, moved by a swap that was cut short) and those staged.
        let new = listed_files(&self.staging.join(SUMMARY_FILE));
        let outgoing: Vec<String> = previous_results(&self.dir)
            .into_iter()
            .filter(|name| {
                let path = self.dir.join(name);
                let rewritten = new.contains(name) || staged.iter().any(|n| *n == **name);
                let file = path.symlink_metadata().is_ok_and(|m| m.is_file());
                !rewritten && name != SUMMARY_FILE && file
            })
            .collect();
        let mut done = Vec::new();
        let result = self.move_all(&staged, &outgoing, rename, &mut done);
        if result.is_err() {
            for (from, to) in done.iter().rev() {
                // Nothing more to do if one cannot be put back: it stays in the staging
                // folder, which is then kept (`commit`).
                let _ = rename(to, from);
            }
        }
        result
    }

    /// Steps 2 to 4, each rename recorded in `done` as (from, to).
    fn move_all(
        &self,
        staged: &[OsString],
        outgoing: &[String],
        rename: Rename,
        done: &mut Vec<(PathBuf, PathBuf)>,
    ) -> Result<(), OutputError> {
        let replaced = self.staging.join(REPLACED);
        if !replaced.is_dir() {
            std::fs::create_dir(&replaced).map_err(|e| OutputError::io(&replaced, e))?;
        }
        let mut step = |from: PathBuf, to: PathBuf| -> Result<(), OutputError> {
            rename(&from, &to).map_err(|e| OutputError::io(&to, e))?;
            done.push((from, to));
            Ok(())
        };
        for name in staged.iter().filter(|n| *n != SUMMARY_FILE) {
            let target = self.dir.join(name);
            if target.symlink_metadata().is_ok() {
                step(target.clone(), replaced.join(name))?;
            }
            step(self.staging.join(name), target)?;
        }
        for name in outgoing {
            step(self.dir.join(name), replaced.join(name))?;
        }
        let summary = OsStr::new(SUMMARY_FILE);
        step(self.staging.join(summary), self.dir.join(summary))
    }

    /// The regular files in the staging folder, by name.
    fn staged(&self) -> Result<Vec<OsString>, OutputError> {
        let io = |e| OutputError::io(&self.staging, e);
        let mut staged = Vec::new();
        for entry in std::fs::read_dir(&self.staging).map_err(io)? {
            let entry = entry.map_err(io)?;
            if entry.file_type().is_ok_and(|t| t.is_file()) {
                staged.push(entry.file_name());
            }
        }
        Ok(staged)
    }
}

/// True when `dir` is missing or holds nothing.
fn is_empty_or_missing(dir: &Path) -> bool {
    std::fs::read_dir(dir).map_or(true, |mut entries| entries.next().is_none())
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

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;

    use super::*;
    use crate::output::{SUMMARY_FORMAT, SUMMARY_FORMAT_VERSION};

    /// A fresh folder for one test under the system's temporary folder, removed when the
    /// guard drops (at the test's end, also when an assertion fails and unwinds).
    fn folder(name: &str) -> tempfile::TempDir {
        tempfile::Builder::new()
            .prefix(&format!("mechanism-staging-{name}-"))
            .tempdir()
            .unwrap()
    }

    /// A summary of ours listing `files`, with `tag` to tell two apart.
    fn summary(files: &[&str], tag: &str) -> String {
        serde_json::json!({
            "format": SUMMARY_FORMAT,
            "format_version": SUMMARY_FORMAT_VERSION,
            "tag": tag,
            "files": files,
        })
        .to_string()
    }

    /// Every regular file of `dir` but the staging folder, by name, with its text.
    fn contents(dir: &Path) -> BTreeMap<String, String> {
        std::fs::read_dir(dir)
            .unwrap()
            .filter_map(|e| {
                let e = e.unwrap();
                let name = e.file_name().into_string().unwrap();
                let text = std::fs::read_to_string(e.path()).ok()?;
                Some((name, text))
            })
            .collect()
    }

    /// A folder holding a previous run (a.csv, b.png, its summary) and the user's notes,
    /// and the staged results of a new run (a.csv, c.png, its summary); the guard removes
    /// the folder.
    fn prepared(name: &str) -> (tempfile::TempDir, Staging) {
        let guard = folder(name);
        let dir = guard.path().to_path_buf();
        std::fs::write(dir.join("a.csv"), "old a").unwrap();
        std::fs::write(dir.join("b.png"), "old b").unwrap();
        std::fs::write(dir.join("notes.txt"), "the user's").unwrap();
        let old = summary(&["a.csv", "summary.json", "b.png"], "old");
        std::fs::write(dir.join(SUMMARY_FILE), old).unwrap();
        let staging = dir.join(STAGING_FOLDER);
        std::fs::create_dir(&staging).unwrap();
        std::fs::write(staging.join("a.csv"), "new a").unwrap();
        std::fs::write(staging.join("c.png"), "new c").unwrap();
        let new = summary(&["a.csv", "summary.json", "c.png"], "new");
        std::fs::write(staging.join(SUMMARY_FILE), new).unwrap();
        (guard, Staging { dir, staging })
    }

    #[test]
    fn a_swap_that_fails_at_any_rename_leaves_the_previous_results() {
        // The swap that succeeds: count its renames and see its result.
        let (_folder, whole) = prepared("whole");
        let mut renames = 0;
        whole
            .swap_with(&mut |from, to| {
                renames += 1;
                std::fs::rename(from, to)
            })
            .unwrap();
        let after = contents(&whole.dir);
        assert_eq!(after["a.csv"], "new a");
        assert_eq!(after["c.png"], "new c");
        assert!(!after.contains_key("b.png"), "b.png is no longer listed");
        assert_eq!(after["notes.txt"], "the user's");
        // a.csv aside and in, c.png in, b.png aside, the summary in.
        assert_eq!(renames, 5);
        // A failure injected at each rename in turn (a full disk, a file that cannot be
        // replaced): the folder is byte for byte as before, and the run's files are staged
        // still.
        for fail_at in 0..renames {
            let (_folder, staging) = prepared(&format!("fail-{fail_at}"));
            let before = contents(&staging.dir);
            let mut k = 0;
            let result = staging.swap_with(&mut |from, to| {
                k += 1;
                if k == fail_at + 1 {
                    return Err(std::io::Error::from(std::io::ErrorKind::StorageFull));
                }
                std::fs::rename(from, to)
            });
            assert!(result.is_err(), "rename {fail_at} fails");
            assert_eq!(
                contents(&staging.dir),
                before,
                "failure at rename {fail_at}"
            );
            let staged = contents(&staging.staging);
            assert_eq!(staged.len(), 3, "failure at rename {fail_at}: {staged:?}");
            assert!(staging.commit().is_ok_and(|swapped| swapped));
        }
    }

    #[test]
    fn a_target_that_is_not_a_file_stops_the_swap_before_anything_moves() {
        for blocked in ["a.csv", "c.png", SUMMARY_FILE] {
            let (_folder, staging) = prepared(&format!("blocked-{blocked}"));
            let target = staging.dir.join(blocked);
            let _ = std::fs::remove_file(&target);
            std::fs::create_dir(&target).unwrap();
            let before = contents(&staging.dir);
            let dir = staging.dir.clone();
            match staging.commit() {
                Err(OutputError::NotAFile { path, kind }) => {
                    assert_eq!(path, target);
                    assert_eq!(kind, "a directory");
                }
                other => panic!("{blocked}: expected NotAFile, got {other:?}"),
            }
            assert_eq!(contents(&dir), before, "{blocked}");
            assert!(target.is_dir(), "{blocked}");
            assert!(
                !dir.join(STAGING_FOLDER).exists(),
                "the run's files discarded"
            );
        }
    }

    #[test]
    fn discarded_results_leave_the_folder_as_it_was() {
        let (_folder, staging) = prepared("discard");
        let dir = staging.dir.clone();
        let before = contents(&dir);
        staging.discard().unwrap();
        assert_eq!(contents(&dir), before);
        assert!(!dir.join(STAGING_FOLDER).exists());
    }
}
