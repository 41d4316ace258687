//! The results a previous run left in an output folder: the files its `summary.json` lists,
//! if that summary is ours.
//!
//! Our summaries open with `"format": "mechanism-summary"` and `"format_version": 1`
//! ([`SUMMARY_FORMAT`], [`SUMMARY_FORMAT_VERSION`]). A `summary.json` without them (another
//! tool's, a hand-written one, or one of ours from before the mark) is foreign: it lists
//! nothing, so a run never removes a file on its word. Of a summary of ours, only the plain
//! file names it lists count, plus any temporary `.<name>.partial.<extension>` a killed run
//! left ([`super::write_atomically`]): every other file in the folder is the user's.

use std::path::{Component, Path, PathBuf};

use super::OutputError;
use super::atomic::PARTIAL;

/// The name of the summary a run leaves in its folder.
pub const SUMMARY_FILE: &str = "summary.json";

/// The `format` key of every summary we write.
pub const SUMMARY_FORMAT: &str = "mechanism-summary";

/// The `format_version` key of every summary we write: 1 since the mark was introduced.
pub const SUMMARY_FORMAT_VERSION: u64 = 1;

/// Removes from `dir` the results of the run before (the files its `summary.json` lists,
/// when that summary is ours: [`is_ours`]; the summary included) and returns the paths
/// removed. Only regular files are removed.
pub fn remove_previous_results(dir: &Path) -> Result<Vec<PathBuf>, OutputError> {
    let mut names = previous_results(dir);
    if is_ours(&dir.join(SUMMARY_FILE)) {
        names.push(SUMMARY_FILE.to_string());
    }
    let mut removed = Vec::new();
    for name in names {
        let path = dir.join(name);
        if path.symlink_metadata().is_ok_and(|m| m.is_file()) {
            std::fs::remove_file(&path).map_err(|e| OutputError::io(&path, e))?;
            removed.push(path);
        }
    }
    Ok(removed)
}

/// The names of the previous run's results in `dir`: the plain file names our summary lists
/// (none for a foreign summary or none), and the temporaries a killed run left. An entry
/// with a path separator or `..` is never one.
pub(crate) fn previous_results(dir: &Path) -> Vec<String> {
    let mut names = listed_files(&dir.join(SUMMARY_FILE));
    if let Ok(entries) = std::fs::read_dir(dir) {
        names.extend(
            entries
                .filter_map(|e| e.ok()?.file_name().into_string().ok())
                .filter(|n| n.starts_with('.') && n.contains(PARTIAL)),
        );
    }
    names.retain(|n| is_plain_name(n));
    names
}

/// True when `summary` is a summary we wrote (it carries our format and version).
pub fn is_ours(summary: &Path) -> bool {
    read_ours(summary).is_some()
}

/// The summary at `summary` as JSON, if it is ours.
fn read_ours(summary: &Path) -> Option<serde_json::Value> {
    let text = std::fs::read_to_string(summary).ok()?;
    let json = serde_json::from_str::<serde_json::Value>(&text).ok()?;
    let format = json.get("format")?.as_str()? == SUMMARY_FORMAT;
    let version = json.get("format_version")?.as_u64()? == SUMMARY_FORMAT_VERSION;
    (format && version).then_some(json)
}

/// The `files` our summary lists; none for a foreign or unreadable one.
pub(crate) fn listed_files(summary: &Path) -> Vec<String> {
    let Some(json) = read_ours(summary) else {
        return Vec::new();
    };
    json.get("files")
        .and_then(|f| f.as_array())
        .map(|files| {
            files
                .iter()
                .filter_map(|f| f.as_str().map(str::to_string))
                .collect()
        })
        .unwrap_or_default()
}

/// True for a single normal path component (`phi.png`), never `..`, `a/b` or `/x`.
fn is_plain_name(name: &str) -> bool {
    let mut parts = Path::new(name).components();
    matches!(
        (parts.next(), parts.next()),
        (Some(Component::Normal(_)), None)
    )
}
