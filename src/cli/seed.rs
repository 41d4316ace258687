//! The seed paper's mechanism, which the command-line tool treats apart: its figures
//! carry the paper's numbers, and its summary shows the initial state the paper printed.

use mechanism::System;
use mechanism::output::{Figure, FigureNames};

/// The initial state the seed paper printed (Section 2.2): phi, beta, gamma, x_C. It
/// violates the constraints by about 2 m: beta and gamma are swapped and x_C lost a
/// decimal point (solving the constraints at phi = 0 gives beta = 0.463648,
/// gamma = 0.841069, x_C = 0.2 m).
pub const SEED_PRINTED: [(&str, f64); 4] = [
    ("phi", 0.0),
    ("beta", 0.841069),
    ("gamma", 0.201082),
    ("x_c", 2.0),
];

/// True when the name the mechanism was asked by (`key`) or its struct name is the seed
/// mechanism's (`spatial_crank_slider`, `SpatialCrankSlider`: any case, `_` and `-`
/// ignored).
pub fn is_seed(key: &str, system: &dyn System) -> bool {
    let seed = |name: &str| {
        name.chars()
            .filter(|&c| c != '_' && c != '-')
            .flat_map(char::to_lowercase)
            .eq("spatialcrankslider".chars())
    };
    seed(key) || seed(&system.info().name)
}

/// The figures' file names: for the seed mechanism the paper's numbers (`fig_3_1_phi` ..
/// `fig_3_4_x_c`, `fig_3_5_constraint_error`), otherwise each figure's own name.
pub fn figure_names(key: &str, system: &dyn System) -> FigureNames {
    if !is_seed(key, system) {
        return FigureNames::default();
    }
    let numbered = SEED_PRINTED
        .iter()
        .map(|&(name, _)| Figure::Coordinate(name))
        .chain([Figure::ConstraintError]);
    FigureNames {
        renamed: numbered
            .enumerate()
            .map(|(i, figure)| (figure.stem(), format!("fig_3_{}_{}", i + 1, figure.stem())))
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mechanism::builtin::builtin;

    #[test]
    fn the_papers_figure_numbers_go_to_the_seed_only() {
        let seed = builtin("spatial_crank_slider").expect("built in");
        let other = builtin("planar_four_bar").expect("built in");
        for key in [
            "spatial_crank_slider",
            "SPATIAL-CRANK-SLIDER",
            "SpatialCrankSlider",
        ] {
            assert!(is_seed(key, other.as_ref()), "{key}");
        }
        // A file of another name that declares the seed's struct is the seed too.
        assert!(is_seed("mine.mech", seed.as_ref()));
        assert!(!is_seed("planar_four_bar", other.as_ref()));
        let paper = figure_names("spatial_crank_slider", seed.as_ref());
        let cases = [
            (Figure::Coordinate("phi"), "fig_3_1_phi"),
            (Figure::Coordinate("beta"), "fig_3_2_beta"),
            (Figure::Coordinate("gamma"), "fig_3_3_gamma"),
            (Figure::Coordinate("x_c"), "fig_3_4_x_c"),
            (Figure::ConstraintError, "fig_3_5_constraint_error"),
            (Figure::DrivingTorque, "driving_torque"),
            (Figure::Coordinate("theta"), "theta"),
        ];
        for (figure, stem) in cases {
            assert_eq!(paper.stem(figure), stem, "{figure:?}");
        }
        let plain = figure_names("planar_four_bar", other.as_ref());
        assert_eq!(plain, FigureNames::default());
        assert_eq!(plain.stem(Figure::Coordinate("phi")), "phi");
    }
}
