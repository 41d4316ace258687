//! Common-subexpression elimination: a straight-line SSA [`Program`] for several matrices.
//!
//! The arena is already hash-consed, so every distinct subexpression is one node; the
//! program gives each needed node one register (one `let`), in id (topological) order, and
//! lowers the canonical n-ary forms into lean binary operations:
//!
//! | expression                      | lowered to                                  |
//! |---------------------------------|---------------------------------------------|
//! | `a + (-1)*b + (-2)*c`           | `a - b - 2*c` (negative terms subtract)     |
//! | `(-1)*x*y`                      | `-(x*y)` (a -1 coefficient is a negation)   |
//! | `c*x*y` with `c != 1`           | `c*(x*y)` (coefficient last: `x*y` shared)  |
//! | `x*y*z^-1*w^-2`                 | `(x*y)/(z*(w*w))` (one division)            |
//! | `x^2`, `x^3`, `x^4`             | `x*x`, `x*x*x`, `x2*x2` (shared squares)    |
//! | `x^k`, `k > 4`                  | `x.powi(k)`                                 |
//! | `x^-k` alone                    | `1/(x^k)`                                   |
//! | `x^(1/2)`, `x^(p/2)`            | `sqrt(x)`, `sqrt(x)*x^((p-1)/2)`            |
//! | `sin u` and `cos u` both needed | one `u.sin_cos()` for all outputs           |
//! | `tan u` with `sin u`, `cos u`   | `s/c` from that `sin_cos`                   |
//! | constant subexpressions         | folded to one f64 constant                  |
//!
//! Identical instructions are value-numbered (one register), so partial products such as
//! `x*y` are shared across terms and outputs. Unused registers are removed at the end.

use crate::error::{Error, Result};
use crate::eval::{for_each_child, pow_value};
use crate::expr::{Arena, Func, FxHashMap, Id, Node, SymbolId};
use crate::matrix::Matrix;
use crate::number::Number;

/// A register of a [`Program`]: the value of one instruction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Reg(pub u32);

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
#[derive(Clone, Copy, Debug, PartialEq)]
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
            Instr::Binary { op: BinOp::Div, .. } => c.divs = 1,
            _ => c.calls = 1,
        }
        c
    }
}

/// Operation counts: what the emitted code executes, one per instruction.
///
/// `adds` counts additions, subtractions and negations; `muls` multiplications; `divs`
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

/// One output matrix of a [`Program`]: where each entry's value is, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct Output {
    /// Rows.
    pub rows: usize,
    /// Columns.
    pub cols: usize,
    /// Entry (i, j) at `i * cols + j`.
    pub entries: Vec<Operand>,
}

/// A straight-line SSA program computing several matrices at once, with common
/// subexpressions shared between all of them (module docs list the lowering rules).
#[derive(Clone, Debug, PartialEq)]
pub struct Program {
    instrs: Vec<Instr>,
    outputs: Vec<Output>,
    registers: u32,
    symbols: Vec<(SymbolId, String)>,
}

impl Program {
    /// The CSE'd program computing every entry of every matrix in `outputs`.
    ///
    /// # Errors
    /// [`Error::InvalidId`] for an entry that is not a node of `arena`, [`Error::Model`] for a
    /// matrix whose data length is not rows x cols, [`Error::NonFinite`] for a constant
    /// subexpression that is not finite.
    ///
    /// # Example
    /// ```
    /// use mechanism_codegen::{Arena, Matrix, Program};
    ///
    /// // sin(u) in one output and cos(u) in another: one sin_cos call for both.
    /// let mut a = Arena::new();
    /// let [p, ..] = a.coordinate("th1");
    /// let [q, ..] = a.coordinate("th2");
    /// let u = a.sub(p, q);
    /// let (s, c) = (a.sin(u), a.cos(u));
    /// let program = Program::new(&a, &[&Matrix::column(vec![s]), &Matrix::column(vec![c])]).unwrap();
    /// let n = program.op_counts();
    /// assert_eq!((n.adds, n.calls, n.total()), (1, 1, 2));
    /// assert_eq!(program.output_op_counts(1).unwrap().total(), 2);
    /// ```
    pub fn new(arena: &Arena, outputs: &[&Matrix]) -> Result<Program> {
        let len = arena.len();
        for m in outputs {
            if m.rows.checked_mul(m.cols) != Some(m.data.len()) {
                return Err(Error::Model(format!(
                    "matrix of size {} x {} has {} entries",
                    m.rows,
                    m.cols,
                    m.data.len()
                )));
            }
            if let Some(bad) = m.data.iter().find(|i| i.index() >= len) {
                return Err(Error::InvalidId { id: bad.0, len });
            }
        }
        let mut lower = Lowering::new(arena, outputs);
        lower.run()?;
        let outs = outputs
            .iter()
            .map(|m| Output {
                rows: m.rows,
                cols: m.cols,
                entries: m.data.iter().map(|i| lower.op(*i)).collect(),
            })
            .collect();
        let mut symbols: Vec<(SymbolId, String)> = lower
            .used_symbols
            .into_iter()
            .map(|s| {
                (
                    s,
                    arena
                        .symbols()
                        .get(s.0 as usize)
                        .map_or_else(|| format!("#{}", s.0), |x| x.name.clone()),
                )
            })
            .collect();
        symbols.sort_by_key(|p| p.0);
        Ok(compact(&lower.b.instrs, outs, &symbols))
    }

    /// The instructions, in execution order.
    pub fn instructions(&self) -> &[Instr] {
        &self.instrs
    }

    /// The outputs, in the order given to [`Program::new`].
    pub fn outputs(&self) -> &[Output] {
        &self.outputs
    }

    /// Number of registers (registers are numbered 0..registers in instruction order).
    pub fn registers(&self) -> usize {
        self.registers as usize
    }

    /// The input symbols the program reads (sorted by id), with their names.
    pub fn symbols(&self) -> &[(SymbolId, String)] {
        &self.symbols
    }

    /// Operation counts of the whole program.
    pub fn op_counts(&self) -> OpCounts {
        self.instrs
            .iter()
            .fold(OpCounts::default(), |acc, i| acc + i.op_counts())
    }

    /// Operation counts of the instructions needed by output `k` alone (`None` when there
    /// is no output `k`).
    pub fn output_op_counts(&self, k: usize) -> Option<OpCounts> {
        (k < self.outputs.len()).then(|| self.op_counts_of(&[k]))
    }

    /// Operation counts of the instructions needed by the outputs `ks` together (shared
    /// instructions counted once). Indices past the last output are ignored.
    pub fn op_counts_of(&self, ks: &[usize]) -> OpCounts {
        let live = self.live_registers(ks);
        self.instrs
            .iter()
            .filter(|i| defines(i).iter().flatten().any(|r| live[r.0 as usize]))
            .fold(OpCounts::default(), |acc, i| acc + i.op_counts())
    }

    /// The program restricted to the outputs `ks` (in that order), without the
    /// instructions only the others need.
    ///
    /// # Errors
    /// [`Error::Model`] when some index is not an output.
    pub fn restrict(&self, ks: &[usize]) -> Result<Program> {
        let mut outs = Vec::with_capacity(ks.len());
        for &k in ks {
            let o = self.outputs.get(k).ok_or_else(|| {
                Error::Model(format!(
                    "the program has {} outputs, not {}",
                    self.outputs.len(),
                    k + 1
                ))
            })?;
            outs.push(o.clone());
        }
        let mut p = compact(&self.instrs, outs, &self.symbols);
        // keep only the symbols still read
        let mut used = vec![];
        for i in &p.instrs {
            i.for_each_operand(|o| push_sym(&mut used, o));
        }
        for o in &p.outputs {
            o.entries.iter().for_each(|&e| push_sym(&mut used, e));
        }
        p.symbols.retain(|(s, _)| used.contains(s));
        Ok(p)
    }

    /// Which registers the outputs `ks` need (indexed by register number).
    pub(crate) fn live_registers(&self, ks: &[usize]) -> Vec<bool> {
        let mut live = vec![false; self.registers as usize];
        for o in ks.iter().filter_map(|&k| self.outputs.get(k)) {
            for e in &o.entries {
                mark(&mut live, *e);
            }
        }
        for i in self.instrs.iter().rev() {
            if defines(i).iter().flatten().any(|r| live[r.0 as usize]) {
                i.for_each_operand(|o| mark(&mut live, o));
            }
        }
        live
    }
}

fn push_sym(used: &mut Vec<SymbolId>, o: Operand) {
    if let Operand::Sym(s) = o
        && !used.contains(&s)
    {
        used.push(s);
    }
}

fn mark(live: &mut [bool], o: Operand) {
    if let Operand::Reg(r) = o
        && let Some(l) = live.get_mut(r.0 as usize)
    {
        *l = true;
    }
}

/// The registers an instruction defines.
pub(crate) fn defines(i: &Instr) -> [Option<Reg>; 2] {
    match *i {
        Instr::Unary { dst, .. } | Instr::Binary { dst, .. } | Instr::Powi { dst, .. } => {
            [Some(dst), None]
        }
        Instr::SinCos { sin, cos, .. } => [Some(sin), Some(cos)],
    }
}

/// Dead-code elimination and register renumbering: keeps what `outputs` need, downgrades a
/// `SinCos` with one dead half to a plain `sin` or `cos`, numbers registers in order.
fn compact(instrs: &[Instr], mut outputs: Vec<Output>, symbols: &[(SymbolId, String)]) -> Program {
    let nregs = instrs
        .iter()
        .flat_map(defines)
        .flatten()
        .map(|r| r.0 as usize + 1)
        .max()
        .unwrap_or(0);
    let mut live = vec![false; nregs];
    for o in &outputs {
        o.entries.iter().for_each(|&e| mark(&mut live, e));
    }
    for i in instrs.iter().rev() {
        if defines(i).iter().flatten().any(|r| live[r.0 as usize]) {
            i.for_each_operand(|o| mark(&mut live, o));
        }
    }
    let mut rename = vec![u32::MAX; nregs];
    let mut next = 0u32;
    let mut fresh = |r: Reg, rename: &mut Vec<u32>| {
        rename[r.0 as usize] = next;
        next += 1;
        Reg(next - 1)
    };
    let map = |o: Operand, rename: &[u32]| match o {
        Operand::Reg(r) => Operand::Reg(Reg(rename[r.0 as usize])),
        x => x,
    };
    let mut out = Vec::new();
    for i in instrs {
        let new = match *i {
            Instr::SinCos { sin, cos, arg } => {
                let arg = map(arg, &rename);
                match (live[sin.0 as usize], live[cos.0 as usize]) {
                    (true, true) => {
                        let s = fresh(sin, &mut rename);
                        Instr::SinCos {
                            sin: s,
                            cos: fresh(cos, &mut rename),
                            arg,
                        }
                    }
                    (true, false) => Instr::Unary {
                        dst: fresh(sin, &mut rename),
                        op: UnOp::Sin,
                        arg,
                    },
                    (false, true) => Instr::Unary {
                        dst: fresh(cos, &mut rename),
                        op: UnOp::Cos,
                        arg,
                    },
                    (false, false) => continue,
                }
            }
            Instr::Unary { dst, op, arg } if live[dst.0 as usize] => Instr::Unary {
                arg: map(arg, &rename),
                op,
                dst: fresh(dst, &mut rename),
            },
            Instr::Binary { dst, op, lhs, rhs } if live[dst.0 as usize] => Instr::Binary {
                lhs: map(lhs, &rename),
                rhs: map(rhs, &rename),
                op,
                dst: fresh(dst, &mut rename),
            },
            Instr::Powi { dst, base, exp } if live[dst.0 as usize] => Instr::Powi {
                base: map(base, &rename),
                exp,
                dst: fresh(dst, &mut rename),
            },
            _ => continue,
        };
        out.push(new);
    }
    for o in &mut outputs {
        for e in &mut o.entries {
            *e = map(*e, &rename);
        }
    }
    Program {
        instrs: out,
        outputs,
        registers: next,
        symbols: symbols.to_vec(),
    }
}

// ----- instruction builder with value numbering and constant folding -----

/// Hashable identity of an instruction (f64 constants by their bits).
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
enum Key {
    Un(UnOp, OpKey),
    Bin(BinOp, OpKey, OpKey),
    Powi(OpKey, i32),
    SinCos(OpKey),
}

#[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
enum OpKey {
    Const(u64),
    Sym(u32),
    Reg(u32),
}

fn key(o: Operand) -> OpKey {
    match o {
        Operand::Const(c) => OpKey::Const(c.to_bits()),
        Operand::Sym(s) => OpKey::Sym(s.0),
        Operand::Reg(r) => OpKey::Reg(r.0),
    }
}

#[derive(Default)]
struct Builder {
    instrs: Vec<Instr>,
    next: u32,
    vn: FxHashMap<Key, (Operand, Operand)>,
}

fn finite(v: f64, op: &str, args: &[f64]) -> Result<Operand> {
    if v.is_finite() {
        Ok(Operand::Const(if v == 0.0 { 0.0 } else { v }))
    } else {
        let arguments = args
            .iter()
            .map(|a| format!("{a:?}"))
            .collect::<Vec<_>>()
            .join(", ");
        Err(Error::NonFinite {
            operation: format!("constant {op}"),
            arguments: format!("({arguments})"),
        })
    }
}

impl Builder {
    fn reg(&mut self) -> Reg {
        self.next += 1;
        Reg(self.next - 1)
    }

    fn lookup(
        &mut self,
        k: Key,
        make: impl FnOnce(&mut Self) -> (Instr, Operand, Operand),
    ) -> (Operand, Operand) {
        if let Some(&r) = self.vn.get(&k) {
            return r;
        }
        let (i, a, b) = make(self);
        self.instrs.push(i);
        self.vn.insert(k, (a, b));
        (a, b)
    }

    fn un(&mut self, op: UnOp, arg: Operand) -> Result<Operand> {
        if let Operand::Const(c) = arg {
            let v = match op {
                UnOp::Neg => -c,
                UnOp::Sin => c.sin(),
                UnOp::Cos => c.cos(),
                UnOp::Tan => c.tan(),
                UnOp::Exp => c.exp(),
                UnOp::Ln => c.ln(),
                UnOp::Sqrt => c.sqrt(),
                UnOp::Abs => c.abs(),
            };
            return finite(v, &format!("{op:?}"), &[c]);
        }
        let k = Key::Un(op, key(arg));
        Ok(self
            .lookup(k, |b| {
                let dst = b.reg();
                (
                    Instr::Unary { dst, op, arg },
                    Operand::Reg(dst),
                    Operand::Reg(dst),
                )
            })
            .0)
    }

    fn bin(&mut self, op: BinOp, lhs: Operand, rhs: Operand) -> Result<Operand> {
        if let (Operand::Const(a), Operand::Const(b)) = (lhs, rhs) {
            let v = match op {
                BinOp::Add => a + b,
                BinOp::Sub => a - b,
                BinOp::Mul => a * b,
                BinOp::Div => a / b,
                BinOp::Atan2 => a.atan2(b),
                BinOp::Powf => pow_value(a, b, None),
            };
            return finite(v, &format!("{op:?}"), &[a, b]);
        }
        // Identities and sign moves that keep the emitted code free of `x * 1.0`, `x + 0.0`,
        // `x * -1.0` and `x - -c` (clippy's identity_op / neg_multiply).
        let c = |o: Operand| {
            if let Operand::Const(c) = o {
                Some(c)
            } else {
                None
            }
        };
        // A constant operand of a commutative operation goes first (`2.0 * x`).
        let (lhs, rhs) = match (op, c(rhs)) {
            (BinOp::Add | BinOp::Mul, Some(_)) => (rhs, lhs),
            _ => (lhs, rhs),
        };
        match (op, c(lhs), c(rhs)) {
            (BinOp::Add, Some(0.0), _) => return Ok(rhs),
            (BinOp::Add, Some(k), _) if k < 0.0 => {
                return self.bin(BinOp::Sub, rhs, Operand::Const(-k));
            }
            (BinOp::Sub, _, Some(0.0)) => return Ok(lhs),
            (BinOp::Sub, _, Some(k)) if k < 0.0 => {
                return self.bin(BinOp::Add, lhs, Operand::Const(-k));
            }
            (BinOp::Sub, Some(0.0), _) => return self.un(UnOp::Neg, rhs),
            (BinOp::Mul, Some(1.0), _) => return Ok(rhs),
            (BinOp::Mul, Some(0.0), _) => return Ok(Operand::Const(0.0)),
            (BinOp::Mul, Some(-1.0), _) => return self.un(UnOp::Neg, rhs),
            (BinOp::Div, _, Some(1.0)) => return Ok(lhs),
            (BinOp::Div, _, Some(k)) if k != 0.0 && (1.0 / k).is_finite() => {
                return self.bin(BinOp::Mul, Operand::Const(1.0 / k), lhs);
            }
            _ => {}
        }
        if lhs == rhs && matches!(op, BinOp::Sub) {
            return Ok(Operand::Const(0.0));
        }
        // Value numbering sees `a + b` and `b + a` as one instruction (the emitted order is
        // the first one met).
        let (ka, kb) = (key(lhs), key(rhs));
        let k = match op {
            BinOp::Add | BinOp::Mul if kb < ka => Key::Bin(op, kb, ka),
            _ => Key::Bin(op, ka, kb),
        };
        Ok(self
            .lookup(k, |b| {
                let dst = b.reg();
                (
                    Instr::Binary { dst, op, lhs, rhs },
                    Operand::Reg(dst),
                    Operand::Reg(dst),
                )
            })
            .0)
    }

    fn powi(&mut self, base: Operand, exp: i32) -> Result<Operand> {
        if let Operand::Const(c) = base {
            return finite(c.powi(exp), "powi", &[c, exp as f64]);
        }
        let k = Key::Powi(key(base), exp);
        Ok(self
            .lookup(k, |b| {
                let dst = b.reg();
                (
                    Instr::Powi { dst, base, exp },
                    Operand::Reg(dst),
                    Operand::Reg(dst),
                )
            })
            .0)
    }

    fn sin_cos(&mut self, arg: Operand) -> Result<(Operand, Operand)> {
        if let Operand::Const(c) = arg {
            return Ok((finite(c.sin(), "sin", &[c])?, finite(c.cos(), "cos", &[c])?));
        }
        Ok(self.lookup(Key::SinCos(key(arg)), |b| {
            let sin = b.reg();
            let cos = b.reg();
            (
                Instr::SinCos { sin, cos, arg },
                Operand::Reg(sin),
                Operand::Reg(cos),
            )
        }))
    }
}

// ----- lowering of arena nodes -----

/// Largest integer power written as a multiplication chain.
const MAX_CHAIN: i64 = 4;

struct Lowering<'a> {
    arena: &'a Arena,
    order: Vec<Id>,
    node_op: FxHashMap<Id, Operand>,
    /// For each argument u: (sin u needed, cos u needed).
    trig: FxHashMap<Id, (bool, bool)>,
    /// x^k by (base node, k), shared between products.
    powers: FxHashMap<(Id, i64), Operand>,
    /// coefficient-free products by factor list.
    products: FxHashMap<Box<[Id]>, Operand>,
    used_symbols: Vec<SymbolId>,
    b: Builder,
}

impl<'a> Lowering<'a> {
    fn new(arena: &'a Arena, outputs: &[&Matrix]) -> Self {
        let top = outputs
            .iter()
            .flat_map(|m| m.data.iter())
            .map(|i| i.index())
            .max();
        let mut order = Vec::new();
        let mut trig: FxHashMap<Id, (bool, bool)> = FxHashMap::default();
        if let Some(top) = top {
            let mut needed = vec![false; top + 1];
            for i in outputs.iter().flat_map(|m| m.data.iter()) {
                needed[i.index()] = true;
            }
            let nodes = &arena.nodes()[..=top];
            for k in (0..=top).rev() {
                if needed[k] {
                    for_each_child(&nodes[k], |c| needed[c.index()] = true);
                }
            }
            for (k, node) in nodes.iter().enumerate() {
                if !needed[k] {
                    continue;
                }
                order.push(Id(k as u32));
                match node {
                    Node::Func(Func::Sin, u) => trig.entry(*u).or_default().0 = true,
                    Node::Func(Func::Cos, u) => trig.entry(*u).or_default().1 = true,
                    _ => {}
                }
            }
        }
        Lowering {
            arena,
            order,
            node_op: FxHashMap::default(),
            trig,
            powers: FxHashMap::default(),
            products: FxHashMap::default(),
            used_symbols: Vec::new(),
            b: Builder::default(),
        }
    }

    fn run(&mut self) -> Result<()> {
        for k in 0..self.order.len() {
            let id = self.order[k];
            let op = self.lower_node(id)?;
            self.node_op.insert(id, op);
        }
        Ok(())
    }

    fn op(&self, id: Id) -> Operand {
        // Children are lowered before parents (id order); a miss cannot happen.
        self.node_op
            .get(&id)
            .copied()
            .unwrap_or(Operand::Const(0.0))
    }

    fn lower_node(&mut self, id: Id) -> Result<Operand> {
        let arena = self.arena;
        match arena.node(id) {
            Node::Num(n) => finite(n.to_f64(), "number", &[]),
            Node::Pi => Ok(Operand::Const(std::f64::consts::PI)),
            Node::Sym(s) => {
                if !self.used_symbols.contains(s) {
                    self.used_symbols.push(*s);
                }
                Ok(Operand::Sym(*s))
            }
            Node::Add(ts) => self.lower_sum(ts),
            Node::Mul(fs) => {
                let (c, rest) = self.split_constants(fs)?;
                let p = self.lower_product(&rest)?;
                self.b.bin(BinOp::Mul, Operand::Const(c), p)
            }
            Node::Pow(b, e) => match arena.as_number(*e) {
                Some(n) if n.is_negative() => {
                    let d = self.lower_power(*b, n.neg())?;
                    self.b.bin(BinOp::Div, Operand::Const(1.0), d)
                }
                Some(n) => self.lower_power(*b, n),
                None => {
                    let (x, y) = (self.op(*b), self.op(*e));
                    self.b.bin(BinOp::Powf, x, y)
                }
            },
            Node::Func(f, u) => self.lower_func(*f, *u),
            Node::Atan2(y, x) => {
                let (y, x) = (self.op(*y), self.op(*x));
                self.b.bin(BinOp::Atan2, y, x)
            }
        }
    }

    fn lower_func(&mut self, f: Func, u: Id) -> Result<Operand> {
        let arg = self.op(u);
        let (has_sin, has_cos) = self.trig.get(&u).copied().unwrap_or((false, false));
        let pair = has_sin && has_cos;
        match f {
            Func::Sin | Func::Cos if pair => {
                let (s, c) = self.b.sin_cos(arg)?;
                Ok(if f == Func::Sin { s } else { c })
            }
            Func::Tan if pair => {
                let (s, c) = self.b.sin_cos(arg)?;
                self.b.bin(BinOp::Div, s, c)
            }
            Func::Sin => self.b.un(UnOp::Sin, arg),
            Func::Cos => self.b.un(UnOp::Cos, arg),
            Func::Tan => self.b.un(UnOp::Tan, arg),
            Func::Exp => self.b.un(UnOp::Exp, arg),
            Func::Ln => self.b.un(UnOp::Ln, arg),
            Func::Abs => self.b.un(UnOp::Abs, arg),
        }
    }

    /// A sum, with negative terms subtracted; starts from the first positive term.
    fn lower_sum(&mut self, ts: &[Id]) -> Result<Operand> {
        let mut terms = Vec::with_capacity(ts.len());
        for &t in ts {
            terms.push(self.lower_term(t)?);
        }
        let start = terms.iter().position(|t| !t.0).unwrap_or(0);
        let Some(&(neg0, first)) = terms.get(start) else {
            return Ok(Operand::Const(0.0));
        };
        let mut acc = if neg0 {
            self.b.un(UnOp::Neg, first)?
        } else {
            first
        };
        for (k, &(neg, x)) in terms.iter().enumerate() {
            if k != start {
                acc = self
                    .b
                    .bin(if neg { BinOp::Sub } else { BinOp::Add }, acc, x)?;
            }
        }
        Ok(acc)
    }

    /// A term of a sum as (negative, magnitude): `-2*x*y` is (true, 2*(x*y)).
    fn lower_term(&mut self, t: Id) -> Result<(bool, Operand)> {
        let arena = self.arena;
        match arena.node(t) {
            Node::Num(n) => Ok((n.is_negative(), finite(n.to_f64().abs(), "number", &[])?)),
            Node::Mul(fs) => {
                let (c, rest) = self.split_constants(fs)?;
                let p = self.lower_product(&rest)?;
                Ok((c < 0.0, self.b.bin(BinOp::Mul, Operand::Const(c.abs()), p)?))
            }
            _ => Ok((false, self.op(t))),
        }
    }

    /// A coefficient-free product: numerator factors multiplied in order, factors with a
    /// negative constant exponent collected into one denominator.
    fn lower_product(&mut self, fs: &[Id]) -> Result<Operand> {
        if fs.len() == 1 && !self.is_reciprocal(fs[0]) {
            return Ok(self.op(fs[0]));
        }
        if let Some(&o) = self.products.get(fs) {
            return Ok(o);
        }
        let arena = self.arena;
        let mut num: Option<Operand> = None;
        let mut den: Option<Operand> = None;
        for &f in fs {
            let (slot, x) = match arena.node(f) {
                Node::Pow(b, e) if arena.as_number(*e).is_some_and(Number::is_negative) => {
                    let n = arena.as_number(*e).map_or(Number::int(1), Number::neg);
                    (&mut den, self.lower_power(*b, n)?)
                }
                _ => (&mut num, self.op(f)),
            };
            *slot = Some(match *slot {
                None => x,
                Some(acc) => self.b.bin(BinOp::Mul, acc, x)?,
            });
        }
        let r = match (num, den) {
            (Some(n), Some(d)) => self.b.bin(BinOp::Div, n, d)?,
            (None, Some(d)) => self.b.bin(BinOp::Div, Operand::Const(1.0), d)?,
            (Some(n), None) => n,
            (None, None) => Operand::Const(1.0),
        };
        self.products.insert(fs.into(), r);
        Ok(r)
    }

    /// Splits a product's factors into the product of its constant factors (the numeric
    /// coefficient, `pi`, constant subexpressions) and the non-constant rest.
    fn split_constants(&self, fs: &[Id]) -> Result<(f64, Vec<Id>)> {
        let mut c = 1.0;
        let mut rest = Vec::with_capacity(fs.len());
        for &f in fs {
            match self.op(f) {
                Operand::Const(k) => c *= k,
                _ => rest.push(f),
            }
        }
        finite(c, "product", &[])?;
        Ok((c, rest))
    }

    fn is_reciprocal(&self, f: Id) -> bool {
        matches!(self.arena.node(f), Node::Pow(_, e) if self.arena.as_number(*e).is_some_and(Number::is_negative))
    }

    /// base^e for a constant e > 0: multiplication chains for small integers, sqrt for
    /// halves, powi / powf otherwise.
    fn lower_power(&mut self, base: Id, e: Number) -> Result<Operand> {
        let x = self.op(base);
        match e {
            Number::Rational(k, 1) => self.int_power(base, x, k),
            Number::Rational(p, 2) if (1..=2 * MAX_CHAIN + 1).contains(&p) => {
                let s = self.b.un(UnOp::Sqrt, x)?;
                if p == 1 {
                    return Ok(s);
                }
                let rest = self.int_power(base, x, (p - 1) / 2)?;
                self.b.bin(BinOp::Mul, rest, s)
            }
            _ => {
                let y = finite(e.to_f64(), "exponent", &[])?;
                self.b.bin(BinOp::Powf, x, y)
            }
        }
    }

    fn int_power(&mut self, base: Id, x: Operand, k: i64) -> Result<Operand> {
        if k == 1 {
            return Ok(x);
        }
        if let Some(&o) = self.powers.get(&(base, k)) {
            return Ok(o);
        }
        let r = if (2..=MAX_CHAIN).contains(&k) {
            let half = self.int_power(base, x, k / 2)?;
            let sq = self.b.bin(BinOp::Mul, half, half)?;
            if k % 2 == 1 {
                self.b.bin(BinOp::Mul, sq, x)?
            } else {
                sq
            }
        } else {
            match i32::try_from(k) {
                Ok(k32) => self.b.powi(x, k32)?,
                Err(_) => self.b.bin(BinOp::Powf, x, Operand::Const(k as f64))?,
            }
        };
        self.powers.insert((base, k), r);
        Ok(r)
    }
}
