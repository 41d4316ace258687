//! The output folder belongs to one run at a time: its lock refuses a second holder and is
//! taken over once its holder is gone; staged results replace the previous ones whole, and
//! a swap cut short is completed by the next run.

use crate::support::{files_in, set, temp_dir};
use mechanism::output::{
    FolderLock, LOCK_FILE, OutputError, STAGING_FOLDER, SUMMARY_FORMAT, SUMMARY_FORMAT_VERSION,
    Staging,
};

/// A summary of ours listing `files`.
fn our_summary(files: &[&str]) -> String {
    serde_json::json!({
        "format": SUMMARY_FORMAT,
        "format_version": SUMMARY_FORMAT_VERSION,
        "files": files,
    })
    .to_string()
}

#[test]
fn a_held_folder_is_refused_and_a_released_one_taken_over() {
    let dir = temp_dir("lock");
    let first = FolderLock::acquire(&dir).unwrap();
    let pid = std::process::id().to_string();
    assert_eq!(std::fs::read_to_string(dir.join(LOCK_FILE)).unwrap(), pid);
    match FolderLock::acquire(&dir) {
        Err(OutputError::Locked { holder, .. }) => assert_eq!(holder, format!("process {pid}")),
        other => panic!("expected Locked, got {other:?}"),
    }
    drop(first);
    assert!(!dir.join(LOCK_FILE).exists(), "the holder removes its file");
    // A lock file its holder left behind (a process killed with SIGKILL leaves the file but
    // not the lock) is taken over.
    std::fs::write(dir.join(LOCK_FILE), "999999999").unwrap();
    let again = FolderLock::acquire(&dir).unwrap();
    assert_eq!(std::fs::read_to_string(dir.join(LOCK_FILE)).unwrap(), pid);
    drop(again);
}

#[test]
fn staged_results_replace_the_previous_ones_whole() {
    let dir = temp_dir("staging");
    for f in ["trajectory.csv", "old.png", "notes.txt"] {
        std::fs::write(dir.join(f), "old").unwrap();
    }
    let previous = our_summary(&["trajectory.csv", "summary.json", "old.png"]);
    std::fs::write(dir.join("summary.json"), &previous).unwrap();
    let lock = FolderLock::acquire(&dir).unwrap();
    let staging = Staging::begin(&lock).unwrap();
    std::fs::write(staging.path().join("trajectory.csv"), "new").unwrap();
    std::fs::write(staging.path().join("new.png"), "new").unwrap();
    // Until the run ends the folder holds the previous results only.
    assert_eq!(
        std::fs::read_to_string(dir.join("trajectory.csv")).unwrap(),
        "old"
    );
    let summary = our_summary(&["trajectory.csv", "summary.json", "new.png"]);
    std::fs::write(staging.path().join("summary.json"), &summary).unwrap();
    assert!(staging.commit().unwrap());
    drop(lock);
    assert_eq!(
        files_in(&dir),
        set(&["trajectory.csv", "summary.json", "new.png", "notes.txt"])
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("trajectory.csv")).unwrap(),
        "new"
    );
}

#[test]
fn results_without_a_summary_are_discarded() {
    let dir = temp_dir("staging-incomplete");
    std::fs::write(dir.join("trajectory.csv"), "old").unwrap();
    std::fs::write(dir.join("summary.json"), our_summary(&["trajectory.csv"])).unwrap();
    let lock = FolderLock::acquire(&dir).unwrap();
    let staging = Staging::begin(&lock).unwrap();
    std::fs::write(staging.path().join("trajectory.csv"), "new").unwrap();
    assert!(!staging.commit().unwrap());
    drop(lock);
    assert_eq!(files_in(&dir), set(&["trajectory.csv", "summary.json"]));
    assert_eq!(
        std::fs::read_to_string(dir.join("trajectory.csv")).unwrap(),
        "old"
    );
}

#[test]
fn what_a_killed_run_left_is_completed_or_discarded() {
    // Killed before its summary was staged: the staged files are dropped.
    let dir = temp_dir("staging-killed");
    std::fs::write(dir.join("trajectory.csv"), "old").unwrap();
    std::fs::write(dir.join("summary.json"), our_summary(&["trajectory.csv"])).unwrap();
    std::fs::create_dir(dir.join(STAGING_FOLDER)).unwrap();
    std::fs::write(dir.join(STAGING_FOLDER).join("trajectory.csv"), "killed").unwrap();
    let lock = FolderLock::acquire(&dir).unwrap();
    let staging = Staging::begin(&lock).unwrap();
    assert_eq!(files_in(staging.path()), set(&[]));
    assert_eq!(
        std::fs::read_to_string(dir.join("trajectory.csv")).unwrap(),
        "old"
    );
    drop(staging);
    drop(lock);

    // Killed in the middle of the swap (one file moved, the summary still staged): the
    // next run completes it.
    let dir = temp_dir("staging-mid-swap");
    std::fs::write(dir.join("old.png"), "old").unwrap();
    std::fs::write(dir.join("trajectory.csv"), "new").unwrap();
    let previous = our_summary(&["trajectory.csv", "summary.json", "old.png"]);
    std::fs::write(dir.join("summary.json"), previous).unwrap();
    let left = dir.join(STAGING_FOLDER);
    std::fs::create_dir(&left).unwrap();
    std::fs::write(left.join("new.png"), "new").unwrap();
    let summary = our_summary(&["trajectory.csv", "summary.json", "new.png"]);
    std::fs::write(left.join("summary.json"), &summary).unwrap();
    let lock = FolderLock::acquire(&dir).unwrap();
    let staging = Staging::begin(&lock).unwrap();
    assert_eq!(files_in(staging.path()), set(&[]));
    drop(staging);
    drop(lock);
    assert_eq!(
        files_in(&dir),
        set(&["trajectory.csv", "summary.json", "new.png", STAGING_FOLDER])
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("summary.json")).unwrap(),
        summary
    );
}

#[cfg(unix)]
#[test]
fn a_lock_file_that_is_not_a_regular_file_is_refused_and_left_alone() {
    // A symbolic link to another file: that file would take the process id.
    let dir = temp_dir("lock-symlink");
    let victim = temp_dir("lock-victim").join("victim.txt");
    std::fs::write(&victim, "the user's").unwrap();
    std::os::unix::fs::symlink(&victim, dir.join(LOCK_FILE)).unwrap();
    match FolderLock::acquire(&dir) {
        Err(OutputError::LockNotAFile { kind, .. }) => assert_eq!(kind, "a symbolic link"),
        other => panic!("expected LockNotAFile, got {other:?}"),
    }
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "the user's");
    assert!(dir.join(LOCK_FILE).symlink_metadata().unwrap().is_symlink());
    // A dangling link: following it would create its target.
    let dangling = temp_dir("lock-dangling");
    let nowhere = dangling.join("created-through-the-link");
    std::os::unix::fs::symlink(&nowhere, dangling.join(LOCK_FILE)).unwrap();
    assert!(matches!(
        FolderLock::acquire(&dangling),
        Err(OutputError::LockNotAFile { .. })
    ));
    assert!(!nowhere.exists());
    // A folder in its place.
    let dir = temp_dir("lock-folder");
    std::fs::create_dir(dir.join(LOCK_FILE)).unwrap();
    match FolderLock::acquire(&dir) {
        Err(OutputError::LockNotAFile { kind, .. }) => assert_eq!(kind, "a directory"),
        other => panic!("expected LockNotAFile, got {other:?}"),
    }
    assert!(dir.join(LOCK_FILE).is_dir());
}
