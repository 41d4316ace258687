//! Generated declarations: well-formed ones with random energies and constraints, and
//! broken ones made from them by deleting, inserting, duplicating or truncating text.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::{Duration, Instant};

use mechanism::{Interpreted, Kinematic, SimulationOptions, simulate};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};

/// A scalar expression in the coordinates `q0..q{n-1}` and the parameters `a`, `b`, `c`.
fn expr(n: usize) -> impl Strategy<Value = String> {
    let leaf = prop_oneof![
        (0..n).prop_map(|i| format!("q{i}")),
        prop_oneof![Just("a"), Just("b"), Just("c"), Just("pi")].prop_map(String::from),
        (-5.0..5.0_f64).prop_map(|x| format!("{x:.3}")),
        (1..9_i32).prop_map(|k| k.to_string()),
    ];
    leaf.prop_recursive(4, 24, 3, |inner| {
        prop_oneof![
            (inner.clone(), inner.clone()).prop_map(|(x, y)| format!("({x} + {y})")),
            (inner.clone(), inner.clone()).prop_map(|(x, y)| format!("({x} - {y})")),
            (inner.clone(), inner.clone()).prop_map(|(x, y)| format!("{x}*{y}")),
            (inner.clone(), inner.clone()).prop_map(|(x, y)| format!("{x}/(2 + {y}^2)")),
            (inner.clone(), 2..4_i32).prop_map(|(x, k)| format!("({x})^{k}")),
            inner.clone().prop_map(|x| format!("sin({x})")),
            inner.clone().prop_map(|x| format!("cos({x})")),
            inner.clone().prop_map(|x| format!("sqrt(1 + ({x})^2)")),
            inner.clone().prop_map(|x| format!("atan2({x}, 1.5)")),
            inner.prop_map(|x| format!("exp(-({x})^2)")),
        ]
    })
}

/// A well-formed declaration: n coordinates, m < n constraint rows, a kinetic energy that is
/// a positive definite quadratic form in the rates, any potential.
pub fn declaration() -> impl Strategy<Value = String> {
    (1..4_usize, 0..3_usize).prop_flat_map(|(n, m)| {
        let m = m.min(n - 1);
        (
            Just((n, m)),
            prop::collection::vec(expr(n), n),
            expr(n),
            prop::collection::vec(expr(n), m),
            prop::collection::vec(-1.0..1.0_f64, n),
        )
            .prop_map(|((n, m), weights, potential, rows, guesses)| {
                let coords: Vec<String> = (0..n)
                    .map(|i| format!("q{i} = {:.3};", guesses[i]))
                    .collect();
                let free: Vec<String> = (0..n - m).map(|i| format!("q{i} = {:.3};", guesses[i])).collect();
                let kinetic: Vec<String> = weights
                    .iter()
                    .enumerate()
                    .map(|(i, w)| format!("1/2*(1 + ({w})^2)*der(q{i})^2"))
                    .collect();
                let constraints = if rows.is_empty() {
                    String::new()
                } else {
                    format!("constraints {{ {} }}", rows.iter().map(|r| format!("{r};")).collect::<String>())
                };
                format!(
                    "pub struct Fuzz;\nparameters {{ a = 0.7; b = 1.3; c = 2.0; }}\ncoordinates {{ {} }}\nindependent {{ {} }}\nkinetic = {};\npotential = {};\n{constraints}\n",
                    coords.join(" "),
                    free.join(" "),
                    kinetic.join(" + "),
                    potential
                )
            })
    })
}

/// A declaration broken by one edit: a deleted span, an inserted character, a duplicated
/// span or a truncation.
pub fn broken() -> impl Strategy<Value = String> {
    (
        declaration(),
        0..4_u8,
        any::<prop::sample::Index>(),
        any::<prop::sample::Index>(),
        prop::sample::select(
            &[
                ';', '{', '}', '[', ']', '(', ')', '=', ',', '+', '*', '^', '.', '#', '!', '"',
                '\'', '/', 'x', '9', ' ',
            ][..],
        ),
    )
        .prop_map(|(text, kind, i, j, ch)| {
            let chars: Vec<char> = text.chars().collect();
            let (a, b) = {
                let (x, y) = (i.index(chars.len()), j.index(chars.len()));
                (x.min(y), x.max(y).min(x.min(y) + 12))
            };
            let mut out: Vec<char> = match kind {
                0 => [&chars[..a], &chars[b..]].concat(),
                1 => [&chars[..a], &[ch][..], &chars[a..]].concat(),
                2 => [&chars[..b], &chars[a..b], &chars[b..]].concat(),
                _ => chars[..a].to_vec(),
            };
            out.shrink_to_fit();
            out.into_iter().collect()
        })
}

/// What one declaration did: built and simulated, refused with an error, or (a failure of
/// the property) panicked or took too long.
#[derive(Debug, PartialEq)]
pub enum Outcome {
    Simulated,
    DeclarationError,
    RunError,
}

/// Runs `text` through the interpreter route and a 0.05 s simulation; Err on a property
/// violation (panic, non-finite result, an error without a message, over the time budget).
pub fn run(text: &str, budget: Duration) -> Result<Outcome, String> {
    let start = Instant::now();
    let result = catch_unwind(AssertUnwindSafe(|| -> Result<Outcome, String> {
        let system = match Interpreted::from_source(text) {
            Ok(s) => s,
            Err(e) => {
                let message = e.to_string();
                if std::env::var_os("FUZZ_SHOW").is_some() {
                    eprintln!("DECL {message}");
                }
                return if message.trim().is_empty() {
                    Err("an empty declaration error".into())
                } else {
                    Ok(Outcome::DeclarationError)
                };
            }
        };
        let options = SimulationOptions {
            t_end: 0.05,
            output_rate: 200.0,
            ..Default::default()
        };
        match simulate(&system, &options) {
            Ok(trajectory) => {
                for s in trajectory.samples() {
                    let values = s.q.iter().chain(s.qd).chain(s.qdd).chain(s.lambda);
                    if !values.into_iter().all(|v| v.is_finite()) {
                        return Err(format!("a non-finite sample at t = {}", s.t));
                    }
                }
                let _ = system.info();
                Ok(Outcome::Simulated)
            }
            Err(e) if !e.to_string().trim().is_empty() => Ok(Outcome::RunError),
            Err(_) => Err("an empty run error".into()),
        }
    }));
    let elapsed = start.elapsed();
    match result {
        Err(_) => Err("panicked".into()),
        Ok(_) if elapsed > budget => Err(format!("took {elapsed:?}")),
        Ok(r) => r,
    }
}

/// Runs `cases` generated inputs of `strategy`; returns the counts of each outcome.
pub fn campaign(
    strategy: impl Strategy<Value = String>,
    cases: u32,
    budget: Duration,
) -> [usize; 3] {
    let mut runner = TestRunner::new(Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    });
    let counts = std::cell::RefCell::new([0; 3]);
    let result = runner.run(&strategy, |text| {
        let outcome =
            run(&text, budget).map_err(|why| TestCaseError::fail(format!("{why}:\n{text}")))?;
        counts.borrow_mut()[outcome as usize] += 1;
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    counts.into_inner()
}

/// Time budget per declaration: these are at most 3 coordinates, so a derivation takes
/// milliseconds; 10 s only catches a hang, even on a loaded machine in a debug build.
const BUDGET: Duration = Duration::from_secs(10);

#[test]
fn generated_declarations_never_panic() {
    let n = crate::cases(150);
    let [ok, declaration, run] = campaign(declaration(), n, BUDGET);
    // Most well-formed declarations run: a generator that only produced errors would test
    // nothing. (Random constraints are often unsatisfiable; random guesses often far off.)
    assert!(
        ok > n as usize / 10,
        "only {ok} of {n} simulated ({declaration} refused, {run} failed)"
    );
}

#[test]
fn broken_declarations_are_refused_with_an_error() {
    let n = crate::cases(300);
    let [ok, declaration, run] = campaign(broken(), n, BUDGET);
    assert!(
        declaration > n as usize / 3,
        "{declaration} of {n} refused ({ok} ran, {run} failed)"
    );
}

#[test]
#[ignore = "the full campaign (10^5 declarations): cargo test --release --test fuzz -- --ignored --nocapture"]
fn campaign_of_declarations() {
    for (name, counts, elapsed) in [
        {
            let t = Instant::now();
            (
                "well-formed",
                campaign(declaration(), 50_000, BUDGET),
                t.elapsed(),
            )
        },
        {
            let t = Instant::now();
            ("broken", campaign(broken(), 50_000, BUDGET), t.elapsed())
        },
    ] {
        println!(
            "{name}: 50000 cases in {elapsed:.1?}: {} simulated, {} declaration errors, {} run errors",
            counts[0], counts[1], counts[2]
        );
    }
}
