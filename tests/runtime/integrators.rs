//! Two routes: different integrators agree to their tolerances, and the seed in redundant
//! coordinates agrees with the same mechanism reduced by hand to the one coordinate phi.

use std::f64::consts::PI;

use crate::common::{CrankSlider, FourBar, drift, max_diff};
use mechanism::{
    IntegratorOptions, Method, SimulationOptions, StepController, System, Trajectory, simulate,
};

fn run(s: &dyn System, method: Method, rtol: f64, t_end: f64) -> Trajectory {
    let o = SimulationOptions {
        t_end,
        integrator: IntegratorOptions {
            method,
            rtol,
            atol: rtol * 1e-2,
            ..Default::default()
        },
        ..Default::default()
    };
    simulate(s, &o).unwrap()
}

/// Largest difference of q over all common samples.
fn q_diff(a: &Trajectory, b: &Trajectory) -> f64 {
    assert_eq!(a.len(), b.len());
    a.samples()
        .zip(b.samples())
        .map(|(x, y)| max_diff(x.q, y.q))
        .fold(0.0, f64::max)
}

#[test]
fn explicit_integrators_agree() {
    let s = FourBar::crank_rocker();
    let reference = run(&s, Method::Dop853, 1e-13, 2.0);
    let d5 = run(&s, Method::Dopri5, 1e-10, 2.0);
    let rk4 = run(&s, Method::Rk4 { h: 1e-3 }, 1e-6, 2.0);
    let rk4_half = run(&s, Method::Rk4 { h: 5e-4 }, 1e-6, 2.0);
    let (e5, e4) = (q_diff(&d5, &reference), q_diff(&rk4, &reference));
    let e4_half = q_diff(&rk4_half, &reference);
    println!(
        "four-bar, 2 s: |DOPRI5(1e-10) - DOP853(1e-13)| = {e5:e} rad ({} steps vs {}), |RK4(h=1e-3) - DOP853| = {e4:e} rad",
        d5.stats.steps, reference.stats.steps
    );
    // Global error of a tolerance-controlled run is a small multiple of rtol times the
    // angle scale (~5 rad) and the error growth over 2 s.
    assert!(e5 < 1e-7, "{e5:e}");
    // RK4: fourth order, halving h divides the error by 16 or more (24 measured: the
    // step-independent part of the error, from projection, is not yet negligible).
    println!("RK4 h = 5e-4: {e4_half:e} rad, ratio {:.1}", e4 / e4_half);
    assert!(
        (12.0..32.0).contains(&(e4 / e4_half)),
        "RK4 ratio {}",
        e4 / e4_half
    );
    assert!(e4 < 1e-5, "{e4:e}");
}

#[test]
fn hht_converges_to_the_explicit_solution() {
    let s = FourBar::crank_rocker();
    let reference = run(&s, Method::Dop853, 1e-13, 0.5);
    let err = |h, alpha| q_diff(&run(&s, Method::Hht { h, alpha }, 1e-6, 0.5), &reference);
    let (a1, a2) = (err(5e-4, 0.0), err(2.5e-4, 0.0));
    let (b1, b2) = (err(5e-4, -0.05), err(2.5e-4, -0.05));
    println!(
        "HHT vs DOP853 over 0.5 s, h = 5e-4 and 2.5e-4: alpha 0: {a1:e}, {a2:e} (ratio {:.2}); alpha -0.05: {b1:e}, {b2:e} (ratio {:.2})",
        a1 / a2,
        b1 / b2
    );
    // alpha = 0: second order, halving h divides the error by about 4.
    assert!((3.5..4.5).contains(&(a1 / a2)), "ratio {}", a1 / a2);
    assert!(a2 < 1e-4, "{a2:e}");
    // alpha = -0.05: convergent, but only first order on this mechanism, whose M depends on
    // q (the order reduction the hht module docs describe); halving h must at least about
    // halve the error.
    assert!((1.7..4.5).contains(&(b1 / b2)), "{b1:e} {b2:e}");
}

/// With a configuration-independent M (the seed), HHT-alpha with alpha < 0 is second order
/// in Negrut's HHT-I3 form (constraint forces alpha-weighted with the applied forces).
#[test]
fn hht_with_damping_is_second_order_on_the_seed() {
    let sys = mechanism::builtin::builtin("spatial_crank_slider").expect("built in");
    let run = |method| {
        let o = mechanism::SimulationOptions {
            t_end: 0.5,
            output_rate: 2.0,
            integrator: mechanism::IntegratorOptions {
                method,
                rtol: 1e-13,
                atol: 1e-13,
                ..mechanism::IntegratorOptions::default()
            },
            ..mechanism::SimulationOptions::default()
        };
        mechanism::simulate(sys.as_ref(), &o)
            .expect("simulates")
            .last()
            .expect("samples")
            .q[0]
    };
    let reference = run(Method::Dop853);
    let err = |h| (run(Method::Hht { h, alpha: -0.05 }) - reference).abs();
    let (e1, e2) = (err(5e-4), err(2.5e-4));
    // Measured 4.1e-5 and 1.0e-5: ratio 4 (3.5 to 4.5 for the asymptotic regime).
    assert!((3.5..4.5).contains(&(e1 / e2)), "errors {e1:e}, {e2:e}");
}

/// The seed reduced to phi by the chain rule. With alpha = 0 the constraints give
/// l2 cos(gamma) = h + l1 cos(phi), l2 sin(gamma) sin(beta) = d + l1 sin(phi), and
/// x_c = l2 sin(gamma) cos(beta) = X(phi) = sqrt(S), S = l2^2 - (h + l1 cos phi)^2 - (d + l1 sin phi)^2,
/// S' = 2 l1 (h sin phi - d cos phi), S'' = 2 l1 (h cos phi + d sin phi),
/// X' = S'/(2X), X'' = (S''/2 - X'^2)/X. With T = 1/2 (J + mx X'^2) phi'^2, J = J1 + m2/2 l1^2,
/// mx = m2/2 + m3, Lagrange's equation is
/// (J + mx X'^2) phi'' + mx X' X'' phi'^2 - (m1 a1 + m2/2 l1) g sin(phi) = tau(t).
fn reduced_rhs(t: f64, y: [f64; 2]) -> [f64; 2] {
    let (h, l1, l2, d, m1, m2, m3, j1, a1, g) =
        (0.12, 0.08, 0.3, 0.1, 0.12, 0.5, 2.0, 1e-4, 0.04, 9.81);
    let (sp, cp) = y[0].sin_cos();
    let s = l2 * l2 - (h + l1 * cp).powi(2) - (d + l1 * sp).powi(2);
    let x = s.sqrt();
    let s1 = 2.0 * l1 * (h * sp - d * cp);
    let s2 = 2.0 * l1 * (h * cp + d * sp);
    let x1 = s1 / (2.0 * x);
    let x2 = (s2 / 2.0 - x1 * x1) / x;
    let (jj, mx) = (j1 + m2 / 2.0 * l1 * l1, m2 / 2.0 + m3);
    let tau = 0.005 * (2.0 * PI * t).sin();
    let acc = (tau - mx * x1 * x2 * y[1] * y[1] + (m1 * a1 + m2 / 2.0 * l1) * g * sp)
        / (jj + mx * x1 * x1);
    [y[1], acc]
}

#[test]
fn seed_agrees_with_the_hand_reduced_one_coordinate_model() {
    let tr = run(&CrankSlider::seed(), Method::Dop853, 1e-12, 2.0);
    // Reference: RK4 on the reduced model with h = 1e-5 (error ~ 1e-13 rad), sampled at 100 Hz.
    let h = 1e-5;
    let mut y = [0.0, 2.0 * PI];
    let mut worst = 0.0f64;
    let mut worst_x = 0.0f64;
    for (k, smp) in tr.samples().enumerate() {
        if k > 0 {
            for i in 0..1000 {
                let t = (k - 1) as f64 * 0.01 + i as f64 * h;
                let k1 = reduced_rhs(t, y);
                let k2 = reduced_rhs(
                    t + h / 2.0,
                    [y[0] + h / 2.0 * k1[0], y[1] + h / 2.0 * k1[1]],
                );
                let k3 = reduced_rhs(
                    t + h / 2.0,
                    [y[0] + h / 2.0 * k2[0], y[1] + h / 2.0 * k2[1]],
                );
                let k4 = reduced_rhs(t + h, [y[0] + h * k3[0], y[1] + h * k3[1]]);
                for j in 0..2 {
                    y[j] += h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
                }
            }
        }
        worst = worst
            .max((smp.q[0] - y[0]).abs())
            .max((smp.qd[0] - y[1]).abs() / 10.0);
        let (sp, cp) = y[0].sin_cos();
        let x = (0.09f64 - (0.12 + 0.08 * cp).powi(2) - (0.1 + 0.08 * sp).powi(2)).sqrt();
        worst_x = worst_x.max((smp.q[3] - x).abs());
    }
    println!(
        "seed redundant (DOP853 1e-12) vs reduced 1-DOF (RK4 1e-5): max |dphi| or |dphi'|/10 = {worst:e}, max |dx_c| = {worst_x:e} m"
    );
    assert!(worst < 1e-9, "{worst:e}");
    assert!(worst_x < 1e-10, "{worst_x:e}");
}

/// The predictive step controller: the same tolerance met (its trajectory agrees with a
/// DOP853 run at 1e-13 as the PI controller's does, within a small factor), with fewer
/// rejected steps on the seed, whose error constant grows steeply near the dead centres.
#[test]
fn predictive_controller_rejects_fewer_steps_at_the_same_tolerance() {
    let s = CrankSlider::seed();
    let reference = run(&s, Method::Dop853, 1e-13, 2.0);
    let with = |controller| {
        let o = SimulationOptions {
            t_end: 2.0,
            integrator: IntegratorOptions {
                method: Method::Dop853,
                rtol: 1e-9,
                atol: 1e-9,
                controller,
                ..Default::default()
            },
            ..Default::default()
        };
        simulate(&s, &o).unwrap()
    };
    let pi = with(StepController::Pi);
    let predictive = with(StepController::Predictive);
    assert!(
        predictive.stats.rejected_steps * 2 < pi.stats.rejected_steps,
        "rejected: predictive {} vs PI {}",
        predictive.stats.rejected_steps,
        pi.stats.rejected_steps
    );
    let (e_pi, e_pred) = (q_diff(&pi, &reference), q_diff(&predictive, &reference));
    assert!(
        e_pi < 1e-6 && e_pred < 10.0 * e_pi.max(1e-9),
        "{e_pi:e} {e_pred:e}"
    );
}

/// DOP853 with projection costs 12 right-hand sides per accepted step and 11 per rejected
/// one: after a projection within the error tolerance the step's last stage starts the
/// next step (first same as last) instead of a 13th evaluation. Beyond the steps: per
/// sample one solve and at most 3 stages of the dense output, and 3 at the start (the
/// initial solve, k1 and the starting-step estimate). The seed at 1e-10 for 10 s takes
/// about 1200 steps against 101 samples, so a 13th evaluation per step would exceed the
/// bound by hundreds. The energy balance T + Pi - W of the same run shows the reused stage
/// costs no accuracy (the same bound as `energy::seed_energy_balance_with_work`).
#[test]
fn dop853_with_projection_needs_twelve_right_hand_sides_per_step() {
    let s = CrankSlider::seed();
    let o = SimulationOptions {
        t_end: 10.0,
        output_rate: 10.0,
        integrator: IntegratorOptions {
            method: Method::Dop853,
            rtol: 1e-10,
            atol: 1e-10,
            ..Default::default()
        },
        ..Default::default()
    };
    let tr = simulate(&s, &o).unwrap();
    let st = &tr.stats;
    let bound = 12 * st.steps + 11 * st.rejected_steps + 4 * tr.len() + 3;
    assert!(
        st.rhs_evaluations <= bound,
        "{} right-hand sides for {} steps ({} rejected) and {} samples: bound {bound}",
        st.rhs_evaluations,
        st.steps,
        st.rejected_steps,
        tr.len()
    );
    assert!(
        st.steps > 4 * tr.len(),
        "too few steps for the bound to tell"
    );
    let (_, relative) = drift(&tr);
    assert!(relative < 1e-8, "relative drift {relative:e}");
}
