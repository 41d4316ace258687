//! The results a previous run left in an output folder, removed before a new run writes
//! there, so that a run that fails never leaves older results looking current.
//!
//! A run's `summary.json` lists the files it wrote (`files`). Only those are removed,
//! plus the summary itself and any temporary `.<name>.partial.<extension>` a killed run left
//! ([`super::write_atomically`]): every other file in the folder is the user's and stays.

use std::path::{Component, Path, PathBuf};

use super::OutputError;
use super::atomic::PARTIAL;

/// The name of the summary a run leaves in its folder.
pub const SUMMARY_FILE: &str = "summary.json";

/// What a `summary.json` without a `files` key (written before the key existed) stands for.
const LEGACY_RESULTS: [&str; 2] = ["trajectory.csv", "inverse.csv"];

/// Removes from `dir` the results of the run before (see the module docs) and returns the
/// paths removed. A folder that does not exist, or holds no summary, has nothing to remove.
/// Only plain file names are honoured: an entry with a path separator or `..`, or one that
/// is not a regular file, is left alone.
pub fn remove_previous_results(dir: &Path) -> Result<Vec<PathBuf>, OutputError> {
    let mut names = listed_files(&dir.join(SUMMARY_FILE));
    names.push(SUMMARY_FILE.to_string());
    if let Ok(entries) = std::fs::read_dir(dir) {
        names.extend(
            entries
                .filter_map(|e| e.ok()?.file_name().into_string().ok())
                .filter(|n| n.starts_with('.') && n.contains(PARTIAL)),
        );
    }
    let mut removed = Vec::new();
    for name in names.iter().filter(|n| is_plain_name(n)) {
        let path = dir.join(name);
        if path.symlink_metadata().is_ok_and(|m| m.is_file()) {
            std::fs::remove_file(&path).map_err(|e| OutputError::io(&path, e))?;
            removed.push(path);
        }
    }
    Ok(removed)
}

/// The `files` a summary lists; [`LEGACY_RESULTS`] for one without the key; none when there
/// is no readable summary.
fn listed_files(summary: &Path) -> Vec<String> {
    let Ok(text) = std::fs::read_to_string(summary) else {
        return Vec::new();
    };
    let Ok(json) = serde_json::from_str::<serde_json::Value>(&text) else {
        return Vec::new();
    };
    match json.get("files").and_then(|f| f.as_array()) {
        Some(files) => files
            .iter()
            .filter_map(|f| f.as_str().map(str::to_string))
            .collect(),
        None => LEGACY_RESULTS.map(String::from).to_vec(),
    }
}

/// True for a single normal path component (`phi.png`), never `..`, `a/b` or `/x`.
fn is_plain_name(name: &str) -> bool {
    let mut parts = Path::new(name).components();
    matches!(
        (parts.next(), parts.next()),
        (Some(Component::Normal(_)), None)
    )
}
