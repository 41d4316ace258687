//! The interpreter route for repeated evaluation: a [`Program`] compiled into a flat list of
//! register operations over one preallocated register file.
//!
//! The register file holds, in order, the program's constants, its input symbols and its
//! SSA registers, so every operand is a plain slot index and the inner loop is one `match`
//! per instruction with no allocation. This is what the runtime uses for a `.mech` file
//! that was not compiled in.
//!
//! Two ways to run it: [`Tape::eval`] checks its inputs and outputs and keeps its own
//! register file; [`Tape::run`] checks nothing and uses the caller's (the inputs already at
//! their [`Tape::input_slots`]), for a caller that validated the inputs once and evaluates
//! from many threads.

use crate::algebra::expr::{FxHashMap, SymbolId};
use crate::error::{Error, Result};
use crate::error::{EvalError, ProgramError};
use crate::program::cse::Program;
use crate::program::instructions::{BinOp, Instr, Operand, UnOp};
use crate::program::tape_op::{LaneLayout, Op};
use mechanism_math::{mul_add, sin_cos};

/// A compiled [`Program`]: `eval` and `run` write every output entry (each output matrix
/// row-major, the matrices one after another) without allocating.
#[derive(Clone, Debug)]
pub struct Tape {
    pub(super) ops: Vec<Op>,
    /// The constants, in slots 0.. of the register file.
    pub(super) constants: Vec<f64>,
    /// The register file of `eval`.
    regs: Vec<f64>,
    /// (symbol, register-file slot, name) of each input.
    inputs: Vec<(SymbolId, u32, String)>,
    outputs: Vec<u32>,
    shapes: Vec<(usize, usize)>,
    /// The operations renumbered for [`Tape::execute_lanes`], whose register file reuses
    /// the slot of a value after its last use.
    pub(super) lanes: LaneLayout,
}

impl Tape {
    /// Compiles `program`.
    ///
    /// # Example
    /// ```
    /// use mechanism_codegen::{Arena, Matrix, Program, SymbolKind, Tape};
    ///
    /// let mut a = Arena::new();
    /// let x = a.symbol("x", SymbolKind::Free);
    /// let y = a.symbol("y", SymbolKind::Free);
    /// let m = Matrix::column(vec![a.mul2(x, y), a.sin(x)]);
    /// let mut tape = Tape::new(&Program::new(&a, &[&m]).unwrap());
    /// let mut out = [0.0; 2];
    /// tape.eval(&[0.5, 4.0], &mut out).unwrap(); // values indexed by SymbolId
    /// assert_eq!(out, [2.0, mechanism_math::sin_cos(0.5).0]);
    /// ```
    pub fn new(program: &Program) -> Tape {
        let layout = SlotLayout::of(program);
        let ops: Vec<Op> = program
            .instructions()
            .iter()
            .map(|i| layout.op(i))
            .collect();
        let nc = layout.constants.len();
        let constants: Vec<f64> = layout
            .constants
            .iter()
            .map(|b| f64::from_bits(*b))
            .collect();
        let regs = vec![0.0; layout.base as usize + program.registers()];
        let inputs = program
            .symbols()
            .iter()
            .enumerate()
            .map(|(k, (s, name))| (*s, (nc + k) as u32, name.clone()))
            .collect();
        let outputs: Vec<u32> = program
            .outputs()
            .iter()
            .flat_map(|o| o.entries.iter().map(|&e| layout.slot(e)))
            .collect();
        let shapes = program.outputs().iter().map(|o| (o.rows, o.cols)).collect();
        let lanes = LaneLayout::of(&ops, layout.base as usize, &outputs, regs.len());
        Tape {
            lanes,
            ops,
            constants,
            regs,
            inputs,
            outputs,
            shapes,
        }
    }

    /// Length of the register file [`Tape::run`] works in.
    pub fn register_len(&self) -> usize {
        self.regs.len()
    }

    /// Each symbol the tape reads, with the register-file slot its value goes in before
    /// [`Tape::run`], in the order of [`Program::symbols`].
    pub fn input_slots(&self) -> impl Iterator<Item = (SymbolId, usize)> + '_ {
        self.inputs.iter().map(|(s, slot, _)| (*s, *slot as usize))
    }

    /// Total number of output entries `eval` writes.
    pub fn output_len(&self) -> usize {
        self.outputs.len()
    }

    /// (rows, cols) of each output matrix, in order.
    pub fn output_shapes(&self) -> &[(usize, usize)] {
        &self.shapes
    }

    /// Number of operations per evaluation.
    pub fn len(&self) -> usize {
        self.ops.len()
    }

    /// True when the tape has no operation (every output is a constant or a symbol).
    pub fn is_empty(&self) -> bool {
        self.ops.is_empty()
    }

    /// Evaluates all outputs at `inputs` (symbol values indexed by `SymbolId`), writing them
    /// into `out` (length [`Tape::output_len`]). No allocation on the success path.
    ///
    /// Intermediate values are not checked one by one (that would cost a branch per
    /// operation); a NaN or infinity propagates to an output, and the outputs are checked.
    ///
    /// # Errors
    /// [`crate::error::EvalError::MissingValue`] when `inputs` is too short for a symbol the
    /// program reads, [`crate::error::EvalError::NonFinite`] for a non-finite input or output,
    /// [`crate::error::ProgramError::OutputCount`] when `out` has the wrong length.
    pub fn eval(&mut self, inputs: &[f64], out: &mut [f64]) -> Result<()> {
        if out.len() != self.outputs.len() {
            return Err(Error::Program(ProgramError::OutputCount {
                what: "output slots",
                given: out.len(),
                outputs: self.outputs.len(),
            }));
        }
        for (s, slot, name) in &self.inputs {
            match inputs.get(s.index()) {
                Some(&v) if v.is_finite() => self.regs[*slot as usize] = v,
                Some(&v) => {
                    return Err(Error::Eval(EvalError::NonFinite {
                        operation: name.clone(),
                        arguments: format!("{v:?}"),
                    }));
                }
                None => return Err(Error::Eval(EvalError::MissingValue { name: name.clone() })),
            }
        }
        // `take` leaves an empty Vec behind: no allocation.
        let mut regs = std::mem::take(&mut self.regs);
        self.run(&mut regs, out);
        self.regs = regs;
        for (k, v) in out.iter().enumerate() {
            if !v.is_finite() {
                return Err(Error::Eval(EvalError::NonFinite {
                    operation: format!("output entry {k}"),
                    arguments: format!("{v:?}"),
                }));
            }
        }
        Ok(())
    }

    /// Evaluates all outputs into `out`, in the caller's register file `registers` whose
    /// [`Tape::input_slots`] already hold the input values. Nothing is checked and nothing
    /// allocated: a non-finite value propagates to the outputs it reaches, as in the emitted
    /// code.
    ///
    /// `out` receives the first `out.len()` output entries: all of them when it has
    /// [`Tape::output_len`].
    ///
    /// # Panics
    /// When `registers` is shorter than [`Tape::register_len`] (a caller sizes it once).
    pub fn run(&self, registers: &mut [f64], out: &mut [f64]) {
        self.execute(registers);
        for (o, &slot) in out.iter_mut().zip(&self.outputs) {
            *o = registers[slot as usize];
        }
    }

    /// The register-file slot that holds output entry `k` after [`Tape::execute`] (entries
    /// numbered as [`Tape::run`] writes them), or `None` past the last.
    pub fn output_slot(&self, k: usize) -> Option<usize> {
        self.outputs.get(k).map(|&s| s as usize)
    }

    /// [`Tape::run`] without copying the outputs: afterwards output entry k is in
    /// `registers[output_slot(k)]`, for a caller that reads a few of many outputs (the
    /// structural nonzeros of a large M).
    ///
    /// # Panics
    /// When `registers` is shorter than [`Tape::register_len`].
    pub fn execute(&self, registers: &mut [f64]) {
        let r = registers;
        r[..self.constants.len()].copy_from_slice(&self.constants);
        for op in &self.ops {
            match *op {
                Op::Add(a, b, t) => r[t as usize] = r[a as usize] + r[b as usize],
                Op::Sub(a, b, t) => r[t as usize] = r[a as usize] - r[b as usize],
                Op::Mul(a, b, t) => r[t as usize] = r[a as usize] * r[b as usize],
                Op::Div(a, b, t) => r[t as usize] = r[a as usize] / r[b as usize],
                Op::Atan2(a, b, t) => r[t as usize] = r[a as usize].atan2(r[b as usize]),
                Op::Powf(a, b, t) => r[t as usize] = r[a as usize].powf(r[b as usize]),
                Op::Neg(a, t) => r[t as usize] = -r[a as usize],
                Op::Sin(a, t) => r[t as usize] = sin_cos(r[a as usize]).0,
                Op::Cos(a, t) => r[t as usize] = sin_cos(r[a as usize]).1,
                Op::Tan(a, t) => r[t as usize] = r[a as usize].tan(),
                Op::Exp(a, t) => r[t as usize] = r[a as usize].exp(),
                Op::Ln(a, t) => r[t as usize] = r[a as usize].ln(),
                Op::Sqrt(a, t) => r[t as usize] = r[a as usize].sqrt(),
                Op::Abs(a, t) => r[t as usize] = r[a as usize].abs(),
                Op::Powi(a, k, t) => r[t as usize] = r[a as usize].powi(k),
                Op::SinCos(a, s, c) => {
                    let (x, y) = sin_cos(r[a as usize]);
                    r[s as usize] = x;
                    r[c as usize] = y;
                }
                Op::MulAdd(a, b, c, t, negate_product, negate_addend) => {
                    let (x, z) = (r[a as usize], r[c as usize]);
                    let x = if negate_product { -x } else { x };
                    let z = if negate_addend { -z } else { z };
                    r[t as usize] = mul_add(x, r[b as usize], z);
                }
            }
        }
    }
}

/// Where each operand of a program lives in a tape's register file: its distinct constants
/// first, then its symbols in [`Program::symbols`] order, then its registers.
struct SlotLayout {
    /// The distinct constants' bits, in order of first use.
    constants: Vec<u64>,
    /// The slot of each constant, by its bits.
    const_slot: FxHashMap<u64, u32>,
    /// The slot of each symbol.
    sym_slot: FxHashMap<SymbolId, u32>,
    /// The slot of register 0.
    base: u32,
}

impl SlotLayout {
    fn of(program: &Program) -> SlotLayout {
        let mut constants: Vec<u64> = Vec::new();
        let mut const_slot: FxHashMap<u64, u32> = FxHashMap::default();
        let mut collect = |o: Operand| {
            if let Operand::Const(c) = o {
                const_slot.entry(c.to_bits()).or_insert_with(|| {
                    constants.push(c.to_bits());
                    constants.len() as u32 - 1
                });
            }
        };
        for i in program.instructions() {
            i.for_each_operand(&mut collect);
        }
        for o in program.outputs() {
            o.entries.iter().for_each(|&e| collect(e));
        }
        let nc = constants.len();
        let syms = program.symbols();
        let sym_slot = syms
            .iter()
            .enumerate()
            .map(|(k, (s, _))| (*s, (nc + k) as u32))
            .collect();
        SlotLayout {
            base: (nc + syms.len()) as u32,
            constants,
            const_slot,
            sym_slot,
        }
    }

    /// The slot of operand `o`.
    fn slot(&self, o: Operand) -> u32 {
        match o {
            Operand::Const(c) => self.const_slot.get(&c.to_bits()).copied().unwrap_or(0),
            Operand::Sym(s) => self.sym_slot.get(&s).copied().unwrap_or(0),
            Operand::Reg(r) => self.base + r.0,
        }
    }

    /// The slot of register `r`.
    fn dst(&self, r: crate::program::instructions::Reg) -> u32 {
        self.base + r.0
    }

    /// The tape operation of instruction `i`.
    fn op(&self, i: &Instr) -> Op {
        match *i {
            Instr::Binary { dst, op, lhs, rhs } => {
                let (a, b, t) = (self.slot(lhs), self.slot(rhs), self.dst(dst));
                match op {
                    BinOp::Add => Op::Add(a, b, t),
                    BinOp::Sub => Op::Sub(a, b, t),
                    BinOp::Mul => Op::Mul(a, b, t),
                    BinOp::Div => Op::Div(a, b, t),
                    BinOp::Atan2 => Op::Atan2(a, b, t),
                    BinOp::Powf => Op::Powf(a, b, t),
                }
            }
            Instr::Unary { dst, op, arg } => {
                let (a, t) = (self.slot(arg), self.dst(dst));
                match op {
                    UnOp::Neg => Op::Neg(a, t),
                    UnOp::Sin => Op::Sin(a, t),
                    UnOp::Cos => Op::Cos(a, t),
                    UnOp::Tan => Op::Tan(a, t),
                    UnOp::Exp => Op::Exp(a, t),
                    UnOp::Ln => Op::Ln(a, t),
                    UnOp::Sqrt => Op::Sqrt(a, t),
                    UnOp::Abs => Op::Abs(a, t),
                }
            }
            Instr::Powi { dst, base, exp } => Op::Powi(self.slot(base), exp, self.dst(dst)),
            Instr::SinCos { sin, cos, arg } => {
                Op::SinCos(self.slot(arg), self.dst(sin), self.dst(cos))
            }
            Instr::MulAdd {
                dst,
                a,
                b,
                c,
                negate_product,
                negate_addend,
            } => Op::MulAdd(
                self.slot(a),
                self.slot(b),
                self.slot(c),
                self.dst(dst),
                negate_product,
                negate_addend,
            ),
        }
    }
}
