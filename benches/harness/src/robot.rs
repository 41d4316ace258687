//! `harness robot <rounds>`: the Panda's routines timed like Pinocchio's C++ baseline
//! (`benches/baselines/pinocchio/panda_bench.cpp`): 1000 random states inside the joint
//! limits (q), rates in (-2, 2) rad/s, accelerations in (-5, 5) rad/s^2 and efforts in
//! (-20, 20) N m; each round calls every routine once per state and records the mean ns per
//! call; the JSON gives each routine's median and minimum over the rounds.

use std::hint::black_box;
use std::time::Instant;

use mechanism::Mechanism;
use mechanism::builtin::Panda;
use mechanism::nalgebra::SVector;

type V = SVector<f64, 7>;

/// The Panda's joint limits (rad), from its URDF.
const LIMITS: [(f64, f64); 7] = [
    (-2.8973, 2.8973),
    (-1.7628, 1.7628),
    (-2.8973, 2.8973),
    (-3.0718, -0.0698),
    (-2.8973, 2.8973),
    (-0.0175, 3.7525),
    (-2.8973, 2.8973),
];

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

struct State {
    q: V,
    qd: V,
    qdd: V,
    tau: V,
}

fn states(count: usize) -> Vec<State> {
    let mut u = Uniform(20_261_126);
    (0..count)
        .map(|_| {
            let q = V::from_fn(|i, _| LIMITS[i].0 + (LIMITS[i].1 - LIMITS[i].0) * u.next());
            let qd = V::from_fn(|_, _| -2.0 + 4.0 * u.next());
            let qdd = V::from_fn(|_, _| -5.0 + 10.0 * u.next());
            let tau = V::from_fn(|_, _| -20.0 + 40.0 * u.next());
            State { q, qd, qdd, tau }
        })
        .collect()
}

/// Mean ns per call of `f` over all states.
fn round(states: &[State], mut f: impl FnMut(&State)) -> f64 {
    let start = Instant::now();
    for s in states {
        f(black_box(s));
    }
    start.elapsed().as_nanos() as f64 / states.len() as f64
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The JSON of `harness robot <rounds>`.
pub fn robot_json(rounds: usize) -> String {
    let r = Panda::default();
    let r = black_box(&r);
    let st = states(1000);
    let hand = Panda::frame_index("panda_hand").unwrap_or(0);
    let mut e = r.evaluate(0.0, &V::zeros(), &V::zeros());
    type Routine<'a> = (&'static str, Box<dyn FnMut(&State) + 'a>);
    let mut routines: Vec<Routine<'_>> = vec![
        (
            "evaluate_into",
            Box::new(|s: &State| r.evaluate_into(0.0, &s.q, &s.qd, black_box(&mut e))),
        ),
        (
            "mass_and_bias",
            Box::new(|s: &State| {
                black_box(r.mass_and_bias(0.0, &s.q, &s.qd));
            }),
        ),
        (
            "bias",
            Box::new(|s: &State| {
                black_box(r.bias(0.0, &s.q, &s.qd));
            }),
        ),
        (
            "mass_matrix",
            Box::new(|s: &State| {
                black_box(r.mass_matrix(&s.q));
            }),
        ),
        (
            "inverse_dynamics",
            Box::new(|s: &State| {
                black_box(r.inverse_dynamics(0.0, &s.q, &s.qd, &s.qdd));
            }),
        ),
        (
            "forward_dynamics",
            Box::new(|s: &State| {
                black_box(r.forward_dynamics(0.0, &s.q, &s.qd, &s.tau));
            }),
        ),
        (
            "gravity",
            Box::new(|s: &State| {
                black_box(r.gravity(&s.q));
            }),
        ),
        (
            "frame_jacobian",
            Box::new(|s: &State| {
                black_box(r.frame_jacobian(hand, &s.q));
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
