//! The banded direct route of `Dynamics` (issue 28) against dense truth computed apart:
//! the KKT matrix [M Phi_q^T; Phi_q 0] built from the same evaluation and solved by
//! nalgebra's SVD (its pseudo-inverse, with gamma first projected onto range(Phi_q) by the
//! pseudo-inverse of Phi_q), on A02 chains of N = 10 and 40 loops at random states,
//! exactly at the flat singular position (Phi_q loses N rows of rank) and close to it, and
//! on an A02 chain whose every coupler row is declared twice (redundant rows at every
//! state). The pseudo-inverse solution of a consistent singular KKT system is its
//! minimum-norm solution: q'' (unique) and the minimum-norm multipliers.

use mechanism::nalgebra::{DMatrix, DVector};
use mechanism::{Dynamics, Interpreted, Kinematic, System};

use crate::sparsity::Lcg;

/// A02 with `loops` couplers in natural coordinates (the tips (x_i, y_i) of loops + 1
/// rockers, every bar 1 m and 1 kg); with `twice`, every coupler row is declared a second
/// time, multiplied by 2 (rank 2 loops + 1 of 3 loops + 1 rows).
pub(crate) fn a02(loops: usize, twice: bool) -> Interpreted {
    let tips = 0..=loops;
    let coordinates: String = tips
        .clone()
        .map(|i| format!("x{i} = {i}.0; y{i} = 1.0; "))
        .collect();
    let speed = |i: usize| format!("der(x{i})^2 + der(y{i})^2");
    let mut kinetic: Vec<String> = tips
        .clone()
        .map(|i| format!("m/6*({})", speed(i)))
        .collect();
    let mut potential: Vec<String> = tips.clone().map(|i| format!("m*g*y{i}/2")).collect();
    let mut rows: Vec<String> = tips
        .clone()
        .map(|i| format!("(x{i} - {i})^2 + y{i}^2 - 1;"))
        .collect();
    for (i, j) in (0..loops).map(|i| (i, i + 1)) {
        let cross = format!("der(x{i})*der(x{j}) + der(y{i})*der(y{j})");
        kinetic.push(format!("m/6*({} + {cross} + {})", speed(i), speed(j)));
        potential.push(format!("m*g*(y{i} + y{j})/2"));
        let bar = format!("(x{j} - x{i})^2 + (y{j} - y{i})^2 - 1");
        rows.push(format!("{bar};"));
        if twice {
            rows.push(format!("2*({bar});"));
        }
    }
    let source = format!(
        "pub struct Chain; parameters {{ m = 1.0; g = 9.81; }} coordinates {{ {coordinates} }} \
         independent {{ x0 = 0.0; der(x0) = 1.0; }} kinetic = {}; potential = {}; constraints {{ {} }}",
        kinetic.join(" + "),
        potential.join(" + "),
        rows.join(" "),
    );
    Interpreted::from_source(&source).unwrap()
}

/// Tips at rocker angle `theta` (all rockers parallel: the exact branch), each coordinate
/// moved by up to `offset`.
fn positions(loops: usize, theta: f64, offset: f64, rng: &mut Lcg) -> Vec<f64> {
    (0..=loops)
        .flat_map(|i| [i as f64 + theta.cos(), theta.sin()])
        .map(|v| v + offset * rng.next())
        .collect()
}

/// The dense truth at the evaluation `dynamics` holds: (q'', minimum-norm lambda) by the SVD
/// pseudo-inverse of the KKT matrix, gamma projected onto range(Phi_q); and the ratio of
/// the largest to the smallest nonzero singular value of that matrix.
fn dense_truth(dynamics: &Dynamics) -> (Vec<f64>, Vec<f64>, f64) {
    let e = dynamics.evaluation();
    let (n, m) = (e.mass.nrows(), e.phi_q.nrows());
    let mut k = DMatrix::zeros(n + m, n + m);
    k.view_mut((0, 0), (n, n)).copy_from(&e.mass);
    k.view_mut((n, 0), (m, n)).copy_from(&e.phi_q);
    k.view_mut((0, n), (n, m)).copy_from(&e.phi_q.transpose());
    let a_pinv = e.phi_q.clone().pseudo_inverse(1e-12).unwrap();
    let mut w = &a_pinv * &e.gamma;
    w += &a_pinv * (&e.gamma - &e.phi_q * &w);
    let gamma = &e.phi_q * w;
    let mut rhs = DVector::zeros(n + m);
    rhs.rows_mut(0, n)
        .copy_from(&(&e.forces - &e.coriolis - &e.gravity));
    rhs.rows_mut(n, m).copy_from(&gamma);
    let svd = k.clone().svd(true, true);
    let largest = svd.singular_values.max();
    let cut = 1e-13 * largest;
    let smallest = svd
        .singular_values
        .iter()
        .copied()
        .filter(|&s| s > cut)
        .fold(f64::INFINITY, f64::min);
    // nalgebra's SVD solve alone leaves residuals up to 1e-9 on some of these matrices;
    // iterative refinement with it (each step contracts the error by the factorisation's
    // relative accuracy) brings the residual to round-off, which is asserted.
    let mut sol = svd.solve(&rhs, cut).unwrap();
    for _ in 0..3 {
        let residual = &rhs - &k * &sol;
        sol += svd.solve(&residual, cut).unwrap();
    }
    let residual = (&rhs - &k * &sol).amax();
    assert!(
        residual < 1e-12 * rhs.amax().max(1.0),
        "dense truth: residual {residual:.1e}"
    );
    (
        sol.rows(0, n).iter().copied().collect(),
        sol.rows(n, m).iter().copied().collect(),
        largest / smallest,
    )
}

/// Solves at (q, q') and compares q'' and the minimum-norm multipliers with the dense
/// truth. Both solutions are backward stable, so they differ by at most about kappa eps
/// times the solution's size (kappa the condition of the KKT matrix on its range): the
/// tolerance is 100 kappa eps |sol|, the 100 covering the growth of the n + m = 40..170
/// term sums. Returns kappa.
fn agrees(system: &dyn System, dynamics: &mut Dynamics, q: &[f64], qd: &[f64], what: &str) -> f64 {
    let banded = dynamics.banded_solves;
    dynamics.solve(system, 0.0, q, qd).unwrap();
    assert_eq!(
        dynamics.banded_solves,
        banded + 1,
        "{what}: not the banded route"
    );
    let (qdd, lambda, kappa) = dense_truth(dynamics);
    let scale = qdd
        .iter()
        .chain(&lambda)
        .fold(1.0f64, |a, v| a.max(v.abs()));
    let tol = 100.0 * kappa * f64::EPSILON * scale;
    for (i, (got, want)) in dynamics.accelerations().iter().zip(&qdd).enumerate() {
        assert!(
            (got - want).abs() <= tol,
            "{what}: q''[{i}] {got} vs {want} (tol {tol:.1e})"
        );
    }
    let got = dynamics.min_norm_multipliers().to_vec();
    for (r, (got, want)) in got.iter().zip(&lambda).enumerate() {
        assert!(
            (got - want).abs() <= tol,
            "{what}: lambda[{r}] {got} vs {want} (tol {tol:.1e})"
        );
    }
    kappa
}

#[test]
fn banded_route_matches_the_dense_kkt_solve_on_random_states_of_a02() {
    let mut rng = Lcg(0x28a0);
    for loops in [10, 40] {
        let system = a02(loops, false);
        let n = system.info().n();
        let mut dynamics = Dynamics::new(system.info());
        for k in 0..6 {
            // Off the manifold by up to 1e-3 m and at random rates: the solve must hold for
            // every state an integrator stage can hand it.
            let theta = 0.3 + 2.5 * (rng.next() + 1.0) / 2.0;
            let q = positions(loops, theta, 1e-3, &mut rng);
            let qd: Vec<f64> = (0..n).map(|_| 2.0 * rng.next()).collect();
            let kappa = agrees(
                &system,
                &mut dynamics,
                &q,
                &qd,
                &format!("N {loops} state {k}"),
            );
            assert!(kappa < 1e8, "N {loops}: kappa {kappa:.1e}");
        }
    }
}

#[test]
fn banded_route_passes_the_flat_position_with_consistent_gamma_and_minimum_norm_multipliers() {
    let mut rng = Lcg(0xf1a7);
    for loops in [10, 40] {
        let system = a02(loops, false);
        let n = system.info().n();
        let mut dynamics = Dynamics::new(system.info());
        // Exactly flat (the rockers along x): Phi_q has rank loops + 1 of 2 loops + 1. First
        // on the exact branch (tips moving up at 1 m/s, gamma consistent), then at random
        // rates (gamma with a part outside range(Phi_q), which both sides project away).
        let q = positions(loops, 0.0, 0.0, &mut rng);
        let up: Vec<f64> = (0..n).map(|k| (k % 2) as f64).collect();
        let random: Vec<f64> = (0..n).map(|_| rng.next()).collect();
        for (qd, what) in [(&up, "exact branch"), (&random, "random rates")] {
            agrees(
                &system,
                &mut dynamics,
                &q,
                qd,
                &format!("N {loops} flat, {what}"),
            );
        }
        // Close to flat (rocker angle 1e-5 rad): full rank, the smallest singular value of
        // Phi_q about 1e-5 of its largest.
        let q = positions(loops, 1e-5, 0.0, &mut rng);
        let kappa = agrees(
            &system,
            &mut dynamics,
            &q,
            &up,
            &format!("N {loops} near flat"),
        );
        assert!(kappa > 1e6, "N {loops}: near flat, kappa {kappa:.1e}");
    }
}

#[test]
fn banded_route_leaves_out_redundant_rows_and_gives_the_minimum_norm_multipliers() {
    let mut rng = Lcg(0x2ed);
    let loops = 10;
    let system = a02(loops, true);
    let (n, m) = (system.info().n(), system.info().m());
    assert_eq!(m, 3 * loops + 1);
    let mut dynamics = Dynamics::new(system.info());
    for k in 0..4 {
        let theta = 0.3 + 2.5 * (rng.next() + 1.0) / 2.0;
        let q = positions(loops, theta, 1e-3, &mut rng);
        let qd: Vec<f64> = (0..n).map(|_| rng.next()).collect();
        agrees(
            &system,
            &mut dynamics,
            &q,
            &qd,
            &format!("redundant, state {k}"),
        );
    }
    // Flat: the rocker rows' rank drop on top of the repeated rows.
    let q = positions(loops, 0.0, 0.0, &mut rng);
    let qd: Vec<f64> = (0..n).map(|_| rng.next()).collect();
    agrees(&system, &mut dynamics, &q, &qd, "redundant, flat");
    assert_eq!(dynamics.augmented_solves, 0);
}

/// A run of A02 reports its right-hand sides on the banded route: every solve of the
/// N = 10 chain (n + m = 43, band 4) goes there and none falls back, and the count reaches
/// the run's statistics (and so summary.json's `banded_solves`).
#[test]
fn a_run_counts_its_banded_solves() {
    use mechanism::{IntegratorOptions, Method, SimulationOptions, simulate};
    let system = a02(10, false);
    let options = SimulationOptions {
        t_end: 0.2,
        integrator: IntegratorOptions {
            method: Method::Dop853,
            rtol: 1e-8,
            atol: 1e-8,
            ..Default::default()
        },
        ..Default::default()
    };
    let tr = simulate(&system, &options).unwrap();
    assert!(tr.stats.banded_solves > 0);
    assert_eq!(tr.stats.augmented_solves, 0);
    assert!(tr.stats.banded_solves <= tr.stats.rhs_evaluations);
}
