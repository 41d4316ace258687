//! The output folder a run owns, and how a failed run is recorded there.
//!
//! Once the options are checked, a run claims its folder: it takes the folder's lock (a
//! second run into a folder in use is refused: [`FolderLock`]) and writes every file into
//! a staging folder inside it ([`Staging`]). When the run ends, completed or failed, its
//! results replace the previous run's whole: the files the previous `summary.json` lists
//! (only if that summary is ours) go, the new ones come in, the user's other files stay.
//! Until then the previous results are untouched, so a run that is killed, or cannot even
//! write its summary, leaves them as they were. A run that fails, even before its first
//! sample (an unreadable declaration, a bad `--set`, an assembly that fails), still writes
//! a `summary.json` with `status: failed`, the stage and the error, and that summary
//! replaces the previous results: a folder never shows older results as current.

use std::path::{Path, PathBuf};

use super::CliError;
use super::args::CommonArgs;
use super::load::{is_file_spec, key_of, load};
use mechanism::System;
use mechanism::output::summary::NamedValues;
use mechanism::output::{FolderLock, OutputError, Staging};
use mechanism_codegen::Tangents;

/// The folder of one run and the files written into it so far.
pub struct RunDir {
    staging: Staging,
    /// Data files (CSV), then figures, in the order written (in the staging folder).
    data: Vec<PathBuf>,
    figures: Vec<PathBuf>,
    /// Held until the run's results are swapped in (declared last: dropped last).
    _lock: FolderLock,
}

impl RunDir {
    /// The folder of a run of `common` (`--out`, or `out/<key>`), locked, with a fresh
    /// staging folder; `None` when there is none to claim (an unknown mechanism name and no
    /// `--out`).
    pub fn claim(common: &CommonArgs) -> Result<Option<Self>, CliError> {
        let dir = match (&common.out, key_of(&common.mechanism)) {
            (Some(out), _) => out.clone(),
            (None, Some(key)) => Path::new("out").join(key),
            (None, None) => return Ok(None),
        };
        let lock = FolderLock::acquire(&dir)?;
        let staging = Staging::begin(&lock)?;
        Ok(Some(Self {
            staging,
            data: Vec::new(),
            figures: Vec::new(),
            _lock: lock,
        }))
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
        self.staging.commit()
    }
}

/// Runs `run` in the output folder of `common` (options already checked): claims the
/// folder ([`RunDir::claim`]), runs, and when the run fails without having recorded it,
/// writes the summary `failed_summary` makes of what is known; then the results replace the
/// previous ones ([`RunDir::end`]). With no folder to claim (an unknown name or a missing
/// file, and no `--out`) nothing is touched and the error is the loader's.
pub fn owning_folder(
    common: &CommonArgs,
    run: impl FnOnce(&mut RunDir, &mut Known) -> Result<(), Failure>,
    failed_summary: impl FnOnce(Known, &Failure, &RunDir) -> Result<(), OutputError>,
) -> Result<(), CliError> {
    // A file that is not there (a typo, a folder) names no folder of its own, as an
    // unknown name does not: without `--out` its error comes before any folder is claimed,
    // so that it neither replaces the results in out/<stem> with a failed summary nor
    // leaves a new folder behind. (A folder given with `--out` records the failure.)
    let missing = common.out.is_none()
        && is_file_spec(&common.mechanism)
        && !Path::new(&common.mechanism).is_file();
    let claimed = if missing {
        None
    } else {
        RunDir::claim(common)?
    };
    let Some(mut out) = claimed else {
        return load(&common.mechanism, Tangents::None).map(|_| ());
    };
    let mut known = Known::given(common);
    let failure = match run(&mut out, &mut known) {
        Ok(()) => return out.end().map(|_| ()).map_err(CliError::Output),
        Err(failure) => failure,
    };
    if !failure.summarized {
        // The run's own error is what the user needs; a summary that cannot be written
        // either (a full disk) adds nothing to it.
        let _ = failed_summary(known, &failure, &out);
    }
    // Likewise a swap that fails: the run's error comes first.
    let _ = out.end();
    Err(*failure.error)
}

/// Where a run stopped and why.
pub struct Failure {
    /// `setup`, `assembly`, `integration`, `inverse dynamics` or `output`.
    pub stage: &'static str,
    /// Why (boxed: the error is large and a failure is rare).
    pub error: Box<CliError>,
    /// The run already wrote its `summary.json` saying so.
    pub summarized: bool,
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

/// What a failed run's summary can say about the mechanism: its name and parameters once
/// it is loaded, the name given before.
pub struct Known {
    /// The mechanism's declared name, or the name given.
    pub mechanism: String,
    /// Parameter values by name (empty before loading).
    pub parameters: NamedValues,
}

impl Known {
    /// What is known before loading: the name given.
    pub fn given(common: &CommonArgs) -> Self {
        Self {
            mechanism: key_of(&common.mechanism).unwrap_or_else(|| common.mechanism.clone()),
            parameters: NamedValues::default(),
        }
    }

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
