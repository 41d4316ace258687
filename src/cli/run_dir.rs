//! The output folder a run owns, and how a failed run is recorded there.
//!
//! A run is refused before it starts (an unknown mechanism, a missing file, a bad `--set`,
//! `--init` or `--drive`, an output too large, a fixed step too small: everything checked
//! before the assembly) without touching its folder: the command checks all of it first,
//! and only then claims the folder ([`owning_folder`]). Claiming takes the folder's lock (a
//! second run into a folder in use is refused: [`FolderLock`]) and a staging folder inside
//! it ([`Staging`]) that every file is written into.
//!
//! When a run that started ends, completed or failed, its results replace the previous
//! run's whole: the files the previous `summary.json` lists (only if that summary is ours)
//! go, the new ones come in, the user's other files stay. A run that fails after it started
//! (the assembly, the integration, the inverse dynamics) writes a `summary.json` with
//! `status: failed`, the stage and the error, and that summary replaces the previous
//! results: a folder never shows older results as current. Until then the previous results
//! are untouched, and they stay so when the new results cannot all be written (a full
//! disk, a folder in the place of a file: the error says the folder is left as it was), or
//! when the run is killed. An interrupt (SIGINT, SIGTERM) that comes during the swap waits
//! until it is done ([`signals::deferred`]).

use std::path::{Path, PathBuf};

use super::args::CommonArgs;
use super::{CliError, signals};
use mechanism::System;
use mechanism::output::summary::NamedValues;
use mechanism::output::{FolderLock, OutputError, SUMMARY_FILE, Staging, check_target};

/// The folder of one run and the files written into it so far.
pub struct RunDir {
    staging: Staging,
    /// Data files (CSV), then figures, in the order written (in the staging folder).
    data: Vec<PathBuf>,
    figures: Vec<PathBuf>,
    /// Whether claiming the folder created it (removed again if the run leaves it empty).
    created: bool,
    /// Held until the run's results are swapped in (declared last: dropped last).
    lock: FolderLock,
}

impl RunDir {
    /// Claims `dir` for a run whose data file is `data` (`trajectory.csv`): refused before
    /// anything is touched when `summary.json` or `data` there is not a regular file (the
    /// swap could not put the results in: [`check_target`]), else locked, with a fresh
    /// staging folder.
    fn claim(dir: &Path, data: &str) -> Result<Self, CliError> {
        for name in [SUMMARY_FILE, data] {
            check_target(&dir.join(name))?;
        }
        let created = !dir.exists();
        let lock = FolderLock::acquire(dir)?;
        // It may complete the swap of a run killed midway: not to be cut short either.
        let staging = signals::deferred(|| Staging::begin(&lock))?;
        Ok(Self {
            staging,
            data: Vec::new(),
            figures: Vec::new(),
            created,
            lock,
        })
    }
    /// The output folder (where the results are once the run ends).
    pub fn dir(&self) -> &Path {
        self.staging.target()
    }

    /// The staging folder the run writes into.
    pub fn staging(&self) -> &Path {
        self.staging.path()
    }

    /// The path of `name` in the staging folder.
    pub fn file(&self, name: &str) -> PathBuf {
        self.staging().join(name)
    }

    /// Records a data file written.
    pub fn wrote_data(&mut self, path: PathBuf) {
        self.data.push(path);
    }

    /// Records figures written.
    pub fn wrote_figures(&mut self, paths: Vec<PathBuf>) {
        self.figures.extend(paths);
    }

    /// [`RunDir::paths`] by file name, as `summary.json` lists them: the data, then
    /// `summary.json`, then the figures.
    pub fn names(&self) -> Vec<String> {
        let summary = PathBuf::from(mechanism::output::SUMMARY_FILE);
        let data = self.data.iter();
        data.chain([&summary])
            .chain(&self.figures)
            .filter_map(|p| p.file_name())
            .map(|n| n.to_string_lossy().into_owned())
            .collect()
    }

    /// The line that says what the run wrote: the folder and how many files (their list is
    /// `summary.json`'s `files`; a large mechanism's would fill the terminal).
    pub fn wrote(&self) -> String {
        let count = self.names().len();
        let files = if count == 1 { "file" } else { "files" };
        format!(
            "wrote {count} {files} to {} (listed in summary.json)",
            self.dir().display()
        )
    }

    /// Swaps the staged results in when the summary is staged, else leaves the previous
    /// results as they were ([`Staging::commit`]); then releases the folder.
    fn end(self) -> Result<bool, OutputError> {
        let Self {
            staging,
            created,
            lock,
            ..
        } = self;
        // An interrupt waits for the swap: the folder holds the previous results or these.
        signals::deferred(|| {
            let swapped = staging.commit();
            release(lock, created);
            swapped
        })
    }

    /// Discards the staged results, leaving the folder as it was ([`Staging::discard`]);
    /// then releases it (and removes it if the claim created it).
    fn discard(self) {
        let Self {
            staging,
            created,
            lock,
            ..
        } = self;
        // A staging folder that cannot be removed is the next run's to remove.
        let _ = staging.discard();
        release(lock, created);
    }
}

/// Releases `lock`, then removes its folder if the claim `created` it and nothing is in it.
fn release(lock: FolderLock, created: bool) {
    let dir = lock.dir().to_path_buf();
    drop(lock);
    if created {
        // Fails, as it should, when the folder holds anything.
        let _ = std::fs::remove_dir(&dir);
    }
}

/// The output folder of a run of `common` whose mechanism's key is `key`: `--out`, or
/// `out/<key>`.
pub fn output_folder(common: &CommonArgs, key: &str) -> PathBuf {
    match &common.out {
        Some(out) => out.clone(),
        None => Path::new("out").join(key),
    }
}

/// Runs `run` in `dir` (everything that can refuse the run checked already): claims the
/// folder ([`RunDir::claim`], with the run's data file `data`), runs, and ends:
///
/// - the run completed: its results replace the previous ones;
/// - it failed after it started: the summary `failed_summary` makes of `known` and the
///   failure (unless the run wrote its own) is staged, and the results replace the
///   previous ones;
/// - its results could not all be written ([`Failure::replaces`] false), or the swap
///   fails: the folder is left as it was, and the error says so.
pub fn owning_folder(
    dir: &Path,
    data: &str,
    mut known: Known,
    run: impl FnOnce(&mut RunDir, &mut Known) -> Result<(), Failure>,
    failed_summary: impl FnOnce(Known, &Failure, &RunDir) -> Result<(), OutputError>,
) -> Result<(), CliError> {
    let mut out = RunDir::claim(dir, data)?;
    let failure = match run(&mut out, &mut known) {
        Ok(()) => {
            return out
                .end()
                .map(|_| ())
                .map_err(|e| left_as_it_was(e.into(), None, dir));
        }
        Err(failure) => failure,
    };
    if !failure.replaces() {
        out.discard();
        return Err(match *failure.error {
            said @ CliError::NotReplaced { .. } => said,
            error => left_as_it_was(error, None, dir),
        });
    }
    // The run's own error is what the user needs; a summary that cannot be written either
    // (a full disk) only means that the folder stays as it was.
    let summary = if failure.summarized {
        Ok(())
    } else {
        failed_summary(known, &failure, &out)
    };
    match (summary, out.end()) {
        (Ok(()), Ok(true)) => Err(*failure.error),
        (Err(e), _) | (Ok(()), Err(e)) => Err(left_as_it_was(*failure.error, Some(e), dir)),
        (Ok(()), Ok(false)) => Err(left_as_it_was(*failure.error, None, dir)),
    }
}

/// `error`, said to have left `dir` as it was (with `why` the results could not be put
/// in, when that is another error).
pub fn left_as_it_was(error: CliError, why: Option<OutputError>, dir: &Path) -> CliError {
    CliError::NotReplaced {
        error: Box::new(error),
        why: why.map(|e| e.to_string()),
        dir: dir.display().to_string(),
    }
}

/// Where a run stopped and why.
pub struct Failure {
    /// `assembly`, `integration`, `inverse dynamics` or [`OUTPUT`].
    pub stage: &'static str,
    /// Why (boxed: the error is large and a failure is rare).
    pub error: Box<CliError>,
    /// The run already wrote its `summary.json` saying so.
    pub summarized: bool,
}

/// The stage of writing the results.
pub const OUTPUT: &str = "output";

impl Failure {
    /// False when the run's results could not all be written (a failure in [`OUTPUT`]
    /// before its summary was staged): they replace nothing. A failure after the summary
    /// (printing the report) leaves complete results, which replace the previous ones.
    pub fn replaces(&self) -> bool {
        self.stage != OUTPUT || self.summarized
    }
}

/// Tags an error with the stage of the run it stopped.
pub trait At<T> {
    /// `Err(e)` becomes a [`Failure`] in `stage` with no summary written yet.
    fn at(self, stage: &'static str) -> Result<T, Failure>;
}

impl<T, E: Into<CliError>> At<T> for Result<T, E> {
    fn at(self, stage: &'static str) -> Result<T, Failure> {
        self.map_err(|e| Failure {
            stage,
            error: Box::new(e.into()),
            summarized: false,
        })
    }
}

/// What a failed run's summary says about the mechanism: its name and parameters.
pub struct Known {
    /// The mechanism's declared name.
    pub mechanism: String,
    /// Parameter values by name.
    pub parameters: NamedValues,
}

impl Known {
    /// The declared name and current parameter values of `system`.
    pub fn of(system: &dyn System) -> Self {
        let info = system.info();
        let mut values = vec![0.0; info.parameters.len()];
        system.parameter_values(&mut values);
        Self {
            mechanism: info.name.clone(),
            parameters: NamedValues::zip(&info.parameters, &values).unwrap_or_default(),
        }
    }
}
