//! `harness floating <robot> <rounds>`: a floating-base robot's routines (Solo12 or Talos,
//! imported with `floating = true`) timed like Pinocchio's C++ baseline
//! (`benches/baselines/pinocchio/floating_bench.cpp`): 1000 random states (unit quaternion,
//! position in (-1, 1), joints in (-1, 1) rad on Solo12 and (-0.5, 0.5) on Talos, v in
//! (-2, 2), a in (-5, 5), efforts in (-20, 20); both sides' code takes the same time at any
//! values: straight-line code here, fixed loops there); each round calls every routine once per state and records the mean ns per
//! call; the JSON gives each routine's median and minimum over the rounds.

use std::hint::black_box;
use std::time::Instant;

use mechanism::FloatingBase;
use mechanism::nalgebra::SVector;

mechanism::mechanism!(urdf = "../../mechanisms/urdf/solo12.urdf", floating = true);
mechanism::mechanism!(
    urdf = "../../mechanisms/urdf/talos_reduced.urdf",
    lock = ["gripper_left_joint", "gripper_right_joint"],
    floating = true,
    name = Talos
);

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

struct State<const NQ: usize, const NV: usize> {
    q: SVector<f64, NQ>,
    v: SVector<f64, NV>,
    a: SVector<f64, NV>,
    tau: SVector<f64, NV>,
}

fn states<R: FloatingBase<NQ, NV>, const NQ: usize, const NV: usize>(
    limits: &[(f64, f64)],
) -> Vec<State<NQ, NV>> {
    let mut u = Uniform(20_261_128);
    (0..1000)
        .map(|_| {
            let mut q = R::neutral();
            for k in 0..3 {
                q[k] = -1.0 + 2.0 * u.next();
            }
            let quat: Vec<f64> = (0..4).map(|_| u.next() - 0.5).collect();
            let norm = quat.iter().map(|x| x * x).sum::<f64>().sqrt();
            for k in 0..4 {
                q[3 + k] = quat[k] / norm;
            }
            for (j, (lo, hi)) in limits.iter().enumerate() {
                q[7 + j] = lo + (hi - lo) * u.next();
            }
            let mut r = |lo: f64, hi: f64| SVector::from_fn(|_, _| lo + (hi - lo) * u.next());
            State {
                q,
                v: r(-2.0, 2.0),
                a: r(-5.0, 5.0),
                tau: r(-20.0, 20.0),
            }
        })
        .collect()
}

/// Mean ns per call of `f` over all states.
fn round<S>(states: &[S], mut f: impl FnMut(&S)) -> f64 {
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

/// The JSON of one robot's routines over `rounds` rounds.
fn json<R: FloatingBase<NQ, NV> + Default, const NQ: usize, const NV: usize>(
    rounds: usize,
    limits: &[(f64, f64)],
) -> String {
    let r = R::default();
    let r = black_box(&r);
    let st = states::<R, NQ, NV>(limits);
    type Routine<'a, const NQ: usize, const NV: usize> =
        (&'static str, Box<dyn FnMut(&State<NQ, NV>) + 'a>);
    let mut routines: Vec<Routine<'_, NQ, NV>> = vec![
        (
            "mass_and_bias",
            Box::new(|s| {
                black_box(r.mass_and_bias(0.0, &s.q, &s.v));
            }),
        ),
        (
            "bias",
            Box::new(|s| {
                black_box(r.bias(0.0, &s.q, &s.v));
            }),
        ),
        (
            "mass_matrix",
            Box::new(|s| {
                black_box(r.mass_matrix(&s.q));
            }),
        ),
        (
            "inverse_dynamics",
            Box::new(|s| {
                black_box(r.inverse_dynamics(0.0, &s.q, &s.v, &s.a));
            }),
        ),
        (
            "forward_dynamics",
            Box::new(|s| {
                black_box(r.forward_dynamics(0.0, &s.q, &s.v, &s.tau));
            }),
        ),
        (
            "centroidal_momentum_matrix",
            Box::new(|s| {
                black_box(r.centroidal_momentum_matrix(&s.q));
            }),
        ),
        (
            "inverse_dynamics_derivatives",
            Box::new(|s| {
                black_box(r.inverse_dynamics_derivatives(0.0, &s.q, &s.v, &s.a));
            }),
        ),
        (
            "forward_dynamics_derivatives",
            Box::new(|s| {
                black_box(r.forward_dynamics_derivatives(0.0, &s.q, &s.v, &s.tau));
            }),
        ),
    ];
    for (_, f) in routines.iter_mut() {
        round(&st, f);
    }
    let mut times: Vec<Vec<f64>> = vec![Vec::new(); routines.len()];
    for _ in 0..rounds {
        for (k, (_, f)) in routines.iter_mut().enumerate() {
            times[k].push(round(&st, f));
        }
    }
    let items: Vec<String> = (routines.iter().zip(times.iter_mut()))
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

/// The JSON of `harness floating <robot> <rounds>`, `None` for an unknown robot.
pub fn floating_json(robot: &str, rounds: usize) -> Option<String> {
    match robot {
        "solo12" => Some(json::<Solo, 19, 18>(rounds, &[(-1.0, 1.0); 12])),
        "talos" => Some(json::<Talos, 37, 36>(rounds, &[(-0.5, 0.5); 30])),
        _ => None,
    }
}
