//! `harness derivatives <robot> <rounds>`: the derivatives of the dynamics of the Panda, the
//! UR5 or Solo12 (base fixed) timed like Pinocchio's C++ baseline
//! (`benches/baselines/pinocchio/derivatives_bench.cpp`): 1000 random states, q uniform
//! inside the joint limits clipped to [-pi, pi], rates in (-2, 2), accelerations in (-5, 5)
//! and efforts in (-20, 20); each round calls every routine once per state and records the
//! mean ns of this thread's CPU time per call (`CLOCK_THREAD_CPUTIME_ID`, as the C++ side); the JSON gives each routine's median and minimum over the rounds.
//! Routines: `inverse_dynamics` and `forward_dynamics` (for scale),
//! `inverse_dynamics_derivatives` (Pinocchio's `computeRNEADerivatives`) and
//! `forward_dynamics_derivatives` (`computeABADerivatives`).

use std::f64::consts::PI;
use std::hint::black_box;

use mechanism::Mechanism;
use mechanism::builtin::Panda;
use mechanism::nalgebra::SVector;

mechanism::mechanism!(urdf = "../../mechanisms/urdf/ur5_robot.urdf", name = Ur5);
mechanism::mechanism!(urdf = "../../mechanisms/urdf/solo12.urdf", name = Solo12);

/// A small deterministic generator (xorshift64*), uniform in [0, 1).
struct Uniform(u64);

impl Uniform {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }
}

struct State<const N: usize> {
    q: SVector<f64, N>,
    qd: SVector<f64, N>,
    qdd: SVector<f64, N>,
    tau: SVector<f64, N>,
}

fn states<T: Mechanism<N, 0>, const N: usize>(count: usize) -> Vec<State<N>> {
    let mut limits = [(-PI, PI); N];
    for l in T::JOINT_LIMITS {
        if let Some([lo, hi]) = l.position {
            limits[l.coordinate] = (lo.max(-PI), hi.min(PI));
        }
    }
    let mut u = Uniform(20_261_126);
    (0..count)
        .map(|_| {
            let q = SVector::from_fn(|i, _| limits[i].0 + (limits[i].1 - limits[i].0) * u.next());
            let qd = SVector::from_fn(|_, _| -2.0 + 4.0 * u.next());
            let qdd = SVector::from_fn(|_, _| -5.0 + 10.0 * u.next());
            let tau = SVector::from_fn(|_, _| -20.0 + 40.0 * u.next());
            State { q, qd, qdd, tau }
        })
        .collect()
}

/// Nanoseconds of this thread's CPU time (Linux `CLOCK_THREAD_CPUTIME_ID`): on a machine
/// shared with other work, what the calls cost, without the waits for a core.
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

/// Mean ns of thread CPU time per call of `f` over all states.
fn round<const N: usize>(states: &[State<N>], mut f: impl FnMut(&State<N>)) -> f64 {
    let start = thread_ns();
    for s in states {
        f(black_box(s));
    }
    (thread_ns() - start) / states.len() as f64
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The JSON of `harness derivatives <robot> <rounds>` for the robot `T`.
fn json<T: Mechanism<N, 0> + Default, const N: usize>(rounds: usize) -> String {
    let r = T::default();
    let r = black_box(&r);
    let st = states::<T, N>(1000);
    type Routine<'a, const N: usize> = (&'static str, Box<dyn FnMut(&State<N>) + 'a>);
    let mut routines: Vec<Routine<'_, N>> = vec![
        (
            "inverse_dynamics",
            Box::new(|s: &State<N>| {
                black_box(r.inverse_dynamics(0.0, &s.q, &s.qd, &s.qdd));
            }),
        ),
        (
            "forward_dynamics",
            Box::new(|s: &State<N>| {
                black_box(r.forward_dynamics(0.0, &s.q, &s.qd, &s.tau));
            }),
        ),
        (
            "inverse_dynamics_derivatives",
            Box::new(|s: &State<N>| {
                black_box(r.inverse_dynamics_derivatives(0.0, &s.q, &s.qd, &s.qdd));
            }),
        ),
        (
            "forward_dynamics_derivatives",
            Box::new(|s: &State<N>| {
                black_box(r.forward_dynamics_derivatives(0.0, &s.q, &s.qd, &s.tau));
            }),
        ),
        (
            // The trait's default for the same (M and b, then a dense factorisation and
            // solves at run time): the route the emitted program replaces, for comparison.
            "forward_dynamics_derivatives_dense",
            Box::new(|s: &State<N>| {
                black_box(mechanism::fixed::forward_dynamics_derivatives(
                    r, 0.0, &s.q, &s.qd, &s.tau,
                ));
            }),
        ),
    ];
    // One warm-up round, then the timed ones.
    for (_, f) in routines.iter_mut() {
        round(&st, f);
    }
    let mut times: Vec<Vec<f64>> = vec![Vec::new(); routines.len()];
    for _ in 0..rounds {
        for (k, (_, f)) in routines.iter_mut().enumerate() {
            times[k].push(round(&st, f));
        }
    }
    let items: Vec<String> = routines
        .iter()
        .zip(times.iter_mut())
        .map(|((name, _), t)| {
            let min = t.iter().copied().fold(f64::INFINITY, f64::min);
            format!(
                "\"{name}\": {{\"median_ns\": {:.1}, \"min_ns\": {min:.1}}}",
                median(t)
            )
        })
        .collect();
    format!("{{{}}}", items.join(", "))
}

/// The JSON for the robot called `name` (`panda`, `ur5`, `solo12`), `None` for another name.
pub fn derivatives_json(name: &str, rounds: usize) -> Option<String> {
    match name {
        "panda" => Some(json::<Panda, 7>(rounds)),
        "ur5" => Some(json::<Ur5, 6>(rounds)),
        "solo12" => Some(json::<Solo12, 12>(rounds)),
        _ => None,
    }
}
