//! The timed loops: evaluation into the caller's buffer and the augmented solve, with the
//! inputs varied as in the C peers' loop (q_0 += 1e-15 before every call).

use std::hint::black_box;
use std::time::Instant;

use mechanism::nalgebra::{SMatrix, SVector};
use mechanism::{
    AssemblyOptions, Compiled, Dynamics, Kinematic, Mechanism, StaticEvaluation, assemble_from,
};

/// The state every timing starts from.
pub struct Inputs<const N: usize> {
    /// q from the assembly at the declared independent coordinates.
    pub q: SVector<f64, N>,
    /// q', with the first independent rate set to 1 rad/s when the declaration gives none.
    pub qd: SVector<f64, N>,
    /// t (s).
    pub t: f64,
}

impl<const N: usize> Inputs<N> {
    /// The assembled state of `m` (see [`Inputs`]), at t = 0.3 s.
    pub fn of<T: Mechanism<N, M>, const M: usize>(m: &T) -> Self {
        let system = Compiled::new(m.clone());
        let info = system.info();
        let mut independent = info.independent.clone();
        if independent.iter().all(|i| i.velocity == 0.0)
            && let Some(first) = independent.first_mut()
        {
            first.velocity = 1.0;
        }
        let options = AssemblyOptions::default();
        let s = assemble_from(&system, 0.0, &independent, &info.initial_guess, &options)
            .unwrap_or_else(|e| panic!("{}: assembly failed: {e}", info.name));
        Inputs {
            q: SVector::from_column_slice(&s.q),
            qd: SVector::from_column_slice(&s.qd),
            t: 0.3,
        }
    }
}

/// M, C q', g, Phi and Phi_q in the caller's buffers (SymPy's five matrices).
pub struct Five<const N: usize, const M: usize> {
    mass: SMatrix<f64, N, N>,
    coriolis: SVector<f64, N>,
    gravity: SVector<f64, N>,
    phi: SVector<f64, M>,
    phi_q: SMatrix<f64, M, N>,
}

type Evaluate<T, const N: usize, const M: usize> =
    fn(&T, f64, &SVector<f64, N>, &SVector<f64, N>, &mut StaticEvaluation<N, M>);

/// ns per call of `what` on `m`, one value per batch of `calls` calls. The function is
/// called through a pointer read from `black_box`, so that it is compiled on its own and
/// nothing is hoisted out of the loop (the C peers call a function in another object file).
pub fn time_eval<T: Mechanism<N, M>, const N: usize, const M: usize>(
    m: &T,
    what: &str,
    batches: usize,
    calls: usize,
) -> Result<Vec<f64>, String> {
    let i = Inputs::of(m);
    let (t, mut q, qd) = (i.t, i.q, i.qd);
    match what {
        "evaluate" => {
            let f: Evaluate<T, N, M> = black_box(T::evaluate_into);
            let mut out = StaticEvaluation::zeros();
            Ok(batched(batches, calls, || {
                q[0] += 1e-15;
                f(black_box(m), black_box(t), &q, &qd, black_box(&mut out));
            }))
        }
        "five" => {
            let mass = black_box(T::mass_matrix as fn(&T, &SVector<f64, N>) -> _);
            let coriolis = black_box(T::coriolis_forces as fn(&T, &_, &_) -> _);
            let gravity = black_box(T::gravity as fn(&T, &SVector<f64, N>) -> _);
            let phi = black_box(T::constraints as fn(&T, f64, &SVector<f64, N>) -> _);
            let phi_q = black_box(T::constraint_jacobian as fn(&T, f64, &SVector<f64, N>) -> _);
            let mut out = Five::<N, M> {
                mass: SMatrix::zeros(),
                coriolis: SVector::zeros(),
                gravity: SVector::zeros(),
                phi: SVector::zeros(),
                phi_q: SMatrix::zeros(),
            };
            Ok(batched(batches, calls, || {
                q[0] += 1e-15;
                let (m, o) = (black_box(m), black_box(&mut out));
                o.mass = mass(m, &q);
                o.coriolis = coriolis(m, &q, &qd);
                o.gravity = gravity(m, &q);
                o.phi = phi(m, t, &q);
                o.phi_q = phi_q(m, t, &q);
            }))
        }
        _ => Err(format!("unknown evaluation {what:?} (evaluate or five)")),
    }
}

/// ns per `Dynamics::solve` of `m` through `Compiled` (evaluation, copy into the run-time
/// buffers, checks and the augmented solve), one value per batch.
pub fn time_solve<T: Mechanism<N, M>, const N: usize, const M: usize>(
    m: T,
    batches: usize,
    calls: usize,
) -> Vec<f64> {
    let i = Inputs::of(&m);
    let (t, mut q, qd) = (i.t, i.q.as_slice().to_vec(), i.qd.as_slice().to_vec());
    let system = Compiled::new(m);
    let mut dynamics = Dynamics::new(system.info());
    // The first solve picks the system's static-size solver.
    let _ = dynamics.solve(&system, t, &q, &qd);
    batched(batches, calls, || {
        q[0] += 1e-15;
        let ok = dynamics
            .solve(black_box(&system), black_box(t), &q, &qd)
            .is_ok();
        black_box((ok, dynamics.accelerations()[0]));
    })
}

/// Runs `call` `calls` times per batch after one untimed batch; ns per call of each batch.
fn batched(batches: usize, calls: usize, mut call: impl FnMut()) -> Vec<f64> {
    let calls = calls.max(1);
    for _ in 0..calls {
        call();
    }
    (0..batches)
        .map(|_| {
            let start = Instant::now();
            for _ in 0..calls {
                call();
            }
            start.elapsed().as_secs_f64() * 1e9 / calls as f64
        })
        .collect()
}
