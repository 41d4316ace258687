//! One evaluation of the interpreted route: a codegen [`Tape`] of one compiled routine and
//! where each of its inputs comes from (the routines' [`Sources`] table), checked once when
//! it is built so that running it cannot fail. It runs one state at a time or a batch's
//! rows side by side ([`Routine::execute_rows`]).

use mechanism_codegen::error::{EvalError, ProgramError};
use mechanism_codegen::{Error, Program, Source, Sources, Tape};

use crate::system::registers::{LANES, with_lanes, with_registers};

/// The values one evaluation reads; a slice an evaluation does not have is empty.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Values<'a> {
    pub(crate) parameters: &'a [f64],
    /// The parameter cache of `parameters` (the routines' `ParameterCache` output).
    pub(crate) cache: &'a [f64],
    pub(crate) t: f64,
    pub(crate) q: &'a [f64],
    pub(crate) qd: &'a [f64],
    pub(crate) qdd: &'a [f64],
    pub(crate) lambda: &'a [f64],
    /// The efforts u of a forward dynamics (M q'' + b = u).
    pub(crate) effort: &'a [f64],
}

impl Values<'_> {
    /// The value `source` names; NaN when the slice is too short, so that a caller's short
    /// buffer shows as a non-finite result instead of a panic.
    fn get(&self, source: Source) -> f64 {
        let at = |values: &[f64], k: usize| values.get(k).copied().unwrap_or(f64::NAN);
        match source {
            Source::Parameter(k) => at(self.parameters, k),
            Source::Cache(k) => at(self.cache, k),
            Source::Coordinate(k) => at(self.q, k),
            Source::Rate(k) => at(self.qd, k),
            Source::Acceleration(k) => at(self.qdd, k),
            Source::Multiplier(k) => at(self.lambda, k),
            Source::Effort(k) => at(self.effort, k),
            Source::Time => self.t,
        }
    }

    /// The value `source` names for row `row` of a batch whose `q`, `qd`, `qdd` hold one
    /// state of `n` values per row (row-major); the parameters, cache and t are shared, and
    /// a multiplier (which no batch carries) is NaN, as is a value past a short slice.
    fn get_row(&self, source: Source, row: usize, n: usize) -> f64 {
        let at = |values: &[f64], k: usize| match k < n {
            true => values.get(row * n + k).copied().unwrap_or(f64::NAN),
            false => f64::NAN,
        };
        match source {
            Source::Coordinate(k) => at(self.q, k),
            Source::Rate(k) => at(self.qd, k),
            Source::Acceleration(k) => at(self.qdd, k),
            Source::Multiplier(_) => f64::NAN,
            _ => self.get(source),
        }
    }
}

/// A tape with the register-file slot and the source of each of its inputs.
#[derive(Clone, Debug)]
pub(crate) struct Routine {
    tape: Tape,
    inputs: Vec<(usize, Source)>,
}

impl Routine {
    /// Compiles `program`, whose every input must have a source, for `outputs` output
    /// entries.
    ///
    /// # Errors
    /// [`mechanism_codegen::error::EvalError::MissingValue`] for an input symbol without a
    /// source (a hand-built model's free symbol),
    /// [`mechanism_codegen::error::ProgramError::OutputCount`] when the program does not have
    /// `outputs` entries.
    pub(crate) fn new(program: &Program, sources: &Sources, outputs: usize) -> Result<Self, Error> {
        let tape = Tape::new(program);
        if tape.output_len() != outputs {
            return Err(Error::Program(ProgramError::OutputCount {
                what: "output slots",
                given: outputs,
                outputs: tape.output_len(),
            }));
        }
        let name = |symbol| {
            let named = program.symbols().iter().find(|(s, _)| *s == symbol);
            named.map_or("?", |(_, name)| name.as_str()).to_string()
        };
        let inputs = tape
            .input_slots()
            .map(|(symbol, slot)| match sources.get(symbol) {
                Some(source) => Ok((slot, source)),
                None => Err(Error::Eval(EvalError::MissingValue { name: name(symbol) })),
            })
            .collect::<Result<_, _>>()?;
        Ok(Self { tape, inputs })
    }

    /// Runs the tape at `values` and hands its outputs to `sink`. Neither fails nor (after
    /// the thread's first evaluation) allocates: a non-finite value reaches the outputs it
    /// affects, where the solvers' finiteness checks report it with t and q.
    pub(crate) fn run<R>(&self, values: &Values<'_>, sink: impl FnOnce(&[f64]) -> R) -> R {
        self.run_with(values, true, |regs, out| {
            let _ = regs;
            sink(out)
        })
    }

    /// [`Routine::run`] handing `sink` the register file itself, without copying the
    /// outputs: output entry k is at [`Routine::output_slot`]`(k)` of it.
    pub(crate) fn execute<R>(&self, values: &Values<'_>, sink: impl FnOnce(&[f64]) -> R) -> R {
        self.run_with(values, false, |regs, _| sink(regs))
    }

    /// Runs the tape on rows `rows.start..rows.end` of the batch `values` (see
    /// [`Values::get_row`]: n values per state) side by side, `L` at a time in the thread's
    /// lane register file ([`with_lanes`]), and calls `sink(first, count, registers)` after
    /// each block: lane l of `registers[lane_slot(output_slot(k))]` is output entry k of row
    /// `first + l`, for l < `count`, bit for bit what [`Routine::execute`] gives for that
    /// row alone ([`mechanism_codegen::Tape::execute_lanes`]). The lanes of a last, partial
    /// block repeat its last row. Allocates nothing after the thread's first block.
    pub(crate) fn execute_rows<E>(
        &self,
        values: &Values<'_>,
        n: usize,
        rows: core::ops::Range<usize>,
        mut sink: impl FnMut(usize, usize, &[[f64; LANES]]) -> Result<(), E>,
    ) -> Result<(), E> {
        with_lanes(self.tape.lane_register_len(), |regs| {
            let mut first = rows.start;
            while first < rows.end {
                let count = (rows.end - first).min(LANES);
                for &(slot, source) in &self.inputs {
                    let lanes = &mut regs[slot];
                    for (l, x) in lanes.iter_mut().enumerate() {
                        *x = values.get_row(source, first + l.min(count - 1), n);
                    }
                }
                self.tape.execute_lanes(regs);
                sink(first, count, regs)?;
                first += count;
            }
            Ok(())
        })
    }

    /// Every output entry of each of the first `out.len() / output_len` rows of the batch
    /// `values` (n values per state) into `out`, one row's outputs after another: the rows
    /// side by side ([`Routine::execute_rows`]), each bit for bit [`Routine::run`].
    pub(crate) fn run_rows(&self, values: &Values<'_>, n: usize, out: &mut [f64]) {
        let width = self.tape.output_len();
        let rows = out.len().checked_div(width).unwrap_or(0);
        let Ok(()) = self.execute_rows::<core::convert::Infallible>(
            values,
            n,
            0..rows,
            |first, count, regs| {
                for k in 0..width {
                    let lanes = self
                        .tape
                        .lane_output_slot(k)
                        .map_or(&[f64::NAN; LANES], |s| &regs[s]);
                    for (l, x) in lanes[..count].iter().enumerate() {
                        out[(first + l) * width + k] = *x;
                    }
                }
                Ok(())
            },
        );
    }

    /// The lane register-file slot ([`Routine::execute_rows`]) of register-file slot `slot`
    /// of [`Routine::execute`] that holds a constant, an input or an output.
    pub(crate) fn lane_slot(&self, slot: usize) -> Option<usize> {
        self.tape.lane_slot(slot)
    }

    /// The register-file slot of output entry `k` after [`Routine::execute`].
    pub(crate) fn output_slot(&self, k: usize) -> Option<usize> {
        self.tape.output_slot(k)
    }

    /// Loads the inputs, runs the tape (copying its outputs when `copy`) and calls `sink`
    /// with the register file and the outputs (empty unless copied).
    fn run_with<R>(
        &self,
        values: &Values<'_>,
        copy: bool,
        sink: impl FnOnce(&[f64], &[f64]) -> R,
    ) -> R {
        let registers = self.tape.register_len();
        let outputs = if copy { self.tape.output_len() } else { 0 };
        with_registers(registers, outputs, |regs, out| {
            for &(slot, source) in &self.inputs {
                regs[slot] = values.get(source);
            }
            if copy {
                self.tape.run(regs, out);
            } else {
                self.tape.execute(regs);
            }
            sink(regs, out)
        })
    }
}
