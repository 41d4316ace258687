//! A user crate: declares the seed's crank-slider and calls its generated code.
use mechanism::Mechanism;

mechanism::mechanism!(file = "spatial_crank_slider.mech");

/// M[0, 0] at q.
pub fn mass(q: [f64; 4]) -> f64 {
    SpatialCrankSlider::default().mass_matrix(&q.into())[(0, 0)]
}
