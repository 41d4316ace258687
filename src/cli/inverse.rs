//! `mechanism inverse`: the driving force for a prescribed motion, and the joint reactions.
//! Writes inverse.csv, the figures and summary.json (see [`RunDir`] for the folder).

use std::fmt::Write as _;

use super::CliError;
use super::args::{CommonArgs, InverseArgs};
use super::drawing::write_drawing;
use super::load::{Loaded, did_you_mean, load};
use super::physical::{apply_sets, initial_values};
use super::run_dir::{At, Failure, Known, OUTPUT, RunDir, output_folder, owning_folder};
use super::seed::figure_names;
use super::stdio::print;
use super::validate::{check_csv_size, check_span};
use mechanism::AssemblyOptions;
use mechanism::output::Unit;
use mechanism::output::{
    CoordinateSeries, Figure, FigureNames, Figures, InverseSummary, InverseTable, OutputError,
    SUMMARY_FILE, excursion_lines, inverse_excursions, plot_coordinates, plot_driving_torque,
    write_inverse_csv, write_inverse_summary,
};
use mechanism::{Drive, System, parse_drive};
use mechanism::{check_inverse_dynamics, inverse_dynamics_from, sample_times};
use mechanism_codegen::Tangents;

/// Runs `inverse` with `a`: everything that can refuse the run is checked ([`prepare`]),
/// with the output folder untouched; then the folder is claimed ([`owning_folder`]) and the
/// run starts. A failure from the first position solve on leaves a `summary.json` saying
/// where and why.
pub fn run(a: &InverseArgs) -> Result<(), CliError> {
    check_span(&a.common)?;
    super::floating::refuse(&a.common.mechanism, "inverse")?;
    let prepared = prepare(a)?;
    let dir = output_folder(&a.common, &prepared.loaded.key);
    let known = Known::of(prepared.loaded.system.as_ref());
    let run = |out: &mut RunDir, known: &mut Known| inverse(a, prepared, out, known);
    owning_folder(&dir, "inverse.csv", known, run, |known, failure, out| {
        let mut summary = InverseSummary::not_started(
            &known.mechanism,
            known.parameters,
            &a.drive,
            failure.stage,
            &failure.error,
        );
        summary.outcome.files = out.names();
        write_inverse_summary(&out.file(SUMMARY_FILE), &summary)
    })
}

/// A run checked and ready to start: the mechanism with its `--set` values, the drives,
/// the sample times and the guesses the first position solve starts from.
struct Prepared {
    loaded: Loaded,
    drives: Vec<Drive>,
    times: Vec<f64>,
    guess: Vec<f64>,
}

/// Everything that refuses a run before it starts, with nothing written: the mechanism
/// loaded, `--set`, `--drive` and `--init` applied and checked, the CSV's size, and the
/// library's own refusals ([`check_inverse_dynamics`]: a coordinate driven twice, an output
/// too large to hold).
fn prepare(a: &InverseArgs) -> Result<Prepared, CliError> {
    let mut loaded = load(&a.common.mechanism, Tangents::None)?;
    apply_sets(&mut loaded, &a.common.set)?;
    let system = loaded.system.as_ref();
    let drives = a
        .drive
        .iter()
        .map(|d| drive(system, d))
        .collect::<Result<Vec<_>, _>>()?;
    let info = system.info();
    let columns = 1 + 3 * info.n() + drives.len() + info.m();
    check_csv_size(&a.common, "inverse.csv", columns)?;
    let times = sample_times(0.0, a.common.t_end, a.common.samples_per_second);
    let guess = guesses(system, &a.common, &drives)?;
    check_inverse_dynamics(system, &drives, &times)?;
    Ok(Prepared {
        loaded,
        drives,
        times,
        guess,
    })
}

/// The run itself: solve along the drives, write.
fn inverse(
    a: &InverseArgs,
    prepared: Prepared,
    out: &mut RunDir,
    known: &mut Known,
) -> Result<(), Failure> {
    let Prepared {
        mut loaded,
        drives,
        times,
        guess,
    } = prepared;
    let system = loaded.system.as_ref();
    let info = system.info();
    let result = inverse_dynamics_from(system, drives, &guess, &times, &AssemblyOptions::default())
        .at("inverse dynamics")?;
    let table = InverseTable {
        coordinates: info.coordinates.clone(),
        driven: result
            .driven
            .iter()
            .map(|&k| info.coordinates[k].clone())
            .collect(),
        constraints: info.m(),
        rows: result.into_rows(),
    };
    let parameters = std::mem::take(&mut known.parameters);
    let mut summary = InverseSummary::new(&known.mechanism, parameters, &a.drive, &table);
    summary.joint_limit_excursions = inverse_excursions(info, &table);
    let figures = a.common.figures.resolve(info.n());
    let names = figure_names(&loaded.key, system);
    write_data(&table, out, &names, figures).at(OUTPUT)?;
    let n = info.n();
    let rows = &table.rows;
    let drawing = write_drawing(system, &a.common, out.staging(), rows.len(), |i| {
        (rows[i][0], &rows[i][1..1 + n])
    })
    .at(OUTPUT)?;
    out.wrote_figures(drawing);
    summary.outcome.files = out.names();
    write_inverse_summary(&out.file(SUMMARY_FILE), &summary).at(OUTPUT)?;
    let mut text = String::new();
    for (name, peak) in &summary.max_abs_driving_force.0 {
        let samples = summary.samples;
        let _ = writeln!(
            text,
            "{name}: max |tau| = {peak:.6e} over {samples} samples"
        );
    }
    let passed = &summary.joint_limit_excursions;
    if !passed.is_empty() {
        let _ = writeln!(
            text,
            "the motion and its driving forces pass {} declared joint limit(s) \
             (summary.json, joint_limit_excursions):",
            passed.len()
        );
        for line in excursion_lines(passed, 8) {
            let _ = writeln!(text, "  {line}");
        }
    }
    let _ = writeln!(text, "{}", out.wrote());
    loaded.source.clear();
    print(&text).map_err(|e| Failure {
        stage: OUTPUT,
        error: Box::new(e),
        summarized: true,
    })
}

/// The drive `text` (`COORD = f(t)`) of `system`; an unknown coordinate is named with the
/// likely one it mistypes, the coordinates and which of them are independent.
fn drive(system: &dyn System, text: &str) -> Result<Drive, CliError> {
    let info = system.info();
    if let Some((name, _)) = text.split_once('=')
        && info.coordinate_index(name.trim()).is_none()
    {
        let name = name.trim();
        let independent: Vec<&str> = info
            .independent
            .iter()
            .map(|i| info.coordinates[i.coordinate].as_str())
            .collect();
        return Err(CliError::Argument(format!(
            "--drive `{text}`: unknown coordinate `{name}`{}; coordinates: {} (independent: {})",
            did_you_mean(name, &info.coordinates),
            info.coordinates.join(", "),
            independent.join(", ")
        )));
    }
    parse_drive(system, text).map_err(|e| CliError::Argument(format!("--drive: {e}")))
}

/// inverse.csv, the coordinate figures `figures` asks for and the driving-torque figure.
fn write_data(
    table: &InverseTable,
    out: &mut RunDir,
    names: &FigureNames,
    figures: Figures,
) -> Result<(), OutputError> {
    let csv = out.file("inverse.csv");
    write_inverse_csv(&csv, table)?;
    out.wrote_data(csv);
    if figures == Figures::None {
        return Ok(());
    }
    let t = table.times();
    let n = table.coordinates.len();
    let series = CoordinateSeries {
        names: &table.coordinates,
        units: table.coordinates.iter().map(|c| Unit::guess(c)).collect(),
        t: &t,
        q: (0..n).map(|i| table.positions(i)).collect(),
        qd: (0..n).map(|i| table.rates(i)).collect(),
    };
    out.wrote_figures(plot_coordinates(out.staging(), names, &series, figures)?);
    let stem = out.file(&names.stem(Figure::DrivingTorque));
    out.wrote_figures(plot_driving_torque(&stem, table, Unit::guess)?);
    Ok(())
}

/// The guesses the first position solve starts from: the declared ones, with each
/// `--init COORD=VALUE` in place (to pick the assembly branch). A driven coordinate's value
/// and every rate follow from the drives: `--init` of one is refused.
fn guesses(
    system: &dyn System,
    common: &CommonArgs,
    drives: &[Drive],
) -> Result<Vec<f64>, CliError> {
    let info = system.info();
    for s in &common.init {
        let lhs = s.split('=').next().unwrap_or_default().trim();
        if lhs.starts_with("der(") {
            return Err(CliError::Argument(format!(
                "--init {lhs}: in inverse the rates follow from the drives; --init gives guesses of positions"
            )));
        }
        if let Some(d) = drives
            .iter()
            .find(|d| info.coordinates[d.coordinate] == lhs)
        {
            return Err(CliError::Argument(format!(
                "--init {lhs}: `{}` is driven; its drive prescribes it",
                info.coordinates[d.coordinate]
            )));
        }
    }
    let (independent, mut guess) = initial_values(system, common)?;
    for i in independent {
        guess[i.coordinate] = i.position;
    }
    Ok(guess)
}
