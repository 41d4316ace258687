//! Common-subexpression elimination: a straight-line SSA [`Program`] for several matrices.
//!
//! The sums are first factored (`super::factor`: sum_j w_j sin a cos b_j ... becomes
//! sin a (sum_j w_j cos b_j ...), on a copy of what the outputs reach), and that form is
//! kept when it needs fewer operations per call than the derived one. The arena is
//! hash-consed, so every distinct subexpression is one node; the
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
//! | `a*b + c` (`a*b` used once)     | `mul_add(a, b, c)` (see [`super::fuse`])    |
//!
//! Identical instructions are value-numbered (one register), so partial products such as
//! `x*y` are shared across terms and outputs. Unused registers are removed at the end.

use crate::algebra::expr::{Arena, SymbolId, SymbolKind, size_budget};
use crate::algebra::matrix::Matrix;
use crate::error::{Error, Result};
use crate::program::builder::InstructionSelection;
use crate::program::factor::factored_copy;
use crate::program::fuse::fuse_multiply_add;
use crate::program::instructions::{Instr, OpCounts, Operand, Output, Reg, UnOp, defines};
use crate::program::scale::scale_early;
use crate::program::schedule::schedule;

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
    /// The CSE'd program computing every entry of every matrix in `outputs`. Its sums are
    /// lowered either as derived or factored by their most frequent factors (module
    /// `factor`), whichever needs fewer operations per call once the parameter-only values
    /// are cached; the value is the same up to rounding.
    ///
    /// # Errors
    /// [`Error::InvalidId`] for an entry that is not a node of `arena`, [`Error::MalformedMatrix`]
    /// for a matrix whose data length is not rows x cols, [`Error::NonFinite`] for a constant
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
        arena.check_size(size_budget())?;
        let len = arena.len();
        for m in outputs {
            if m.rows.checked_mul(m.cols) != Some(m.data.len()) {
                return Err(Error::MalformedMatrix {
                    rows: m.rows,
                    cols: m.cols,
                    len: m.data.len(),
                });
            }
            if let Some(bad) = m.data.iter().find(|i| i.index() >= len) {
                return Err(Error::InvalidId { id: bad.0, len });
            }
        }
        // The factoring is greedy: where expanding a product of shared sums loses more
        // sharing than the factors save (the rotation matrices of bodies), the program as
        // derived is the leaner one. Both are lowered; the one with fewer operations per
        // call (parameter-only ones go to the cache) is kept, the derived one on a tie.
        let plain = Self::lowered(arena, outputs)?;
        let (mut local, factored) = factored_copy(arena, outputs);
        if local.take_overflow().is_some() {
            // A constant of the rewrite overflowed (exponents near f64::MAX) and folded to 0
            // there: that form is wrong, the derived one is not.
            return Ok(plain);
        }
        let factored: Vec<&Matrix> = factored.iter().collect();
        let factored = Self::lowered(&local, &factored)?;
        Ok(
            if factored.ops_per_call(arena) < plain.ops_per_call(arena) {
                factored
            } else {
                plain
            },
        )
    }

    /// The lowering of `outputs` (valid entries of `arena`) into a program.
    pub(crate) fn lowered(arena: &Arena, outputs: &[&Matrix]) -> Result<Program> {
        let mut lower = InstructionSelection::new(arena, outputs);
        lower.run()?;
        let outs: Vec<Output> = outputs
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
        // Dead instructions first, so that a product counts only its live readers.
        let live = compact(&lower.b.instrs, outs, &symbols);
        let parameter: Vec<bool> = arena
            .symbols()
            .iter()
            .map(|s| s.kind == SymbolKind::Parameter)
            .collect();
        // Twice: a scaling moved onto a product of its own (`c (a b) q` to `(c (a b)) q`)
        // moves on into that product.
        let scaled = scale_early(&live.instrs, &live.outputs, &parameter);
        let scaled = scale_early(&scaled, &live.outputs, &parameter);
        let fused = fuse_multiply_add(&scaled, &live.outputs);
        let scheduled = schedule(&fused, &live.outputs);
        Ok(compact(&scheduled, live.outputs, &symbols))
    }

    /// A program of the instructions `instrs` (in execution order, registers defined
    /// before they are read) computing `outputs`: dead instructions dropped, registers
    /// renumbered, the symbols read named from `arena`.
    pub(crate) fn from_parts(arena: &Arena, instrs: &[Instr], outputs: Vec<Output>) -> Program {
        let mut p = compact(instrs, outputs, &[]);
        let mut symbols: Vec<(SymbolId, String)> = p
            .read_symbols()
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
        p.symbols = symbols;
        p
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
    /// [`Error::NoSuchOutput`] when some index is not an output.
    pub fn restrict(&self, ks: &[usize]) -> Result<Program> {
        let mut outs = Vec::with_capacity(ks.len());
        for &k in ks {
            let o = self.outputs.get(k).ok_or_else(|| Error::NoSuchOutput {
                outputs: self.outputs.len(),
                wanted: k + 1,
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
/// `SinCos` with one dead half to a plain `sin` or `cos`, numbers registers in order.
// One function: liveness, the SinCos downgrade and the renumbering are one backward and
// one forward pass over the same instructions.
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
            Instr::MulAdd {
                dst,
                a,
                b,
                c,
                negate_product,
                negate_addend,
            } if live[dst.0 as usize] => Instr::MulAdd {
                a: map(a, &rename),
                b: map(b, &rename),
                c: map(c, &rename),
                negate_product,
                negate_addend,
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
