//! `kkt_tree ops FILE.mech...` and `kkt_tree time ROUNDS`: the constrained forward dynamics
//! by the dense augmented-Lagrangian solve (`fixed::kkt_solve` on `evaluate`) against the
//! solve that follows M's pattern (the emitted `constrained_dynamics`).
//!
//! `ops`: per file, n, m, the operations of the dense route (the evaluation's program plus
//! `dense_kkt_operations(n, m)` for the run-time solve) and of the tree route (the
//! `ConstrainedDynamics` program plus the m x m finish, m^3/3 + 2 m^2 + 2 n m), and which
//! one `mechanism!` emits (`-`: no tree route, M singular at every q).
//!
//! `time`: per compiled mechanism, ns per call of each route over 200 states along its
//! motion, ROUNDS interleaved rounds (dense then tree in each), median.

use std::hint::black_box;
use std::time::Instant;

use mechanism::builtin::{
    Bricard, ClosedChain4, FiveBar, PlanarFourBar, SpatialCrankSlider, WhippleBicycle,
};
use mechanism::fixed::kkt_solve;
use mechanism::{Compiled, IntegratorOptions, Mechanism, SimulationOptions, simulate};
use mechanism_codegen::{Role, dense_kkt_operations};
use nalgebra::SVector;

mechanism::mechanism!(
    urdf = "../tests/runtime/mimic_gripper.urdf",
    name = MimicGripper
);

fn ops(paths: &[String]) {
    println!(
        "| mechanism | n | m | dense: evaluation + solve | tree: program + finish | emitted |"
    );
    println!("|---|---:|---:|---:|---:|---|");
    for path in paths {
        let source = std::fs::read_to_string(path).expect("readable");
        let source = if path.ends_with(".urdf") {
            let options = mechanism_codegen::UrdfOptions {
                file_name: path.clone(),
                ..Default::default()
            };
            mechanism_codegen::urdf_to_mech(&source, &options).expect("imports")
        } else {
            source
        };
        let mut model = mechanism_codegen::parse_model_str(&source).expect("parses");
        let eqs = mechanism_codegen::derive(&mut model).expect("derives");
        let tangent = mechanism_codegen::residual_tangent(&mut model, &eqs).expect("tangent");
        let r = mechanism_codegen::compile(&mut model, &eqs, &tangent).expect("compiles");
        let (n, m) = (eqs.n, eqs.m);
        let evaluation = r.get(Role::Evaluation).unwrap().op_counts().total();
        let dense = evaluation + dense_kkt_operations(n, m);
        let tree = r
            .get(Role::ConstrainedDynamics)
            .filter(|p| !p.outputs().is_empty())
            .map(|p| p.op_counts().total() + m * m * m / 3 + 2 * m * m + 2 * n * m);
        let (tree_text, emitted) = match tree {
            Some(t) => (t.to_string(), "tree"),
            None => ("-".to_string(), "dense"),
        };
        println!(
            "| {} | {n} | {m} | {evaluation} + {} = {dense} | {tree_text} | {emitted} |",
            model.name,
            dense_kkt_operations(n, m)
        );
    }
}

type Sample<const N: usize> = (f64, SVector<f64, N>, SVector<f64, N>);

fn states<T: Mechanism<N, M>, const N: usize, const M: usize>(m: &T) -> Vec<Sample<N>> {
    let options = SimulationOptions {
        t_end: 1.0,
        integrator: IntegratorOptions::dop853(1e-10),
        ..Default::default()
    };
    let run = simulate(&Compiled::new(m.clone()), &options).expect("simulated");
    let stride = (run.len() / 200).max(1);
    let mut out: Vec<Sample<N>> = run
        .samples()
        .step_by(stride)
        .map(|s| {
            let q = SVector::from_column_slice(s.q);
            (s.t, q, SVector::from_column_slice(s.qd))
        })
        .collect();
    out.truncate(200);
    out
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn time<T: Mechanism<N, M>, const N: usize, const M: usize>(m: T, rounds: usize) {
    let states = states(&m);
    let reps = 20_000 / states.len().max(1) + 1;
    let calls = (reps * states.len()) as f64;
    let (mut dense, mut tree) = (Vec::new(), Vec::new());
    for _ in 0..rounds {
        let start = Instant::now();
        for _ in 0..reps {
            for (t, q, qd) in &states {
                black_box(kkt_solve(&m.evaluate(*t, q, qd), *t).unwrap());
            }
        }
        dense.push(start.elapsed().as_secs_f64() * 1e9 / calls);
        let start = Instant::now();
        for _ in 0..reps {
            for (t, q, qd) in &states {
                black_box(m.constrained_dynamics(*t, q, qd).unwrap());
            }
        }
        tree.push(start.elapsed().as_secs_f64() * 1e9 / calls);
    }
    let (d, t) = (median(dense), median(tree));
    println!(
        "| {} | {N} | {M} | {d:.0} | {t:.0} | {:.2} |",
        T::NAME,
        t / d
    );
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        Some("ops") => ops(&args[1..]),
        Some("time") => {
            let rounds = args.get(1).and_then(|r| r.parse().ok()).unwrap_or(7);
            println!("| mechanism | n | m | dense (ns) | tree (ns) | tree / dense |");
            println!("|---|---:|---:|---:|---:|---:|");
            time(SpatialCrankSlider::default(), rounds);
            time(MimicGripper::default(), rounds);
            time(FiveBar::default(), rounds);
            time(PlanarFourBar::default(), rounds);
            time(ClosedChain4::default(), rounds);
            time(Bricard::default(), rounds);
            time(WhippleBicycle::default(), rounds);
        }
        _ => {
            eprintln!("usage: kkt_tree ops FILE.mech... | kkt_tree time [ROUNDS]");
            std::process::exit(2);
        }
    }
}
