//! `trajectory.csv` and `inverse.csv`: exact headers, and every number read back bit for bit.

use std::path::Path;

use crate::support::{SAMPLES, info, temp_dir, trajectory};
use mechanism::output::csv::format_f64;
use mechanism::output::{InverseTable, OutputError, write_inverse_csv, write_trajectory_csv};
use mechanism::{ConstraintRow, SystemInfo, Trajectory};

/// Reads a CSV file back: (header, rows of f64).
fn read_back(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let mut reader = csv::Reader::from_path(path).expect("open CSV");
    let header = reader
        .headers()
        .expect("header")
        .iter()
        .map(String::from)
        .collect();
    let rows = reader
        .records()
        .map(|r| {
            r.expect("record")
                .iter()
                .map(|f| f.parse::<f64>().unwrap_or_else(|e| panic!("{f:?}: {e}")))
                .collect()
        })
        .collect();
    (header, rows)
}

fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

#[test]
fn trajectory_header_is_the_documented_list() {
    let dir = temp_dir("csv-header");
    let path = dir.join("trajectory.csv");
    write_trajectory_csv(&path, &trajectory("spatial_crank_slider")).expect("write");
    let expected = [
        "t",
        "phi",
        "beta",
        "gamma",
        "x_c",
        "phi_dot",
        "beta_dot",
        "gamma_dot",
        "x_c_dot",
        "phi_ddot",
        "beta_ddot",
        "gamma_ddot",
        "x_c_ddot",
        "lambda_1",
        "lambda_2",
        "lambda_3",
        "constraint_error",
        "velocity_constraint_error",
        "kinetic",
        "potential",
        "work",
    ];
    let first_line = std::fs::read_to_string(&path)
        .expect("read")
        .lines()
        .next()
        .unwrap_or_default()
        .to_string();
    assert_eq!(first_line, expected.join(","));
    let (header, rows) = read_back(&path);
    assert_eq!(header, expected);
    assert_eq!(rows.len(), SAMPLES);
}

#[test]
fn trajectory_values_round_trip_bit_for_bit() {
    let dir = temp_dir("csv-roundtrip");
    let tr = trajectory("spatial_crank_slider");
    let path = dir.join("nested/out/trajectory.csv");
    write_trajectory_csv(&path, &tr).expect("write creates the directory");
    let (_, rows) = read_back(&path);
    for (i, row) in rows.iter().enumerate() {
        assert!(
            same_bits(row, tr.row(i)),
            "row {i}: {row:?} != {:?}",
            tr.row(i)
        );
    }
}

#[test]
fn awkward_values_round_trip() {
    let awkward = [
        0.0,
        -0.0,
        0.1 + 0.2,
        1.0 / 3.0,
        -2.5e-15,
        5e-324,
        f64::MIN_POSITIVE,
        f64::MAX,
        f64::MIN,
        1e16,
        123456.789,
        1e-5,
        9.999999999999999e-6,
        -1e300,
        f64::EPSILON,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ];
    for x in awkward {
        let s = format_f64(x);
        assert_eq!(
            s.parse::<f64>().expect("parse").to_bits(),
            x.to_bits(),
            "{x:e} written as {s}"
        );
        assert!(s.len() <= 24, "{s} is not short");
    }
    assert_eq!(format_f64(0.5), "0.5");
    assert_eq!(format_f64(3.5e-13), "3.5e-13");
    assert!(
        format_f64(f64::NAN)
            .parse::<f64>()
            .expect("NaN parses")
            .is_nan()
    );

    // The same values through a whole file, NaN included.
    let info = SystemInfo {
        constraints: 1,
        constraint_rows: vec![ConstraintRow::unnamed(0)],
        velocity_rows: 0,
        energy_depends_on_time: false,
        drawing: Default::default(),
        joint_limits: Vec::new(),
        frames: Vec::new(),
        ..info("awkward")
    };
    let mut tr = Trajectory::with_capacity(info, 2);
    let q = [awkward[2], awkward[3], awkward[4], awkward[5]];
    tr.push(
        f64::MIN_POSITIVE,
        &q,
        &[-0.0, 1e-300, 1e300, 2.0],
        &[f64::NAN; 4],
        &[f64::INFINITY],
        0.0,
        1e-17,
        [1.0, -1.0, 0.0],
    );
    let path = temp_dir("csv-awkward").join("trajectory.csv");
    write_trajectory_csv(&path, &tr).expect("write");
    let (header, rows) = read_back(&path);
    assert_eq!(header.len(), tr.stride());
    let (got, want) = (&rows[0], tr.row(0));
    for (j, (a, b)) in got.iter().zip(want).enumerate() {
        assert!(
            a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
            "column {}: {a:e} != {b:e}",
            header[j]
        );
    }
}

fn inverse_table() -> InverseTable {
    let coordinates = info("x").coordinates;
    let rows = (0..5)
        .map(|i| {
            let t = f64::from(i) * 0.1;
            let mut row = vec![t];
            row.extend((0..12).map(|k| f64::from(k) + t / 7.0));
            row.extend([0.005 * (2.0 * std::f64::consts::PI * t).sin(), -t / 3.0]);
            row.extend([1.0e-3, -2.0e5 * t, t.sqrt()]);
            row
        })
        .collect();
    InverseTable {
        coordinates,
        driven: vec!["phi".into(), "x_c".into()],
        constraints: 3,
        rows,
    }
}

#[test]
fn inverse_header_and_values() {
    let table = inverse_table();
    let path = temp_dir("csv-inverse").join("inverse.csv");
    write_inverse_csv(&path, &table).expect("write");
    let expected = [
        "t",
        "phi",
        "beta",
        "gamma",
        "x_c",
        "phi_dot",
        "beta_dot",
        "gamma_dot",
        "x_c_dot",
        "phi_ddot",
        "beta_ddot",
        "gamma_ddot",
        "x_c_ddot",
        "tau_phi",
        "tau_x_c",
        "lambda_1",
        "lambda_2",
        "lambda_3",
    ];
    let (header, rows) = read_back(&path);
    assert_eq!(header, expected);
    assert_eq!(table.headers(), expected);
    assert_eq!(rows.len(), table.rows.len());
    for (got, want) in rows.iter().zip(&table.rows) {
        assert!(same_bits(got, want), "{got:?} != {want:?}");
    }
    let column = |j: usize| table.rows.iter().map(|r| r[j]).collect::<Vec<_>>();
    assert!(same_bits(&table.torque(1), &column(14)));
    // The figures' series: beta is column 2, its rate column 6.
    assert!(same_bits(&table.positions(1), &column(2)));
    assert!(same_bits(&table.rates(1), &column(6)));
    assert!(same_bits(&table.times(), &column(0)));
}

#[test]
fn ragged_inverse_rows_are_an_error() {
    let mut table = inverse_table();
    table.rows[3].pop();
    let path = temp_dir("csv-ragged").join("inverse.csv");
    let err = write_inverse_csv(&path, &table).expect_err("a short row is rejected");
    assert!(matches!(err, OutputError::InvalidData { .. }), "{err:?}");
    assert!(err.to_string().contains("row 3"), "{err}");
}

#[test]
fn a_folder_that_is_a_file_is_named() {
    let dir = temp_dir("csv-unwritable");
    let blocker = dir.join("file");
    std::fs::write(&blocker, "not a directory").expect("write blocker");
    let err = write_trajectory_csv(&blocker.join("trajectory.csv"), &trajectory("x"))
        .expect_err("cannot write under a file");
    // The folder to write into is a file: said so, naming it.
    match &err {
        OutputError::NotAFolder { path } => assert_eq!(path, &blocker),
        other => panic!("{other:?}"),
    }
}

/// The text the CSV files held before their numbers came from `zmij`: Rust's own shortest
/// round-trip `Display` in 1e-5 <= |x| < 1e16 and `{:e}` outside.
fn display_text(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-5..1e16).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// `format_f64` on `count` doubles from `seed`: every bit pattern's sign and exponent
/// alike (subnormals, both ends of the range), then values of the sizes a run writes
/// (times, angles, residuals around 1e-15, multipliers up to 1e6), then the neighbours of
/// the powers of ten where the form switches (1e-5, 1e16) and of every power of ten.
fn doubles(seed: u64, count: usize) -> Vec<f64> {
    let mut state = seed;
    let mut next = || {
        // A 64-bit LCG (Knuth's MMIX constants): its high bits are well mixed.
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        state
    };
    let mut xs: Vec<f64> = (0..count / 2).map(|_| f64::from_bits(next())).collect();
    for _ in 0..count / 2 {
        let unit = (next() >> 11) as f64 / (1u64 << 53) as f64;
        let decade = (next() % 44) as i32 - 22;
        let sign = if next() & 1 == 0 { 1.0 } else { -1.0 };
        xs.push(sign * unit * 10f64.powi(decade));
    }
    for e in -324..=308 {
        let p: f64 = format!("1e{e}").parse().expect("a power of ten");
        for k in -3i64..=3 {
            let bits = p.to_bits() as i64 + k;
            xs.push(f64::from_bits(bits as u64));
            xs.push(-f64::from_bits(bits as u64));
        }
    }
    xs
}

/// Two routes to one text: `format_f64` (zmij's digits, laid out by `push_f64`) and Rust's
/// own formatting give the same characters for every double tried, so the files are the
/// ones the std formatting wrote, byte for byte. Both are the shortest correctly rounded
/// decimal, so any difference would be a layout slip (a kept `.0`, a `+` in an exponent,
/// the switch to exponent form one decade off).
#[test]
fn numbers_are_written_as_rust_display_writes_them() {
    for x in doubles(0x5eed_c5f0, 200_000) {
        assert_eq!(format_f64(x), display_text(x), "bits {:#x}", x.to_bits());
    }
    // A tie: 1758940400194218.25 lies halfway between the two shortest decimals; zmij alone
    // writes the even ...218.2, Display ...218.3, and the file keeps Display's.
    // (Both values exact: the integers are below 2^53 and the divisions by powers of two.)
    assert_eq!(
        format_f64(7_035_761_600_776_873.0 / 4.0),
        "1758940400194218.3"
    );
    assert_eq!(
        format_f64(-993_814_039_202_777.0 / 8.0),
        "-124226754900347.13"
    );
}
