//! Andrews' squeezing mechanism (`examples/andrews_squeezer.mech`) against published truth:
//! the forces and constraint Jacobian written out by hand in Hairer and Wanner (Solving
//! ODEs II, Section VII.7), and the reference solution of the Test Set for IVP Solvers
//! (problem `andrews`: the consistent accelerations and multipliers at t = 0, and q, q' at
//! t = 0.03 s, computed with PSIDE at tolerance 1e-14). Both routes are checked: the code
//! the macro emits and the interpreter.

use mechanism::{
    Compiled, Dynamics, IntegratorOptions, Interpreted, SimulationOptions, System, simulate,
};

mechanism::mechanism!(file = "examples/andrews_squeezer.mech");

const SOURCE: &str = include_str!("../../examples/andrews_squeezer.mech");

/// The Test Set's accelerations q''(0) (beta'' and theta''; the others are 0) and
/// multipliers lambda(0) (rows 1 and 2; the others are 0), for q' = 0, to double precision.
const QDD0: [f64; 2] = [14_222.443_919_954_114, -10_666.832_939_965_585];
const LAMBDA0: [f64; 2] = [98.566_870_396_241_09, -6.122_688_344_255_663];

/// The Test Set's q(0.03) and q'(0.03).
const Q_END: [f64; 7] = [
    0.1581077119629904e+2,
    -0.1575637105984298e+2,
    0.4082224013073101e-1,
    -0.5347301163226948,
    0.5244099658805304,
    0.5347301163226948,
    0.1048080741042263e+1,
];
const QD_END: [f64; 7] = [
    0.1139920302151208e+4,
    -0.1424379294994111e+4,
    0.1103291221937134e+2,
    0.1929337464421385e+2,
    0.5735699284790808,
    -0.1929337464421385e+2,
    0.3231791658026955,
];

/// The two routes, as run-time systems.
fn routes() -> [(&'static str, Box<dyn System>); 2] {
    [
        (
            "emitted",
            Box::new(Compiled::new(AndrewsSqueezer::default())),
        ),
        (
            "interpreted",
            Box::new(Interpreted::from_source(SOURCE).expect("the declaration derives")),
        ),
    ]
}

/// Largest |a_i - b_i| relative to the largest |b_j|: the coordinates are coupled by the
/// constraints, so each one's error is of the order of the largest one's (theta' = -1,424
/// rad/s carries error into gamma' = 11 rad/s), and the scale is the whole vector's.
fn worst(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0_f64, |s, v| s.max(v.abs()));
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs() / scale)
        .fold(0.0, f64::max)
}

/// Hairer and Wanner's right-hand side f(q, q') (drive, spring and velocity terms) and
/// constraint Jacobian G (6 x 7, row-major), with the declared parameter values. The book's
/// equations are M q'' = f - G^T lambda; ours M q'' + C q' + g + Phi_q^T lambda = tau, so
/// f = tau - C q' - g and G = Phi_q.
fn book(q: &[f64], qd: &[f64]) -> ([f64; 7], [f64; 42]) {
    let (m2, m4, m6) = (0.00365, 0.00706, 0.00706);
    let (xb, yb, xc, yc) = (-0.03635, 0.03273, 0.014, 0.072);
    let (d, da, e, ea, rr) = (0.028, 0.0115, 0.02, 0.01421, 0.007);
    let (ss, sc, sd, u, zf, zt, fa) = (0.035, 0.018, 0.02, 0.04, 0.02, 0.04, 0.01421);
    let (mom, c0, l0) = (0.033, 4530.0, 0.07785);
    let [be, th, ga, ph, de, om, ep]: [f64; 7] = q.try_into().unwrap();
    let [bep, thp, _, php, dep, omp, epp]: [f64; 7] = qd.try_into().unwrap();
    let (xd, yd) = (
        sd * ga.cos() + sc * ga.sin() + xb,
        sd * ga.sin() - sc * ga.cos() + yb,
    );
    let length = ((xd - xc).powi(2) + (yd - yc).powi(2)).sqrt();
    let force = -c0 * (length - l0) / length;
    let (fx, fy) = (force * (xd - xc), force * (yd - yc));
    let f = [
        mom - m2 * da * rr * thp * (thp + 2.0 * bep) * th.sin(),
        m2 * da * rr * bep * bep * th.sin(),
        fx * (sc * ga.cos() - sd * ga.sin()) + fy * (sd * ga.cos() + sc * ga.sin()),
        m4 * zt * (e - ea) * dep * dep * ph.cos(),
        -m4 * zt * (e - ea) * php * (php + 2.0 * dep) * ph.cos(),
        -m6 * u * (zf - fa) * epp * epp * om.cos(),
        m6 * u * (zf - fa) * omp * (omp + 2.0 * epp) * om.cos(),
    ];
    let mut g = [0.0; 42];
    let (sbt, cbt) = ((be + th).sin(), (be + th).cos());
    for row in [0, 2, 4] {
        g[row * 7] = -rr * be.sin() + d * sbt;
        g[row * 7 + 1] = d * sbt;
        g[(row + 1) * 7] = rr * be.cos() - d * cbt;
        g[(row + 1) * 7 + 1] = -d * cbt;
    }
    g[2] = -ss * ga.cos();
    g[7 + 2] = -ss * ga.sin();
    g[14 + 3] = -e * (ph + de).cos();
    g[14 + 4] = -e * (ph + de).cos() + zt * de.sin();
    g[21 + 3] = -e * (ph + de).sin();
    g[21 + 4] = -e * (ph + de).sin() - zt * de.cos();
    g[28 + 5] = zf * (om + ep).sin();
    g[28 + 6] = zf * (om + ep).sin() - u * ep.cos();
    g[35 + 5] = -zf * (om + ep).cos();
    g[35 + 6] = -zf * (om + ep).cos() - u * ep.sin();
    (f, g)
}

/// At random states (q' up to 2,000 rad/s, the run's scale), tau - C q' - g is the book's f
/// and Phi_q its G: C q' derived from M by Khang's formula, g from the spring's potential and
/// Phi_q from the rows, against the book's hand derivation. Tolerance 1e-12 of each
/// quantity's largest entry: the two are different formulas of one value, equal to rounding.
#[test]
fn forces_and_jacobian_are_the_books() {
    let mut x = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = move || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        (x >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    };
    for (route, system) in routes() {
        let mut out = mechanism::Evaluation::zeros(7, 6);
        for _ in 0..20 {
            let q: Vec<f64> = (0..7).map(|_| 4.0 * next()).collect();
            let qd: Vec<f64> = (0..7).map(|_| 2000.0 * next()).collect();
            system.evaluate(0.0, &q, &qd, &mut out);
            let (f, g) = book(&q, &qd);
            let ours: Vec<f64> = (0..7)
                .map(|i| out.forces[i] - out.coriolis[i] - out.gravity[i])
                .collect();
            let scale = f.iter().fold(0.0_f64, |s, v| s.max(v.abs()));
            for i in 0..7 {
                assert!(
                    (ours[i] - f[i]).abs() <= 1e-12 * scale,
                    "{route}: f[{i}] = {} against the book's {}",
                    ours[i],
                    f[i]
                );
            }
            let scale = g.iter().fold(0.0_f64, |s, v| s.max(v.abs()));
            for (k, book) in g.iter().enumerate() {
                let ours = out.phi_q[(k / 7, k % 7)];
                assert!(
                    (ours - book).abs() <= 1e-12 * scale,
                    "{route}: G[{}, {}] = {ours} against the book's {book}",
                    k / 7,
                    k % 7,
                );
            }
        }
    }
}

/// At the declared state (the book's consistent configuration, at rest), q'' and lambda
/// are the Test Set's: beta'' = 14,222.44, theta'' = -10,666.83, lambda = (98.57, -6.12, 0,
/// 0, 0, 0), the rest 0. Tolerance 1e-10 relative to the largest: the augmented system's
/// condition (M ~ 1e-5 kg m^2 against Phi_q ~ 1e-2 m) costs a few digits of the 16.
#[test]
fn initial_accelerations_and_multipliers_are_the_test_sets() {
    for (route, system) in routes() {
        let q = system.info().initial_guess.clone();
        let mut dynamics = Dynamics::new(system.info());
        dynamics.solve(system.as_ref(), 0.0, &q, &[0.0; 7]).unwrap();
        let mut qdd = [0.0; 7];
        qdd[..2].copy_from_slice(&QDD0);
        let mut lambda = [0.0; 6];
        lambda[..2].copy_from_slice(&LAMBDA0);
        let rel = |a: &[f64], b: &[f64]| {
            let scale = b.iter().fold(0.0_f64, |s, v| s.max(v.abs()));
            a.iter()
                .zip(b)
                .map(|(x, y)| (x - y).abs() / scale)
                .fold(0.0, f64::max)
        };
        let (e_qdd, e_lambda) = (
            rel(dynamics.accelerations(), &qdd),
            rel(dynamics.multipliers(), &lambda),
        );
        println!("{route}: q''(0) off by {e_qdd:e}, lambda(0) by {e_lambda:e}");
        assert!(
            e_qdd < 1e-10,
            "{route}: q''(0) = {:?}",
            dynamics.accelerations()
        );
        assert!(
            e_lambda < 1e-10,
            "{route}: lambda(0) = {:?}",
            dynamics.multipliers()
        );
    }
}

/// From the declared state, 0.03 s with DOP853 at rtol = atol = 1e-12: q and q' match the
/// Test Set's reference to 1e-8 of the largest entry (15.8 rad, 1,424 rad/s). Measured:
/// 9e-11 in q and 4e-10 in q' (the crank turns 2.5 times and reaches 1,140 rad/s); the
/// bound leaves a factor 25 or more for another platform's sin and cos. The constraints hold to
/// round-off throughout.
#[test]
fn the_motion_to_30_ms_is_the_test_sets_reference() {
    let options = SimulationOptions {
        t_end: 0.03,
        output_rate: 1000.0,
        integrator: IntegratorOptions::dop853(1e-12),
        ..Default::default()
    };
    for (route, system) in routes() {
        let run = simulate(system.as_ref(), &options).unwrap();
        let end = run.last().unwrap();
        assert_eq!(end.t, 0.03);
        let (e_q, e_qd) = (worst(end.q, &Q_END), worst(end.qd, &QD_END));
        println!("{route}: q(0.03) off by {e_q:e}, q'(0.03) by {e_qd:e}");
        assert!(e_q < 1e-8, "{route}: q(0.03) = {:?}", end.q);
        assert!(e_qd < 1e-8, "{route}: q'(0.03) = {:?}", end.qd);
        let phi = run
            .samples()
            .map(|s| s.constraint_error)
            .fold(0.0, f64::max);
        assert!(phi < 1e-12, "{route}: max |Phi| = {phi:e}");
    }
}
