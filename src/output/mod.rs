//! Result files of a run: `trajectory.csv`, `inverse.csv`, `summary.json` and the figures.
//!
//! File names and column headers are stable: other tools and the tests read them.
//!
//! - [`csv`]: [`write_trajectory_csv`] and [`write_inverse_csv`], every value written with
//!   the shortest decimal representation that parses back to the same `f64` bit for bit.
//! - [`summary`]: [`Summary`], serialised to `summary.json`, with the maxima of the
//!   constraint residuals and of the energy balance error ([`TrajectoryMaxima`]).
//! - [`plot`]: PNG and SVG figures (seed Figures 3.1–3.5, the driving torque, the overview
//!   of a large mechanism, the strobe figure), as many as [`Figures`] asks for.
//!
//! - The output folder belongs to one run at a time: [`FolderLock`] (a lock file held for
//!   the run), [`Staging`] (the run writes apart; its results replace the previous ones
//!   whole when it ends), [`remove_previous_results`] (only the files our own marked
//!   `summary.json` lists are ever removed: the user's other files stay).
//!
//! Every file is written under a temporary name and renamed when complete
//! ([`write_atomically`]), so none is ever left half-written. Every function returns
//! `Result<_, OutputError>`; none panics on bad data. CSV and JSON need the cargo feature
//! `files`, the figures `plots` (both on by default).

#[cfg(feature = "files")]
pub mod animation;
mod atomic;
#[cfg(feature = "files")]
pub mod csv;
#[cfg(feature = "files")]
mod excursions;
#[cfg(feature = "files")]
mod floating_summary;
#[cfg(feature = "files")]
mod inverse_summary;
mod lock;
#[cfg(feature = "files")]
mod outcome;
#[cfg(feature = "plots")]
pub mod plot;
#[cfg(feature = "files")]
mod previous;
mod scene;
#[cfg(feature = "files")]
mod staging;
#[cfg(feature = "files")]
pub mod summary;
mod table;
mod unit;

#[cfg(feature = "files")]
pub use self::animation::{MAX_FRAMES, animation_html, write_animation};
pub use self::atomic::{check_target, temporary_path, write_atomically};
#[cfg(feature = "files")]
pub use self::csv::{write_inverse_csv, write_trajectory_csv};
#[cfg(feature = "files")]
pub use self::excursions::{LimitExcursion, LimitWatch, excursion_lines, inverse_excursions};
#[cfg(feature = "files")]
pub use self::floating_summary::{
    Conservation, FloatingInitialState, FloatingSummary, write_floating_summary,
};
#[cfg(feature = "files")]
pub use self::inverse_summary::{InverseSummary, write_inverse_summary};
pub use self::lock::{FolderLock, LOCK_FILE};
#[cfg(feature = "files")]
pub use self::outcome::Outcome;
#[cfg(feature = "plots")]
pub use self::plot::{
    CoordinateSeries, Figure, FigureNames, Figures, MAX_LEGEND, PER_COORDINATE_LIMIT, View,
    plot_constraint_error, plot_coordinate, plot_coordinate_scaled, plot_coordinates,
    plot_driving_torque, plot_overview, plot_run, plot_strobe, plot_trajectory, strobe_frames,
};
#[cfg(feature = "files")]
pub use self::previous::{
    SUMMARY_FILE, SUMMARY_FORMAT, SUMMARY_FORMAT_VERSION, is_ours, remove_previous_results,
};
pub use self::scene::{Cycle, MAX_VALUES, Scene, SceneCoordinate, ScenePoint};
#[cfg(feature = "files")]
pub use self::staging::{STAGING_FOLDER, Staging};
#[cfg(feature = "files")]
pub use self::summary::{
    MobilityReport, PassageReport, RunSettings, Summary, TrajectoryMaxima, write_summary,
};
pub use self::table::InverseTable;
pub use self::unit::Unit;

use std::path::PathBuf;

/// Everything that can go wrong while writing result files.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// Creating a directory or writing a file failed.
    #[error("cannot write {path}: {source}")]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The CSV writer failed.
    #[cfg(feature = "files")]
    #[error("cannot write CSV {path}: {source}")]
    Csv {
        /// The CSV file.
        path: PathBuf,
        /// The underlying error.
        source: ::csv::Error,
    },
    /// Serialising `summary.json` failed.
    #[cfg(feature = "files")]
    #[error("cannot write JSON {path}: {source}")]
    Json {
        /// The JSON file.
        path: PathBuf,
        /// The underlying error.
        source: serde_json::Error,
    },
    /// Drawing or encoding a figure failed.
    #[error("cannot draw figure {path}: {message}")]
    Plot {
        /// The figure file.
        path: PathBuf,
        /// What plotters reported.
        message: String,
    },
    /// Another run holds the output folder ([`FolderLock`]).
    #[error(
        "the output folder {dir} is in use by another run ({holder}): wait for it to end or \
         write elsewhere; a run that died leaves no hold on it"
    )]
    Locked {
        /// The folder.
        dir: PathBuf,
        /// Who holds it: `process <id>` from the lock file.
        holder: String,
    },
    /// The lock file of an output folder exists and is not a regular file (a symbolic
    /// link, which is never followed, a directory, a device or a named pipe).
    #[error(
        "the lock file {path} is {kind}, not a regular file: a run never writes through it; \
         remove it (each run creates its own) or write elsewhere"
    )]
    LockNotAFile {
        /// The lock file.
        path: PathBuf,
        /// What it is: `a symbolic link`, `a directory`, `a device or a named pipe`.
        kind: &'static str,
    },
    /// The target of a result file exists and is not a regular file (a directory, a
    /// device, a named pipe or a symbolic link): renaming over it would replace it.
    #[error("cannot write {path}: it exists and is {kind}, not a regular file; write elsewhere")]
    NotAFile {
        /// The target.
        path: PathBuf,
        /// What it is: `a directory`, `a symbolic link`, `a device or a named pipe`.
        kind: &'static str,
    },
    /// An output folder whose path is an existing file (or a device).
    #[error("cannot write into {path}: it exists and is not a folder; give --out a folder")]
    NotAFolder {
        /// The path.
        path: PathBuf,
    },
    /// The input is inconsistent (empty, or series of different lengths).
    #[error("invalid data for {what}: {message}")]
    InvalidData {
        /// What was being written.
        what: String,
        /// What is wrong with it.
        message: String,
    },
}

impl OutputError {
    #[allow(dead_code)] // used by the writers of the `files` and `plots` features
    pub(crate) fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io {
            path: path.into(),
            source,
        }
    }

    #[allow(dead_code)] // used by the writers of the `files` and `plots` features
    pub(crate) fn invalid(what: impl Into<String>, message: impl Into<String>) -> Self {
        Self::InvalidData {
            what: what.into(),
            message: message.into(),
        }
    }
}

/// Creates `dir` and its parents if they do not exist.
#[allow(dead_code)] // used by the writers of the `files` and `plots` features
pub(crate) fn ensure_dir(dir: &std::path::Path) -> Result<(), OutputError> {
    // An output folder named by a path that is a file (`--out results.csv`) is said so,
    // rather than as the operating system's "File exists".
    if let Ok(meta) = std::fs::metadata(dir)
        && !meta.is_dir()
    {
        return Err(OutputError::NotAFolder {
            path: dir.to_path_buf(),
        });
    }
    std::fs::create_dir_all(dir).map_err(|e| OutputError::io(dir, e))
}
