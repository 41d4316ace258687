//! Snapshots of every library mechanism's derived equations (`equations()`, the text the
//! emitted code carries), reviewed by eye: M, C q', g (signs!), Phi, Phi_q, gamma.
//!
//! And the numeric facts a reviewer checks in them: ERRATA item 4 (the sign of g_phi of the
//! seed crank-slider) and the closed forms of the Cartesian pendulum.

use mechanism::Mechanism;
use mechanism::builtin::{
    CartesianPendulum, ClosedChain4, FiveBar, Panda, PlanarFourBar, PlanarSliderCrank,
    SpatialCrankSlider, SpatialFourBar, builtin_source,
};
use mechanism_codegen::{derive, equations_text, parse_model_str};
use nalgebra::SVector;

/// The emitted `equations()` is exactly the codegen pretty printer's text of the same file.
fn same_as_codegen(name: &str, emitted: &str) {
    let mut model = parse_model_str(builtin_source(name).unwrap()).unwrap();
    let eqs = derive(&mut model).unwrap();
    assert_eq!(emitted, equations_text(&model, &eqs), "{name}");
}

#[test]
fn spatial_crank_slider() {
    same_as_codegen("spatial_crank_slider", SpatialCrankSlider::equations());
    insta::assert_snapshot!("spatial_crank_slider", SpatialCrankSlider::equations());
}

#[test]
fn planar_four_bar() {
    same_as_codegen("planar_four_bar", PlanarFourBar::equations());
    insta::assert_snapshot!("planar_four_bar", PlanarFourBar::equations());
}

/// Links: the recursive route's M, C q' and g, their shared sums and products named once.
#[test]
fn five_bar() {
    same_as_codegen("five_bar", FiveBar::equations());
    insta::assert_snapshot!("five_bar", FiveBar::equations());
}

/// The Panda from its URDF: 99 kB of equations (its recursion's shared terms by name).
#[test]
fn panda() {
    same_as_codegen("panda", Panda::equations());
    insta::assert_snapshot!("panda", Panda::equations());
}

#[test]
fn spatial_four_bar() {
    same_as_codegen("spatial_four_bar", SpatialFourBar::equations());
    insta::assert_snapshot!("spatial_four_bar", SpatialFourBar::equations());
}

#[test]
fn closed_chain() {
    same_as_codegen("closed_chain", ClosedChain4::equations());
    insta::assert_snapshot!("closed_chain", ClosedChain4::equations());
}

#[test]
fn planar_slider_crank() {
    same_as_codegen("planar_slider_crank", PlanarSliderCrank::equations());
    insta::assert_snapshot!("planar_slider_crank", PlanarSliderCrank::equations());
}

#[test]
fn cartesian_pendulum() {
    same_as_codegen("cartesian_pendulum", CartesianPendulum::equations());
    insta::assert_snapshot!("cartesian_pendulum", CartesianPendulum::equations());
}

/// ERRATA item 4: with Pi as printed in (2.9), g_phi = dPi/dphi = -(m1 a1 + m2 l1/2) g
/// sin(phi) (the paper prints the opposite sign); g_beta = g_gamma = g_x = 0. Checked at
/// several angles, to 1e-15 relative (one product and one sine: a few ulps).
#[test]
fn seed_gravity_sign_follows_errata_item_4() {
    let s = SpatialCrankSlider::default();
    for phi in [0.3, 1.0, 2.5, -0.7, 4.0] {
        let q = SVector::<f64, 4>::new(phi, 0.46, 0.84, 0.2);
        let g = s.gravity(&q);
        let expected = -(s.m1 * s.a1 + s.m2 * s.l1 / 2.0) * s.g * f64::sin(phi);
        assert!(
            (g[0] - expected).abs() <= 1e-15 * expected.abs().max(1e-300),
            "phi = {phi}: {} vs {expected}",
            g[0]
        );
        assert_eq!((g[1], g[2], g[3]), (0.0, 0.0, 0.0));
    }
}

/// The seed's lumped connecting rod leaves zero rows for beta and gamma in M (ERRATA 7):
/// M = diag(J1 + m2/2 l1^2, 0, 0, m2/2 + m3).
#[test]
fn seed_mass_matrix_is_the_lumped_one() {
    let s = SpatialCrankSlider::default();
    let m = s.mass_matrix(&SVector::<f64, 4>::new(0.4, 0.5, 0.8, 0.2));
    let mut expected = nalgebra::SMatrix::<f64, 4, 4>::zeros();
    expected[(0, 0)] = s.J1 + s.m2 / 2.0 * s.l1 * s.l1;
    expected[(3, 3)] = s.m2 / 2.0 + s.m3;
    assert!((m - expected).amax() <= 1e-15, "{m}");
}

/// Cartesian pendulum closed forms: M = m I, C = 0, g = [0, m g], Phi_q = [2x, 2y],
/// gamma = -2 (x'^2 + y'^2).
#[test]
fn cartesian_pendulum_closed_forms() {
    let p = CartesianPendulum::default();
    let (q, qd) = (
        SVector::<f64, 2>::new(0.3, -0.9),
        SVector::<f64, 2>::new(1.5, -0.5),
    );
    let e = p.evaluate(0.0, &q, &qd);
    assert_eq!(e.mass, nalgebra::SMatrix::<f64, 2, 2>::identity() * p.m);
    assert_eq!(e.coriolis, SVector::<f64, 2>::zeros());
    assert_eq!(e.gravity, SVector::<f64, 2>::new(0.0, p.m * p.g));
    assert_eq!(e.phi_q, nalgebra::SMatrix::<f64, 1, 2>::new(0.6, -1.8));
    assert!((e.gamma[0] + 2.0 * (1.5f64.powi(2) + 0.25)).abs() < 1e-14);
}
