//! Our side of the CasADi baseline: the robots' generated code (`mechanism!(urdf = ..)`,
//! declared in the `robots` module that casadi_bench.py writes above this file), timed and
//! checked like CasADi's C (casadi_main.c):
//!
//!   ours ROBOT names                      the coordinates, in our order
//!   ours ROBOT check STATES S             every routine at each of the S states
//!   ours ROBOT time ROUTINE STATES S BATCHES CALLS   ns of thread CPU per call, per batch
//!   ours counts URDF SNAP [LOCK..]        the arithmetic operations of each routine's
//!                                         program (SNAP: the angle tolerance, or `none`)
//!
//! STATES: S states of 4 n doubles (q, q', q'', tau in our coordinate order), native byte
//! order. Matrices are printed row-major.

use std::hint::black_box;

use mechanism::Mechanism;
use mechanism::nalgebra::SVector;

/// Nanoseconds of this thread's CPU time (Linux `CLOCK_THREAD_CPUTIME_ID`, as the C side).
fn thread_ns() -> f64 {
    #[repr(C)]
    struct Timespec {
        sec: i64,
        nsec: i64,
    }
    unsafe extern "C" {
        fn clock_gettime(clock: i32, t: *mut Timespec) -> i32;
    }
    let mut t = Timespec { sec: 0, nsec: 0 };
    // SAFETY: a valid out pointer; clock 3 is CLOCK_THREAD_CPUTIME_ID on Linux.
    unsafe { clock_gettime(3, &mut t) };
    1e9 * t.sec as f64 + t.nsec as f64
}

struct State<const N: usize> {
    q: SVector<f64, N>,
    qd: SVector<f64, N>,
    qdd: SVector<f64, N>,
    tau: SVector<f64, N>,
}

fn states<const N: usize>(path: &str, count: usize) -> Vec<State<N>> {
    let bytes = std::fs::read(path).expect("the states file");
    let x: Vec<f64> = bytes
        .chunks_exact(8)
        .map(|b| f64::from_ne_bytes(b.try_into().unwrap()))
        .collect();
    assert_eq!(x.len(), 4 * N * count, "{count} states of {N} coordinates");
    let v = |s: &[f64]| SVector::<f64, N>::from_column_slice(s);
    x.chunks_exact(4 * N)
        .map(|s| State {
            q: v(&s[..N]),
            qd: v(&s[N..2 * N]),
            qdd: v(&s[2 * N..3 * N]),
            tau: v(&s[3 * N..]),
        })
        .collect()
}

const ROUTINES: [&str; 6] = [
    "mass_matrix",
    "bias",
    "cqg_id",
    "mass_and_bias",
    "inverse_dynamics",
    "forward_dynamics",
];

/// Routine `k` at state `s`, its outputs row-major.
fn call<R: Mechanism<N, M>, const N: usize, const M: usize>(
    r: &R,
    k: usize,
    s: &State<N>,
) -> Vec<f64> {
    let z = SVector::<f64, N>::zeros();
    match k {
        0 => r.mass_matrix(&s.q).transpose().as_slice().to_vec(),
        1 => r.bias(0.0, &s.q, &s.qd).as_slice().to_vec(),
        2 => r.inverse_dynamics(0.0, &s.q, &s.qd, &z).as_slice().to_vec(),
        3 => {
            let (m, b) = r.mass_and_bias(0.0, &s.q, &s.qd);
            let mut v = m.transpose().as_slice().to_vec();
            v.extend_from_slice(b.as_slice());
            v
        }
        4 => r.inverse_dynamics(0.0, &s.q, &s.qd, &s.qdd).as_slice().to_vec(),
        _ => r
            .forward_dynamics(0.0, &s.q, &s.qd, &s.tau)
            .map_or(vec![f64::NAN; N], |a| a.as_slice().to_vec()),
    }
}

/// ns per call of `calls` calls of routine `k`, cycling through the states, per batch.
fn time<R: Mechanism<N, M>, const N: usize, const M: usize>(
    r: &R,
    k: usize,
    st: &[State<N>],
    batches: usize,
    calls: usize,
) -> Vec<f64> {
    let z = SVector::<f64, N>::zeros();
    let mut out = Vec::new();
    // Batch 0 warms up.
    for b in 0..=batches {
        let t0 = thread_ns();
        for i in 0..calls {
            let s = black_box(&st[i % st.len()]);
            match k {
                0 => drop(black_box(r.mass_matrix(&s.q))),
                1 => drop(black_box(r.bias(0.0, &s.q, &s.qd))),
                2 => drop(black_box(r.inverse_dynamics(0.0, &s.q, &s.qd, &z))),
                3 => drop(black_box(r.mass_and_bias(0.0, &s.q, &s.qd))),
                4 => drop(black_box(r.inverse_dynamics(0.0, &s.q, &s.qd, &s.qdd))),
                _ => drop(black_box(r.forward_dynamics(0.0, &s.q, &s.qd, &s.tau))),
            }
        }
        if b > 0 {
            out.push((thread_ns() - t0) / calls as f64);
        }
    }
    out
}

fn run<R: Mechanism<N, M>, const N: usize, const M: usize>(r: &R, args: &[String]) {
    match args[0].as_str() {
        "names" => println!("{}", R::COORDINATES.join(" ")),
        "check" => {
            let st = states::<N>(&args[1], args[2].parse().unwrap());
            for (k, name) in ROUTINES.iter().enumerate() {
                for (i, s) in st.iter().enumerate() {
                    let v: Vec<String> = call(r, k, s).iter().map(|x| format!("{x:?}")).collect();
                    println!("{name} {i} {}", v.join(" "));
                }
            }
        }
        "time" => {
            let k = ROUTINES.iter().position(|x| *x == args[1]).expect("a routine");
            let st = states::<N>(&args[2], args[3].parse().unwrap());
            let (batches, calls) = (args[4].parse().unwrap(), args[5].parse().unwrap());
            for ns in time(r, k, &st, batches, calls) {
                println!("{ns:.2}");
            }
        }
        other => panic!("unknown mode {other}"),
    }
}

/// The arithmetic operations of each routine's program, as the macro compiles them.
fn counts(urdf: &str, snap: &str, lock: &[String]) {
    use mechanism_codegen::{Role, UrdfOptions, compile, derive, parse_model_str, residual_tangent};
    let options = UrdfOptions {
        file_name: urdf.into(),
        lock: lock.to_vec(),
        snap_angles: snap.parse().ok(),
        ..Default::default()
    };
    let xml = std::fs::read_to_string(urdf).expect("the URDF");
    let text = mechanism_codegen::urdf_to_mech(&xml, &options).expect("imported");
    let mut model = parse_model_str(&text).expect("parses");
    let eqs = derive(&mut model).expect("derives");
    let tangent = residual_tangent(&mut model, &eqs).expect("a tangent");
    let routines = compile(&mut model, &eqs, &tangent).expect("compiles");
    let ops = |role| routines.program(role).map_or(0, |p| p.op_counts().total());
    println!(
        "{{\"mass_matrix\": {}, \"bias\": {}, \"coriolis_forces\": {}, \"gravity\": {}, \"mass_and_bias\": {}, \"inverse_dynamics\": {}, \"forward_dynamics\": {}}}",
        ops(Role::Mass),
        ops(Role::Bias),
        ops(Role::CoriolisForces),
        ops(Role::Gravity),
        ops(Role::MassAndBias),
        ops(Role::InverseDynamics),
        ops(Role::ForwardDynamics)
    );
}
