//! Linearisation about equilibria of mechanisms with redundant constraint rows (exact
//! tangents, `linearize_steady`): the dependent rows are dropped, so the eigenvalues are
//! those of the same mechanism written with independent rows; and a mechanism with
//! neither stiffness nor damping has only structural zeros (an empty reduced matrix).

use mechanism::{
    AssemblyOptions, Dynamics, Independent, Interpreted, Kinematic, SteadyOptions, assemble_from,
    linearize_steady,
};

/// A pendulum of length L in (th, x, y): two rows tie the bob to th, and the third row,
/// x^2 + y^2 = L^2, is implied by them (a combination of them on the constraint manifold
/// only, so that off it all three rows look independent).
fn pendulum(g: f64, redundant: bool) -> Interpreted {
    let third = if redundant { "x^2 + y^2 - L^2;" } else { "" };
    let text = format!(
        "pub struct RedundantPendulum;
         parameters {{ m = 1.5; L = 0.8; g = {g:?}; }}
         coordinates {{ th = 0.0; x = 0.0; y = -0.8; }}
         independent {{ th = 0.0; der(th) = 0.0; }}
         kinetic = 1/2*m*(der(x)^2 + der(y)^2);
         potential = m*g*y;
         constraints {{ x - L*sin(th); y + L*cos(th); {third} }}"
    );
    let model = mechanism_codegen::parse_model_str(&text).expect("parses");
    Interpreted::for_linearization(model).expect("derives")
}

fn mechanism_file(name: &str) -> Interpreted {
    let path = format!("{}/mechanisms/{name}.mech", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap();
    Interpreted::for_linearization(mechanism_codegen::parse_model_str(&text).unwrap()).unwrap()
}

/// The eigenvalues (re, im) sorted.
fn sorted(values: &[nalgebra::Complex<f64>]) -> Vec<(f64, f64)> {
    let mut v: Vec<(f64, f64)> = values.iter().map(|z| (z.re, z.im)).collect();
    v.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    v
}

/// Hanging at rest, the pendulum with the redundant row oscillates at sqrt(g / L), as the
/// one without it does.
#[test]
fn a_redundant_row_leaves_the_pendulum_frequency() {
    let omega = (9.81_f64 / 0.8).sqrt();
    for redundant in [false, true] {
        let system = pendulum(9.81, redundant);
        let q = [0.0, 0.0, -0.8];
        let lin = linearize_steady(&system, 0.0, &q, &[0.0; 3], &SteadyOptions::default())
            .unwrap_or_else(|e| panic!("redundant = {redundant}: {e}"));
        let s = sorted(&lin.eigenvalues);
        println!("redundant = {redundant}: {s:?}");
        assert_eq!(lin.variables, ["th", "der(th)"]);
        assert_eq!(s.len(), 2);
        // Exact tangents: round-off of a 2 x 2 eigenproblem.
        for (z, im) in s.iter().zip([-omega, omega]) {
            assert!(
                z.0.abs() < 1e-12 && (z.1 - im).abs() < 1e-12 * omega,
                "{s:?}"
            );
        }
    }
}

/// With g = 0 nothing restores or damps the pendulum: th and der(th) are both structural
/// zeros, and the matrix left without them is empty (no eigenvalues, no failure).
#[test]
fn no_stiffness_and_no_damping_leave_only_structural_zeros() {
    let system = pendulum(0.0, true);
    let q = [0.0, 0.0, -0.8];
    let lin = linearize_steady(&system, 0.0, &q, &[0.0; 3], &SteadyOptions::default()).unwrap();
    assert_eq!(lin.structural, [0, 1]);
    assert!(lin.reduced.is_empty());
    assert!(
        lin.eigenvalues.iter().all(|z| z.norm() == 0.0),
        "{:?}",
        lin.eigenvalues
    );
}

/// The crank angle at which the four-bar hangs at rest (th1'' = 0 with th1' = 0), by
/// bisection of th1'' between two angles where it has opposite signs; returns the
/// configuration and th1'' there.
fn hanging_equilibrium(system: &Interpreted, (mut lo, mut hi): (f64, f64)) -> (Vec<f64>, f64) {
    let crank = system.info().coordinate_index("th1").expect("th1");
    let mut dynamics = Dynamics::new(system.info());
    let mut at = |th1: f64| {
        let independent = [Independent {
            coordinate: crank,
            position: th1,
            velocity: 0.0,
        }];
        let guess = &system.info().initial_guess;
        let s = assemble_from(
            system,
            0.0,
            &independent,
            guess,
            &AssemblyOptions::default(),
        )
        .unwrap();
        dynamics.solve(system, 0.0, &s.q, &s.qd).unwrap();
        (s.q, dynamics.accelerations()[crank])
    };
    let sign_lo = at(lo).1.signum();
    assert_ne!(sign_lo, at(hi).1.signum(), "no equilibrium bracketed");
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if at(mid).1.signum() == sign_lo {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let (q, qdd) = at(0.5 * (lo + hi));
    (q, qdd)
}

/// The planar four-bar written with bodies and spatial revolute joints (12 rows of which
/// 9 are independent, 20 rows in all) and written with its two loop rows: about the same
/// hanging equilibrium both linearise to the same pair +-i omega.
#[test]
fn four_bar_with_spatial_joints_linearises_as_the_planar_one() {
    let planar = mechanism_file("planar_four_bar");
    let bodies = mechanism_file("planar_four_bar_bodies");
    let mut pairs = Vec::new();
    for system in [&planar, &bodies] {
        let (q, qdd) = hanging_equilibrium(system, (-2.5, -0.7));
        let qd = vec![0.0; q.len()];
        let options = SteadyOptions {
            steady_tolerance: 1e-9_f64.max(10.0 * qdd.abs()),
            ..SteadyOptions::default()
        };
        let lin = linearize_steady(system, 0.0, &q, &qd, &options).unwrap();
        let s = sorted(&lin.reduced);
        let crank = system.info().coordinate_index("th1").unwrap();
        println!("{} rows: th1 = {:.12}, {s:?}", system.info().m(), q[crank]);
        assert_eq!(s.len(), 2, "{s:?}");
        assert!(s[1].1 > 0.0 && s[1].0.abs() < 1e-9 * s[1].1, "{s:?}");
        pairs.push((q[crank], s[1].1));
    }
    // The equilibria agree to the bisection's resolution; the frequencies to round-off of
    // the tangents (relative 1e-9 leaves room for the equilibria's 1e-15 difference
    // magnified by the stiffness's slope).
    assert!((pairs[0].0 - pairs[1].0).abs() < 1e-12, "{pairs:?}");
    assert!(
        (pairs[0].1 - pairs[1].1).abs() < 1e-9 * pairs[0].1,
        "{pairs:?}"
    );
}
