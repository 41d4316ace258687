//! Figures: valid PNG and SVG files with the expected names, sizes and axis labels.

use std::path::{Path, PathBuf};

use crate::support::{SAMPLES, residuals, temp_dir, time, trajectory};
use mechanism::output::{
    Figure, FigureNames, Figures, InverseTable, OutputError, Unit, plot_constraint_error,
    plot_coordinate, plot_driving_torque, plot_run, plot_trajectory,
};

/// Checks the PNG signature and returns (width, height) from the IHDR chunk.
fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(
        bytes.len() > 1000,
        "{} is only {} bytes",
        path.display(),
        bytes.len()
    );
    assert_eq!(
        &bytes[..8],
        b"\x89PNG\r\n\x1a\n",
        "PNG signature of {}",
        path.display()
    );
    assert_eq!(&bytes[12..16], b"IHDR", "first chunk of {}", path.display());
    let be = |o: usize| u32::from_be_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]]);
    (be(16), be(20))
}

fn svg_text(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(
        text.trim_start().starts_with("<svg"),
        "{} does not start with <svg",
        path.display()
    );
    assert!(
        text.trim_end().ends_with("</svg>"),
        "{} is not closed",
        path.display()
    );
    text
}

fn names(paths: &[PathBuf]) -> Vec<String> {
    paths
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect()
}

/// The seed paper's numbering, as the command-line tool passes it (its own unit test holds
/// it to the seed mechanism only).
fn paper_names() -> FigureNames {
    let renamed = [
        ("phi", "fig_3_1_phi"),
        ("beta", "fig_3_2_beta"),
        ("gamma", "fig_3_3_gamma"),
        ("x_c", "fig_3_4_x_c"),
        ("constraint_error", "fig_3_5_constraint_error"),
    ];
    FigureNames {
        renamed: renamed
            .iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect(),
    }
}

#[test]
fn figures_carry_their_own_names_unless_renamed() {
    let paper = paper_names();
    let plain = FigureNames::default();
    let cases = [
        (&paper, Figure::Coordinate("phi"), "fig_3_1_phi"),
        (&paper, Figure::Coordinate("x_c"), "fig_3_4_x_c"),
        (&paper, Figure::ConstraintError, "fig_3_5_constraint_error"),
        (&paper, Figure::DrivingTorque, "driving_torque"),
        (&paper, Figure::Overview, "coordinates"),
        (&paper, Figure::Coordinate("theta"), "theta"),
        (&plain, Figure::Coordinate("phi"), "phi"),
        (&plain, Figure::ConstraintError, "constraint_error"),
        (&plain, Figure::DrivingTorque, "driving_torque"),
    ];
    for (names, figure, stem) in cases {
        assert_eq!(names.stem(figure), stem, "{figure:?}");
    }
}

#[test]
fn unit_guess_separates_lengths_from_angles() {
    let cases = [
        ("x", Unit::Length),
        ("x_c", Unit::Length),
        ("y2", Unit::Length),
        ("s", Unit::Length),
        ("z_B", Unit::Length),
    ];
    let angles = [
        ("phi", Unit::Angle),
        ("beta", Unit::Angle),
        ("gamma", Unit::Angle),
        ("theta_1", Unit::Angle),
        ("sigma", Unit::Angle),
        ("xi", Unit::Angle),
    ];
    for (name, unit) in cases.into_iter().chain(angles) {
        assert_eq!(Unit::guess(name), unit, "{name}");
    }
}

#[test]
fn seed_trajectory_writes_all_five_figures_as_png_and_svg_under_the_papers_names() {
    let dir = temp_dir("seed");
    let tr = trajectory("spatial_crank_slider");
    let written = plot_run(
        &dir,
        &tr,
        None,
        Some(&residuals()),
        Figures::All,
        &paper_names(),
    )
    .expect("plots");
    let expected: Vec<String> = [
        "fig_3_1_phi",
        "fig_3_2_beta",
        "fig_3_3_gamma",
        "fig_3_4_x_c",
        "fig_3_5_constraint_error",
    ]
    .iter()
    .flat_map(|s| [format!("{s}.png"), format!("{s}.svg")])
    .collect();
    assert_eq!(names(&written), expected);
    for path in &written {
        assert!(path.is_file(), "{} missing", path.display());
    }
    assert_eq!(png_size(&dir.join("fig_3_1_phi.png")), (1000, 760));
    assert_eq!(
        png_size(&dir.join("fig_3_5_constraint_error.png")),
        (1000, 600)
    );
    let phi = svg_text(&dir.join("fig_3_1_phi.svg"));
    for label in ["t (s)", "φ (rad)", "dφ/dt (rad/s)"] {
        assert!(
            phi.contains(label),
            "fig_3_1_phi.svg lacks the label {label:?}"
        );
    }
    let x_c = svg_text(&dir.join("fig_3_4_x_c.svg"));
    for label in ["x_c (m)", "dx_c/dt (m/s)"] {
        assert!(
            x_c.contains(label),
            "fig_3_4_x_c.svg lacks the label {label:?}"
        );
    }
    let err = svg_text(&dir.join("fig_3_5_constraint_error.svg"));
    for label in ["t (s)", "|f₁|", "|f₂|", "|f₃|", "log scale", "10⁻¹⁸"] {
        assert!(err.contains(label), "constraint error SVG lacks {label:?}");
    }
}

#[test]
fn other_mechanisms_get_plain_names_and_recorded_error_fallback() {
    let dir = temp_dir("other");
    let tr = trajectory("four_bar");
    let units = [Unit::Angle, Unit::Angle, Unit::Unknown, Unit::Length];
    let written = plot_trajectory(&dir, &tr, Some(&units), None).expect("plots");
    let stems = ["phi", "beta", "gamma", "x_c", "constraint_error"];
    let expected: Vec<String> = stems
        .iter()
        .flat_map(|s| [format!("{s}.png"), format!("{s}.svg")])
        .collect();
    assert_eq!(names(&written), expected);
    let gamma = svg_text(&dir.join("gamma.svg"));
    assert!(
        gamma.contains("dγ/dt") && !gamma.contains("dγ/dt (rad/s)"),
        "Unknown unit prints no unit"
    );
    assert!(svg_text(&dir.join("constraint_error.svg")).contains("‖Φ(q)‖∞"));
}

#[test]
fn exact_zeros_and_all_zero_series_plot_on_the_log_axis() {
    let dir = temp_dir("zeros");
    let t: Vec<f64> = (0..SAMPLES).map(time).collect();
    let zeros = vec![vec![0.0; SAMPLES], vec![0.0; SAMPLES]];
    let written =
        plot_constraint_error(&dir.join("all_zero"), &t, &zeros).expect("all-zero residuals plot");
    assert_eq!(png_size(&written[0]), (1000, 600));
    let mut mixed = residuals();
    mixed[1][10] = f64::NAN;
    mixed[1][11] = f64::INFINITY;
    let written =
        plot_constraint_error(&dir.join("mixed"), &t, &mixed).expect("zeros, NaN and inf plot");
    assert_eq!(png_size(&written[0]), (1000, 600));
}

#[test]
fn driving_torque_figure_has_units_per_coordinate_kind() {
    let dir = temp_dir("torque");
    let rows = (0..SAMPLES)
        .map(|i| {
            let t = time(i);
            let mut row = vec![t];
            row.extend([0.0; 12]);
            row.extend([
                0.005 * (2.0 * std::f64::consts::PI * t).sin(),
                0.0,
                1.0,
                2.0,
            ]);
            row
        })
        .collect();
    let table = InverseTable {
        coordinates: crate::support::info("x").coordinates,
        driven: vec!["phi".into()],
        constraints: 3,
        rows,
    };
    let written =
        plot_driving_torque(&dir.join("driving_torque"), &table, Unit::guess).expect("torque plot");
    assert_eq!(
        names(&written),
        ["driving_torque.png", "driving_torque.svg"]
    );
    assert_eq!(png_size(&written[0]), (1000, 600));
    let svg = svg_text(&written[1]);
    assert!(
        svg.contains("τ (N m)") && svg.contains("τ on φ"),
        "torque SVG labels"
    );
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let dir = temp_dir("bad");
    let t = [0.0, 1.0, 2.0];
    let short = plot_coordinate(
        &dir.join("short"),
        "phi",
        Unit::Angle,
        &t,
        &[1.0, 2.0],
        &[0.0; 3],
    );
    assert!(
        matches!(short, Err(OutputError::InvalidData { .. })),
        "{short:?}"
    );
    let empty = plot_constraint_error(&dir.join("empty"), &[], &[vec![]]);
    assert!(
        matches!(empty, Err(OutputError::InvalidData { .. })),
        "{empty:?}"
    );
    let constant = plot_coordinate(
        &dir.join("constant"),
        "x",
        Unit::Length,
        &t,
        &[1.0; 3],
        &[0.0; 3],
    );
    assert!(constant.is_ok(), "constant data plots: {constant:?}");
    let single = plot_coordinate(
        &dir.join("single"),
        "x",
        Unit::Length,
        &[0.0],
        &[1.0],
        &[0.0],
    );
    assert!(single.is_ok(), "a single sample plots: {single:?}");
}
