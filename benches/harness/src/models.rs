//! The benchmarked mechanisms, each as a compiled `Mechanism` with static sizes, and the
//! dispatch from a model name to the generic timing code.

use mechanism::builtin::{PlanarFourBar, SpatialCrankSlider, SpatialFourBar};
use mechanism::{Compiled, Kinematic, System};

use crate::json_list;
use crate::simulate::{reference, simulate_runs};
use crate::timing::{Inputs, time_eval, time_solve};

mechanism::mechanism!(file = "mechanisms/closed_chain_8.mech");
mechanism::mechanism!(file = "mechanisms/closed_chain_16.mech");
mechanism::mechanism!(file = "mechanisms/closed_chain_32.mech");

/// The model names, in table order.
pub const NAMES: [&str; 6] = ["seed", "four_bar", "rssr", "chain8", "chain16", "chain32"];

/// One benchmarked model.
pub struct Model(&'static str);

/// Calls `$body` with `$m` bound to the default mechanism of the model named `$name` (its
/// sizes are then static in the generic code `$body` calls).
macro_rules! with_model {
    ($name:expr, |$m:ident| $body:expr) => {
        match $name {
            "seed" => {
                let $m = SpatialCrankSlider::default();
                $body
            }
            "four_bar" => {
                let $m = PlanarFourBar::default();
                $body
            }
            "rssr" => {
                let $m = SpatialFourBar::default();
                $body
            }
            "chain8" => {
                let $m = ClosedChain8::default();
                $body
            }
            "chain16" => {
                let $m = ClosedChain16::default();
                $body
            }
            _ => {
                let $m = ClosedChain32::default();
                $body
            }
        }
    };
}

impl Model {
    /// The model called `name`, if it is one of [`NAMES`].
    pub fn named(name: &str) -> Option<Model> {
        NAMES.iter().find(|n| **n == name).map(|n| Model(n))
    }

    /// q, q', t and the parameter values (the C inputs are [q, q', parameters, t]).
    pub fn state_json(&self) -> String {
        with_model!(self.0, |m| {
            let i = Inputs::of(&m);
            let system = Compiled::new(m);
            let mut p = vec![0.0; system.info().parameters.len()];
            system.parameter_values(&mut p);
            format!(
                "{{\"model\": \"{}\", \"q\": {}, \"qd\": {}, \"t\": {:?}, \"parameters\": {}, \"parameter_names\": {:?}}}",
                self.0,
                json_list(i.q.as_slice()),
                json_list(i.qd.as_slice()),
                i.t,
                json_list(&p),
                system.info().parameters
            )
        })
    }

    /// ns per call of `what` (`evaluate` or `five`), one value per batch.
    pub fn eval_json(&self, what: &str, batches: usize, calls: usize) -> Result<String, String> {
        let ns = with_model!(self.0, |m| time_eval(&m, what, batches, calls))?;
        Ok(format!(
            "{{\"model\": \"{}\", \"what\": \"{what}\", \"calls\": {calls}, \"ns\": {}}}",
            self.0,
            json_list(&ns)
        ))
    }

    /// ns per `Dynamics::solve` (through `Compiled`), one value per batch.
    pub fn solve_json(&self, batches: usize, calls: usize) -> String {
        let ns = with_model!(self.0, |m| time_solve(m, batches, calls));
        format!(
            "{{\"model\": \"{}\", \"calls\": {calls}, \"ns\": {}}}",
            self.0,
            json_list(&ns)
        )
    }

    /// `runs` timed runs of 10 s of DOP853 at rtol = atol = `tol` (after one untimed run),
    /// with the predictive step controller when `predictive`.
    pub fn simulate_json(&self, runs: usize, tol: f64, predictive: bool) -> String {
        let r = with_model!(self.0, |m| simulate_runs(
            &Compiled::new(m),
            runs,
            tol,
            predictive
        ));
        format!(
            "{{\"model\": \"{}\", \"tol\": {tol:?}, \"wall_s\": {}, \"steps\": {}, \"rejected\": {}, \"rhs\": {}, \"q_end\": {}, \"max_phi\": {:?}, \"controller\": \"{}\"}}",
            self.0,
            json_list(&r.wall_s),
            r.steps,
            r.rejected,
            r.rhs,
            json_list(&r.q_end),
            r.max_phi,
            if r.predictive { "predictive" } else { "pi" }
        )
    }

    /// q at 10 s from DOP853 at rtol = atol = 1e-13.
    pub fn reference_json(&self) -> String {
        let q = with_model!(self.0, |m| reference(&Compiled::new(m)));
        format!(
            "{{\"model\": \"{}\", \"q_end\": {}}}",
            self.0,
            json_list(&q)
        )
    }
}
