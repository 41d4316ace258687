//! The derivatives of the constrained forward dynamics (q'' and lambda by q, q' and an
//! effort u) against central differences of our own dynamics, on the five-bar leg (two loop
//! rows, full rank) and Bricard's linkage (30 rows of rank 29: one redundant), through the
//! three routes: the emitted code with the fixed-size solver
//! (`Mechanism::constrained_dynamics_derivatives`), and `DynamicsDerivatives` on the
//! compiled and on the interpreted system (`Interpreted::for_derivatives`). And the
//! derivatives by the parameters (`inverse_dynamics_parameter_derivatives`) against
//! central differences and, on the Panda, against dtau/dg = g(q)/g.
//!
//! The central differences, D(h) = (f(x + h v) - f(x - h v)) / 2h, carry a truncation
//! error h^2/6 |f'''| and a round-off error about eps |f| kappa / h (kappa: the error
//! growth of the KKT solve, below 1e3 here). With h = 1e-4 for q and q' the first is about
//! 2e-9 of the derivative's scale (|f'''| ~ |f'| for these trigonometric dynamics) and the
//! second at most about 2e-9 of it; for u, h = 1 (f is affine in u: no truncation).
//! Measured: at most 4.0e-9 (five-bar, by q), 1.4e-9 (Bricard, by q), 5e-11 (by q'),
//! 2e-15 (by u), and the error by q falls by 4.05 when h is halved: truncation, as
//! estimated. The tolerance, 1e-7 of the largest entry of the derivative (at least 1), is
//! 25 times the bound; a wrong term, sign or column is O(1) of it.

use mechanism::builtin::{Bricard, FiveBar, Panda, builtin_source};
use mechanism::fixed::{KktDerivatives, kkt_solve};
use mechanism::{
    AssemblyOptions, Compiled, DynamicsDerivatives, Interpreted, Kinematic, Mechanism, System,
    assemble,
};
use nalgebra::{DMatrix, DVector, SMatrix, SVector};

/// q'' and lambda of the fixed-size solver at (q, q') with the effort u: the function the
/// derivatives differentiate.
fn solve<T: Mechanism<N, M>, const N: usize, const M: usize>(
    mech: &T,
    q: &SVector<f64, N>,
    qd: &SVector<f64, N>,
    u: &SVector<f64, N>,
) -> DVector<f64> {
    let mut e = mech.evaluate(0.0, q, qd);
    e.forces += u;
    let s = kkt_solve(&e, 0.0).expect("determined");
    DVector::from_iterator(N + M, s.qdd.iter().chain(s.lambda.iter()).copied())
}

/// The derivative of [q''; lambda] along `v` in the variable `which` (0: q, 1: q', 2: u).
fn analytic<const N: usize, const M: usize>(
    d: &KktDerivatives<N, M>,
    which: usize,
    v: &SVector<f64, N>,
) -> DVector<f64> {
    let (a, b) = match which {
        0 => (d.dqdd_dq * v, d.dlambda_dq * v),
        1 => (d.dqdd_dqd * v, d.dlambda_dqd * v),
        _ => (d.dqdd_du * v, d.dlambda_du * v),
    };
    DVector::from_iterator(N + M, a.iter().chain(b.iter()).copied())
}

/// Central differences of [`solve`] along `v` in the variable `which`.
fn central<T: Mechanism<N, M>, const N: usize, const M: usize>(
    mech: &T,
    (q, qd, u): (&SVector<f64, N>, &SVector<f64, N>, &SVector<f64, N>),
    which: usize,
    v: &SVector<f64, N>,
) -> DVector<f64> {
    let h = if which == 2 { 1.0 } else { 1e-4 };
    let at = |s: f64| {
        let step = v * (s * h);
        match which {
            0 => solve(mech, &(q + step), qd, u),
            1 => solve(mech, q, &(qd + step), u),
            _ => solve(mech, q, qd, &(u + step)),
        }
    };
    (at(1.0) - at(-1.0)) / (2.0 * h)
}

/// Each derivative of `d` along each direction of `directions` (per variable) against the
/// central differences, within 1e-7 of its largest entry (module docs).
fn check_against_differences<T: Mechanism<N, M>, const N: usize, const M: usize>(
    name: &str,
    mech: &T,
    state: (&SVector<f64, N>, &SVector<f64, N>, &SVector<f64, N>),
    d: &KktDerivatives<N, M>,
    directions: [&[SVector<f64, N>]; 3],
) {
    for (which, vs) in directions.iter().enumerate() {
        for (k, v) in vs.iter().enumerate() {
            let ours = analytic(d, which, v);
            let theirs = central(mech, state, which, v);
            let scale = ours.amax().max(1.0);
            let err = (&ours - &theirs).amax();
            assert!(
                err <= 1e-7 * scale,
                "{name}: derivative by variable {which} along direction {k}: error {err:e} \
                 (scale {scale:e})"
            );
        }
    }
}

/// The unit vectors of R^N.
fn units<const N: usize>() -> Vec<SVector<f64, N>> {
    (0..N)
        .map(|k| SVector::from_fn(|i, _| f64::from(u8::from(i == k))))
        .collect()
}

/// A state of `mech` on its constraints, its rates along them, and an effort.
fn state<T: Mechanism<N, M> + Default, const N: usize, const M: usize>()
-> (SVector<f64, N>, SVector<f64, N>, SVector<f64, N>) {
    let system = Compiled::new(T::default());
    let s = assemble(&system, 0.0, &AssemblyOptions::default()).expect("assembles");
    let q = SVector::<f64, N>::from_column_slice(&s.q);
    // Rates along the constraints: the null space of Phi_q times a vector of O(1).
    let phi_q = T::default().constraint_jacobian(0.0, &q);
    let free = null_space(&phi_q);
    let weights = DVector::from_fn(free.ncols(), |k, _| 1.5 - 0.7 * k as f64);
    let qd = SVector::<f64, N>::from_column_slice((free * weights).as_slice());
    let u = SVector::<f64, N>::from_fn(|i, _| 0.3 * (i as f64 + 1.0).sin());
    (q, qd, u)
}

/// An orthonormal basis of the null space of `a` (M x N), by SVD.
fn null_space<const N: usize, const M: usize>(a: &SMatrix<f64, M, N>) -> DMatrix<f64> {
    let a = DMatrix::from_column_slice(M, N, a.as_slice());
    let ata = a.transpose() * &a;
    let eigen = ata.symmetric_eigen();
    let scale = eigen.eigenvalues.amax().max(1.0);
    let columns: Vec<DVector<f64>> = (0..N)
        .filter(|&k| eigen.eigenvalues[k] <= 1e-20 * scale)
        .map(|k| eigen.eigenvectors.column(k).into_owned())
        .collect();
    DMatrix::from_columns(&columns)
}

#[test]
fn five_bar_derivatives_match_central_differences() {
    let mech = FiveBar::default();
    let (q, qd, u) = state::<FiveBar, 4, 2>();
    let d = mech
        .constrained_dynamics_derivatives(0.0, &q, &qd, &u)
        .expect("determined");
    // Full row rank: every direction of q, q' and u, off the constraints too.
    let e = units::<4>();
    check_against_differences("five-bar", &mech, (&q, &qd, &u), &d, [&e, &e, &e]);
}

#[test]
fn bricard_derivatives_match_central_differences() {
    let mech = Bricard::default();
    let (q, qd, u) = state::<Bricard, 30, 30>();
    let d = mech
        .constrained_dynamics_derivatives(0.0, &q, &qd, &u)
        .expect("determined");
    // One row is redundant: its multiplier and its derivatives are zero.
    let dropped: Vec<usize> = (0..30).filter(|&r| d.lambda[r] == 0.0).collect();
    assert_eq!(dropped.len(), 1, "one redundant row");
    let r = dropped[0];
    for m in [&d.dlambda_dq, &d.dlambda_dqd, &d.dlambda_du] {
        assert!(m.row(r).iter().all(|&x| x == 0.0));
    }
    // q along the motion (the one direction the rows allow: off it the redundant row's
    // dependence breaks and the solver's choice of multipliers jumps); q' and u along
    // every coordinate.
    let phi_q = mech.constraint_jacobian(0.0, &q);
    let free = null_space(&phi_q);
    assert_eq!(free.ncols(), 1, "Bricard's mobility is 1");
    let along = [SVector::<f64, 30>::from_column_slice(free.as_slice())];
    let e = units::<30>();
    check_against_differences("Bricard", &mech, (&q, &qd, &u), &d, [&along, &e, &e]);
}

/// The run-time workspace on the compiled and on the interpreted system gives the fixed
/// solver's numbers: the same algorithm on run-time storage, with the same sums in the same
/// order (measured: the same bits; the tolerance, 1e-10 of each matrix's largest entry,
/// leaves room for a build that fuses multiply-adds in one of them only).
fn routes_agree<T: Mechanism<N, M> + Default, const N: usize, const M: usize>(name: &str) {
    let (q, qd, u) = state::<T, N, M>();
    let fixed = T::default()
        .constrained_dynamics_derivatives(0.0, &q, &qd, &u)
        .expect("determined");
    let source = builtin_source(name).expect("a library mechanism");
    let model = mechanism_codegen::parse_model_str(source).expect("parses");
    let interpreted = Interpreted::for_derivatives(model).expect("compiles");
    let compiled = Compiled::new(T::default());
    for system in [&compiled as &dyn System, &interpreted] {
        let mut d = DynamicsDerivatives::new(system.info());
        d.compute(system, 0.0, q.as_slice(), qd.as_slice(), u.as_slice())
            .expect("determined");
        let pairs: [(&[f64], &[f64]); 8] = [
            (d.accelerations(), fixed.qdd.as_slice()),
            (d.multipliers(), fixed.lambda.as_slice()),
            (d.dqdd_dq().as_slice(), fixed.dqdd_dq.as_slice()),
            (d.dqdd_dqd().as_slice(), fixed.dqdd_dqd.as_slice()),
            (d.dqdd_du().as_slice(), fixed.dqdd_du.as_slice()),
            (d.dlambda_dq().as_slice(), fixed.dlambda_dq.as_slice()),
            (d.dlambda_dqd().as_slice(), fixed.dlambda_dqd.as_slice()),
            (d.dlambda_du().as_slice(), fixed.dlambda_du.as_slice()),
        ];
        for (k, (ours, theirs)) in pairs.iter().enumerate() {
            let scale = theirs.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
            let err = ours
                .iter()
                .zip(*theirs)
                .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(err <= 1e-10 * scale, "{name}, output {k}: {err:e}");
        }
    }
}

#[test]
fn the_run_time_routes_give_the_fixed_solvers_derivatives() {
    routes_agree::<FiveBar, 4, 2>("five_bar");
    routes_agree::<Bricard, 30, 30>("bricard");
}

#[test]
fn parameter_derivatives_match_central_differences() {
    // The five-bar's six parameters (lengths, masses, g), at a state off equilibrium.
    let mech = FiveBar::default();
    let (q, qd, _) = state::<FiveBar, 4, 2>();
    let qdd = SVector::<f64, 4>::new(0.7, -1.1, 0.4, 2.0);
    let p = FiveBar::PARAMETERS.len();
    let mut dp = vec![0.0; 4 * p];
    assert!(mech.inverse_dynamics_parameter_derivatives(0.0, &q, &qd, &qdd, &mut dp));
    assert!(!mech.inverse_dynamics_parameter_derivatives(0.0, &q, &qd, &qdd, &mut dp[1..]));
    for k in 0..p {
        let value = mech.parameter(k).unwrap();
        // tau is polynomial of degree 3 at most in each parameter (m l^2): truncation
        // h^2 |tau'''| / 6 with h = 1e-4 of the value is below 1e-9 of tau.
        let h = 1e-4 * value.abs().max(1e-3);
        let at = |x: f64| {
            let mut m = mech.clone();
            m.set_parameter(k, x)
                .expect("a value within the declared range");
            m.inverse_dynamics(0.0, &q, &qd, &qdd)
        };
        let fd = (at(value + h) - at(value - h)) / (2.0 * h);
        let ours = SVector::<f64, 4>::from_column_slice(&dp[4 * k..4 * k + 4]);
        let scale = ours.amax().max(1.0);
        assert!(
            (ours - fd).amax() <= 1e-7 * scale,
            "dtau/d{}: {ours} against {fd}",
            FiveBar::PARAMETERS[k]
        );
    }
    // The interpreter runs the same program: the same bits.
    let source = builtin_source("five_bar").unwrap();
    let model = mechanism_codegen::parse_model_str(source).unwrap();
    let interpreted = Interpreted::for_derivatives(model).unwrap();
    let mut out = DMatrix::zeros(4, p);
    interpreted
        .parameter_derivatives(0.0, q.as_slice(), qd.as_slice(), qdd.as_slice(), &mut out)
        .expect("compiled with its derivatives");
    assert_eq!(out.as_slice(), dp.as_slice());
}

#[test]
fn the_pandas_derivative_by_g_is_its_gravity_over_g() {
    // g(q) is linear in the parameter g and nothing else of tau reads it: dtau/dg = g(q)/g.
    let arm = Panda::default();
    let q = SVector::<f64, 7>::from([0.1, -0.7, 0.2, -2.2, 0.1, 1.5, 0.8]);
    let qd = SVector::<f64, 7>::from([0.3, -0.2, 0.1, 0.4, -0.5, 0.2, 0.1]);
    let qdd = SVector::<f64, 7>::from([1.0, -2.0, 0.5, 0.3, -0.1, 0.2, 0.9]);
    assert_eq!(Panda::PARAMETERS, ["g"]);
    let mut dp = [0.0; 7];
    assert!(arm.inverse_dynamics_parameter_derivatives(0.0, &q, &qd, &qdd, &mut dp));
    let expected = arm.gravity(&q) / arm.parameter(0).unwrap();
    let ours = SVector::<f64, 7>::from(dp);
    assert!((ours - expected).amax() <= 1e-14 * expected.amax());
}

#[test]
fn bad_requests_get_typed_errors() {
    let source = builtin_source("five_bar").unwrap();
    let model = mechanism_codegen::parse_model_str(source).unwrap();
    // Built without its derivatives, the interpreter has no tangent to offer: the error
    // says what is missing and how to get it.
    let mut derived = model.clone();
    let eqs = mechanism_codegen::derive(&mut derived).unwrap();
    let lean =
        Interpreted::from_equations_with(derived, eqs, mechanism_codegen::Tangents::None).unwrap();
    let mut d = DynamicsDerivatives::new(lean.info());
    let (q, qd, u) = state::<FiveBar, 4, 2>();
    let err = d
        .compute(&lean, 0.0, q.as_slice(), qd.as_slice(), u.as_slice())
        .unwrap_err();
    assert!(
        matches!(&err, mechanism::Error::NotProvided { what } if what.contains("residual")),
        "{err}"
    );
    assert!(
        err.to_string().contains("Interpreted::for_derivatives"),
        "{err}"
    );
    // A slice of the wrong length, a NaN in the state.
    let full = Interpreted::for_derivatives(model).unwrap();
    let err = d.compute(&full, 0.0, &q.as_slice()[..3], qd.as_slice(), u.as_slice());
    assert!(matches!(
        err,
        Err(mechanism::Error::WrongLength { what: "q", .. })
    ));
    let mut bad = q;
    bad[1] = f64::NAN;
    let err = d.compute(&full, 0.0, bad.as_slice(), qd.as_slice(), u.as_slice());
    assert!(
        matches!(
            err,
            Err(mechanism::Error::NonFiniteTerm { .. } | mechanism::Error::NonFinite { .. })
        ),
        "{err:?}"
    );
    // The unconstrained form refuses a mechanism with rows; the constrained one a NaN.
    let mech = FiveBar::default();
    assert!(
        mech.forward_dynamics_derivatives(0.0, &q, &qd, &u)
            .is_none()
    );
    assert!(matches!(
        mech.constrained_dynamics_derivatives(0.0, &bad, &qd, &u),
        Err(mechanism::fixed::FixedError::NotFinite { .. })
    ));
}
