//! One interpreted system shared by several threads: each evaluates in its own register
//! file, with no lock between them, and gets what one thread alone gets, bit for bit.

use mechanism::builtin::builtin_source;
use mechanism::{Evaluation, Interpreted, Kinematic, System};

#[test]
fn threads_sharing_one_interpreted_system_agree_with_one_thread() {
    let sys = Interpreted::from_source(builtin_source("spatial_four_bar").unwrap()).unwrap();
    let (n, m) = (sys.info().n(), sys.info().m());
    let state = |k: usize| -> (Vec<f64>, Vec<f64>) {
        let s = k as f64;
        let q = (0..n).map(|i| 0.1 * s + 0.2 * i as f64).collect();
        let qd = (0..n).map(|i| 0.3 - 0.05 * (s + i as f64)).collect();
        (q, qd)
    };
    let alone: Vec<Evaluation> = (0..8)
        .map(|k| {
            let (q, qd) = state(k);
            let mut e = Evaluation::zeros(n, m);
            sys.evaluate(0.1 * k as f64, &q, &qd, &mut e);
            e
        })
        .collect();
    std::thread::scope(|scope| {
        let workers: Vec<_> = (0..4)
            .map(|w| {
                let (sys, alone) = (&sys, &alone);
                scope.spawn(move || {
                    // Many rounds, so that the threads' evaluations interleave.
                    for round in 0..200 {
                        let k = (w + round) % 8;
                        let (q, qd) = state(k);
                        let mut e = Evaluation::zeros(n, m);
                        sys.evaluate(0.1 * k as f64, &q, &qd, &mut e);
                        assert_eq!(e, alone[k], "worker {w}, state {k}");
                    }
                })
            })
            .collect();
        for w in workers {
            w.join().unwrap();
        }
    });
}
