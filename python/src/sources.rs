//! The declarations of the repository's `mechanisms/` folder, by file stem: what
//! `mechanism.load("panda")` derives (the command-line tool's built-in names, here through
//! the interpreter route: the wheel does not compile them in). `tests/test_errors.py` checks
//! that the list names every file of the folder.

/// (name, declaration text) of every built-in mechanism, in `mechanism list`'s order.
pub const BUILTIN: &[(&str, &str)] = &[
    (
        "spatial_crank_slider",
        include_str!("../../mechanisms/spatial_crank_slider.mech"),
    ),
    (
        "planar_four_bar",
        include_str!("../../mechanisms/planar_four_bar.mech"),
    ),
    (
        "spatial_four_bar",
        include_str!("../../mechanisms/spatial_four_bar.mech"),
    ),
    (
        "closed_chain",
        include_str!("../../mechanisms/closed_chain.mech"),
    ),
    (
        "planar_slider_crank",
        include_str!("../../mechanisms/planar_slider_crank.mech"),
    ),
    (
        "cartesian_pendulum",
        include_str!("../../mechanisms/cartesian_pendulum.mech"),
    ),
    (
        "spatial_four_bar_bodies",
        include_str!("../../mechanisms/spatial_four_bar_bodies.mech"),
    ),
    (
        "spatial_crank_slider_rigid",
        include_str!("../../mechanisms/spatial_crank_slider_rigid.mech"),
    ),
    (
        "n_four_bar",
        include_str!("../../mechanisms/n_four_bar.mech"),
    ),
    ("bricard", include_str!("../../mechanisms/bricard.mech")),
    (
        "planar_four_bar_bodies",
        include_str!("../../mechanisms/planar_four_bar_bodies.mech"),
    ),
    ("panda", include_str!("../../mechanisms/panda.mech")),
    ("five_bar", include_str!("../../mechanisms/five_bar.mech")),
    (
        "whipple_bicycle",
        include_str!("../../mechanisms/whipple_bicycle.mech"),
    ),
    (
        "rolling_disc",
        include_str!("../../mechanisms/rolling_disc.mech"),
    ),
    (
        "chaplygin_sleigh",
        include_str!("../../mechanisms/chaplygin_sleigh.mech"),
    ),
];

/// The declaration text of the built-in mechanism `name`.
pub fn source(name: &str) -> Option<&'static str> {
    BUILTIN.iter().find(|(n, _)| *n == name).map(|(_, s)| *s)
}
