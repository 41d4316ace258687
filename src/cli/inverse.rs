//! `mechanism inverse`: the driving force for a prescribed motion, and the joint reactions.

use super::CliError;
use super::args::InverseArgs;
use super::load::{apply_sets, load};
use super::simulate::out_dir;
use super::validate::{check_csv_size, check_span};
use mechanism::AssemblyOptions;
use mechanism::output::plot::{Unit, figure_stem, plot_coordinate};
use mechanism::output::{Figure, InverseTable, plot_driving_torque, write_inverse_csv};
use mechanism::parse_drive;
use mechanism::{inverse_dynamics, sample_times};

/// Runs `inverse` with `a`.
pub fn run(a: &InverseArgs) -> Result<(), CliError> {
    check_span(&a.common)?;
    if !a.common.init.is_empty() {
        return Err(CliError::Argument(
            "--init does not apply to inverse: the drives prescribe the motion".into(),
        ));
    }
    let mut loaded = load(&a.common.mechanism)?;
    apply_sets(loaded.system.as_mut(), &a.common.set)?;
    let system = loaded.system.as_ref();
    let drives = a
        .drive
        .iter()
        .map(|d| parse_drive(system, d).map_err(|e| CliError::Argument(format!("--drive: {e}"))))
        .collect::<Result<Vec<_>, _>>()?;
    let info = system.info();
    let columns = 1 + 3 * info.n() + drives.len() + info.m();
    check_csv_size(&a.common, "inverse.csv", columns)?;
    let times = sample_times(0.0, a.common.t_end, a.common.samples_per_second);
    let result = inverse_dynamics(system, drives, &times, &AssemblyOptions::default())?;
    let info = &result.info;
    let table = InverseTable {
        coordinates: info.coordinates.clone(),
        driven: result
            .driven
            .iter()
            .map(|&k| info.coordinates[k].clone())
            .collect(),
        constraints: info.m(),
        rows: result.rows(),
    };
    let dir = out_dir(&a.common, &loaded.key);
    write_inverse_csv(&dir.join("inverse.csv"), &table)?;
    let mut files = vec![dir.join("inverse.csv")];
    let t: Vec<f64> = result.samples.iter().map(|s| s.t).collect();
    for (i, name) in info.coordinates.iter().enumerate() {
        let q: Vec<f64> = result.samples.iter().map(|s| s.q[i]).collect();
        let qd: Vec<f64> = result.samples.iter().map(|s| s.qd[i]).collect();
        let stem = dir.join(figure_stem(&loaded.key, Figure::Coordinate(name)));
        files.extend(plot_coordinate(
            &stem,
            name,
            Unit::guess(name),
            &t,
            &q,
            &qd,
        )?);
    }
    let stem = dir.join(figure_stem(&loaded.key, Figure::DrivingTorque));
    files.extend(plot_driving_torque(&stem, &table, Unit::guess)?);
    let peak = |k: usize| {
        result
            .samples
            .iter()
            .fold(0.0_f64, |a, s| a.max(s.driving[k].abs()))
    };
    for (k, name) in table.driven.iter().enumerate() {
        println!(
            "tau_{name}: max |tau| = {:.6e} over {} samples",
            peak(k),
            result.samples.len()
        );
    }
    let names: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
    println!("wrote {}", names.join(", "));
    loaded.source.clear();
    Ok(())
}
