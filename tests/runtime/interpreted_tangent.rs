//! The exact residual tangent the interpreter route derives symbolically
//! (K = dF/dq, D = dF/dq' of F = M q'' + C q' + g - tau + Phi_q^T lambda) against central
//! finite differences of F, and HHT-alpha using it keeping its second order.

use mechanism::builtin::{builtin, builtin_names, builtin_source};
use mechanism::{
    Evaluation, IntegratorOptions, Interpreted, Kinematic, Method, SimulationOptions,
    Stabilization, System, Tangent, simulate,
};

/// F = M q'' + C q' + g - tau + Phi_q^T lambda, through `evaluate` (a route independent of
/// the symbolic tangent).
fn residual(
    sys: &dyn System,
    t: f64,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    lambda: &[f64],
) -> Vec<f64> {
    let (n, m) = (sys.info().n(), sys.info().m());
    let mut e = Evaluation::zeros(n, m);
    sys.evaluate(t, q, qd, &mut e);
    (0..n)
        .map(|i| {
            let mut f = e.coriolis[i] + e.gravity[i] - e.forces[i];
            f += (0..n).map(|j| e.mass[(i, j)] * qdd[j]).sum::<f64>();
            f += (0..m).map(|k| e.phi_q[(k, i)] * lambda[k]).sum::<f64>();
            f
        })
        .collect()
}

/// A small deterministic generator (xorshift) for reproducible states.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

#[test]
fn tangent_matches_central_differences_on_every_builtin() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for name in builtin_names() {
        let sys = Interpreted::from_source(builtin_source(name).unwrap()).unwrap();
        let (n, m) = (sys.info().n(), sys.info().m());
        for _ in 0..3 {
            let q: Vec<f64> = sys
                .info()
                .initial_guess
                .iter()
                .map(|g| g + 0.2 * rng.next())
                .collect();
            let qd: Vec<f64> = (0..n).map(|_| 2.0 * rng.next()).collect();
            let qdd: Vec<f64> = (0..n).map(|_| 5.0 * rng.next()).collect();
            let lambda: Vec<f64> = (0..m).map(|_| 3.0 * rng.next()).collect();
            let t = 0.3;
            let mut tan = Tangent::zeros(n);
            sys.tangent(t, &q, &qd, &qdd, &lambda, &mut tan)
                .expect("interpreted systems provide the tangent");
            // Central differences: truncation O(h^2) ~ 1e-10 for these smooth, O(1)-scaled
            // functions, rounding ~ eps |F| / h ~ 1e-10; 1e-6 (abs + rel) leaves a wide margin
            // while a wrong entry (a missing term is O(1)) still fails.
            let h = 1e-5;
            for j in 0..n {
                for (which, base) in [("dF/dq", &q), ("dF/dq'", &qd)] {
                    let (mut plus, mut minus) = (base.clone(), base.clone());
                    plus[j] += h;
                    minus[j] -= h;
                    let (fp, fm) = if which == "dF/dq" {
                        (
                            residual(&sys, t, &plus, &qd, &qdd, &lambda),
                            residual(&sys, t, &minus, &qd, &qdd, &lambda),
                        )
                    } else {
                        (
                            residual(&sys, t, &q, &plus, &qdd, &lambda),
                            residual(&sys, t, &q, &minus, &qdd, &lambda),
                        )
                    };
                    for i in 0..n {
                        let fd = (fp[i] - fm[i]) / (2.0 * h);
                        let exact = if which == "dF/dq" {
                            tan.stiffness[(i, j)]
                        } else {
                            tan.damping[(i, j)]
                        };
                        assert!(
                            (fd - exact).abs() <= 1e-6 * (1.0 + exact.abs()),
                            "{name}: {which}[{i},{j}] exact {exact} vs finite difference {fd}"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn hht_with_the_exact_tangent_is_second_order() {
    let sys = Interpreted::from_source(builtin_source("planar_four_bar").unwrap()).unwrap();
    let run = |method| {
        let options = SimulationOptions {
            t_end: 0.5,
            output_rate: 2.0,
            integrator: IntegratorOptions {
                method,
                rtol: 1e-12,
                atol: 1e-12,
                ..IntegratorOptions::default()
            },
            stabilization: Stabilization::Projection,
            ..SimulationOptions::default()
        };
        simulate(&sys, &options).unwrap().last().unwrap().q.to_vec()
    };
    let reference = run(Method::Dop853);
    let err = |h| {
        let q = run(Method::Hht { h, alpha: 0.0 });
        q.iter()
            .zip(&reference)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
    };
    let (e1, e2) = (err(2e-3), err(1e-3));
    let ratio = e1 / e2;
    // Second order: halving h divides the error by 4 (3 to 5 allows for the asymptotic
    // regime not being reached exactly).
    assert!(
        (3.0..5.0).contains(&ratio),
        "errors {e1:e} and {e2:e}, ratio {ratio}"
    );
}

#[test]
fn compiled_tangent_equals_the_interpreter_route() {
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    for name in builtin_names() {
        let compiled = builtin(name).unwrap();
        let interpreted = Interpreted::from_source(builtin_source(name).unwrap()).unwrap();
        let (n, m) = (compiled.info().n(), compiled.info().m());
        let q: Vec<f64> = compiled
            .info()
            .initial_guess
            .iter()
            .map(|g| g + 0.3 * rng.next())
            .collect();
        let qd: Vec<f64> = (0..n).map(|_| 2.0 * rng.next()).collect();
        let qdd: Vec<f64> = (0..n).map(|_| 5.0 * rng.next()).collect();
        let lambda: Vec<f64> = (0..m).map(|_| 3.0 * rng.next()).collect();
        let (mut a, mut b) = (Tangent::zeros(n), Tangent::zeros(n));
        compiled
            .tangent(0.7, &q, &qd, &qdd, &lambda, &mut a)
            .expect("emitted by mechanism!");
        interpreted
            .tangent(0.7, &q, &qd, &qdd, &lambda, &mut b)
            .unwrap();
        // The same derived expressions evaluated by two back ends: they differ only by
        // reassociation in rounding, so 1e-12 relative to the largest entry.
        for (x, y) in [(&a.stiffness, &b.stiffness), (&a.damping, &b.damping)] {
            let scale = y.amax().max(1.0);
            assert!((x - y).amax() <= 1e-12 * scale, "{name}: {x} vs {y}");
        }
    }
}

/// Built without the tangent (`Tangents::None`, what the command-line tool builds for an
/// explicit integrator), a system evaluates the very same bits, reports no tangent, and
/// HHT-alpha falls back to finite differences and reaches the state it reaches with the
/// exact tangent: the Newton iteration converges to the same discrete solution either way.
#[test]
fn without_the_tangent_hht_falls_back_to_finite_differences() {
    use mechanism_codegen::{Tangents, derive, parse_model_str};
    let source = builtin_source("planar_four_bar").unwrap();
    let full = Interpreted::from_source(source).unwrap();
    let mut model = parse_model_str(source).unwrap();
    let eqs = derive(&mut model).unwrap();
    let lean = Interpreted::from_equations_with(model, eqs, Tangents::None).unwrap();
    let (n, m) = (full.info().n(), full.info().m());
    let q: Vec<f64> = full.info().initial_guess.iter().map(|g| g + 0.1).collect();
    let qd: Vec<f64> = (0..n).map(|i| 0.5 - 0.3 * i as f64).collect();
    let (mut a, mut b) = (Evaluation::zeros(n, m), Evaluation::zeros(n, m));
    full.evaluate(0.2, &q, &qd, &mut a);
    lean.evaluate(0.2, &q, &qd, &mut b);
    let bits = |e: &Evaluation| -> Vec<u64> {
        let mut v: Vec<f64> = e.mass.iter().copied().collect();
        v.extend(
            e.coriolis
                .iter()
                .chain(e.gravity.iter())
                .chain(e.phi.iter()),
        );
        v.extend(e.phi_q.iter());
        v.into_iter().map(f64::to_bits).collect()
    };
    assert_eq!(bits(&a), bits(&b));
    let mut tan = Tangent::zeros(n);
    let lambda = vec![0.0; m];
    assert!(
        lean.tangent(0.2, &q, &qd, &qd, &lambda, &mut tan).is_none(),
        "built without the tangent"
    );
    let run = |sys: &Interpreted| {
        let options = SimulationOptions {
            t_end: 0.5,
            output_rate: 2.0,
            integrator: IntegratorOptions {
                method: Method::Hht {
                    h: 1e-3,
                    alpha: -0.05,
                },
                ..IntegratorOptions::default()
            },
            stabilization: Stabilization::Projection,
            ..SimulationOptions::default()
        };
        let trajectory = simulate(sys, &options).unwrap();
        (trajectory.last().unwrap().q.to_vec(), trajectory.stats)
    };
    let ((exact, exact_stats), (fd, fd_stats)) = (run(&full), run(&lean));
    assert_eq!(exact_stats.steps, fd_stats.steps);
    // Each of the 500 steps stops its Newton iteration within 1e-9 (1 + |q|) of the
    // discrete solution (the looser of HHT's two acceptance tests), whichever Jacobian it
    // iterates with: 500 x 1e-9 x (1 + |q| <= 3) bounds the difference.
    let diff = exact
        .iter()
        .zip(&fd)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(
        diff <= 1.5e-6,
        "exact tangent {exact:?} vs finite differences {fd:?}"
    );
}
