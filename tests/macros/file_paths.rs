//! `mechanism!(file = ...)` reads a file relative to CARGO_MANIFEST_DIR, or else relative to
//! the source file that invokes it; both forms must expand (the second to an `include_str!`
//! of the file's own path, not of that path joined once more onto the invoking file's
//! directory).

use mechanism::Mechanism;

mod relative_to_the_crate {
    mechanism::mechanism!(file = "mechanisms/cartesian_pendulum.mech");
}

mod relative_to_this_file {
    mechanism::mechanism!(file = "beside.mech");
}

#[test]
fn both_file_forms_expand_and_derive() {
    use relative_to_the_crate::CartesianPendulum;
    use relative_to_this_file::BesidePendulum;
    assert_eq!(CartesianPendulum::NAME, "CartesianPendulum");
    assert_eq!(BesidePendulum::NAME, "BesidePendulum");
    // The file beside the test is the one read: its own parameters and coordinates.
    assert_eq!(BesidePendulum::COORDINATES, ["x", "y"]);
    let p = BesidePendulum::default();
    let q = nalgebra::SVector::<f64, 2>::new(0.6, -0.8);
    // g(q) = dPi/dq = (0, m g).
    let g = p.gravity(&q);
    assert!(g[0].abs() < 1e-15 && (g[1] - 9.81).abs() < 1e-15, "{g}");
}
