//! The instructions of a [`Program`](crate::Program): registers, operands and the unary,
//! binary, integer-power and `sin_cos` operations of straight-line SSA code.

use crate::algebra::expr::SymbolId;

/// A register of a [`Program`](crate::Program): the value of one instruction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Reg(pub(crate) u32);

impl Reg {
    /// The register's number: registers are numbered 0, 1, .. in program order.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// One output matrix of a [`Program`](crate::Program): where each entry's value is, row-major.
#[derive(Clone, Debug, PartialEq, Hash)]
pub struct Output {
    /// Rows.
    pub rows: usize,
    /// Columns.
    pub cols: usize,
    /// Entry (i, j) at `i * cols + j`.
    pub entries: Vec<Operand>,
}

/// An instruction operand: a register, an input symbol or a constant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Operand {
    /// The value of an earlier instruction.
    Reg(Reg),
    /// An input symbol (coordinate, rate, parameter, time).
    Sym(SymbolId),
    /// A finite constant.
    Const(f64),
}

/// A constant hashes by its bits (`f64` has no `Hash`): equal operands hash equally.
impl std::hash::Hash for Operand {
    fn hash<H: std::hash::Hasher>(&self, h: &mut H) {
        match *self {
            Operand::Reg(r) => (0u8, r.0).hash(h),
            Operand::Sym(s) => (1u8, s).hash(h),
            Operand::Const(c) => (2u8, c.to_bits()).hash(h),
        }
    }
}

impl From<Reg> for Operand {
    /// The register's value as an operand.
    fn from(r: Reg) -> Operand {
        Operand::Reg(r)
    }
}

/// A unary operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum UnOp {
    /// -x
    Neg,
    /// sin x
    Sin,
    /// cos x
    Cos,
    /// tan x
    Tan,
    /// e^x
    Exp,
    /// ln x
    Ln,
    /// sqrt x
    Sqrt,
    /// |x|
    Abs,
}

/// A binary operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BinOp {
    /// lhs + rhs
    Add,
    /// lhs - rhs
    Sub,
    /// lhs * rhs
    Mul,
    /// lhs / rhs
    Div,
    /// atan2(lhs, rhs): the angle of the point (rhs, lhs)
    Atan2,
    /// lhs ^ rhs (real power)
    Powf,
}

/// One SSA instruction; each defines one register (`SinCos` defines two).
#[derive(Clone, Copy, Debug, PartialEq, Hash)]
pub enum Instr {
    /// dst = op(arg)
    Unary {
        /// Destination register.
        dst: Reg,
        /// Operation.
        op: UnOp,
        /// Argument.
        arg: Operand,
    },
    /// dst = lhs op rhs
    Binary {
        /// Destination register.
        dst: Reg,
        /// Operation.
        op: BinOp,
        /// Left operand.
        lhs: Operand,
        /// Right operand.
        rhs: Operand,
    },
    /// dst = base^exp for an integer exp (|exp| > 4; smaller powers are multiplications).
    Powi {
        /// Destination register.
        dst: Reg,
        /// Base.
        base: Operand,
        /// Integer exponent.
        exp: i32,
    },
    /// dst = (+-a) b + (+-c) as one `mul_add` (rounded once where the target fuses, see
    /// `mechanism_math::mul_add`): a product used by nothing but one sum or difference.
    MulAdd {
        /// Destination register.
        dst: Reg,
        /// First factor.
        a: Operand,
        /// Second factor.
        b: Operand,
        /// Addend.
        c: Operand,
        /// The product is subtracted: dst = c - a b.
        negate_product: bool,
        /// The addend is subtracted: dst = a b - c.
        negate_addend: bool,
    },
    /// (sin, cos) = (sin arg, cos arg), computed together.
    SinCos {
        /// Register receiving sin arg.
        sin: Reg,
        /// Register receiving cos arg.
        cos: Reg,
        /// Argument.
        arg: Operand,
    },
}

impl Instr {
    /// Calls `f` on each operand read by the instruction.
    pub fn for_each_operand(&self, mut f: impl FnMut(Operand)) {
        match *self {
            Instr::Unary { arg, .. } | Instr::SinCos { arg, .. } => f(arg),
            Instr::Powi { base, .. } => f(base),
            Instr::Binary { lhs, rhs, .. } => {
                f(lhs);
                f(rhs);
            }
            Instr::MulAdd { a, b, c, .. } => {
                f(a);
                f(b);
                f(c);
            }
        }
    }

    /// The operation count of the instruction (see [`OpCounts`]).
    pub fn op_counts(&self) -> OpCounts {
        let mut c = OpCounts::default();
        match self {
            Instr::Unary { op: UnOp::Neg, .. }
            | Instr::Binary {
                op: BinOp::Add | BinOp::Sub,
                ..
            } => c.adds = 1,
            Instr::Binary { op: BinOp::Mul, .. } => c.muls = 1,
            Instr::MulAdd { .. } => {
                c.muls = 1;
                c.adds = 1;
            }
            Instr::Binary { op: BinOp::Div, .. } => c.divs = 1,
            _ => c.calls = 1,
        }
        c
    }
}

/// Operation counts: what the emitted code executes, one per instruction.
///
/// `adds` counts additions, subtractions and negations; `muls` multiplications (a
/// `mul_add` counts as one multiplication and one addition); `divs`
/// divisions; `calls` the calls `sin_cos`, `sin`, `cos`, `tan`, `exp`, `ln`, `sqrt`, `abs`,
/// `atan2`, `powi`, `powf` (each 1).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct OpCounts {
    /// Additions, subtractions and negations.
    pub adds: usize,
    /// Multiplications.
    pub muls: usize,
    /// Divisions.
    pub divs: usize,
    /// Function calls.
    pub calls: usize,
}

impl OpCounts {
    /// adds + muls + divs + calls.
    pub fn total(&self) -> usize {
        self.adds + self.muls + self.divs + self.calls
    }
}

impl std::ops::Add for OpCounts {
    type Output = OpCounts;
    fn add(self, o: OpCounts) -> OpCounts {
        OpCounts {
            adds: self.adds + o.adds,
            muls: self.muls + o.muls,
            divs: self.divs + o.divs,
            calls: self.calls + o.calls,
        }
    }
}

impl std::ops::AddAssign for OpCounts {
    fn add_assign(&mut self, o: OpCounts) {
        *self = *self + o;
    }
}

impl std::fmt::Display for OpCounts {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} ops ({} add, {} mul, {} div, {} call)",
            self.total(),
            self.adds,
            self.muls,
            self.divs,
            self.calls
        )
    }
}

/// The registers an instruction defines.
pub(crate) fn defines(i: &Instr) -> [Option<Reg>; 2] {
    match *i {
        Instr::Unary { dst, .. }
        | Instr::Binary { dst, .. }
        | Instr::Powi { dst, .. }
        | Instr::MulAdd { dst, .. } => [Some(dst), None],
        Instr::SinCos { sin, cos, .. } => [Some(sin), Some(cos)],
    }
}

/// One more than the highest register `instrs` define: the length of a table by register.
pub(crate) fn register_count(instrs: &[Instr]) -> usize {
    instrs
        .iter()
        .flat_map(defines)
        .flatten()
        .map(|r| r.index() + 1)
        .max()
        .unwrap_or(0)
}

/// How many times each register is read, by the instructions and by the outputs.
pub(crate) fn read_counts(instrs: &[Instr], outputs: &[Output]) -> Vec<u32> {
    let mut uses = vec![0u32; register_count(instrs)];
    let mut count = |o: Operand| {
        if let Operand::Reg(r) = o {
            uses[r.index()] += 1;
        }
    };
    instrs.iter().for_each(|i| i.for_each_operand(&mut count));
    outputs
        .iter()
        .for_each(|o| o.entries.iter().for_each(|&e| count(e)));
    uses
}
