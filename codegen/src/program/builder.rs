//! Lowering of arena nodes into [`Program`](crate::Program) instructions: the rules listed
//! in the `cse` module docs, on top of an instruction builder with value numbering (one
//! register per distinct instruction) and constant folding.

use crate::algebra::expr::{Arena, Func, FxHashMap, FxHasher, Id, Node, SymbolId, SymbolKind};
use crate::algebra::matrix::Matrix;
use crate::algebra::probe_table::ProbeTable;
use crate::error::EvalError;
use crate::error::{Error, Result};
use crate::number::Number;
use crate::program::instructions::{BinOp, Instr, Operand, Reg, UnOp};
use std::hash::{Hash, Hasher};

// ----- instruction builder with value numbering and constant folding -----

/// A value-numbering key: the operation and its operands' keys (constants by their bits).
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
enum Key {
    Un(UnOp, OpKey),
    Bin(BinOp, OpKey, OpKey),
    Powi(OpKey, i32),
    SinCos(OpKey),
    MulAdd(OpKey, OpKey, OpKey, bool, bool),
}

/// An operand as 64 bits: a constant is its own bits (finite, so never a NaN); a symbol or
/// register is a NaN whose payload holds its index, so the three kinds never meet. Eight
/// bytes instead of an enum's sixteen: the value-numbering table of a large mechanism holds
/// millions of keys.
#[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
struct OpKey(u64);

/// The NaN patterns that tag a symbol's and a register's key.
const SYM_KEY: u64 = 0x7ff1 << 48;
const REG_KEY: u64 = 0x7ff2 << 48;

fn key(o: Operand) -> OpKey {
    OpKey(match o {
        Operand::Const(c) => {
            // Constants are folded through `finite` or come from the arena's numbers, never
            // NaN: a NaN's bits could be a symbol's or a register's key.
            debug_assert!(!c.is_nan(), "a NaN constant operand");
            c.to_bits()
        }
        Operand::Sym(s) => SYM_KEY | u64::from(s.0),
        Operand::Reg(r) => REG_KEY | u64::from(r.0),
    })
}

/// The key of `lhs op rhs`: value numbering sees `a + b` and `b + a` as one instruction.
fn binary_key(op: BinOp, lhs: Operand, rhs: Operand) -> Key {
    let (ka, kb) = (key(lhs), key(rhs));
    match op {
        BinOp::Add | BinOp::Mul if kb < ka => Key::Bin(op, kb, ka),
        _ => Key::Bin(op, ka, kb),
    }
}

/// The key an instruction the builder made was looked up by.
fn key_of(i: &Instr) -> Key {
    match *i {
        Instr::Unary { op, arg, .. } => Key::Un(op, key(arg)),
        Instr::Binary { op, lhs, rhs, .. } => binary_key(op, lhs, rhs),
        Instr::Powi { base, exp, .. } => Key::Powi(key(base), exp),
        Instr::SinCos { arg, .. } => Key::SinCos(key(arg)),
        Instr::MulAdd {
            a,
            b,
            c,
            negate_product,
            negate_addend,
            ..
        } => Key::MulAdd(key(a), key(b), key(c), negate_product, negate_addend),
    }
}

/// The registers an instruction writes: (dst, dst), or (sin, cos) for `sin_cos`.
fn written(i: &Instr) -> (Reg, Reg) {
    match *i {
        Instr::Unary { dst, .. }
        | Instr::Binary { dst, .. }
        | Instr::Powi { dst, .. }
        | Instr::MulAdd { dst, .. } => (dst, dst),
        Instr::SinCos { sin, cos, .. } => (sin, cos),
    }
}

#[derive(Default)]
pub(crate) struct Builder {
    pub(crate) instrs: Vec<Instr>,
    next: u32,
    /// Value numbering: the position in `instrs` of each distinct instruction, by the hash
    /// of its key (the key is read back off the instruction, so an entry is 8 bytes).
    vn: ProbeTable,
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
        Err(Error::Eval(EvalError::NonFinite {
            operation: format!("constant {op}"),
            arguments: format!("({arguments})"),
        }))
    }
}

impl Builder {
    fn reg(&mut self) -> Reg {
        self.next += 1;
        Reg(self.next - 1)
    }

    /// The registers instruction `k` writes (see [`written`]), the instruction made when it
    /// is new (`make` is handed its first register).
    fn lookup(&mut self, k: Key, make: impl FnOnce(&mut Self, Reg) -> Instr) -> (Reg, Reg) {
        let mut h = FxHasher::default();
        k.hash(&mut h);
        let hash = h.finish();
        let instrs = &self.instrs;
        let at = instrs.len() as u32;
        if let Some(found) = self
            .vn
            .find_or_insert((hash ^ (hash >> 32)) as u32, at, |i| {
                key_of(&instrs[i as usize]) == k
            })
        {
            return written(&self.instrs[found as usize]);
        }
        let dst = self.reg();
        let i = make(self, dst);
        let regs = written(&i);
        self.instrs.push(i);
        regs
    }

    pub(crate) fn un(&mut self, op: UnOp, arg: Operand) -> Result<Operand> {
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
            .lookup(k, |_, dst| Instr::Unary { dst, op, arg })
            .0
            .into())
    }

    pub(crate) fn bin(&mut self, op: BinOp, lhs: Operand, rhs: Operand) -> Result<Operand> {
        if let (Operand::Const(a), Operand::Const(b)) = (lhs, rhs) {
            let v = match op {
                BinOp::Add => a + b,
                BinOp::Sub => a - b,
                BinOp::Mul => a * b,
                BinOp::Div => a / b,
                BinOp::Atan2 => a.atan2(b),
                BinOp::Powf => a.powf(b),
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
        let k = binary_key(op, lhs, rhs);
        Ok(self
            .lookup(k, |_, dst| Instr::Binary { dst, op, lhs, rhs })
            .0
            .into())
    }

    pub(crate) fn powi(&mut self, base: Operand, exp: i32) -> Result<Operand> {
        if let Operand::Const(c) = base {
            return finite(c.powi(exp), "powi", &[c, exp as f64]);
        }
        let k = Key::Powi(key(base), exp);
        Ok(self
            .lookup(k, |_, dst| Instr::Powi { dst, base, exp })
            .0
            .into())
    }

    /// (+-a) b + (+-c), one fused instruction (see [`crate::program::fuse`]).
    pub(crate) fn mul_add(
        &mut self,
        [a, b, c]: [Operand; 3],
        negate_product: bool,
        negate_addend: bool,
    ) -> Result<Operand> {
        if let (Operand::Const(x), Operand::Const(y), Operand::Const(z)) = (a, b, c) {
            let x = if negate_product { -x } else { x };
            let z = if negate_addend { -z } else { z };
            return finite(mechanism_math::mul_add(x, y, z), "mul_add", &[x, y, z]);
        }
        let k = Key::MulAdd(key(a), key(b), key(c), negate_product, negate_addend);
        Ok(self
            .lookup(k, |_, dst| Instr::MulAdd {
                dst,
                a,
                b,
                c,
                negate_product,
                negate_addend,
            })
            .0
            .into())
    }

    pub(crate) fn sin_cos(&mut self, arg: Operand) -> Result<(Operand, Operand)> {
        if let Operand::Const(c) = arg {
            return Ok((finite(c.sin(), "sin", &[c])?, finite(c.cos(), "cos", &[c])?));
        }
        let (sin, cos) = self.lookup(Key::SinCos(key(arg)), |b, sin| Instr::SinCos {
            sin,
            cos: b.reg(),
            arg,
        });
        Ok((sin.into(), cos.into()))
    }
}

// ----- lowering of arena nodes -----

/// Largest integer power written as a multiplication chain.
const MAX_CHAIN: i64 = 4;

pub(crate) struct InstructionSelection<'a> {
    arena: &'a Arena,
    order: Vec<Id>,
    /// Each lowered node's operand, by id (a dense table: on a large mechanism most nodes up
    /// to the largest output are lowered, and a hash map of them costs more memory and a
    /// cache miss per look-up).
    node_op: Vec<Operand>,
    /// For each argument u: (sin u needed, cos u needed).
    trig: FxHashMap<Id, (bool, bool)>,
    /// x^k by (base node, k), shared between products.
    powers: FxHashMap<(Id, i64), Operand>,
    /// coefficient-free products by factor list.
    products: FxHashMap<Box<[Id]>, Operand>,
    /// Whether node k (up to the largest output node) depends on parameters and constants
    /// only: sums and products take those terms and factors first, so that their partial
    /// results are parameter-only values too (what [`crate::hoist_parameters`] moves out).
    invariant: Vec<bool>,
    pub(crate) used_symbols: Vec<SymbolId>,
    pub(crate) b: Builder,
}

impl<'a> InstructionSelection<'a> {
    pub(crate) fn new(arena: &'a Arena, outputs: &[&Matrix]) -> Self {
        let top = outputs
            .iter()
            .flat_map(|m| m.data.iter())
            .map(|i| i.index())
            .max();
        let mut order = Vec::new();
        let mut trig: FxHashMap<Id, (bool, bool)> = FxHashMap::default();
        let mut invariant = Vec::new();
        if let Some(top) = top {
            let mut needed = vec![false; top + 1];
            for i in outputs.iter().flat_map(|m| m.data.iter()) {
                needed[i.index()] = true;
            }
            let nodes = &arena.nodes()[..=top];
            for k in (0..=top).rev() {
                if needed[k] {
                    nodes[k].for_each_child(|c| needed[c.index()] = true);
                }
            }
            invariant = vec![false; top + 1];
            for (k, node) in nodes.iter().enumerate() {
                if !needed[k] {
                    continue;
                }
                invariant[k] = match node {
                    Node::Sym(s) => arena.symbol_info(*s).kind == SymbolKind::Parameter,
                    _ => {
                        let mut all = true;
                        node.for_each_child(|c| all &= invariant[c.index()]);
                        all
                    }
                };
                order.push(Id(k as u32));
                match node {
                    Node::Func(Func::Sin, u) => trig.entry(*u).or_default().0 = true,
                    Node::Func(Func::Cos, u) => trig.entry(*u).or_default().1 = true,
                    _ => {}
                }
            }
        }
        let lowered = top.map_or(0, |top| top + 1);
        // About one instruction per node lowered: the builder's tables sized once rather
        // than grown by doubling (each growth copies them and faults in fresh pages).
        let mut b = Builder::default();
        b.instrs.reserve(order.len());
        b.vn = ProbeTable::with_capacity(order.len());
        InstructionSelection {
            arena,
            order,
            node_op: vec![Operand::Const(0.0); lowered],
            trig,
            powers: FxHashMap::default(),
            products: FxHashMap::default(),
            invariant,
            used_symbols: Vec::new(),
            b,
        }
    }

    pub(crate) fn run(&mut self) -> Result<()> {
        for k in 0..self.order.len() {
            let id = self.order[k];
            let op = self.lower_node(id)?;
            self.node_op[id.index()] = op;
        }
        Ok(())
    }

    pub(crate) fn op(&self, id: Id) -> Operand {
        // Children are lowered before parents (id order); a miss cannot happen.
        self.node_op
            .get(id.index())
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
                    let d = self.lower_power(*b, -n)?;
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
            Node::Named(x) => Ok(self.op(*x)),
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

    /// Whether `id` depends on parameters and constants only.
    fn is_invariant(&self, id: Id) -> bool {
        self.invariant.get(id.index()).copied().unwrap_or(false)
    }

    /// `ids` with the parameter-only ones first, each group in its given order.
    fn invariant_first(&self, ids: &[Id]) -> Vec<Id> {
        let mut v = ids.to_vec();
        v.sort_by_key(|&i| !self.is_invariant(i));
        v
    }

    /// A sum, with negative terms subtracted; starts from the first positive term.
    fn lower_sum(&mut self, ts: &[Id]) -> Result<Operand> {
        let mut terms = Vec::with_capacity(ts.len());
        for t in self.invariant_first(ts) {
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
        for f in self.invariant_first(fs) {
            let (slot, x) = match arena.node(f) {
                Node::Pow(b, e) if arena.as_number(*e).is_some_and(Number::is_negative) => {
                    let n = arena.as_number(*e).map_or(Number::int(1), |n| -n);
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Value numbering: `x + y` and `y + x` are one instruction, `x - y` and `y - x` two;
    /// a symbol, a register and a constant whose bits equal the same index are three
    /// different operands; `sin_cos` found again gives the pair it made.
    #[test]
    fn value_numbering_merges_exactly_the_same_instructions() {
        let mut b = Builder::default();
        let (x, y) = (Operand::Sym(SymbolId(1)), Operand::Sym(SymbolId(2)));
        let xy = b.bin(BinOp::Add, x, y).unwrap();
        assert_eq!(b.bin(BinOp::Add, y, x).unwrap(), xy);
        let d1 = b.bin(BinOp::Sub, x, y).unwrap();
        let d2 = b.bin(BinOp::Sub, y, x).unwrap();
        assert_ne!(d1, d2);
        assert_eq!(b.instrs.len(), 3);
        // z + Sym(1), z + Reg(1) and z + (the constant whose bits are 1, the smallest
        // subnormal): three instructions.
        let z = Operand::Sym(SymbolId(5));
        let before = b.instrs.len();
        let with_sym = b.bin(BinOp::Add, z, Operand::Sym(SymbolId(1))).unwrap();
        let with_reg = b.bin(BinOp::Add, z, Operand::Reg(Reg(1))).unwrap();
        let with_const = b
            .bin(BinOp::Add, z, Operand::Const(f64::from_bits(1)))
            .unwrap();
        assert_ne!(with_sym, with_reg);
        assert_ne!(with_sym, with_const);
        assert_ne!(with_reg, with_const);
        assert_eq!(b.instrs.len(), before + 3);
        let before = b.instrs.len();
        let pair = b.sin_cos(y).unwrap();
        let _ = b.un(UnOp::Neg, x).unwrap();
        assert_eq!(b.sin_cos(y).unwrap(), pair);
        assert_ne!(pair.0, pair.1);
        assert_eq!(b.instrs.len(), before + 2);
    }
}
