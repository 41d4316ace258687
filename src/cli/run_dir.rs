//! The output folder a run owns, and how a failed run is recorded there.
//!
//! Once the options are checked, a run claims its folder: the results of the run before
//! (the files its `summary.json` lists) are removed first, so that whatever happens next
//! the folder never shows older results as current; the user's other files stay. Every
//! file the run writes is recorded, and its `summary.json` lists them. A run that fails,
//! even before its first sample (an unreadable declaration, a bad `--set`, an assembly
//! that fails), still writes a `summary.json` with `status: failed`, the stage and the
//! error.

use std::path::{Path, PathBuf};

use super::CliError;
use super::args::CommonArgs;
use super::load::{key_of, load};
use mechanism::System;
use mechanism::output::summary::NamedValues;
use mechanism::output::{OutputError, remove_previous_results};

/// The folder of one run and the files written into it so far.
pub struct RunDir {
    dir: PathBuf,
    /// Data files (CSV), then figures, in the order written.
    data: Vec<PathBuf>,
    figures: Vec<PathBuf>,
}

impl RunDir {
    /// The folder of a run of `common` (`--out`, or `out/<key>`) with the previous run's
    /// results removed; `None` when there is none to claim (an unknown mechanism name and
    /// no `--out`).
    pub fn claim(common: &CommonArgs) -> Result<Option<Self>, CliError> {
        let dir = match (&common.out, key_of(&common.mechanism)) {
            (Some(out), _) => out.clone(),
            (None, Some(key)) => Path::new("out").join(key),
            (None, None) => return Ok(None),
        };
        remove_previous_results(&dir)?;
        Ok(Some(Self {
            dir,
            data: Vec::new(),
            figures: Vec::new(),
        }))
    }

    /// The folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The path of `name` in the folder.
    pub fn file(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }

    /// Records a data file written.
    pub fn wrote_data(&mut self, path: PathBuf) {
        self.data.push(path);
    }

    /// Records figures written.
    pub fn wrote_figures(&mut self, paths: Vec<PathBuf>) {
        self.figures.extend(paths);
    }

    /// Every file of the run: the data, then `summary.json`, then the figures.
    pub fn paths(&self) -> Vec<PathBuf> {
        let summary = self.file(mechanism::output::SUMMARY_FILE);
        let data = self.data.iter().cloned();
        data.chain([summary])
            .chain(self.figures.iter().cloned())
            .collect()
    }

    /// [`RunDir::paths`] by file name, as `summary.json` lists them.
    pub fn names(&self) -> Vec<String> {
        self.paths()
            .iter()
            .filter_map(|p| p.file_name())
            .map(|n| n.to_string_lossy().into_owned())
            .collect()
    }

    /// [`RunDir::paths`] as printed.
    pub fn displayed(&self) -> Vec<String> {
        self.paths()
            .iter()
            .map(|p| p.display().to_string())
            .collect()
    }
}

/// Runs `run` in the output folder of `common` (options already checked): claims the
/// folder ([`RunDir::claim`]), runs, and when the run fails without having recorded it,
/// writes the summary `failed_summary` makes of what is known. With no folder to claim
/// (an unknown name and no `--out`) nothing is touched and the error is the loader's.
pub fn owning_folder(
    common: &CommonArgs,
    run: impl FnOnce(&mut RunDir, &mut Known) -> Result<(), Failure>,
    failed_summary: impl FnOnce(Known, &Failure, &RunDir) -> Result<(), OutputError>,
) -> Result<(), CliError> {
    let Some(mut out) = RunDir::claim(common)? else {
        return load(&common.mechanism).map(|_| ());
    };
    let mut known = Known::given(common);
    let failure = match run(&mut out, &mut known) {
        Ok(()) => return Ok(()),
        Err(failure) => failure,
    };
    if !failure.summarized {
        // The run's own error is what the user needs; a summary that cannot be written
        // either (a full disk) adds nothing to it.
        let _ = failed_summary(known, &failure, &out);
    }
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
