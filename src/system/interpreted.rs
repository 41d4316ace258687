//! The interpreter route: a mechanism read at run time (a `.mech` file that was not compiled
//! in), derived by `mechanism-codegen` and evaluated through its [`Tape`].
//!
//! It computes exactly what the code emitted by `mechanism!` computes (the same derived
//! equations, the same CSE'd program), only interpreted: the runtime gets a [`System`] for
//! any declaration without a rebuild, and the tests get a second route to check the
//! emitted code against.

use std::sync::Mutex;

use mechanism_codegen::{
    Equations, EvaluationOutput, Model, Program, SymbolId, Tape, residual_tangent,
};
use nalgebra::DMatrix;

use crate::system::{ConstraintRow, Evaluation, Independent, System, SystemInfo, Tangent};

/// Which evaluations a tape computes.
struct Scratch {
    tape: Tape,
    inputs: Vec<f64>,
    out: Vec<f64>,
}

impl Scratch {
    fn new(program: &Program, symbols: usize) -> Self {
        let tape = Tape::new(program);
        let out = vec![0.0; tape.output_len()];
        Self {
            tape,
            inputs: vec![0.0; symbols],
            out,
        }
    }
}

/// A mechanism interpreted from its declaration.
pub struct Interpreted {
    info: SystemInfo,
    parameters: Vec<f64>,
    parameter_symbols: Vec<SymbolId>,
    q_symbols: Vec<SymbolId>,
    qd_symbols: Vec<SymbolId>,
    qdd_symbols: Vec<SymbolId>,
    lambda_symbols: Vec<SymbolId>,
    time_symbol: Option<SymbolId>,
    /// M, C q', g, tau, Phi, Phi_q, Phi_t, gamma, T, Pi.
    full: Mutex<Scratch>,
    /// Phi.
    phi: Mutex<Scratch>,
    /// Phi_q, Phi_t.
    jacobian: Mutex<Scratch>,
    /// dF/dq, dF/dq' of the residual (exact Jacobians for implicit integrators).
    tangent: Mutex<Scratch>,
    programs: [Program; 4],
    symbols: usize,
    equations_text: String,
}

impl std::fmt::Debug for Interpreted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Interpreted")
            .field("info", &self.info)
            .finish_non_exhaustive()
    }
}

impl Clone for Interpreted {
    fn clone(&self) -> Self {
        let [a, b, c, d] = &self.programs;
        Self {
            info: self.info.clone(),
            parameters: self.parameters.clone(),
            parameter_symbols: self.parameter_symbols.clone(),
            q_symbols: self.q_symbols.clone(),
            qd_symbols: self.qd_symbols.clone(),
            qdd_symbols: self.qdd_symbols.clone(),
            lambda_symbols: self.lambda_symbols.clone(),
            time_symbol: self.time_symbol,
            full: Mutex::new(Scratch::new(a, self.symbols)),
            phi: Mutex::new(Scratch::new(b, self.symbols)),
            jacobian: Mutex::new(Scratch::new(c, self.symbols)),
            tangent: Mutex::new(Scratch::new(d, self.symbols)),
            programs: self.programs.clone(),
            symbols: self.symbols,
            equations_text: self.equations_text.clone(),
        }
    }
}

impl Interpreted {
    /// Parses, checks and derives the declaration `text` (the `.mech` grammar).
    ///
    /// # Errors
    /// The codegen error (parse errors carry line and column).
    pub fn from_source(text: &str) -> Result<Self, mechanism_codegen::Error> {
        let model = mechanism_codegen::parse_model_str(text)?;
        Self::from_model(model)
    }

    /// Derives the equations of `model` and compiles them for evaluation.
    ///
    /// # Errors
    /// A derivation or compilation error from codegen.
    pub fn from_model(mut model: Model) -> Result<Self, mechanism_codegen::Error> {
        let eqs = mechanism_codegen::derive(&mut model)?;
        Self::from_equations(model, eqs)
    }

    /// Compiles already derived equations.
    ///
    /// # Errors
    /// A compilation error from codegen.
    pub fn from_equations(
        mut model: Model,
        eqs: Equations,
    ) -> Result<Self, mechanism_codegen::Error> {
        let tangent = residual_tangent(&mut model, &eqs)?;
        let arena = &model.arena;
        // A hand-built Model may put any expression where a symbol belongs: say so.
        let sym = |id, what: &str| {
            arena
                .as_symbol(id)
                .ok_or_else(|| mechanism_codegen::Error::NotASymbol {
                    role: what.to_string(),
                })
        };
        let outputs = eqs.evaluation_outputs();
        let full = Program::new(arena, &outputs.iter().collect::<Vec<_>>())?;
        let phi = Program::new(arena, &[&eqs.phi])?;
        let jac = Program::new(arena, &[&eqs.phi_q, &eqs.phi_t])?;
        let tan = Program::new(arena, &[&tangent.stiffness, &tangent.damping])?;
        let symbols = arena.symbols().len();
        let info = system_info(&model, eqs.m);
        let equations_text = mechanism_codegen::equations_text(&model, &eqs);
        Ok(Self {
            parameters: model.parameters.iter().map(|p| p.default).collect(),
            parameter_symbols: model
                .parameters
                .iter()
                .map(|p| sym(p.symbol, &format!("parameter `{}`", p.name)))
                .collect::<Result<_, _>>()?,
            q_symbols: model
                .coordinates
                .iter()
                .map(|c| sym(c.q, &format!("coordinate `{}`", c.name)))
                .collect::<Result<_, _>>()?,
            qd_symbols: model
                .coordinates
                .iter()
                .map(|c| sym(c.qd, &format!("the rate of `{}`", c.name)))
                .collect::<Result<_, _>>()?,
            qdd_symbols: model
                .coordinates
                .iter()
                .map(|c| sym(c.qdd, &format!("the acceleration of `{}`", c.name)))
                .collect::<Result<_, _>>()?,
            lambda_symbols: tangent.lambda.clone(),
            time_symbol: arena.as_symbol(model.time),
            full: Mutex::new(Scratch::new(&full, symbols)),
            phi: Mutex::new(Scratch::new(&phi, symbols)),
            jacobian: Mutex::new(Scratch::new(&jac, symbols)),
            tangent: Mutex::new(Scratch::new(&tan, symbols)),
            programs: [full, phi, jac, tan],
            symbols,
            info,
            equations_text,
        })
    }

    /// The derived equations as readable text (the same text `mechanism!` embeds).
    pub fn equations_text(&self) -> &str {
        &self.equations_text
    }

    fn load(&self, s: &mut Scratch, t: f64, q: &[f64], qd: Option<&[f64]>) {
        for (sym, v) in self.parameter_symbols.iter().zip(&self.parameters) {
            s.inputs[sym.0 as usize] = *v;
        }
        for (sym, v) in self.q_symbols.iter().zip(q) {
            s.inputs[sym.0 as usize] = *v;
        }
        if let Some(qd) = qd {
            for (sym, v) in self.qd_symbols.iter().zip(qd) {
                s.inputs[sym.0 as usize] = *v;
            }
        }
        if let Some(ts) = self.time_symbol {
            s.inputs[ts.0 as usize] = t;
        }
    }

    /// Runs one tape; a failed evaluation (non-finite value) fills the outputs with NaN so
    /// the solver's finiteness checks report it with t and q.
    fn run(
        &self,
        cell: &Mutex<Scratch>,
        t: f64,
        q: &[f64],
        qd: Option<&[f64]>,
        sink: impl FnOnce(&[f64]),
    ) {
        let mut guard = cell.lock().unwrap_or_else(|p| p.into_inner());
        let s = &mut *guard;
        self.load(s, t, q, qd);
        // The tape writes its outputs in order and stops at the first non-finite one: the
        // outputs before it keep their values and the rest read NaN, so the first NaN in
        // output order is the entry that failed (what the solvers' error messages name).
        s.out.fill(f64::NAN);
        let _ = s.tape.eval(&s.inputs, &mut s.out);
        sink(&s.out);
    }
}

/// Copies a row-major block of `rows x cols` values into `dst`.
fn copy_block(src: &[f64], rows: usize, cols: usize, dst: &mut DMatrix<f64>) {
    for i in 0..rows {
        for j in 0..cols {
            dst[(i, j)] = src[i * cols + j];
        }
    }
}

impl System for Interpreted {
    fn info(&self) -> &SystemInfo {
        &self.info
    }

    fn parameter_values(&self, out: &mut [f64]) {
        for (o, v) in out.iter_mut().zip(&self.parameters) {
            *o = *v;
        }
    }

    fn set_parameter(&mut self, index: usize, value: f64) -> bool {
        match self.parameters.get_mut(index) {
            Some(p) => {
                *p = value;
                true
            }
            None => false,
        }
    }

    fn evaluate(&self, t: f64, q: &[f64], qd: &[f64], out: &mut Evaluation) {
        let (n, m) = (self.info.n(), self.info.m());
        self.run(&self.full, t, q, Some(qd), |v| {
            let mut k = 0;
            for o in EvaluationOutput::ORDER {
                let (rows, cols) = o.shape(n, m);
                let v = &v[k..k + rows * cols];
                match o {
                    EvaluationOutput::Mass => copy_block(v, n, n, &mut out.mass),
                    EvaluationOutput::CoriolisForces => out.coriolis.copy_from_slice(v),
                    EvaluationOutput::Gravity => out.gravity.copy_from_slice(v),
                    EvaluationOutput::Forces => out.forces.copy_from_slice(v),
                    EvaluationOutput::Phi => out.phi.copy_from_slice(v),
                    EvaluationOutput::PhiQ => copy_block(v, m, n, &mut out.phi_q),
                    EvaluationOutput::PhiT => out.phi_t.copy_from_slice(v),
                    EvaluationOutput::Gamma => out.gamma.copy_from_slice(v),
                    EvaluationOutput::Kinetic => out.kinetic = v[0],
                    EvaluationOutput::Potential => out.potential = v[0],
                }
                k += rows * cols;
            }
        });
    }

    fn constraints(&self, t: f64, q: &[f64], phi: &mut [f64]) {
        self.run(&self.phi, t, q, None, |v| phi.copy_from_slice(v));
    }

    fn constraint_jacobian(&self, t: f64, q: &[f64], phi_q: &mut DMatrix<f64>, phi_t: &mut [f64]) {
        let (n, m) = (self.info.n(), self.info.m());
        self.run(&self.jacobian, t, q, None, |v| {
            copy_block(v, m, n, phi_q);
            phi_t.copy_from_slice(&v[m * n..m * n + m]);
        });
    }

    fn tangent(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        lambda: &[f64],
        out: &mut Tangent,
    ) -> Option<()> {
        let n = self.info.n();
        let mut guard = self.tangent.lock().unwrap_or_else(|p| p.into_inner());
        let s = &mut *guard;
        self.load(s, t, q, Some(qd));
        for (sym, v) in self
            .qdd_symbols
            .iter()
            .zip(qdd)
            .chain(self.lambda_symbols.iter().zip(lambda))
        {
            s.inputs[sym.0 as usize] = *v;
        }
        // On a non-finite tangent the caller falls back to finite differences.
        s.tape.eval(&s.inputs, &mut s.out).ok()?;
        copy_block(&s.out, n, n, &mut out.stiffness);
        copy_block(&s.out[n * n..], n, n, &mut out.damping);
        Some(())
    }
}

/// Names, guesses, independent coordinates and row labels of a model with m constraint rows.
fn system_info(model: &Model, m: usize) -> SystemInfo {
    SystemInfo {
        name: model.name.clone(),
        coordinates: model.coordinates.iter().map(|c| c.name.clone()).collect(),
        parameters: model.parameters.iter().map(|p| p.name.clone()).collect(),
        initial_guess: model.coordinates.iter().map(|c| c.guess).collect(),
        independent: model
            .independent
            .iter()
            .map(|i| Independent {
                coordinate: i.coordinate,
                position: i.position,
                velocity: i.velocity,
            })
            .collect(),
        constraints: m,
        constraint_rows: model
            .constraints
            .iter()
            .enumerate()
            .map(|(k, c)| {
                if c.joint.is_empty() {
                    // A hand-built Model that did not name its rows.
                    ConstraintRow::unnamed(k)
                } else {
                    ConstraintRow {
                        joint: c.joint.clone(),
                        component: c.component.clone(),
                    }
                }
            })
            .collect(),
    }
}
