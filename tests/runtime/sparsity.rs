//! The structural pattern of M and Phi_q (issue 28): what the compile stage emits equals the
//! nonzeros of the symbolic M and Phi_q at random states, the compiled and interpreted
//! routes carry the same pattern, and the evaluation that writes M and Phi_q at their
//! pattern only gives the same values as the symbolic equations and as the dense route.

use mechanism::builtin::{builtin, builtin_source};
use mechanism::{Dynamics, Evaluation, Interpreted, System};
use mechanism_codegen::{EvaluationOutput, compile, derive, eval_matrix, residual_tangent};

/// A deterministic generator of values in [-1, 1) (64-bit LCG, top 53 bits).
pub(crate) struct Lcg(pub(crate) u64);

impl Lcg {
    pub(crate) fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// A02 with N = 40 (the built-in `n_four_bar`): 82 coordinates, 81 rows.
const A02: &str = "n_four_bar";

#[test]
fn pattern_is_the_nonzeros_of_the_symbolic_matrices_at_random_states() {
    let mut model = mechanism_codegen::parse_model_str(builtin_source(A02).unwrap()).unwrap();
    let eqs = derive(&mut model).unwrap();
    let tangent = residual_tangent(&mut model, &eqs).unwrap();
    let routines = compile(&mut model, &eqs, &tangent).unwrap();
    let mass = routines.sparsity(EvaluationOutput::Mass).unwrap();
    let jac = routines.sparsity(EvaluationOutput::PhiQ).unwrap();
    let (n, m) = (model.coordinates.len(), eqs.m);
    assert_eq!((mass.rows, mass.cols, jac.rows, jac.cols), (n, n, m, n));
    // A02's M couples a tip's x (or y) with its own and its two neighbours' (at most 3
    // nonzeros per row) and a row of Phi_q reads at most two tips (4 nonzeros): the pattern
    // is O(n), not n^2.
    assert!(
        mass.len() <= 3 * n && jac.len() <= 4 * m,
        "{} {}",
        mass.len(),
        jac.len()
    );

    let a = &model.arena;
    let mut rng = Lcg(0x2028);
    let (mut seen_mass, mut seen_jac) = (vec![false; n * n], vec![false; m * n]);
    for _ in 0..5 {
        let mut table = Vec::new();
        for c in &model.coordinates {
            table.push((a.lookup(&c.name).unwrap(), 2.0 * rng.next()));
            table.push((a.lookup(&format!("der({})", c.name)).unwrap(), rng.next()));
        }
        for p in &model.parameters {
            table.push((
                a.lookup(&p.name).unwrap(),
                p.default * (1.5 + 0.5 * rng.next()),
            ));
        }
        let env = |s| table.iter().find(|e| e.0 == s).map(|e| e.1);
        for (matrix, pattern, seen) in [
            (&eqs.mass, &mass, &mut seen_mass),
            (&eqs.phi_q, &jac, &mut seen_jac),
        ] {
            let values = eval_matrix(a, matrix, &env).unwrap();
            let cols = pattern.cols;
            for (k, v) in values.iter().enumerate() {
                let in_pattern = pattern.entries.contains(&(k / cols, k % cols));
                assert!(
                    in_pattern || *v == 0.0,
                    "entry {k} = {v} outside the pattern"
                );
                seen[k] |= *v != 0.0;
            }
        }
    }
    // Every entry of the pattern is nonzero at some random state: the pattern is not padded.
    for (pattern, seen) in [(&mass, &seen_mass), (&jac, &seen_jac)] {
        for &(i, j) in &pattern.entries {
            assert!(seen[i * pattern.cols + j], "({i}, {j}) never nonzero");
        }
    }

    // Both routes carry this pattern.
    let compiled = builtin(A02).unwrap();
    let interpreted = Interpreted::from_source(builtin_source(A02).unwrap()).unwrap();
    for s in [compiled.as_ref(), &interpreted as &dyn System] {
        let p = s.sparsity().expect("a pattern");
        assert_eq!((p.n, p.m), (n, m));
        assert_eq!(p.mass, mass.entries, "{}", s.info().name);
        assert_eq!(p.jacobian, jac.entries, "{}", s.info().name);
    }
}

#[test]
fn evaluation_at_the_pattern_matches_the_dense_routes() {
    let compiled = builtin(A02).unwrap();
    let interpreted = Interpreted::from_source(builtin_source(A02).unwrap()).unwrap();
    let (n, m) = (compiled.info().n(), compiled.info().m());
    let mut rng = Lcg(7);
    // One buffer each, reused across states: entries outside the pattern are never written
    // and must stay zero.
    let (mut ec, mut ei) = (Evaluation::zeros(n, m), Evaluation::zeros(n, m));
    let (mut phi_q, mut phi_t) = (nalgebra::DMatrix::zeros(m, n), vec![0.0; m]);
    for _ in 0..3 {
        let q: Vec<f64> = (0..n).map(|_| 2.0 * rng.next()).collect();
        let qd: Vec<f64> = (0..n).map(|_| rng.next()).collect();
        let t = rng.next();
        compiled.evaluate(t, &q, &qd, &mut ec);
        interpreted.evaluate(t, &q, &qd, &mut ei);
        // The emitted code and the tape run the same program: the same bits.
        assert_eq!(ec, ei);
        // The compiled dense Jacobian (its own emitted method, every entry written).
        compiled.constraint_jacobian(t, &q, &mut phi_q, &mut phi_t);
        assert_eq!(ec.phi_q, phi_q);
        // The reused buffer equals a fresh one evaluated at this state alone.
        let mut fresh = Evaluation::zeros(n, m);
        compiled.evaluate(t, &q, &qd, &mut fresh);
        assert_eq!(ec, fresh);
    }
}

#[test]
fn dynamics_with_the_pattern_matches_a_dense_kkt_solve() {
    // The large-system route (the banded direct solve, ordered from the pattern) against
    // nalgebra's dense LU of [M Phi_q^T; Phi_q 0] at a regular state of A02, N = 40.
    let system = builtin(A02).unwrap();
    let (n, m) = (system.info().n(), system.info().m());
    // Rockers at 60 degrees, couplers horizontal: a consistent, regular configuration.
    let th = std::f64::consts::FRAC_PI_3;
    let mut q = vec![0.0; n];
    let mut qd = vec![0.0; n];
    for i in 0..n / 2 {
        q[2 * i] = i as f64 + th.cos();
        q[2 * i + 1] = th.sin();
        qd[2 * i] = -0.7 * th.sin();
        qd[2 * i + 1] = 0.7 * th.cos();
    }
    let mut d = Dynamics::new(system.info());
    d.solve(system.as_ref(), 0.0, &q, &qd).unwrap();
    let e = d.evaluation();
    let k = n + m;
    let mut a = nalgebra::DMatrix::zeros(k, k);
    a.view_mut((0, 0), (n, n)).copy_from(&e.mass);
    a.view_mut((n, 0), (m, n)).copy_from(&e.phi_q);
    a.view_mut((0, n), (n, m)).copy_from(&e.phi_q.transpose());
    let mut rhs = nalgebra::DVector::zeros(k);
    for i in 0..n {
        rhs[i] = e.forces[i] - e.coriolis[i] - e.gravity[i];
    }
    for r in 0..m {
        rhs[n + r] = e.gamma[r];
    }
    let x = a.lu().solve(&rhs).unwrap();
    // q'' is of order g = 9.81 m/s^2; the KKT matrix at 60 degrees has a condition of
    // about 1e4, so both solutions carry ~1e4 eps ~ 1e-12 relative error: 1e-9 absolute is
    // a bound with margin, far below any real difference.
    for i in 0..n {
        let (got, want) = (d.accelerations()[i], x[i]);
        assert!((got - want).abs() < 1e-9, "q''[{i}] {got} vs {want}");
    }
    assert!(d.banded_solves > 0, "the large-system route was taken");
}
