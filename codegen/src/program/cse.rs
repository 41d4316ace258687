//! The [`Program`] type: a straight-line SSA program computing several matrices, with
//! common subexpressions shared; and dead-code elimination with register renumbering
//! (`compact`). The passes that make a program, and their order, are in
//! `crate::compile::passes`.
//!
//! The arena is hash-consed, so every distinct subexpression is one node; instruction
//! selection (`super::builder`) gives each needed node one register (one `let`), in id
//! (topological) order, and lowers the canonical n-ary forms into lean binary operations:
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
//! | `a*b + c` (`a*b` used once)     | `mul_add(a, b, c)` (see [`super::fuse`])    |
//!
//! Identical instructions are value-numbered (one register), so partial products such as
//! `x*y` are shared across terms and outputs. Unused registers are removed at the end.

use crate::algebra::expr::{Arena, SymbolId, SymbolKind};
use crate::error::ProgramError;
use crate::error::{Error, Result};
use crate::program::instructions::{Instr, OpCounts, Operand, Output, Reg, UnOp, defines};

/// A straight-line SSA program computing several matrices at once, with common
/// subexpressions shared between all of them (module docs list the lowering rules).
#[derive(Clone, Debug, PartialEq, Hash)]
pub struct Program {
    instrs: Vec<Instr>,
    outputs: Vec<Output>,
    registers: u32,
    symbols: Vec<(SymbolId, String)>,
}

impl Program {
    /// A program of the instructions `instrs` (in execution order, registers defined
    /// before they are read) computing `outputs`: dead instructions dropped, registers
    /// renumbered, the symbols read named from `arena`.
    pub(crate) fn from_parts(arena: &Arena, instrs: &[Instr], outputs: Vec<Output>) -> Program {
        let mut p = compact(instrs, outputs, &[]);
        p.symbols = named_symbols(arena, p.read_symbols());
        p
    }

    /// This program with its first output cut to its first `rows` entries (a column:
    /// the parameter cache's first slots) and every other output dropped, dead
    /// instructions removed.
    pub(crate) fn first_rows(&self, rows: usize) -> Program {
        let entries = self
            .outputs
            .first()
            .map(|o| o.entries[..rows.min(o.entries.len())].to_vec())
            .unwrap_or_default();
        let column = Output {
            rows: entries.len(),
            cols: 1,
            entries,
        };
        let mut p = compact(&self.instrs, vec![column], &self.symbols);
        let used = p.read_symbols();
        p.symbols.retain(|(s, _)| used.contains(s));
        p
    }

    /// The instructions and the outputs, taken apart (for the next pass).
    pub(crate) fn into_parts(self) -> (Vec<Instr>, Vec<Output>) {
        (self.instrs, self.outputs)
    }

    /// The symbols the instructions and the outputs read, in order of first read.
    fn read_symbols(&self) -> Vec<SymbolId> {
        let mut used = vec![];
        for i in &self.instrs {
            i.for_each_operand(|o| push_sym(&mut used, o));
        }
        for o in &self.outputs {
            o.entries.iter().for_each(|&e| push_sym(&mut used, e));
        }
        used
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

    /// The operations that depend on more than parameters and constants: what one call
    /// costs once the parameter-only values are cached ([`crate::hoist_parameters`]).
    pub(crate) fn ops_per_call(&self, arena: &Arena) -> usize {
        let mut fixed = vec![false; self.registers as usize];
        let mut n = 0;
        for i in &self.instrs {
            let mut all = true;
            i.for_each_operand(|o| {
                all &= match o {
                    Operand::Const(_) => true,
                    Operand::Sym(s) => arena
                        .symbols()
                        .get(s.index())
                        .is_some_and(|x| x.kind == SymbolKind::Parameter),
                    Operand::Reg(r) => fixed.get(r.index()).copied().unwrap_or(false),
                }
            });
            for r in defines(i).into_iter().flatten() {
                if let Some(f) = fixed.get_mut(r.index()) {
                    *f = all;
                }
            }
            if !all {
                n += i.op_counts().total();
            }
        }
        n
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
    /// [`crate::error::ProgramError::NoSuchOutput`] when some index is not an output.
    pub fn restrict(&self, ks: &[usize]) -> Result<Program> {
        let mut outs = Vec::with_capacity(ks.len());
        for &k in ks {
            let o = self.outputs.get(k).ok_or_else(|| {
                Error::Program(ProgramError::NoSuchOutput {
                    outputs: self.outputs.len(),
                    wanted: k + 1,
                })
            })?;
            outs.push(o.clone());
        }
        let mut p = compact(&self.instrs, outs, &self.symbols);
        // keep only the symbols still read
        let used = p.read_symbols();
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

/// The symbols `used`, sorted by id, with their names in `arena` (`#k` for an id past its
/// symbols).
pub(crate) fn named_symbols(arena: &Arena, used: Vec<SymbolId>) -> Vec<(SymbolId, String)> {
    let mut symbols: Vec<(SymbolId, String)> = used
        .into_iter()
        .map(|s| {
            let name = arena
                .symbols()
                .get(s.0 as usize)
                .map_or_else(|| format!("#{}", s.0), |x| x.name.clone());
            (s, name)
        })
        .collect();
    symbols.sort_by_key(|p| p.0);
    symbols
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

/// Dead-code elimination and register renumbering: keeps what `outputs` need, downgrades a
/// `SinCos` with one dead half to a plain `sin` or `cos`, numbers registers in order (one
/// backward pass for liveness, one forward pass for the rest).
pub(crate) fn compact(
    instrs: &[Instr],
    mut outputs: Vec<Output>,
    symbols: &[(SymbolId, String)],
) -> Program {
    let live = live_registers(instrs, &outputs);
    let mut ren = Renumbering {
        rename: vec![u32::MAX; live.len()],
        next: 0,
    };
    let out: Vec<Instr> = instrs
        .iter()
        .filter_map(|i| ren.live_instr(i, &live))
        .collect();
    for o in &mut outputs {
        for e in &mut o.entries {
            *e = ren.map(*e);
        }
    }
    Program {
        instrs: out,
        outputs,
        registers: ren.next,
        symbols: symbols.to_vec(),
    }
}

/// Which registers the outputs need, directly or through the instructions that define
/// what they read (a backward pass).
fn live_registers(instrs: &[Instr], outputs: &[Output]) -> Vec<bool> {
    let nregs = instrs
        .iter()
        .flat_map(defines)
        .flatten()
        .map(|r| r.0 as usize + 1)
        .max()
        .unwrap_or(0);
    let mut live = vec![false; nregs];
    for o in outputs {
        o.entries.iter().for_each(|&e| mark(&mut live, e));
    }
    for i in instrs.iter().rev() {
        if defines(i).iter().flatten().any(|r| live[r.0 as usize]) {
            i.for_each_operand(|o| mark(&mut live, o));
        }
    }
    live
}

/// Registers renumbered in order of definition.
struct Renumbering {
    /// The new number of each old register (`u32::MAX`: not defined yet).
    rename: Vec<u32>,
    /// The next new number.
    next: u32,
}

impl Renumbering {
    /// A new number for the old register `r`.
    fn fresh(&mut self, r: Reg) -> Reg {
        self.rename[r.0 as usize] = self.next;
        self.next += 1;
        Reg(self.next - 1)
    }

    /// `o` with its register renumbered.
    fn map(&self, o: Operand) -> Operand {
        match o {
            Operand::Reg(r) => Operand::Reg(Reg(self.rename[r.0 as usize])),
            x => x,
        }
    }

    /// `i` renumbered when it defines a live register (a `SinCos` with one dead half
    /// becomes a plain `sin` or `cos`); `None` when all it defines is dead.
    fn live_instr(&mut self, i: &Instr, live: &[bool]) -> Option<Instr> {
        let is_live = |r: Reg| live[r.0 as usize];
        Some(match *i {
            Instr::SinCos { sin, cos, arg } => {
                let arg = self.map(arg);
                match (is_live(sin), is_live(cos)) {
                    (true, true) => {
                        let sin = self.fresh(sin);
                        let cos = self.fresh(cos);
                        Instr::SinCos { sin, cos, arg }
                    }
                    (true, false) => Instr::Unary {
                        dst: self.fresh(sin),
                        op: UnOp::Sin,
                        arg,
                    },
                    (false, true) => Instr::Unary {
                        dst: self.fresh(cos),
                        op: UnOp::Cos,
                        arg,
                    },
                    (false, false) => return None,
                }
            }
            Instr::Unary { dst, op, arg } if is_live(dst) => Instr::Unary {
                arg: self.map(arg),
                op,
                dst: self.fresh(dst),
            },
            Instr::Binary { dst, op, lhs, rhs } if is_live(dst) => Instr::Binary {
                lhs: self.map(lhs),
                rhs: self.map(rhs),
                op,
                dst: self.fresh(dst),
            },
            Instr::Powi { dst, base, exp } if is_live(dst) => Instr::Powi {
                base: self.map(base),
                exp,
                dst: self.fresh(dst),
            },
            Instr::MulAdd {
                dst,
                a,
                b,
                c,
                negate_product,
                negate_addend,
            } if is_live(dst) => Instr::MulAdd {
                a: self.map(a),
                b: self.map(b),
                c: self.map(c),
                negate_product,
                negate_addend,
                dst: self.fresh(dst),
            },
            _ => return None,
        })
    }
}
