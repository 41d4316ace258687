//! The short summary `mechanism simulate` prints (with the seed paper's printed initial
//! state for its mechanism).

use std::fmt::Write as _;

use mechanism::PassageGeometry;
use mechanism::System;
use mechanism::output::summary::PassageReport;
use mechanism::output::{Summary, excursion_lines};

use super::seed::{SEED_PRINTED, is_seed};

/// Formats the run summary: the mobility, the consistent initial state (with the paper's
/// printed values and their constraint residual for the seed; past [`TABLE_LIMIT`]
/// coordinates only where to find it), the maxima, the counters, the singular
/// configurations passed and the line `wrote` (what was written where).
pub fn summary_text(key: &str, system: &dyn System, summary: &Summary, wrote: &str) -> String {
    let mut s = String::new();
    let mob = &summary.mobility;
    let _ = writeln!(
        s,
        "{key}: {} coordinates, {} constraint rows, {} degree(s) of freedom",
        mob.n, mob.m, mob.degrees_of_freedom
    );
    if mob.rank < mob.m {
        let _ = writeln!(
            s,
            "  Phi_q has rank {} (Grubler's n - m = {}); redundant rows: {}",
            mob.rank,
            mob.grubler,
            mob.redundant_rows.join("; ")
        );
        let _ = writeln!(s, "  multipliers {}", mob.multipliers);
    }
    initial_state_lines(&mut s, key, system, summary);
    run_lines(&mut s, summary);
    let _ = writeln!(s, "{wrote}");
    s
}

/// Most coordinates whose initial state the terminal shows; a larger mechanism's table is
/// in `summary.json` only.
pub const TABLE_LIMIT: usize = 12;

/// The consistent initial state, with the paper's printed values and their constraint
/// residual for the seed.
fn initial_state_lines(s: &mut String, key: &str, system: &dyn System, summary: &Summary) {
    let info = system.info();
    let seed = is_seed(key, system);
    if info.n() > TABLE_LIMIT {
        let _ = writeln!(
            *s,
            "consistent initial state of the {} coordinates (positions by Newton on Phi = 0, \
             rates from Phi_q q' = -Phi_t): in summary.json, consistent_initial_state",
            info.n()
        );
        return;
    }
    let _ = writeln!(
        *s,
        "consistent initial state (positions by Newton on Phi = 0, rates from Phi_q q' = -Phi_t):"
    );
    let header = if seed { "   paper printed" } else { "" };
    let _ = writeln!(
        *s,
        "  {:<10} {:>20} {:>20}{header}",
        "coordinate", "q(0)", "q'(0)"
    );
    let q0 = &summary.consistent_initial_state.q.0;
    let qd0 = &summary.consistent_initial_state.q_dot.0;
    for ((name, q), (_, qd)) in q0.iter().zip(qd0) {
        let printed = SEED_PRINTED.iter().find(|p| p.0 == name).filter(|_| seed);
        let p = printed.map_or(String::new(), |p| format!(" {:>15}", p.1));
        // Values that round to zero at the 15 printed decimals (e.g. -7e-49 from round-off)
        // print as 0, not -0.000000000000000.
        let clean = |x: f64| if x.abs() < 5e-16 { 0.0 } else { x };
        let (q, qd) = (clean(*q), clean(*qd));
        let _ = writeln!(*s, "  {name:<10} {q:>20.15} {qd:>20.15}{p}");
    }
    if seed {
        let mut q = info.initial_guess.clone();
        for (name, v) in SEED_PRINTED {
            if let Some(k) = info.coordinate_index(name) {
                q[k] = v;
            }
        }
        let mut phi = vec![0.0; info.m()];
        system.constraints(0.0, &q, &mut phi);
        let worst = phi.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
        let _ = writeln!(
            s,
            "  the paper's printed state violates the constraints by |Phi|_inf = {worst:.4} m; \
             it swapped beta and gamma and dropped a decimal point in x_C"
        );
    }
}

/// The integrator, the counters, the maxima, the singular passages and the failure.
fn run_lines(s: &mut String, summary: &Summary) {
    let tol = match (summary.rtol, summary.atol) {
        (Some(r), Some(a)) => format!(" (rtol {r:e}, atol {a:e})"),
        _ => String::new(),
    };
    let _ = writeln!(
        *s,
        "integrator {}{tol}, stabilization {}",
        summary.integrator, summary.stabilization
    );
    let _ = writeln!(
        *s,
        "steps {} (rejected {}), right-hand sides {}, wall time {:.3} s",
        summary.steps, summary.rejected_steps, summary.rhs_evaluations, summary.wall_time_s
    );
    let _ = writeln!(
        *s,
        "max |Phi|_inf                  = {:.3e}",
        summary.max_constraint_error
    );
    let _ = writeln!(
        *s,
        "max |Phi_q q' + Phi_t|_inf     = {:.3e}",
        summary.max_velocity_constraint_error
    );
    let _ = writeln!(
        *s,
        "max |T + Pi - W - (T + Pi)(0)| = {:.3e} J",
        summary.max_energy_balance_error
    );
    if summary.energy_depends_on_time {
        let _ = writeln!(
            *s,
            "  (not an error measure: T or Pi depends on t explicitly, and W leaves out the work of that dependence)"
        );
    }
    if !summary.singular_passages.is_empty() {
        let times: Vec<String> = summary
            .singular_passages
            .iter()
            .take(8)
            .map(|p| format!("{:.4} s (rank drop {})", p.t, p.rank_drop))
            .collect();
        let more = summary.singular_passages.len().saturating_sub(8);
        let tail = if more > 0 {
            format!(" and {more} more")
        } else {
            String::new()
        };
        let _ = writeln!(
            s,
            "passed {} singular configuration(s): {}{tail}",
            summary.singular_passages.len(),
            times.join(", ")
        );
        apex_lines(s, &summary.singular_passages);
    }
    let passed = &summary.joint_limit_excursions;
    if !passed.is_empty() {
        let _ = writeln!(
            s,
            "went outside {} declared joint limit(s), which the simulation does not enforce \
             (summary.json, joint_limit_excursions):",
            passed.len()
        );
        for line in excursion_lines(passed, 8) {
            let _ = writeln!(s, "  {line}");
        }
    }
    if let Some(e) = &summary.outcome.error {
        let _ = writeln!(*s, "stopped at t = {} s: {e}", summary.outcome.t_last);
    }
}

/// The lines for passages through an apex ([`PassageGeometry::Apex`]): a warning for those
/// a step went over (the run's straight continuation holds only for an exact hit), a note
/// for those whose turn the steps followed (the motion past them is sensitive).
fn apex_lines(s: &mut String, passages: &[PassageReport]) {
    let times = |over: bool| -> Option<String> {
        let t: Vec<String> = passages
            .iter()
            .filter(|p| p.geometry == PassageGeometry::Apex && p.stepped_over == over)
            .map(|p| format!("{:.4} s", p.t))
            .collect();
        let more = match t.len().saturating_sub(4) {
            0 => String::new(),
            k => format!(" and {k} more"),
        };
        (!t.is_empty()).then(|| format!("{}{more}", t[..t.len().min(4)].join(", ")))
    };
    if let Some(t) = times(true) {
        let _ = writeln!(
            s,
            "warning: a step went straight over an apex at {t}: a point where the mechanism \
             keeps 2 or more degrees of freedom and its branches meet like the nappes of a \
             cone. That is the continuation of a motion that hits the point exactly (by \
             symmetry, say); a motion that misses it, by however little, turns around it onto \
             another branch within about (miss) / (speed), a turn shorter than that step. So \
             the motion past it is not determined at this tolerance: compare two tolerances, \
             or a start moved by more than the tolerance (summary.json: \
             singular_passages[].geometry, .stepped_over)"
        );
    }
    if let Some(t) = times(false) {
        let _ = writeln!(
            s,
            "note: the motion turned around an apex within its steps at {t} (a point where \
             the branches meet like the nappes of a cone; closest approach in summary.json, \
             singular_passages[].independence): a near-miss amplifies the state's errors, so \
             the motion past it may move with the tolerance; compare two tolerances"
        );
    }
}
