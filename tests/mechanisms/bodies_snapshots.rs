//! Snapshots of the derived equations of the body-declared mechanisms (reviewed by eye: M,
//! C q', g, Phi, Phi_q, gamma), and the closed forms a reviewer checks in them: the rigid
//! connecting rod of the seed against M and g worked out by hand.

use mechanism::Mechanism;
use mechanism::builtin::{
    SpatialCrankSliderRigid, SpatialCrankSliderRigidParameters, SpatialFourBarBodies,
    builtin_source,
};
use mechanism_codegen::{derive, equations_text, parse_model_str};
use nalgebra::{SMatrix, SVector, Vector3};

/// The emitted `equations()` is exactly the codegen pretty printer's text of the same file.
fn same_as_codegen(name: &str, emitted: &str) {
    let mut model = parse_model_str(builtin_source(name).unwrap()).unwrap();
    let eqs = derive(&mut model).unwrap();
    assert_eq!(emitted, equations_text(&model, &eqs), "{name}");
}

#[test]
fn spatial_four_bar_bodies() {
    same_as_codegen("spatial_four_bar_bodies", SpatialFourBarBodies::equations());
    insta::assert_snapshot!("spatial_four_bar_bodies", SpatialFourBarBodies::equations());
}

#[test]
fn spatial_crank_slider_rigid() {
    same_as_codegen(
        "spatial_crank_slider_rigid",
        SpatialCrankSliderRigid::equations(),
    );
    insta::assert_snapshot!(
        "spatial_crank_slider_rigid",
        SpatialCrankSliderRigid::equations()
    );
}

/// The rigid rod by hand: with the crank pin A(q), the rod direction
/// w = (sin g cos b, sin g sin b, -cos g) and the centre G = A + l2/2 w, a thin uniform rod has
/// T = 1/2 m2 |G'|^2 + 1/2 (m2 l2^2/12) |w'|^2, so
/// M = diag(J1, 0, 0, m3) + m2 (J_A^T J_A + l2/2 (J_A^T J_w + J_w^T J_A) + l2^2/3 J_w^T J_w)
/// and Pi = m1 g (a1 cos phi + h) + m2 g (z_A - l2/2 cos g), so
/// g = (-(m1 a1 + m2 l1) g sin phi, 0, m2 g l2/2 sin g, 0). Checked at random states with
/// alpha = 0.3 (all terms alive) to 1e-15 absolute (entries ~1e-2, a few roundings).
#[test]
fn rigid_rod_mass_matrix_and_gravity_match_the_hand_derivation() {
    let s = SpatialCrankSliderRigid::from(SpatialCrankSliderRigidParameters {
        alpha: 0.3,
        ..Default::default()
    });
    for (phi, beta, gamma) in [(0.4, 0.5, 0.8), (2.0, -1.1, 2.2), (-0.9, 3.0, 0.3)] {
        let q = SVector::<f64, 4>::new(phi, beta, gamma, 0.2);
        let (sa, ca) = s.alpha.sin_cos();
        // Columns d/d(phi, beta, gamma, x_c) of A and w.
        let ja = [
            Vector3::new(
                s.l1 * phi.cos() * sa,
                -s.l1 * phi.cos() * ca,
                -s.l1 * phi.sin(),
            ),
            Vector3::zeros(),
            Vector3::zeros(),
            Vector3::zeros(),
        ];
        let jw = [
            Vector3::zeros(),
            Vector3::new(-gamma.sin() * beta.sin(), gamma.sin() * beta.cos(), 0.0),
            Vector3::new(
                gamma.cos() * beta.cos(),
                gamma.cos() * beta.sin(),
                gamma.sin(),
            ),
            Vector3::zeros(),
        ];
        let mut expected = SMatrix::<f64, 4, 4>::zeros();
        expected[(0, 0)] = s.J1;
        expected[(3, 3)] = s.m3;
        for i in 0..4 {
            for j in 0..4 {
                expected[(i, j)] += s.m2
                    * (ja[i].dot(&ja[j])
                        + s.l2 / 2.0 * (ja[i].dot(&jw[j]) + jw[i].dot(&ja[j]))
                        + s.l2 * s.l2 / 3.0 * jw[i].dot(&jw[j]));
            }
        }
        let m = s.mass_matrix(&q);
        assert!((m - expected).amax() < 1e-15, "M = {m}, by hand {expected}");
        let g = s.gravity(&q);
        let g_hand = SVector::<f64, 4>::new(
            -(s.m1 * s.a1 + s.m2 * s.l1) * s.g * phi.sin(),
            0.0,
            s.m2 * s.g * s.l2 / 2.0 * gamma.sin(),
            0.0,
        );
        assert!((g - g_hand).amax() < 1e-15, "g = {g}, by hand {g_hand}");
        // The rigid rod makes M regular (the lumped seed's M has zero beta, gamma rows).
        assert!(m.determinant().abs() > 1e-12, "det M = {}", m.determinant());
    }
}

/// The compiled-in (emitted) code of both body mechanisms equals the interpreter route of
/// the same file at pseudo-random states, every output: M, C q', g, tau, Phi, Phi_q, Phi_t,
/// gamma, T, Pi. Tolerance 1e-12 relative to max(1, |value|): the same expressions evaluated
/// through CSE'd straight-line code and through the arena interpreter differ by rounding only.
#[test]
fn emitted_code_equals_the_interpreter() {
    use mechanism::{Evaluation, Interpreted, System};
    for name in ["spatial_four_bar_bodies", "spatial_crank_slider_rigid"] {
        let compiled = mechanism::builtin::builtin(name).unwrap();
        let interpreted = Interpreted::from_source(builtin_source(name).unwrap()).unwrap();
        let (n, m) = (compiled.info().n(), compiled.info().m());
        let (mut a, mut b) = (Evaluation::zeros(n, m), Evaluation::zeros(n, m));
        for k in 0..20 {
            let x = |i: usize, s: f64| ((k * 7 + i * 3) as f64 * 0.731 + s).sin() * 2.0;
            let q: Vec<f64> = (0..n).map(|i| x(i, 0.1)).collect();
            let qd: Vec<f64> = (0..n).map(|i| x(i, 1.7) * 3.0).collect();
            let t = 0.1 * k as f64;
            compiled.evaluate(t, &q, &qd, &mut a);
            interpreted.evaluate(t, &q, &qd, &mut b);
            let pairs: [(&str, &[f64], &[f64]); 8] = [
                ("M", a.mass.as_slice(), b.mass.as_slice()),
                ("Cq'", a.coriolis.as_slice(), b.coriolis.as_slice()),
                ("g", a.gravity.as_slice(), b.gravity.as_slice()),
                ("tau", a.forces.as_slice(), b.forces.as_slice()),
                ("Phi", a.phi.as_slice(), b.phi.as_slice()),
                ("Phi_q", a.phi_q.as_slice(), b.phi_q.as_slice()),
                ("Phi_t", a.phi_t.as_slice(), b.phi_t.as_slice()),
                ("gamma", a.gamma.as_slice(), b.gamma.as_slice()),
            ];
            for (what, u, v) in pairs {
                for (p, r) in u.iter().zip(v) {
                    assert!(
                        (p - r).abs() <= 1e-12 * p.abs().max(1.0),
                        "{name} {what}: {p} vs {r}"
                    );
                }
            }
            for (p, r) in [(a.kinetic, b.kinetic), (a.potential, b.potential)] {
                assert!(
                    (p - r).abs() <= 1e-12 * p.abs().max(1.0),
                    "{name} T/Pi: {p} vs {r}"
                );
            }
        }
    }
}
