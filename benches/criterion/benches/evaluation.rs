//! Evaluation, augmented solve and one integrator step of the seed crank-slider, the planar
//! four-bar, the RSSR and the closed chain (N = 8, 16, 32), each through three routes:
//!
//! - the code emitted by `mechanism!` (each generated function, the combined `evaluate`, and
//!   the same through the run-time `System` adapter);
//! - baseline (a): the interpreter route (`mechanism::Interpreted`);
//! - baseline (b): runtime automatic differentiation with num-dual (`mechanism_bench::autodiff`).
//!
//! Benchmark ids are `<model>/<what>_<route>`; `benches/report.py` turns the criterion
//! estimates into the tables of BENCHMARKS.md. The op counts of each program are printed
//! once per model (stderr).

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use mechanism::Compiled;
use mechanism::builtin::{PlanarFourBar, SpatialCrankSlider, SpatialFourBar};
use mechanism::nalgebra::SVector;
use mechanism::{Dynamics, Evaluation, Mechanism, Method, SimulationOptions, Simulator, System};
use mechanism_bench::simulation::options;
use mechanism_bench::{
    Case, builtin_cases, chain_case, check_chain_files, check_routes, model_ops, state,
};

mechanism::mechanism!(file = "mechanisms/closed_chain_8.mech");
mechanism::mechanism!(file = "mechanisms/closed_chain_16.mech");
mechanism::mechanism!(file = "mechanisms/closed_chain_32.mech");

/// Each generated function of the compiled mechanism `mech`, at (0.3, q, q').
fn generated<T: Mechanism<N, M>, const N: usize, const M: usize>(
    c: &mut Criterion,
    case: &Case,
    mech: &T,
) {
    let (q, qd) = state(case.compiled.as_ref());
    let q = SVector::<f64, N>::from_column_slice(&q);
    let qd = SVector::<f64, N>::from_column_slice(&qd);
    let t = 0.3;
    let mut g = c.benchmark_group(case.name);
    g.bench_function("fn_mass_matrix", |b| {
        b.iter(|| black_box(mech).mass_matrix(black_box(&q)))
    });
    g.bench_function("fn_coriolis_forces", |b| {
        b.iter(|| black_box(mech).coriolis_forces(black_box(&q), black_box(&qd)))
    });
    g.bench_function("fn_gravity", |b| {
        b.iter(|| black_box(mech).gravity(black_box(&q)))
    });
    g.bench_function("fn_constraints", |b| {
        b.iter(|| black_box(mech).constraints(t, black_box(&q)))
    });
    g.bench_function("fn_constraint_jacobian", |b| {
        b.iter(|| black_box(mech).constraint_jacobian(t, black_box(&q)))
    });
    g.bench_function("fn_constraint_gamma", |b| {
        b.iter(|| black_box(mech).constraint_gamma(t, black_box(&q), black_box(&qd)))
    });
    g.bench_function("five_separate_static", |b| {
        b.iter(|| {
            let m = black_box(mech);
            let (q, qd) = (black_box(&q), black_box(&qd));
            (
                m.mass_matrix(q),
                m.coriolis_forces(q, qd),
                m.gravity(q),
                m.constraints(t, q),
                m.constraint_jacobian(t, q),
            )
        })
    });
    g.bench_function("evaluate_static", |b| {
        b.iter(|| black_box(mech).evaluate(black_box(t), black_box(&q), black_box(&qd)))
    });
    g.finish();
}

/// The run-time routes: `System::evaluate`, `Dynamics::solve` and one `Simulator::step`.
fn routes(c: &mut Criterion, case: &Case) {
    let (q, qd) = state(case.compiled.as_ref());
    let info = case.compiled.info();
    let (n, m) = (info.n(), info.m());
    let routes: [(&str, &dyn System); 3] = [
        ("compiled", case.compiled.as_ref()),
        ("interpreted", case.interpreted.as_ref()),
        ("autodiff", case.autodiff.as_ref()),
    ];
    let mut g = c.benchmark_group(case.name);
    for (route, system) in routes {
        let mut out = Evaluation::zeros(n, m);
        g.bench_function(format!("evaluate_{route}"), |b| {
            b.iter(|| system.evaluate(black_box(0.3), black_box(&q), black_box(&qd), &mut out))
        });
        let mut dynamics = Dynamics::new(info);
        g.bench_function(format!("solve_{route}"), |b| {
            b.iter(|| {
                dynamics
                    .solve(system, black_box(0.3), black_box(&q), black_box(&qd))
                    .map(|_| dynamics.accelerations()[0])
            })
        });
        step(
            &mut g,
            &format!("step_rk4_{route}"),
            system,
            Method::Rk4 { h: 1e-3 },
        );
    }
    step(
        &mut g,
        "step_dop853_compiled",
        case.compiled.as_ref(),
        Method::Dop853,
    );
    g.finish();
}

/// One accepted step (with projection, the default stabilisation) of a long run, restarted
/// when it ends.
fn step(
    g: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    id: &str,
    system: &dyn System,
    method: Method,
) {
    let mut opts: SimulationOptions = options(method, 1e-10, Default::default());
    opts.t_end = 1e4;
    opts.output_rate = 0.01;
    let mut sim = Simulator::new(system, &opts).expect("simulator");
    g.bench_function(id, |b| {
        b.iter(|| {
            if !matches!(sim.step(), Ok(true)) {
                sim = Simulator::new(system, &opts).expect("simulator");
            }
        })
    });
}

/// All six cases, each checked (the three routes agree) before it is timed.
fn cases() -> Vec<Case> {
    check_chain_files();
    let mut all = builtin_cases();
    all.extend(chain_case(
        8,
        Box::new(Compiled::new(ClosedChain8::default())),
    ));
    all.extend(chain_case(
        16,
        Box::new(Compiled::new(ClosedChain16::default())),
    ));
    all.extend(chain_case(
        32,
        Box::new(Compiled::new(ClosedChain32::default())),
    ));
    for c in &all {
        check_routes(c);
    }
    all
}

fn evaluation(c: &mut Criterion) {
    for case in cases() {
        match model_ops(case.source) {
            Ok(ops) => {
                eprintln!(
                    "{}: M, C q', g, Phi, Phi_q together: {}; evaluate: {}",
                    case.name, ops.five, ops.evaluate
                );
                for (name, o) in &ops.each {
                    eprintln!("{}:   {name}: {o}", case.name);
                }
            }
            Err(e) => eprintln!("{}: op counts failed: {e}", case.name),
        }
        match case.name {
            "seed" => generated(c, &case, &SpatialCrankSlider::default()),
            "four_bar" => generated(c, &case, &PlanarFourBar::default()),
            "rssr" => generated(c, &case, &SpatialFourBar::default()),
            "chain8" => generated(c, &case, &ClosedChain8::default()),
            "chain16" => generated(c, &case, &ClosedChain16::default()),
            "chain32" => generated(c, &case, &ClosedChain32::default()),
            _ => {}
        }
        routes(c, &case);
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .without_plots()
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_millis(1000))
        .sample_size(30);
    targets = evaluation
}
criterion_main!(benches);
