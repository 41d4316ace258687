//! The N four-bar generator (`mechanism_bench::n_four_bar`): `mechanisms/n_four_bar.mech` is
//! its output for N = 40 and `benches/mechanisms/n_four_bar_{10,20,80}.mech` for N = 10, 20,
//! 80, byte for byte (rerun with `MECHANISM_BLESS=1` to rewrite the files after changing the
//! generator), and a small member derives and moves as the benchmark's exact solution says.

use mechanism::{Evaluation, Interpreted, Kinematic, System};
use mechanism_bench::n_four_bar::n_four_bar_source;
use nalgebra::{DMatrix, DVector};

const FILE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../mechanisms/n_four_bar.mech");

#[test]
fn the_committed_file_is_the_generator_output_for_n_40() {
    let text = n_four_bar_source(40);
    if std::env::var_os("MECHANISM_BLESS").is_some() {
        std::fs::write(FILE, &text).expect("write mechanisms/n_four_bar.mech");
    }
    let committed = std::fs::read_to_string(FILE).expect("mechanisms/n_four_bar.mech exists");
    assert!(
        committed == text,
        "mechanisms/n_four_bar.mech is not n_four_bar_source(40): rerun this test with MECHANISM_BLESS=1"
    );
}

/// The sizes compiled into the bench crate (`benches/mechanisms/n_four_bar_{N}.mech`,
/// expanded by `mechanism_bench::a02`); N = 40 is `mechanisms/n_four_bar.mech` above.
#[test]
fn the_bench_variants_are_the_generator_output() {
    for n in [10, 20, 80] {
        let path = format!(
            "{}/mechanisms/n_four_bar_{n}.mech",
            env!("CARGO_MANIFEST_DIR")
        );
        let text = n_four_bar_source(n);
        if std::env::var_os("MECHANISM_BLESS").is_some() {
            std::fs::write(&path, &text).unwrap_or_else(|e| panic!("write {path}: {e}"));
        }
        let committed = std::fs::read_to_string(&path).unwrap_or_default();
        assert!(
            committed == text,
            "{path} is not n_four_bar_source({n}): rerun this test with MECHANISM_BLESS=1"
        );
    }
}

#[test]
fn small_members_parse_and_derive() {
    for n in [1, 2, 5] {
        let mut model = mechanism_codegen::parse_model_str(&n_four_bar_source(n))
            .unwrap_or_else(|e| panic!("N = {n}: {e}"));
        let eqs = mechanism_codegen::derive(&mut model).unwrap_or_else(|e| panic!("N = {n}: {e}"));
        assert_eq!((eqs.n, eqs.m), (2 * (n + 1), 2 * n + 1), "N = {n}");
    }
}

/// q, q' on the exact branch: every rocker at angle th (rate thd), couplers horizontal.
fn branch(n: usize, th: f64, thd: f64) -> (Vec<f64>, Vec<f64>) {
    let mut q = Vec::new();
    let mut qd = Vec::new();
    for i in 0..=n {
        q.extend([i as f64 + th.cos(), th.sin()]);
        qd.extend([-th.sin() * thd, th.cos() * thd]);
    }
    (q, qd)
}

fn rank(a: &DMatrix<f64>) -> usize {
    let sv = a.clone().svd(false, false).singular_values;
    let max = sv.max();
    sv.iter().filter(|&&s| s > 1e-10 * max).count()
}

/// N = 2: M is constant; on the branch the KKT accelerations give
/// ((N+1)/3 + N) th'' = -((N+1)/2 + N) g cos th (read off x0 = cos th:
/// x0'' = -sin th th'' - cos th th'^2); Phi_q has rank 2N + 1 at the vertical start and
/// N + 1 when all rockers lie horizontal.
#[test]
fn n_2_follows_the_exact_branch() {
    let n = 2;
    let sys = Interpreted::from_source(&n_four_bar_source(n)).expect("N = 2 derives");
    let (nq, m) = (sys.info().n(), sys.info().m());
    assert_eq!((nq, m), (6, 5));
    let g = 9.81;
    let (a, b) = (
        (n + 1) as f64 / 3.0 + n as f64,
        (n + 1) as f64 / 2.0 + n as f64,
    );
    let eval = |q: &[f64], qd: &[f64]| {
        let mut e = Evaluation::zeros(nq, m);
        sys.evaluate(0.0, q, qd, &mut e);
        e
    };
    let (q0, qd0) = branch(n, std::f64::consts::FRAC_PI_2, -1.0);
    let start = eval(&q0, &qd0);
    assert!(start.phi.amax() < 1e-15);
    assert_eq!(rank(&start.phi_q), 2 * n + 1);
    for (th, thd) in [(1.2, -0.7), (0.4, 2.0), (-0.9, 1.3), (2.5, -3.0)] {
        let (q, qd) = branch(n, th, thd);
        let e = eval(&q, &qd);
        assert!(e.phi.amax() < 1e-14, "th = {th}: off the constraints");
        assert!(
            (&e.mass - &start.mass).amax() == 0.0,
            "M depends on q: {}",
            e.mass
        );
        // The KKT system [M Phi_q^T; Phi_q 0] [q''; lambda] = [-C q' - g; gamma].
        let mut k = DMatrix::zeros(nq + m, nq + m);
        k.view_mut((0, 0), (nq, nq)).copy_from(&e.mass);
        k.view_mut((0, nq), (nq, m)).copy_from(&e.phi_q.transpose());
        k.view_mut((nq, 0), (m, nq)).copy_from(&e.phi_q);
        let mut rhs = DVector::zeros(nq + m);
        rhs.rows_mut(0, nq).copy_from(&(-&e.coriolis - &e.gravity));
        rhs.rows_mut(nq, m).copy_from(&e.gamma);
        let x = k
            .lu()
            .solve(&rhs)
            .expect("regular away from the horizontal");
        let thdd = -b * g * th.cos() / a;
        let x0dd = -th.sin() * thdd - th.cos() * thd * thd;
        assert!(
            (x[0] - x0dd).abs() < 1e-12 * (1.0 + x0dd.abs()),
            "th = {th}: x0'' = {} against {x0dd}",
            x[0]
        );
        // Every tip moves alike (the couplers stay horizontal).
        for i in 1..=n {
            assert!((x[2 * i] - x[0]).abs() < 1e-12 && (x[2 * i + 1] - x[1]).abs() < 1e-12);
        }
    }
    let (qh, qdh) = branch(n, 0.0, -1.0);
    assert_eq!(rank(&eval(&qh, &qdh).phi_q), n + 1);
}
