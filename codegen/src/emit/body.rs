//! Rust emission: a [`Program`] as the statements of a function body in SSA form.
//!
//! Each instruction becomes one `let x12: f64 = x3 * x7;` (a fused product and sum
//! `let x13: f64 = ::mechanism::math::mul_add(x3, x7, x9);`, a `sin_cos` pair becomes
//! `let (x4, x5): (f64, f64) = q[1].sin_cos();`). With a math module set by
//! [`EmitBindings::set_math`], every real function is a call into it instead of an f64
//! method: `::mechanism::math::sin_cos(q[1])` (lone sines and cosines as `.0` and `.1`),
//! `::mechanism::math::sqrt(x3)`, `::mechanism::math::powi(x3, 2)`; that is what makes the
//! code build without std, where the f64 methods do not exist. In a body with many angles
//! (see [`super::lanes`]) up to four sines and cosines whose arguments are at hand together
//! become one `let ([x4, x8, ..], [x5, x9, ..]) = ::mechanism::math::sin_cos_lanes([q[1],
//! q[2], ..]);`. Symbols are read through caller-supplied
//! tokens ([`EmitBindings`]: `self.l1`, `q[2]`, `qd[2]`, `t`), and each output matrix is
//! written into a caller-named nalgebra matrix (`out_mass[(i, j)] = x12;`), a vector
//! (`out_g[i] = x9;`) or returned as the body's tail expression ([`OutputTarget`]). A
//! written value is stored right after the instruction that computes it, so that it does not
//! stay live to the end of the body.
//!
//! The code has no allocation, no indexing beyond the caller's static sizes, no panics, and
//! is written to be clean under `clippy -D warnings` without any `#[allow]`:
//! - every `let` is used (dead instructions are removed per body), so no unused variables;
//! - no `x * 1.0`, `x + 0.0`, `x * -1.0`, `x - -c` (the builder folds them away);
//! - constants are literals with full round-trip precision (`0.5_f64`), and values equal to
//!   a `core::f64::consts` constant are written as that path (`::core::f64::consts::PI`), so
//!   `clippy::approx_constant` never fires;
//! - a returned value is never `let x = ..; x` (`clippy::let_and_return`): the last
//!   instruction is inlined into the tail;
//! - binding tokens must be postfix expressions (paths, fields, indexing), so that they can
//!   be a method receiver (`q[2].sin()`) without parentheses.

use crate::error::{EvalError, ProgramError};
use std::str::FromStr;

use proc_macro2::{Delimiter, Group, Ident, Literal, Punct, Spacing, Span, TokenStream};
use quote::{ToTokens, TokenStreamExt, quote};

use crate::algebra::expr::{FxHashMap, SymbolId};
use crate::compile::structural_zero;
use crate::emit::lanes;
use crate::error::{Error, Result};
use crate::program::cse::Program;
use crate::program::instructions::{BinOp, Instr, OpCounts, Operand, Reg, UnOp, defines};
use crate::program::liveness;

pub use super::bindings::EmitBindings;
pub use super::target::OutputTarget;

/// How a written output entry is indexed.
#[derive(Clone, Copy)]
enum Layout {
    Matrix,
    Vector,
    ColumnMajor,
}

/// An emitted body with its operation counts.
#[derive(Clone, Debug)]
pub struct EmittedBody {
    /// The statements (and the tail expression, with [`OutputTarget::Return`]).
    pub tokens: TokenStream,
    /// Operations the body executes.
    pub counts: OpCounts,
    /// Number of `let` registers.
    pub registers: usize,
    /// The symbols the body reads (sorted by id): a caller can silence unused parameters
    /// (`let _ = qd;`) for the others.
    pub symbols: Vec<SymbolId>,
}

/// Emits the statements computing the outputs of `program` whose target is not
/// [`OutputTarget::Skip`] (one target per output, in order).
///
/// # Errors
/// [`crate::error::ProgramError::OutputCount`] when the number of targets differs from the
/// number of outputs, [`crate::error::ProgramError::ReturnNotScalar`] or
/// [`crate::error::ProgramError::SeveralReturns`] when a `Return` output is not 1 x 1 or there
/// are two, [`crate::error::ProgramError::MatrixAsVector`] when a `Vector` output has several
/// rows and columns, [`crate::error::ProgramError::RegisterPrefix`] when the prefix is not an
/// identifier; [`crate::error::EvalError::MissingValue`] when a symbol the body reads has no
/// binding.
///
/// # Example
/// ```
/// use mechanism_codegen::{emit_body, Arena, EmitBindings, Matrix, OutputTarget, Program, SymbolKind};
/// use quote::quote;
///
/// // The tip of a crank: (l1 cos phi, l1 sin phi).
/// let mut a = Arena::new();
/// let [phi, ..] = a.coordinate("phi");
/// let l1 = a.symbol("l1", SymbolKind::Parameter);
/// let (c, s) = (a.cos(phi), a.sin(phi));
/// let tip = Matrix::column(vec![a.mul2(l1, c), a.mul2(l1, s)]);
/// let program = Program::new(&a, &[&tip]).unwrap();
///
/// let mut b = EmitBindings::new();
/// b.bind(a.lookup("phi").unwrap(), quote!(q[0])).bind(a.lookup("l1").unwrap(), quote!(self.l1));
/// let body = emit_body(&program, &b, &[OutputTarget::Vector { name: quote!(out), zeroed: false }]).unwrap();
/// let code: String = body.tokens.to_string().split_whitespace().collect();
/// assert_eq!(
///     code,
///     "let(x0,x1):(f64,f64)=q[0].sin_cos();letx2:f64=self.l1*x1;out[0]=x2;letx3:f64=self.l1*x0;out[1]=x3;"
/// );
/// assert_eq!((body.counts.muls, body.counts.calls), (2, 1));
/// ```
pub fn emit_body(
    program: &Program,
    bindings: &EmitBindings,
    targets: &[OutputTarget],
) -> Result<EmittedBody> {
    check_request(program, bindings, targets)?;
    let active: Vec<usize> = (0..targets.len())
        .filter(|&k| !matches!(targets[k], OutputTarget::Skip))
        .collect();
    let targets: Vec<&OutputTarget> = active.iter().map(|&k| &targets[k]).collect();
    let p = program.restrict(&active)?;
    let ret = returned_value(&p, &targets)?;
    check_restricted(&p, bindings, &targets)?;
    let lean = p.instructions().len() > LEAN_ABOVE;
    let e = Emitter { b: bindings, lean };
    let mut writes = e.writes(&p, &targets);
    // Inline the last instruction into a returned tail when nothing else follows it.
    let n = p.instructions().len();
    let inline_last = match (ret, p.instructions().last()) {
        (Some(Operand::Reg(r)), Some(last)) => writes.is_empty() && single_dst(last) == Some(r),
        _ => false,
    };
    let end = if inline_last { n - 1 } else { n };
    let mut tokens = if lean {
        e.hoisted_reads(&p)
    } else {
        TokenStream::new()
    };
    tokens.extend(std::mem::take(&mut writes.fixed));
    let mut at_end: Vec<Operand> = ret.into_iter().collect();
    at_end.extend(
        writes
            .columns
            .iter()
            .flat_map(|(_, o)| o.entries.iter().copied()),
    );
    tokens.extend(e.statements(&p, &at_end, end, &mut writes.after));
    for (name, o) in &writes.columns {
        tokens.extend(e.columns(name, o));
    }
    if let Some(r) = ret {
        match (inline_last, p.instructions().last()) {
            (true, Some(last)) => tokens.extend(e.rhs(last)),
            _ => tokens.extend(e.operand(r)),
        }
    }
    Ok(EmittedBody {
        tokens,
        counts: p.op_counts(),
        registers: p.registers(),
        symbols: p.symbols().iter().map(|(s, _)| *s).collect(),
    })
}

/// One target per output, and a register prefix that is an identifier.
fn check_request(
    program: &Program,
    bindings: &EmitBindings,
    targets: &[OutputTarget],
) -> Result<()> {
    if targets.len() != program.outputs().len() {
        return Err(Error::Program(ProgramError::OutputCount {
            what: "output targets for a program with",
            given: targets.len(),
            outputs: program.outputs().len(),
        }));
    }
    if !is_identifier(&bindings.prefix) {
        return Err(Error::Program(ProgramError::RegisterPrefix {
            prefix: bindings.prefix.clone(),
        }));
    }
    Ok(())
}

/// The operand of the one output targeted as the returned value (1 x 1), if any.
fn returned_value(p: &Program, targets: &[&OutputTarget]) -> Result<Option<Operand>> {
    let returns: Vec<usize> = (0..targets.len())
        .filter(|&k| matches!(targets[k], OutputTarget::Return))
        .collect();
    if let [first, second, ..] = returns[..] {
        return Err(Error::Program(ProgramError::SeveralReturns {
            first,
            second,
        }));
    }
    match returns.first() {
        Some(&k) => {
            let o = &p.outputs()[k];
            if o.entries.len() != 1 {
                return Err(Error::Program(ProgramError::ReturnNotScalar {
                    output: k,
                    rows: o.rows,
                    cols: o.cols,
                }));
            }
            Ok(Some(o.entries[0]))
        }
        None => Ok(None),
    }
}

/// Every symbol the restricted program reads has a binding, and no matrix output is
/// targeted as a vector.
fn check_restricted(p: &Program, bindings: &EmitBindings, targets: &[&OutputTarget]) -> Result<()> {
    for (s, name) in p.symbols() {
        if bindings.get(*s).is_none() {
            return Err(Error::Eval(EvalError::MissingValue { name: name.clone() }));
        }
    }
    for (output, (o, t)) in p.outputs().iter().zip(targets).enumerate() {
        if matches!(t, OutputTarget::Vector { .. }) && o.rows > 1 && o.cols > 1 {
            return Err(Error::Program(ProgramError::MatrixAsVector {
                output,
                rows: o.rows,
                cols: o.cols,
            }));
        }
    }
    Ok(())
}

fn single_dst(i: &Instr) -> Option<Reg> {
    match *i {
        Instr::Unary { dst, .. }
        | Instr::Binary { dst, .. }
        | Instr::Powi { dst, .. }
        | Instr::MulAdd { dst, .. } => Some(dst),
        Instr::SinCos { .. } => None,
    }
}

fn is_identifier(s: &str) -> bool {
    let mut c = s.chars();
    c.next()
        .is_some_and(|f| f.is_ascii_alphabetic() || f == '_')
        && c.all(|x| x.is_ascii_alphanumeric() || x == '_')
}

/// Instruction count above which [`emit_body`] writes a body in its lean form, the one that
/// costs rustc least per instruction (measured on straight-line bodies of 20,000
/// instructions: a third less time and memory than the form below it): `let`s without type
/// annotations, each symbol read once into a local at the top (`let vs3 = q[3];`: an indexed
/// read costs rustc about as much as an arithmetic `let`), and the sines and cosines of a
/// lanes call given those locals (no `read`). Matrix outputs are best given as
/// [`OutputTarget::Columns`] there. Smaller bodies keep the form below, whose reads keep
/// the vector loads of the lanes off pending stores (see `mechanism_math::read`).
pub const LEAN_ABOVE: usize = 2000;

/// Instruction count above which [`emit_body`] groups the `let`s into nested blocks of
/// `BLOCK_LEN`, each returning the values read after it (a flat run of ~8,000 `let`s, the
/// 32-bar chain's `evaluate`, overflowed rustc's stack in a debuginfo build; 2,512 built).
pub const BLOCK_LETS_ABOVE: usize = 2000;

/// `let`s per block above [`BLOCK_LETS_ABOVE`].
const BLOCK_LEN: usize = 1000;

/// The output writes of a body (see [`Emitter::writes`]).
#[derive(Default)]
struct Writes<'p> {
    /// Writes of constants and symbols: before the first instruction.
    fixed: TokenStream,
    /// Writes of each register, by register number: right after its instruction.
    after: FxHashMap<u32, TokenStream>,
    /// The outputs written whole after the last instruction ([`OutputTarget::Columns`]).
    columns: Vec<(TokenStream, &'p crate::program::instructions::Output)>,
}

impl Writes<'_> {
    fn is_empty(&self) -> bool {
        self.fixed.is_empty() && self.after.is_empty() && self.columns.is_empty()
    }
}

struct Emitter<'a> {
    b: &'a EmitBindings,
    /// The lean form (see [`LEAN_ABOVE`]).
    lean: bool,
}

impl Emitter<'_> {
    /// The writes of the matrix and vector outputs, `name[(i, j)] = value;` or
    /// `name[k] = value;` (skipping zeros of a zeroed target): those of constants and symbols
    /// first, each register's right after the instruction that defines it, so that an
    /// output value is stored as soon as it is complete and does not stay live (in a
    /// register or spilled) to the end of the body.
    fn writes<'p>(&self, p: &'p Program, targets: &[&OutputTarget]) -> Writes<'p> {
        let mut w = Writes::default();
        for (o, t) in p.outputs().iter().zip(targets) {
            let (name, zeroed, layout) = match t {
                OutputTarget::Matrix { name, zeroed } => (name, *zeroed, Layout::Matrix),
                OutputTarget::Vector { name, zeroed } => (name, *zeroed, Layout::Vector),
                OutputTarget::ColumnMajor { name } => (name, true, Layout::ColumnMajor),
                OutputTarget::Columns { name } => {
                    w.columns.push((name.clone(), o));
                    continue;
                }
                _ => continue,
            };
            for (k, &v) in o.entries.iter().enumerate() {
                if zeroed && structural_zero(v) {
                    continue;
                }
                let value = self.operand(v);
                let cols = o.cols.max(1);
                let (i, j) = (k / cols, k % cols);
                let write = match layout {
                    Layout::Matrix => {
                        let (i, j) = (Literal::usize_unsuffixed(i), Literal::usize_unsuffixed(j));
                        quote!(#name[(#i, #j)] = #value;)
                    }
                    Layout::Vector => {
                        let k = Literal::usize_unsuffixed(k);
                        quote!(#name[#k] = #value;)
                    }
                    Layout::ColumnMajor => {
                        let k = Literal::usize_unsuffixed(i + j * o.rows);
                        quote!(#name[#k] = #value;)
                    }
                };
                match v {
                    Operand::Reg(r) => w.after.entry(r.0).or_default().extend(write),
                    _ => w.fixed.extend(write),
                }
            }
        }
        w
    }

    /// The `let` statements of the instructions `..end`, each followed by the writes of the
    /// registers it defines (taken from `after`), in blocks when there are many (handing on
    /// what later instructions and `at_end`, read after the last one, read).
    fn statements(
        &self,
        p: &Program,
        at_end: &[Operand],
        end: usize,
        after: &mut FxHashMap<u32, TokenStream>,
    ) -> TokenStream {
        // Which registers are defined so far (values of earlier blocks included).
        let mut defined = vec![false; p.registers()];
        let group = self.b.math.is_some();
        let mut tokens = TokenStream::new();
        if p.instructions().len() > BLOCK_LETS_ABOVE {
            // rustc's debug info nests one lexical scope per `let`; tens of thousands of them
            // (a 32-bar chain) overflow its stack in a default debuginfo build. Blocks of
            // BLOCK_LEN `let`s, each handing its live-out values on as one tuple, bound the
            // depth by BLOCK_LEN + n / BLOCK_LEN, and the values stay SSA (no memory traffic).
            // Sines and cosines are grouped within a block only, so its live-out set holds.
            let last = liveness::last_reads(p, at_end);
            let mut start = 0;
            while end - start > BLOCK_LEN {
                let range = start..start + BLOCK_LEN;
                let mut body = TokenStream::new();
                self.run(
                    &p.instructions()[range.clone()],
                    group,
                    &mut defined,
                    after,
                    &mut body,
                );
                let out: Vec<TokenStream> = liveness::live_out(p, &last, range.clone())
                    .into_iter()
                    .map(|r| self.reg(r))
                    .collect();
                // A block whose values are all written inside it hands nothing on.
                tokens.extend(if out.is_empty() {
                    quote!({ #body })
                } else {
                    quote!(let (#(#out,)*) = { #body (#(#out,)*) };)
                });
                start = range.end;
            }
            self.run(
                &p.instructions()[start..end],
                group,
                &mut defined,
                after,
                &mut tokens,
            );
        } else {
            self.run(
                &p.instructions()[..end],
                group,
                &mut defined,
                after,
                &mut tokens,
            );
        }
        tokens
    }

    /// The statements of `instrs` (see [`lanes::plan`]: with `group`, sines and cosines
    /// whose arguments are at hand together become one lanes call), each followed by the
    /// writes of the registers it defines.
    fn run(
        &self,
        instrs: &[Instr],
        group: bool,
        defined: &mut [bool],
        after: &mut FxHashMap<u32, TokenStream>,
        tokens: &mut TokenStream,
    ) {
        let mut write = |i: &Instr, tokens: &mut TokenStream| {
            for r in defines(i).into_iter().flatten() {
                if let Some(w) = after.remove(&r.0) {
                    tokens.extend(w);
                }
            }
        };
        for step in lanes::plan(instrs, defined, group) {
            match step {
                lanes::Step::Single(k) => {
                    tokens.extend(self.instr(&instrs[k]));
                    write(&instrs[k], tokens);
                }
                lanes::Step::Group(members) => {
                    let group: Vec<&Instr> = members.iter().map(|&k| &instrs[k]).collect();
                    tokens.extend(self.lanes(&group));
                    for i in group {
                        write(i, tokens);
                    }
                }
            }
        }
    }

    /// `let ([s0, s1, _], [c0, _, c2]) = math::sin_cos_lanes([math::read(&q[0]), v3, ..]);`
    /// for a group of sine and cosine instructions (`_` for a half no instruction needs;
    /// symbols read through `math::read`).
    fn lanes(&self, group: &[&Instr]) -> TokenStream {
        let ls: Vec<lanes::Lane> = group.iter().filter_map(|i| lanes::lane(i)).collect();
        let slot = |r: Option<Reg>| r.map_or_else(|| quote!(_), |r| self.reg(r));
        let sins = ls.iter().map(|l| slot(l.sin));
        let coss = ls.iter().map(|l| slot(l.cos));
        let m = self.b.math.clone().unwrap_or_default();
        // Inputs read one by one (`mechanism_math::read`): no wide load of neighbouring
        // coordinates waiting on the caller's last store.
        let args = ls.iter().map(|l| match l.arg {
            // The lean form's locals are copies already.
            Operand::Sym(_) if self.lean => self.operand(l.arg),
            Operand::Sym(_) => {
                // Parenthesised: a binding may be any expression, not only a place.
                let place = self.operand(l.arg);
                quote!(#m::read(&(#place)))
            }
            Operand::Reg(_) | Operand::Const(_) => self.operand(l.arg),
        });
        let call = match &self.b.isa {
            Some(isa) => quote!(#isa.sin_cos_lanes),
            None => quote!(#m::sin_cos_lanes),
        };
        quote!(let ([#(#sins),*], [#(#coss),*]) = #call([#(#args),*]);)
    }

    /// `let vs3 = q[3];` for each symbol the program reads (the lean form reads each once).
    fn hoisted_reads(&self, p: &Program) -> TokenStream {
        let mut t = TokenStream::new();
        for (s, _) in p.symbols() {
            let local = self.symbol_local(*s);
            let read = self.b.get(*s).cloned().unwrap_or_default();
            t.extend(quote!(let #local = #read;));
        }
        t
    }

    /// The local holding symbol `s` in the lean form: `{prefix}s{id}` (registers are
    /// `{prefix}{number}`, so the two never meet).
    fn symbol_local(&self, s: SymbolId) -> TokenStream {
        Ident::new(
            &format!("{}s{}", self.b.prefix, s.index()),
            Span::call_site(),
        )
        .into_token_stream()
    }

    /// `name = [[..], ..];`: every entry of `o`, column by column.
    fn columns(&self, name: &TokenStream, o: &crate::program::instructions::Output) -> TokenStream {
        let cols = o.cols.max(1);
        let columns = (0..o.cols).map(|j| {
            let column = (0..o.rows).map(|i| self.operand(o.entries[i * cols + j]));
            quote!([#(#column),*])
        });
        quote!(#name = [#(#columns),*];)
    }

    fn reg(&self, r: Reg) -> TokenStream {
        Ident::new(&format!("{}{}", self.b.prefix, r.0), Span::call_site()).into_token_stream()
    }

    fn operand(&self, o: Operand) -> TokenStream {
        match o {
            Operand::Reg(r) => self.reg(r),
            Operand::Sym(s) if self.lean => self.symbol_local(s),
            Operand::Sym(s) => self.b.get(s).cloned().unwrap_or_default(),
            Operand::Const(c) => f64_tokens(c),
        }
    }

    /// An operand as a method receiver: a negative constant needs parentheses.
    fn receiver(&self, o: Operand) -> TokenStream {
        match o {
            Operand::Const(c) if c < 0.0 => {
                Group::new(Delimiter::Parenthesis, f64_tokens(c)).into_token_stream()
            }
            _ => self.operand(o),
        }
    }

    /// `f` applied to `arg` (and a second argument): `math::f(arg, second)` with a math
    /// module, else the method call `arg.f(second)`.
    fn call(&self, f: &Ident, arg: Operand, second: Option<TokenStream>) -> TokenStream {
        match (&self.b.math, second) {
            (Some(m), None) => {
                let a = self.operand(arg);
                quote!(#m::#f(#a))
            }
            (Some(m), Some(b)) => {
                let a = self.operand(arg);
                quote!(#m::#f(#a, #b))
            }
            (None, None) => {
                let a = self.receiver(arg);
                quote!(#a.#f())
            }
            (None, Some(b)) => {
                let a = self.receiver(arg);
                quote!(#a.#f(#b))
            }
        }
    }

    fn instr(&self, i: &Instr) -> TokenStream {
        let rhs = self.rhs(i);
        match *i {
            Instr::SinCos { sin, cos, .. } => {
                let (s, c) = (self.reg(sin), self.reg(cos));
                if self.lean {
                    quote!(let (#s, #c) = #rhs;)
                } else {
                    quote!(let (#s, #c): (f64, f64) = #rhs;)
                }
            }
            Instr::Unary { dst, .. }
            | Instr::Binary { dst, .. }
            | Instr::Powi { dst, .. }
            | Instr::MulAdd { dst, .. } => {
                let d = self.reg(dst);
                if self.lean {
                    quote!(let #d = #rhs;)
                } else {
                    quote!(let #d: f64 = #rhs;)
                }
            }
        }
    }

    /// `math::mul_add(+-a, b, +-c)` with a math module; else the unfused `a * b + c`,
    /// `a * b - c` or `c - a * b` (the f64 method `mul_add` would round once, which the
    /// interpreter's portable `mul_add` does not).
    fn mul_add(
        &self,
        a: Operand,
        b: Operand,
        c: Operand,
        neg_ab: bool,
        neg_c: bool,
    ) -> TokenStream {
        let (bt, ct) = (self.operand(b), self.operand(c));
        match &self.b.math {
            Some(m) => {
                let at = self.signed(a, neg_ab);
                let ct = self.signed(c, neg_c);
                quote!(#m::mul_add(#at, #bt, #ct))
            }
            None => {
                let at = self.operand(a);
                match (neg_ab, neg_c) {
                    (false, false) => quote!(#at * #bt + #ct),
                    (false, true) => quote!(#at * #bt - #ct),
                    (true, false) => quote!(#ct - #at * #bt),
                    (true, true) => quote!(-(#at * #bt) - #ct),
                }
            }
        }
    }

    /// `o`, or `-o` (a negative constant written as its magnitude).
    fn signed(&self, o: Operand, negate: bool) -> TokenStream {
        match (o, negate) {
            (_, false) => self.operand(o),
            (Operand::Const(c), true) => f64_tokens(-c),
            (_, true) => {
                let t = self.operand(o);
                quote!(-#t)
            }
        }
    }

    /// The expression an instruction computes.
    fn rhs(&self, i: &Instr) -> TokenStream {
        match *i {
            Instr::Unary {
                op: UnOp::Neg, arg, ..
            } => {
                let a = self.operand(arg);
                quote!(-#a)
            }
            Instr::Unary { op, arg, .. } => {
                if let (Some(m), UnOp::Sin | UnOp::Cos) = (&self.b.math, op) {
                    let a = self.operand(arg);
                    let k = Literal::usize_unsuffixed(usize::from(op == UnOp::Cos));
                    return quote!(#m::sin_cos(#a).#k);
                }
                let f = Ident::new(
                    match op {
                        UnOp::Sin => "sin",
                        UnOp::Cos => "cos",
                        UnOp::Tan => "tan",
                        UnOp::Exp => "exp",
                        UnOp::Ln => "ln",
                        UnOp::Sqrt => "sqrt",
                        UnOp::Abs | UnOp::Neg => "abs",
                    },
                    Span::call_site(),
                );
                self.call(&f, arg, None)
            }
            Instr::SinCos { arg, .. } => {
                self.call(&Ident::new("sin_cos", Span::call_site()), arg, None)
            }
            Instr::Powi { base, exp, .. } => {
                let k = Literal::u32_unsuffixed(exp.unsigned_abs());
                let k = if exp < 0 { quote!(-#k) } else { quote!(#k) };
                self.call(&Ident::new("powi", Span::call_site()), base, Some(k))
            }
            Instr::MulAdd {
                a,
                b,
                c,
                negate_product,
                negate_addend,
                ..
            } => self.mul_add(a, b, c, negate_product, negate_addend),
            Instr::Binary { op, lhs, rhs, .. } => {
                let b = self.operand(rhs);
                match op {
                    BinOp::Atan2 | BinOp::Powf => {
                        let f = Ident::new(
                            if op == BinOp::Atan2 { "atan2" } else { "powf" },
                            Span::call_site(),
                        );
                        self.call(&f, lhs, Some(b))
                    }
                    _ => {
                        let a = self.operand(lhs);
                        let mut t = a;
                        t.append(Punct::new(
                            match op {
                                BinOp::Add => '+',
                                BinOp::Sub => '-',
                                BinOp::Mul => '*',
                                _ => '/',
                            },
                            Spacing::Alone,
                        ));
                        t.extend(b);
                        t
                    }
                }
            }
        }
    }
}

/// The named constants of `core::f64::consts`, written as paths instead of literals.
const NAMED: [(&str, f64); 19] = [
    ("PI", std::f64::consts::PI),
    ("TAU", std::f64::consts::TAU),
    ("E", std::f64::consts::E),
    ("FRAC_1_PI", std::f64::consts::FRAC_1_PI),
    ("FRAC_1_SQRT_2", std::f64::consts::FRAC_1_SQRT_2),
    ("FRAC_2_PI", std::f64::consts::FRAC_2_PI),
    ("FRAC_2_SQRT_PI", std::f64::consts::FRAC_2_SQRT_PI),
    ("FRAC_PI_2", std::f64::consts::FRAC_PI_2),
    ("FRAC_PI_3", std::f64::consts::FRAC_PI_3),
    ("FRAC_PI_4", std::f64::consts::FRAC_PI_4),
    ("FRAC_PI_6", std::f64::consts::FRAC_PI_6),
    ("FRAC_PI_8", std::f64::consts::FRAC_PI_8),
    ("LN_10", std::f64::consts::LN_10),
    ("LN_2", std::f64::consts::LN_2),
    ("LOG10_E", std::f64::consts::LOG10_E),
    ("LOG2_E", std::f64::consts::LOG2_E),
    ("SQRT_2", std::f64::consts::SQRT_2),
    ("LOG2_10", std::f64::consts::LOG2_10),
    ("LOG10_2", std::f64::consts::LOG10_2),
];

/// An f64 constant as tokens: `::core::f64::consts::PI` for a named constant, otherwise a
/// suffixed literal in Rust's shortest round-trip form (`0.5_f64`, `1e-300_f64`); negative
/// values as `-` followed by the magnitude. (A program's constants are always finite; NaN
/// and infinities, if passed here, become `::core::f64::NAN` and `::core::f64::INFINITY`.)
pub fn f64_tokens(v: f64) -> TokenStream {
    if v.is_nan() {
        return quote!(::core::f64::NAN);
    }
    let mut t = TokenStream::new();
    if v < 0.0 {
        t.append(Punct::new('-', Spacing::Alone));
    }
    let a = v.abs();
    if let Some((name, _)) = NAMED.iter().find(|(_, c)| c.to_bits() == a.to_bits()) {
        let n = Ident::new(name, Span::call_site());
        t.extend(quote!(::core::f64::consts::#n));
        return t;
    }
    if a.is_infinite() {
        t.extend(quote!(::core::f64::INFINITY));
        return t;
    }
    let text = format!("{a:?}_f64");
    match Literal::from_str(&text) {
        Ok(l) => t.append(l),
        Err(_) => t.append(Literal::f64_suffixed(a)),
    }
    t
}
