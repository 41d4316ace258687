//! HHT-alpha as a [`Stepper`]: a fixed step on the index-3 DAE ([`Hht`]), the work W by
//! the trapezoidal rule on tau . q', and a cubic Hermite dense output from the step's end
//! values and derivatives.

use super::{Stepper, fixed_first_step, trial_step};
use crate::algorithms::dynamics::Dynamics;
use crate::error::Error;
use crate::integrators::{Dense, Hht, IntegratorOptions};
use crate::simulation::rhs::Rhs;
use crate::system::System;

/// HHT-alpha with its Hermite dense output.
pub(super) struct HhtStepper {
    hht: Box<Hht>,
    n: usize,
    /// The fixed step and the largest step allowed (s).
    h: f64,
    h_max: f64,
    /// y' = [q', q'', tau . q' + lambda . Phi_t] at the start and the end of the last step.
    f0: Vec<f64>,
    f1: Vec<f64>,
    /// tau . q' + lambda . Phi_t at the current state.
    power: f64,
    hermite: Dense,
    /// Size of the last accepted step, and whether its dense output is built.
    h_step: f64,
    dense_ready: bool,
}

impl HhtStepper {
    /// HHT with step `h` and damping `alpha` from the state `y` at `t0`, started from the
    /// accelerations and multipliers of the first solve in `dynamics`.
    pub(super) fn new(
        system: &dyn System,
        h: f64,
        alpha: f64,
        options: &IntegratorOptions,
        t0: f64,
        y: &[f64],
        dynamics: &Dynamics,
    ) -> Result<Self, Error> {
        let info = system.info();
        let (n, dim) = (info.n(), y.len());
        let mut hht = Box::new(Hht::new(info, alpha)?);
        hht.start(
            system,
            t0,
            &y[..n],
            &y[n..2 * n],
            dynamics.accelerations(),
            dynamics.multipliers(),
        );
        Ok(Self {
            hht,
            n,
            h,
            h_max: options.h_max.unwrap_or(f64::INFINITY),
            f0: vec![0.0; dim],
            f1: vec![0.0; dim],
            power: dynamics.power(&y[n..2 * n]) + dynamics.constraint_power(),
            hermite: Dense::new(dim, 4),
            h_step: 0.0,
            dense_ready: false,
        })
    }
}

impl Stepper for HhtStepper {
    fn start(&mut self, _: &mut Rhs<'_>, _: f64, _: &[f64], span: f64) -> Result<f64, Error> {
        self.h = fixed_first_step(self.h, span)?;
        Ok(self.h)
    }

    fn advance(
        &mut self,
        rhs: &mut Rhs<'_>,
        t: f64,
        t_end: f64,
        y: &[f64],
        y_new: &mut [f64],
        _: &mut usize,
    ) -> Result<f64, Error> {
        self.dense_ready = false;
        let (n, hht) = (self.n, &mut self.hht);
        let (h, _) = trial_step(self.h, self.h_max, t, t_end);
        y_new.copy_from_slice(y);
        self.f0[..n].copy_from_slice(&y[n..2 * n]);
        self.f0[n..2 * n].copy_from_slice(hht.accelerations());
        self.f0[2 * n] = self.power;
        let (q, rest) = y_new.split_at_mut(n);
        hht.step(rhs.system, t, q, &mut rest[..n], h)?;
        let p1 = hht.power();
        y_new[2 * n] = y[2 * n] + 0.5 * h * (self.power + p1);
        self.f1[..n].copy_from_slice(&y_new[n..2 * n]);
        self.f1[n..2 * n].copy_from_slice(hht.accelerations());
        self.f1[2 * n] = p1;
        self.power = p1;
        self.h_step = h;
        Ok(h)
    }

    fn projects(&self) -> bool {
        false
    }

    fn restart(&mut self, _: &mut Rhs<'_>, _: f64, _: &[f64], _: Option<f64>) -> Result<(), Error> {
        Ok(())
    }

    fn dense_built(&self) -> bool {
        // The cubic Hermite extension takes no right-hand side.
        true
    }

    fn dense(
        &mut self,
        _: &mut Rhs<'_>,
        _: f64,
        y: &[f64],
        y_new: &[f64],
        theta: f64,
        out: &mut [f64],
    ) -> Result<(), Error> {
        if !self.dense_ready {
            self.hermite
                .set_hermite(y, y_new, &self.f0, &self.f1, self.h_step);
            self.dense_ready = true;
        }
        self.hermite.eval(theta, out);
        Ok(())
    }

    fn own_evaluations(&self) -> usize {
        self.hht.evaluations
    }
}
