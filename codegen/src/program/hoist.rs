//! Values that depend on parameters only, computed once per parameter set instead of on
//! every evaluation.
//!
//! An instruction of a [`Program`] whose operands are constants, parameter symbols or
//! such values itself (`l1*l1`, `m2*g`, `sin(alpha)`, `J1 + 0.5*m2*l1^2`) gives the same
//! value at every (t, q, q'). [`hoist_parameters`] moves these instructions of several
//! programs into one cache program over the parameters (shared values computed once, a
//! `sin` or `cos` of a parameter always as the pair), and rewrites each program to read
//! the cached values that it still needs as new input symbols, one per cache entry. A
//! program then executes exactly the instructions that depend on t, q or q'; the values are
//! the same to the bit, since every instruction computes what it computed before.

use crate::algebra::expr::{Arena, FxHashMap, SymbolId, SymbolKind};
use crate::error::Result;
use crate::program::builder::Builder;
use crate::program::cse::Program;
use crate::program::instructions::{Instr, Operand, Output, Reg, UnOp};

/// The result of [`hoist_parameters`].
#[derive(Clone, Debug, PartialEq)]
pub struct Hoisted {
    /// Computes the cache from the parameter symbols: one output, a column whose entry k is
    /// the value that `slots[k]` stands for.
    pub cache: Program,
    /// The input symbol that stands for cache entry k in the rewritten programs.
    pub slots: Vec<SymbolId>,
    /// The programs, in the order given, reading the cache entries instead of computing
    /// their parameter-only values.
    pub programs: Vec<Program>,
}

/// Moves the instructions of `programs` that depend on parameters only (symbols of kind
/// [`SymbolKind::Parameter`]) into one cache program; see the module docs. The symbols of
/// the cache entries are named `cache[k]` in `arena` (not an identifier, so they cannot
/// collide with a declared name); a later call reuses the same symbols for its own entries.
///
/// # Errors
/// [`crate::error::EvalError::NonFinite`] if folding a constant fails (it cannot for the
/// instructions of a [`Program`], whose constant subexpressions are already folded).
///
/// # Example
/// ```
/// use mechanism_codegen::{hoist_parameters, Arena, Matrix, Program, SymbolKind};
///
/// // l sin(alpha) q: the product l sin(alpha) is cached, one multiplication is left.
/// let mut a = Arena::new();
/// let [q, ..] = a.coordinate("q");
/// let l = a.symbol("l", SymbolKind::Parameter);
/// let alpha = a.symbol("alpha", SymbolKind::Parameter);
/// let s = a.sin(alpha);
/// let e = a.mul(&[l, s, q]);
/// let program = Program::new(&a, &[&Matrix::column(vec![e])]).unwrap();
/// let h = hoist_parameters(&mut a, &[&program]).unwrap();
/// assert_eq!(h.slots.len(), 1);
/// assert_eq!(h.programs[0].op_counts().total(), 1);
/// assert_eq!(h.cache.op_counts().total(), 2); // sin(alpha), then l * sin(alpha)
/// ```
pub fn hoist_parameters(arena: &mut Arena, programs: &[&Program]) -> Result<Hoisted> {
    let mut h = Hoister {
        parameters: (0..arena.symbols().len())
            .map(|s| arena.symbols()[s].kind == SymbolKind::Parameter)
            .collect(),
        cache: Builder::default(),
        slot_of: FxHashMap::default(),
        entries: Vec::new(),
    };
    let mut rewritten = Vec::with_capacity(programs.len());
    for p in programs {
        rewritten.push(h.rewrite(p)?);
    }
    let slots: Vec<SymbolId> = (0..h.entries.len())
        .map(|k| arena.symbol_id(&format!("cache[{k}]"), SymbolKind::Free))
        .collect();
    let programs = rewritten
        .into_iter()
        .map(|(instrs, outputs)| {
            let resolve = |o: Operand| match o {
                Operand::Sym(s) if s.0 >= SLOT_BASE => {
                    Operand::Sym(slots[(s.0 - SLOT_BASE) as usize])
                }
                x => x,
            };
            let instrs: Vec<Instr> = instrs
                .into_iter()
                .map(|i| map_operands(i, resolve))
                .collect();
            let outputs = outputs
                .into_iter()
                .map(|mut o| {
                    o.entries.iter_mut().for_each(|e| *e = resolve(*e));
                    o
                })
                .collect();
            Program::from_parts(arena, &instrs, outputs)
        })
        .collect();
    let column = Output {
        rows: h.entries.len(),
        cols: 1,
        entries: h.entries,
    };
    Ok(Hoisted {
        cache: Program::from_parts(arena, &h.cache.instrs, vec![column]),
        slots,
        programs,
    })
}

/// Cache entries are first named by placeholder symbols numbered from here (far above any
/// arena symbol), then by the `cache[k]` symbols once their number is known.
const SLOT_BASE: u32 = u32::MAX / 2;

struct Hoister {
    /// Whether symbol s is a parameter.
    parameters: Vec<bool>,
    /// The cache program being built (value numbering shares values between programs).
    cache: Builder,
    /// Cache entry index of a cache-program register.
    slot_of: FxHashMap<u32, u32>,
    /// The cache-program operand of each entry.
    entries: Vec<Operand>,
}

impl Hoister {
    /// The instructions and outputs of `p` with its parameter-only values replaced by
    /// placeholder symbols of cache entries.
    fn rewrite(&mut self, p: &Program) -> Result<(Vec<Instr>, Vec<Output>)> {
        // The cache-program operand of each hoisted register of `p`.
        let mut hoisted: Vec<Option<Operand>> = vec![None; p.registers()];
        let mut kept = Vec::new();
        for i in p.instructions() {
            let mut movable = true;
            i.for_each_operand(|o| {
                movable &= match o {
                    Operand::Const(_) => true,
                    Operand::Sym(s) => self.parameters.get(s.0 as usize).copied().unwrap_or(false),
                    Operand::Reg(r) => hoisted[r.index()].is_some(),
                }
            });
            if movable {
                let arg = |o: Operand| match o {
                    Operand::Reg(r) => hoisted[r.index()].unwrap_or(o),
                    x => x,
                };
                match *i {
                    Instr::Unary { dst, op, arg: a } => {
                        let v = match op {
                            UnOp::Sin => self.cache.sin_cos(arg(a))?.0,
                            UnOp::Cos => self.cache.sin_cos(arg(a))?.1,
                            _ => self.cache.un(op, arg(a))?,
                        };
                        hoisted[dst.index()] = Some(v);
                    }
                    Instr::Binary { dst, op, lhs, rhs } => {
                        hoisted[dst.index()] = Some(self.cache.bin(op, arg(lhs), arg(rhs))?);
                    }
                    Instr::Powi { dst, base, exp } => {
                        hoisted[dst.index()] = Some(self.cache.powi(arg(base), exp)?);
                    }
                    Instr::SinCos { sin, cos, arg: a } => {
                        let (s, c) = self.cache.sin_cos(arg(a))?;
                        hoisted[sin.index()] = Some(s);
                        hoisted[cos.index()] = Some(c);
                    }
                    Instr::MulAdd {
                        dst,
                        a,
                        b,
                        c,
                        negate_product,
                        negate_addend,
                    } => {
                        let abc = [arg(a), arg(b), arg(c)];
                        let v = self.cache.mul_add(abc, negate_product, negate_addend)?;
                        hoisted[dst.index()] = Some(v);
                    }
                }
                continue;
            }
            let mut i = *i;
            i = map_operands(i, |o| self.read(o, &hoisted));
            kept.push(i);
        }
        let outputs = p
            .outputs()
            .iter()
            .map(|o| Output {
                rows: o.rows,
                cols: o.cols,
                entries: o.entries.iter().map(|&e| self.read(e, &hoisted)).collect(),
            })
            .collect();
        Ok((kept, outputs))
    }

    /// How a kept instruction or an output reads operand `o`: a hoisted register becomes
    /// the placeholder of its cache entry (a new entry on first use), unless its value
    /// folded to a constant or is a parameter itself.
    fn read(&mut self, o: Operand, hoisted: &[Option<Operand>]) -> Operand {
        let Operand::Reg(r) = o else { return o };
        let Some(v) = hoisted[r.index()] else {
            return o;
        };
        let key = match v {
            Operand::Reg(Reg(k)) => k,
            Operand::Sym(s) => return Operand::Sym(s),
            Operand::Const(_) => return v,
        };
        let next = self.entries.len() as u32;
        let k = *self.slot_of.entry(key).or_insert(next);
        if k == next {
            self.entries.push(v);
        }
        Operand::Sym(SymbolId(SLOT_BASE + k))
    }
}

/// `i` with `f` applied to each operand.
fn map_operands(i: Instr, mut f: impl FnMut(Operand) -> Operand) -> Instr {
    match i {
        Instr::Unary { dst, op, arg } => Instr::Unary {
            dst,
            op,
            arg: f(arg),
        },
        Instr::Binary { dst, op, lhs, rhs } => Instr::Binary {
            dst,
            op,
            lhs: f(lhs),
            rhs: f(rhs),
        },
        Instr::Powi { dst, base, exp } => Instr::Powi {
            dst,
            base: f(base),
            exp,
        },
        Instr::SinCos { sin, cos, arg } => Instr::SinCos {
            sin,
            cos,
            arg: f(arg),
        },
        Instr::MulAdd {
            dst,
            a,
            b,
            c,
            negate_product,
            negate_addend,
        } => Instr::MulAdd {
            dst,
            a: f(a),
            b: f(b),
            c: f(c),
            negate_product,
            negate_addend,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebra::matrix::Matrix;
    use crate::program::tape::Tape;

    /// Two programs sharing parameter-only values: each value is cached once, and the
    /// rewritten programs fed with the cache give the original programs' values to the bit.
    #[test]
    fn hoisted_programs_give_the_same_bits() {
        let mut a = Arena::new();
        let [q, qd, _] = a.coordinate("q");
        let l = a.symbol("l", SymbolKind::Parameter);
        let m = a.symbol("m", SymbolKind::Parameter);
        let alpha = a.symbol("alpha", SymbolKind::Parameter);
        let (sa, ca) = (a.sin(alpha), a.cos(alpha));
        let sq = a.sin(q);
        let ml = a.mul(&[m, l, l]);
        let e1 = a.mul(&[ml, sa, sq]);
        let e2 = a.add(&[ml, ca]);
        let e3 = a.mul(&[e2, qd, qd]);
        let first = Program::new(&a, &[&Matrix::column(vec![e1, e2])]).unwrap();
        let second = Program::new(&a, &[&Matrix::column(vec![e3, l])]).unwrap();
        let h = hoist_parameters(&mut a, &[&first, &second]).unwrap();
        // sin(alpha) and cos(alpha) are one pair; m l^2 is computed once.
        assert_eq!(
            h.cache
                .instructions()
                .iter()
                .filter(|i| matches!(i, Instr::SinCos { .. }))
                .count(),
            1
        );
        // Inputs indexed by SymbolId: q, q', q'', l, m, alpha, then the cache entries.
        let mut inputs = vec![0.0; a.symbols().len()];
        let id = |name: &str| a.lookup(name).unwrap().0 as usize;
        inputs[id("q")] = 0.7;
        inputs[id("der(q)")] = -1.3;
        inputs[id("l")] = 0.3;
        inputs[id("m")] = 2.5;
        inputs[id("alpha")] = 0.2;
        let mut cache = vec![0.0; h.slots.len()];
        Tape::new(&h.cache).eval(&inputs, &mut cache).unwrap();
        for (s, v) in h.slots.iter().zip(&cache) {
            inputs[s.0 as usize] = *v;
        }
        for (original, hoisted) in [&first, &second].into_iter().zip(&h.programs) {
            let mut want = vec![0.0; 2];
            let mut got = vec![0.0; 2];
            Tape::new(original).eval(&inputs, &mut want).unwrap();
            Tape::new(hoisted).eval(&inputs, &mut got).unwrap();
            assert_eq!(want, got);
            assert!(hoisted.op_counts().total() < original.op_counts().total());
        }
        // The second program's output `l` stays a plain read of the parameter.
        assert_eq!(
            h.programs[1].outputs()[0].entries[1],
            Operand::Sym(SymbolId(id("l") as u32))
        );
    }
}
