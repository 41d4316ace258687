//! The library of mechanisms compiled into this crate, one per file under `mechanisms/`.
//!
//! Each file is expanded by [`mechanism!`](crate::mechanism) at build time (editing a file
//! triggers a rebuild). The registry functions look them up by their snake_case file stem:
//!
//! | name                   | struct                | n | m | source                          |
//! |------------------------|-----------------------|---|---|---------------------------------|
//! | `spatial_crank_slider` | [`SpatialCrankSlider`] | 4 | 3 | seed paper, Section II, corrected |
//! | `planar_four_bar`      | [`PlanarFourBar`]     | 3 | 2 | crank-rocker                    |
//! | `spatial_four_bar`     | [`SpatialFourBar`]    | 4 | 3 | RSSR of the seed paper's title  |
//! | `closed_chain`         | [`ClosedChain4`]      | 4 | 2 | the N-bar chain, N = 4          |
//! | `planar_slider_crank`  | [`PlanarSliderCrank`] | 3 | 2 | textbook slider-crank           |
//! | `cartesian_pendulum`   | [`CartesianPendulum`] | 2 | 1 | pendulum in (x, y)              |
//! | `spatial_four_bar_bodies` | [`SpatialFourBarBodies`] | 4 | 3 | the RSSR declared with bodies |
//! | `spatial_crank_slider_rigid` | [`SpatialCrankSliderRigid`] | 4 | 3 | seed with a rigid rod |
//! | `n_four_bar`           | [`NFourBar40`]        | 82 | 81 | IFToMM benchmark A02, N = 40 (rank 81; 41 where the rockers lie flat) |
//! | `bricard`              | [`Bricard`]           | 30 | 30 | IFToMM benchmark A04 (rank 29: one redundant row) |
//! | `planar_four_bar_bodies` | [`PlanarFourBarBodies`] | 18 | 20 | the four-bar with bodies and spatial revolutes (rank 17) |
//! | `panda`                | [`Panda`]             | 7 | 0 | Franka Panda arm, imported from its URDF (fingers locked) |
//! | `five_bar`             | [`FiveBar`]           | 4 | 2 | five-bar parallel leg, declared with link frames |
//! | `whipple_bicycle`      | [`WhippleBicycle`]    | 9 | 6 | the benchmark bicycle (2 position, 4 velocity rows) |
//! | `rolling_disc`         | [`RollingDisc`]       | 6 | 3 | thin disc rolling on the ground (1 + 2 rows) |
//! | `chaplygin_sleigh`     | [`ChaplyginSleigh`]   | 3 | 1 | knife edge: one velocity row    |

use crate::{Compiled, System};

crate::mechanism!(crate = crate, file = "mechanisms/spatial_crank_slider.mech");
crate::mechanism!(crate = crate, file = "mechanisms/planar_four_bar.mech");
crate::mechanism!(crate = crate, file = "mechanisms/spatial_four_bar.mech");
crate::mechanism!(crate = crate, file = "mechanisms/closed_chain.mech");
crate::mechanism!(crate = crate, file = "mechanisms/planar_slider_crank.mech");
crate::mechanism!(crate = crate, file = "mechanisms/cartesian_pendulum.mech");
crate::mechanism!(
    crate = crate,
    file = "mechanisms/spatial_four_bar_bodies.mech"
);
crate::mechanism!(
    crate = crate,
    file = "mechanisms/spatial_crank_slider_rigid.mech"
);
crate::mechanism!(crate = crate, file = "mechanisms/n_four_bar.mech");
crate::mechanism!(crate = crate, file = "mechanisms/bricard.mech");
crate::mechanism!(
    crate = crate,
    file = "mechanisms/planar_four_bar_bodies.mech"
);
crate::mechanism!(crate = crate, file = "mechanisms/panda.mech");
crate::mechanism!(crate = crate, file = "mechanisms/five_bar.mech");
crate::mechanism!(crate = crate, file = "mechanisms/whipple_bicycle.mech");
crate::mechanism!(crate = crate, file = "mechanisms/rolling_disc.mech");
crate::mechanism!(crate = crate, file = "mechanisms/chaplygin_sleigh.mech");

/// The snake_case names of the compiled-in mechanisms (their file stems under
/// `mechanisms/`), in the order of the table above.
pub fn builtin_names() -> &'static [&'static str] {
    &[
        "spatial_crank_slider",
        "planar_four_bar",
        "spatial_four_bar",
        "closed_chain",
        "planar_slider_crank",
        "cartesian_pendulum",
        "spatial_four_bar_bodies",
        "spatial_crank_slider_rigid",
        "n_four_bar",
        "bricard",
        "planar_four_bar_bodies",
        "panda",
        "five_bar",
        "whipple_bicycle",
        "rolling_disc",
        "chaplygin_sleigh",
    ]
}

/// The compiled-in mechanism called `name`, with its declared parameter defaults, as a
/// run-time [`System`] (wrapped in [`Compiled`]); `None` for an unknown name.
pub fn builtin(name: &str) -> Option<Box<dyn System>> {
    let system: Box<dyn System> = match name {
        "spatial_crank_slider" => Box::new(Compiled::new(SpatialCrankSlider::default())),
        "planar_four_bar" => Box::new(Compiled::new(PlanarFourBar::default())),
        "spatial_four_bar" => Box::new(Compiled::new(SpatialFourBar::default())),
        "closed_chain" => Box::new(Compiled::new(ClosedChain4::default())),
        "planar_slider_crank" => Box::new(Compiled::new(PlanarSliderCrank::default())),
        "cartesian_pendulum" => Box::new(Compiled::new(CartesianPendulum::default())),
        "spatial_four_bar_bodies" => Box::new(Compiled::new(SpatialFourBarBodies::default())),
        "spatial_crank_slider_rigid" => Box::new(Compiled::new(SpatialCrankSliderRigid::default())),
        "n_four_bar" => Box::new(Compiled::new(NFourBar40::default())),
        "bricard" => Box::new(Compiled::new(Bricard::default())),
        "planar_four_bar_bodies" => Box::new(Compiled::new(PlanarFourBarBodies::default())),
        "panda" => Box::new(Compiled::new(Panda::default())),
        "five_bar" => Box::new(Compiled::new(FiveBar::default())),
        "whipple_bicycle" => Box::new(Compiled::new(WhippleBicycle::default())),
        "rolling_disc" => Box::new(Compiled::new(RollingDisc::default())),
        "chaplygin_sleigh" => Box::new(Compiled::new(ChaplyginSleigh::default())),
        _ => return None,
    };
    Some(system)
}

/// The declaration text of the compiled-in mechanism called `name` (the `.mech` file, for
/// the interpreter route and for printing its equations); `None` for an unknown name.
pub fn builtin_source(name: &str) -> Option<&'static str> {
    Some(match name {
        "spatial_crank_slider" => include_str!("../mechanisms/spatial_crank_slider.mech"),
        "planar_four_bar" => include_str!("../mechanisms/planar_four_bar.mech"),
        "spatial_four_bar" => include_str!("../mechanisms/spatial_four_bar.mech"),
        "closed_chain" => include_str!("../mechanisms/closed_chain.mech"),
        "planar_slider_crank" => include_str!("../mechanisms/planar_slider_crank.mech"),
        "cartesian_pendulum" => include_str!("../mechanisms/cartesian_pendulum.mech"),
        "spatial_four_bar_bodies" => include_str!("../mechanisms/spatial_four_bar_bodies.mech"),
        "spatial_crank_slider_rigid" => {
            include_str!("../mechanisms/spatial_crank_slider_rigid.mech")
        }
        "n_four_bar" => include_str!("../mechanisms/n_four_bar.mech"),
        "bricard" => include_str!("../mechanisms/bricard.mech"),
        "planar_four_bar_bodies" => include_str!("../mechanisms/planar_four_bar_bodies.mech"),
        "panda" => include_str!("../mechanisms/panda.mech"),
        "five_bar" => include_str!("../mechanisms/five_bar.mech"),
        "whipple_bicycle" => include_str!("../mechanisms/whipple_bicycle.mech"),
        "rolling_disc" => include_str!("../mechanisms/rolling_disc.mech"),
        "chaplygin_sleigh" => include_str!("../mechanisms/chaplygin_sleigh.mech"),
        _ => return None,
    })
}
