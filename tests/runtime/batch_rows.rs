//! A batch's rows side by side through the interpreter (`Interpreted::evaluate_rows`, the
//! `*_rows` robotics methods) against the same states one at a time through the one-state
//! tape: bit for bit, since each lane runs the same f64 operations
//! (`mechanism_codegen::Tape::execute_lanes`). On the Panda (a tree of links, with
//! Newton-Euler and the frames) and on the five-bar leg (a closed loop: constraint rows,
//! Phi_q, gamma), with a row count that leaves a partial last block; and nothing allocated
//! per batch once the thread's lane register file has grown.

use mechanism::builtin::builtin_source;
use mechanism::{Evaluation, Interpreted, Kinematic, System};
use mechanism_codegen::{Tangents, parse_model_str};
use nalgebra::{DMatrix, Matrix3, Vector3};

/// 37 rows: two full blocks of 16 and a partial one of 5.
const ROWS: usize = 37;

fn robot(name: &str) -> Interpreted {
    let model = parse_model_str(builtin_source(name).unwrap()).unwrap();
    Interpreted::from_model_with(model, Tangents::None, true).unwrap()
}

/// Row-major states: q in (-1.5, 1.5), rates and accelerations in (-3, 3), from a fixed
/// linear congruential sequence (no two rows equal, arguments of every size sin/cos see).
fn states(n: usize, salt: u64) -> [Vec<f64>; 3] {
    let mut x = 0x9e37_79b9_7f4a_7c15_u64 ^ salt;
    let mut next = move |scale: f64| {
        x = x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
        scale * ((x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0)
    };
    let mut draw = |scale: f64| (0..ROWS * n).map(|_| next(scale)).collect::<Vec<_>>();
    [draw(1.5), draw(3.0), draw(3.0)]
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

fn evaluations_agree(system: &Interpreted, t: f64) {
    let (n, m) = (system.info().n(), system.info().m());
    let [q, qd, _] = states(n, 1);
    let (mut scratch, mut one) = (Evaluation::zeros(n, m), Evaluation::zeros(n, m));
    let mut seen = Vec::new();
    system
        .evaluate_rows(t, &q, &qd, &mut scratch, |row, e| {
            let r = row * n..(row + 1) * n;
            system.evaluate(t, &q[r.clone()], &qd[r], &mut one);
            for (what, a, b) in [
                ("M", e.mass.as_slice(), one.mass.as_slice()),
                ("C q'", e.coriolis.as_slice(), one.coriolis.as_slice()),
                ("g", e.gravity.as_slice(), one.gravity.as_slice()),
                ("tau", e.forces.as_slice(), one.forces.as_slice()),
                ("Phi", e.phi.as_slice(), one.phi.as_slice()),
                ("Phi_q", e.phi_q.as_slice(), one.phi_q.as_slice()),
                ("Phi_t", e.phi_t.as_slice(), one.phi_t.as_slice()),
                ("gamma", e.gamma.as_slice(), one.gamma.as_slice()),
                (
                    "T, Pi",
                    &[e.kinetic, e.potential],
                    &[one.kinetic, one.potential],
                ),
            ] {
                assert_eq!(bits(a), bits(b), "{what}, row {row}");
            }
            seen.push(row);
            Ok::<(), ()>(())
        })
        .unwrap();
    assert_eq!(seen, (0..ROWS).collect::<Vec<_>>());
}

#[test]
fn evaluation_rows_equal_one_state_bit_for_bit() {
    evaluations_agree(&robot("panda"), 0.0);
    let leg = Interpreted::from_source(builtin_source("five_bar").unwrap()).unwrap();
    assert!(leg.info().m() > 0, "a mechanism with constraint rows");
    evaluations_agree(&leg, 0.3);
}

#[test]
fn robotics_rows_equal_one_state_bit_for_bit() {
    let panda = robot("panda");
    let n = panda.info().n();
    let [q, qd, qdd] = states(n, 2);
    let mut u = vec![0.0; ROWS * n];
    panda
        .inverse_dynamics_rows(0.0, &q, &qd, &qdd, &mut u)
        .unwrap();
    let frames = panda.info().frames.len();
    let mut placements = vec![0.0; ROWS * 12];
    let mut jacobians = vec![0.0; ROWS * 6 * n];
    for row in 0..ROWS {
        let r = row * n..(row + 1) * n;
        let mut one = vec![0.0; n];
        panda
            .inverse_dynamics(
                0.0,
                &q[r.clone()],
                &qd[r.clone()],
                &qdd[r.clone()],
                &mut one,
            )
            .unwrap();
        assert_eq!(bits(&u[row * n..(row + 1) * n]), bits(&one), "row {row}");
    }
    for frame in [0, frames / 2, frames - 1] {
        panda
            .frame_placement_rows(frame, &q, &mut placements)
            .unwrap();
        panda
            .frame_jacobian_rows(frame, &q, &mut jacobians)
            .unwrap();
        for row in 0..ROWS {
            let qr = &q[row * n..(row + 1) * n];
            let (mut rot, mut p) = (Matrix3::zeros(), Vector3::zeros());
            panda.frame_placement(frame, qr, &mut rot, &mut p).unwrap();
            let want: Vec<f64> = (0..3)
                .flat_map(|i| (0..3).map(move |j| (i, j)))
                .map(|ij| rot[ij])
                .chain(p.iter().copied())
                .collect();
            assert_eq!(bits(&placements[row * 12..(row + 1) * 12]), bits(&want));
            let mut jac = DMatrix::zeros(6, n);
            panda.frame_jacobian(frame, qr, &mut jac).unwrap();
            let want: Vec<f64> = (0..6)
                .flat_map(|i| (0..n).map(move |j| (i, j)))
                .map(|ij| jac[ij])
                .collect();
            let got = &jacobians[row * 6 * n..(row + 1) * 6 * n];
            assert_eq!(bits(got), bits(&want), "frame {frame}, row {row}");
        }
    }
    assert!(
        panda
            .frame_placement_rows(frames, &q, &mut placements)
            .is_none()
    );
}

#[test]
fn batches_allocate_nothing_after_the_first() {
    let panda = robot("panda");
    let n = panda.info().n();
    let [q, qd, qdd] = states(n, 3);
    let mut u = vec![0.0; ROWS * n];
    let mut scratch = Evaluation::zeros(n, 0);
    let mut sum = 0.0;
    let batch = |u: &mut [f64], scratch: &mut Evaluation, sum: &mut f64| {
        panda.inverse_dynamics_rows(0.0, &q, &qd, &qdd, u).unwrap();
        panda
            .evaluate_rows(0.0, &q, &qd, scratch, |_, e| {
                *sum += e.mass[(0, 0)];
                Ok::<(), ()>(())
            })
            .unwrap();
    };
    // The first batch grows this thread's lane register file.
    batch(&mut u, &mut scratch, &mut sum);
    let before = mechanism_test_support::allocations();
    for _ in 0..10 {
        batch(&mut u, &mut scratch, &mut sum);
    }
    assert_eq!(mechanism_test_support::allocations() - before, 0);
    assert!(sum.is_finite() && sum > 0.0, "M's first entry read: {sum}");
}
